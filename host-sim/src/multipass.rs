//! Multipass noise on the host ([`texcore::multipass`]): the command-line settings, the stage
//! contact sheet of `texsim render --show multipass-stages`, and `texsim report multipass` (the
//! measured pass table and the histogram of noise values by hash, `docs/multipass-histogram.png`).
//!
//! Guarantees: every image is computed from the texcore passes themselves (no separate model),
//! and nothing is written unless asked for (an output path, or the report's `--write-docs`).

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};
use plotters::prelude::*;
use texcore::hash::HashKind;
use texcore::multipass::{Band, MultipassConfig, PassHash, PassPrecision, PassTerm};
use texcore::noise::{BasisKind, Fade, NoiseBasis};

use crate::accuracy::font::{draw_text, text_width};
use crate::output::Frame;

/// `--multipass-precision`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    /// 8-bit passes (4.4 coordinates, as on the paper's 2001 hardware).
    #[value(name = "8")]
    Bits8,
    /// The 16.8 fixed-point format the paper proposes.
    #[value(name = "16.8")]
    Fixed16_8,
    /// texcore's native precision (bit-identical to direct evaluation).
    #[default]
    Native,
}

impl From<PrecisionArg> for PassPrecision {
    fn from(p: PrecisionArg) -> Self {
        match p {
            PrecisionArg::Bits8 => PassPrecision::Bits8,
            PrecisionArg::Fixed16_8 => PassPrecision::Fixed16_8,
            PrecisionArg::Native => PassPrecision::Native,
        }
    }
}

/// `--multipass-hash`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum HashArg {
    /// texcore's lattice hash (`--hash`).
    #[default]
    Texcore,
    /// Three per-axis random values summed (the paper's SGI hash; Gaussian bias).
    Summed,
    /// Three per-axis random bytes combined by exclusive or.
    Xor,
}

impl From<HashArg> for PassHash {
    fn from(h: HashArg) -> Self {
        match h {
            HashArg::Texcore => PassHash::Texcore,
            HashArg::Summed => PassHash::SummedRandom,
            HashArg::Xor => PassHash::Xor,
        }
    }
}

/// An evaluation mode's name in reports: `direct`, `fd`, ..., and `multipass-<precision>` (with
/// `-<hash>` unless texcore's).
pub fn mode_name(mode: texcore::span::EvalMode) -> String {
    match mode {
        texcore::span::EvalMode::Multipass(c) => match c.hash {
            PassHash::Texcore => format!("multipass-{}", c.precision.name()),
            h => format!("multipass-{}-{}", c.precision.name(), h.name()),
        },
        m => m.to_string(),
    }
}

/// Side of one stage image (the paper's 256 x 256).
pub const STAGE: u32 = 256;
/// Lattice cells across a stage image (the paper's Fig. 4: `s, t` in `[0, 16)`).
pub const STAGE_CELLS: i32 = 16;

fn term(basis: NoiseBasis, config: MultipassConfig, gradients: bool) -> PassTerm {
    PassTerm {
        hash: basis.hash,
        fade: basis.fade,
        // Amplitude 1 with the model's noise fraction bits for it.
        amp_raw: 1 << 16,
        fv: 13,
        value_bits: 16,
        config,
        gradients,
    }
}

/// The noise basis whose stages `--show multipass-stages` shows for a scene: the first value-noise
/// term of the scene's first texture slot's preset (with the `--hash` lattice hash), else
/// trilinear value noise.
pub fn scene_basis(scene: &texcore::scene::Scene, hash: HashKind) -> NoiseBasis {
    scene
        .slots
        .first()
        .and_then(|s| texcore::presets::by_name(s.material, hash))
        .and_then(|p| {
            p.model
                .terms()
                .iter()
                .find(|t| matches!(t.basis.kind, BasisKind::Value))
                .map(|t| t.basis)
        })
        .unwrap_or(NoiseBasis::trilinear(hash))
}

/// The stage contact sheet (the paper's Figs. 4 and 7-9) of `basis` with `config` on the plane
/// `s, t` in `[0, 16)`, `r = 0` (the paper's Fig. 4): solid_int (`s` red, `t` green, shifted left 4 bits), the
/// weights (`s` red, `t` green), corner 0's random field and the weighted sum, left to right,
/// each 256 x 256 under a caption.
pub fn stage_sheet(basis: NoiseBasis, config: MultipassConfig) -> Frame {
    let caption = 16u32;
    let gap = 8u32;
    let (w, h) = (4 * STAGE + 5 * gap, STAGE + caption + 2 * gap);
    let mut buf = vec![255u8; (w * h * 3) as usize];
    let t = term(basis, config, false);
    let mut band = Box::new(Band::<{ STAGE as usize }>::new());
    let step = (STAGE_CELLS << 16) / STAGE as i32;
    let put = |buf: &mut [u8], panel: u32, x: u32, y: u32, rgb: [u8; 3]| {
        let px = gap + panel * (STAGE + gap) + x;
        let py = caption + gap + y;
        let o = ((py * w + px) * 3) as usize;
        buf[o..o + 3].copy_from_slice(&rgb);
    };
    for y in 0..STAGE {
        let u0 = [0, y as i32 * step, 0];
        band.run(&t, u0, [step, 0, 0], STAGE as usize);
        let noise: Vec<i64> = band.values().to_vec();
        for (x, &n) in noise.iter().enumerate() {
            // The plane spans 16 cells: solid_int shifted left 4 bits, as the paper shows it.
            let is = band.int_part(0)[x] << 4;
            let it = band.int_part(1)[x] << 4;
            put(&mut buf, 0, x as u32, y, [is as u8, it as u8, 0]);
            let ws = (band.weight(0)[x].min(65535) >> 8) as u8;
            let wt = (band.weight(1)[x].min(65535) >> 8) as u8;
            put(&mut buf, 1, x as u32, y, [ws, wt, 0]);
            // The sum in [-1, 1] (2^-45 units at fv 13) as grey.
            let v = ((n >> 45) + 65536).clamp(0, 131071) >> 9;
            put(&mut buf, 3, x as u32, y, [v as u8; 3]);
        }
        let field = band.random_field(&t, 0);
        for (x, &r) in field.iter().enumerate() {
            put(&mut buf, 2, x as u32, y, [r.min(255) as u8; 3]);
        }
    }
    let labels = ["SOLID_INT", "WEIGHT", "CORNER 0 RANDOM", "WEIGHTED SUM"];
    for (i, l) in labels.iter().enumerate() {
        let x = gap + i as u32 * (STAGE + gap) + (STAGE - text_width(l, 1)) / 2;
        draw_text(&mut buf, w, h, x as i32, 6, l, 1, [20, 20, 20]);
    }
    rgb_frame(&buf, w, h)
}

fn rgb_frame(rgb: &[u8], w: u32, h: u32) -> Frame {
    Frame {
        width: w,
        height: h,
        pixels: rgb.chunks(3).map(|p| [p[0], p[1], p[2], 255]).collect(),
    }
}

/// `texsim render SCENE --show multipass-stages -o SHEET.png`: the stage contact sheet of the
/// scene's noise ([`scene_basis`]) with the `--multipass-precision` and `--multipass-hash`
/// settings.
pub fn render_stages(
    a: &crate::cli::RenderArgs,
    scene: &texcore::scene::Scene,
    hash: HashKind,
) -> ExitCode {
    let Some(out) = &a.output else {
        return crate::cli::bad_input(
            "--show multipass-stages writes a contact sheet: give --output",
        );
    };
    if a.frames.is_some() {
        return crate::cli::bad_input("--show multipass-stages is a still: drop --frames");
    }
    let sheet = stage_sheet(scene_basis(scene, hash), a.knobs.multipass());
    if let Err(e) = crate::output::write_png(out, &sheet) {
        return crate::cli::bad_input(e);
    }
    ExitCode::SUCCESS
}

/// Bins of the value histogram over `[-1, 1]`.
pub const BINS: usize = 64;

/// Histogram of linear-fade noise values at native precision with `hash` over a 256 x 256 plane
/// of `s, t` in `[0, 64)` (4096 cells) tilted through `r`; texcore's hash is the integer hash.
pub fn histogram(hash: PassHash) -> [u32; BINS] {
    let basis = NoiseBasis::trilinear(HashKind::Integer);
    let config = MultipassConfig {
        precision: PassPrecision::Native,
        hash,
    };
    let t = term(basis, config, false);
    let mut band = Box::new(Band::<256>::new());
    let mut h = [0u32; BINS];
    let step = (64 << 16) / 256 + 3;
    for y in 0..256 {
        // An oblique plane: every row at another depth, so no single `r` slice (where the XOR
        // hash's two `r` layers can cancel) dominates.
        band.run(
            &t,
            [7, y * step + 11, y * 5003 + 4099],
            [step, 0, step / 7],
            256,
        );
        for &v in band.values() {
            let x = ((v >> 45) + 65536).clamp(0, 131071) as usize;
            h[x * BINS / 131072] += 1;
        }
    }
    h
}

/// The histogram plot of noise values, summed randoms against XOR (and texcore's hash).
pub fn histogram_plot() -> Option<Frame> {
    let (w, h) = (720u32, 420u32);
    let (left, right, top, bottom) = (60i32, 20i32, 50i32, 50i32);
    let series = [
        (PassHash::SummedRandom, RGBColor(200, 40, 40), "SUMMED"),
        (PassHash::Xor, RGBColor(40, 90, 200), "XOR"),
        (PassHash::Texcore, RGBColor(60, 150, 60), "TEXCORE"),
    ];
    let hists: Vec<[u32; BINS]> = series.iter().map(|s| histogram(s.0)).collect();
    let ymax = hists.iter().flatten().copied().max()? as f64 * 1.1;
    let pw = (w as i32 - left - right) as f64;
    let ph = (h as i32 - top - bottom) as f64;
    let sx = |b: f64| left + (b / BINS as f64 * pw) as i32;
    let sy = |c: f64| top + ((1.0 - c / ymax) * ph) as i32;
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.draw(&Rectangle::new(
            [(left, top), (w as i32 - right, h as i32 - bottom)],
            RGBColor(60, 60, 60).stroke_width(1),
        ))
        .ok()?;
        for (s, hist) in series.iter().zip(&hists) {
            let path: Vec<(i32, i32)> = hist
                .iter()
                .enumerate()
                .flat_map(|(i, &c)| {
                    let y = sy(f64::from(c));
                    [(sx(i as f64), y), (sx(i as f64 + 1.0), y)]
                })
                .collect();
            root.draw(&PathElement::new(path, s.1.stroke_width(2)))
                .ok()?;
        }
        root.present().ok()?;
    }
    let black = [20, 20, 20];
    draw_text(
        &mut buf,
        w,
        h,
        left,
        15,
        "MULTIPASS NOISE VALUES BY HASH (65536 SAMPLES)",
        2,
        black,
    );
    for (i, label) in ["-1", "0", "1"].iter().enumerate() {
        let x = sx(i as f64 * BINS as f64 / 2.0) - text_width(label, 1) as i32 / 2;
        draw_text(&mut buf, w, h, x, h as i32 - bottom + 8, label, 1, black);
    }
    for (k, s) in series.iter().enumerate() {
        let x = w as i32 - right - 120;
        let y = top + 10 + k as i32 * 14;
        let c = [s.1 .0, s.1 .1, s.1 .2];
        draw_text(&mut buf, w, h, x, y, s.2, 1, c);
    }
    Some(rgb_frame(&buf, w, h))
}

/// One row of the pass table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PassRow {
    /// Precision name.
    pub precision: &'static str,
    /// Hash name.
    pub hash: &'static str,
    /// Fade name.
    pub fade: &'static str,
    /// Passes for the value of one octave.
    pub value: u32,
    /// Passes with the two gradient components (filter width).
    pub with_gradients: u32,
}

/// The passes one octave takes for every setting, counted by running a band.
pub fn pass_table() -> Vec<PassRow> {
    let fades = [(Fade::Linear, "linear"), (Fade::Smooth, "smooth")];
    let mut rows = Vec::new();
    for precision in PassPrecision::ALL {
        for hash in PassHash::ALL {
            for &(fade, fname) in &fades {
                let count = |grads: bool| {
                    let basis = NoiseBasis {
                        kind: BasisKind::Value,
                        fade,
                        hash: HashKind::Integer,
                    };
                    let t = term(basis, MultipassConfig { precision, hash }, grads);
                    let mut band = Band::<4>::new();
                    band.run(&t, [0; 3], [1; 3], 4);
                    if grads {
                        let mut out = [0i64; 4];
                        band.derivative_into(fade, [1; 3], &mut out);
                        band.derivative_into(fade, [1; 3], &mut out);
                    }
                    band.passes()
                };
                rows.push(PassRow {
                    precision: precision.name(),
                    hash: hash.name(),
                    fade: fname,
                    value: count(false),
                    with_gradients: count(true),
                });
            }
        }
    }
    rows
}

/// `texsim report multipass`.
#[derive(Clone, Debug, Args)]
pub struct ReportArgs {
    /// Write the histogram plot to the workspace's docs/multipass-histogram.png (without it, or
    /// --histogram, the report only prints).
    #[arg(long, conflicts_with = "histogram")]
    pub write_docs: bool,
    /// Write the histogram plot to this file instead.
    #[arg(long)]
    pub histogram: Option<PathBuf>,
}

/// Prints the pass table (markdown) and the histogram counts; writes the histogram plot.
pub fn report(a: &ReportArgs) -> ExitCode {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(
        out,
        "| precision | hash | fade | passes (value) | passes (value + gradients) |"
    );
    let _ = writeln!(out, "|---|---|---|---:|---:|");
    for r in pass_table() {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} |",
            r.precision, r.hash, r.fade, r.value, r.with_gradients
        );
    }
    for hash in PassHash::ALL {
        let h = histogram(hash);
        let n: u32 = h.iter().sum();
        let outer: u32 = h[..BINS / 4].iter().chain(&h[3 * BINS / 4..]).sum();
        let _ = writeln!(
            out,
            "histogram {}: {:.1}% of values with |n| > 0.5",
            hash.name(),
            100.0 * f64::from(outer) / f64::from(n)
        );
    }
    let path = match (&a.histogram, a.write_docs) {
        (Some(p), _) => p.clone(),
        (None, true) => crate::device::workspace_root().join("docs/multipass-histogram.png"),
        (None, false) => return ExitCode::SUCCESS,
    };
    let Some(frame) = histogram_plot() else {
        return crate::cli::bad_input("the histogram plot could not be drawn");
    };
    if let Err(e) = crate::output::write_png(&path, &frame) {
        return crate::cli::bad_input(e);
    }
    let _ = writeln!(out, "wrote {}", path.display());
    ExitCode::SUCCESS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summed_has_the_gaussian_bias() {
        let outer = |h: [u32; BINS]| {
            let o: u32 = h[..BINS / 4].iter().chain(&h[3 * BINS / 4..]).sum();
            f64::from(o) / f64::from(h.iter().sum::<u32>())
        };
        let s = outer(histogram(PassHash::SummedRandom));
        let x = outer(histogram(PassHash::Xor));
        assert!(s < 0.5 * x, "summed {s} xor {x}");
    }

    #[test]
    fn pass_table_counts_the_passes() {
        let rows = pass_table();
        assert_eq!(rows.len(), 3 * 3 * 2);
        let native = rows
            .iter()
            .find(|r| r.precision == "native" && r.hash == "texcore" && r.fade == "linear")
            .unwrap();
        assert_eq!((native.value, native.with_gradients), (19, 29));
    }

    #[test]
    fn stage_sheet_has_four_panels() {
        let f = stage_sheet(
            NoiseBasis::trilinear(HashKind::Integer),
            MultipassConfig::EXACT,
        );
        assert_eq!((f.width, f.height), (4 * STAGE + 40, STAGE + 32));
        // The weighted sum panel is not flat.
        let row = (16 + 8 + 100) * f.width as usize;
        let x0 = (8 + 3 * (STAGE + 8)) as usize;
        let px: std::collections::HashSet<_> = (0..STAGE as usize)
            .map(|x| f.pixels[row + x0 + x])
            .collect();
        assert!(px.len() > 20);
    }
}
