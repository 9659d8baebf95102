//! `texsim report accuracy`: what each accuracy knob of the texture unit costs in time and code.
//!
//! For a documented baseline (the `marble` preset; see [`device_jobs::BASELINE`]) every knob is
//! varied alone, plus a few combinations that are Pareto-front candidates. Each row gets:
//!
//! - **error** against the f64 reference ([`crate::reference`]) on the baseline's check plane
//!   (`psnr`, `max_error`, `within_one_step`; 8-bit units): the reference has the row's own
//!   table, filter, norm and culling, and is exact (ideal precision, exact evaluation), so this
//!   is what `texsim check` reports for those knobs. Rows that render the baseline's texture
//!   also get the error against the **baseline's** reference image (`base`, the Pareto front's
//!   error axis) and against the **supersampled truth** (`supersampled`: 8x8 stratified point
//!   samples a pixel of the f64 model). Precision rows add the error on the `marble` scene
//!   (`scene`, perspective and unaligned coordinates); antialiasing rows add the seascape's
//!   error against its supersampled truth and the **flicker** near its horizon over a few
//!   frames of its animation. Perspective and band-limiting rows are measured on the seascape
//!   against the f64 reference of the same scene drawn with exact perspective (band-limiting rows
//!   add its supersampled truth and flicker, as antialiasing rows do).
//! - **cost**: host nanoseconds per pixel (median and range of repeated timed runs of the
//!   device's own job code), and exact device instructions per pixel on the Cortex-M4F and
//!   rv32imc under QEMU ([`device`]), with the device checksum compared against the same code
//!   run here; and the **code size** of texcore on both targets for the features the row's
//!   configuration needs, with the RAM of one texture-unit instance ([`codesize`]).
//!
//! Rows are measured in parallel (rayon); host timings run afterwards, one row at a time. It
//! prints JSON rows (`--json`) or a summary, and with `--write-docs` writes `docs/accuracy.md`,
//! `docs/accuracy.png` (error against device instructions, Pareto front highlighted),
//! `docs/precision.png` (the paper's Fig. 10: the `marble` scene at each coordinate precision)
//! and a generated summary between the `<!-- accuracy:begin -->` and `<!-- accuracy:end -->`
//! markers of `README.md`.

pub mod blend;
pub mod codesize;
pub mod device;
pub mod font;
pub mod measure;
pub mod output;
pub mod plot;
pub mod shading;

/// The report's configurations and device jobs, shared with the firmware (`workloads::accuracy`).
pub use workloads::accuracy as device_jobs;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use rayon::prelude::*;
use serde::Serialize;
use texcore::raster::Perspective;

use crate::metrics::Metrics;
use crate::unit::UnitError;
use device::{DevicePolicy, DeviceResults};
use device_jobs::{Config, Knob, Row, BASELINE, ROWS};
use measure::References;

/// `texsim report accuracy`.
#[derive(Clone, Debug, Args)]
pub struct AccuracyArgs {
    /// Few configurations, small images, few timed runs (seconds to a minute; for CI).
    #[arg(long)]
    pub quick: bool,
    /// Print the rows as one JSON array.
    #[arg(long)]
    pub json: bool,
    /// Write accuracy.md, accuracy.png and precision.png to the workspace's docs/ and the
    /// summary into its README.md (without it, --out or --readme, the report only prints).
    #[arg(long)]
    pub write_docs: bool,
    /// Directory for accuracy.md, accuracy.png and precision.png.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// README whose accuracy section is rewritten.
    #[arg(long)]
    pub readme: Option<PathBuf>,
    /// Write no files (the default; kept for older command lines).
    #[arg(long, hide = true, conflicts_with_all = ["write_docs", "out", "readme"])]
    pub no_write: bool,
    /// No device measurements: no instruction counts, no code size (not allowed when CI is
    /// set).
    #[arg(long)]
    pub no_device: bool,
}

/// Sizes and repetitions of a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Settings {
    /// Side of the check-plane error images (the device renders the top-left 64x64).
    pub plane_size: u32,
    /// Supersampling factor (per axis) of the supersampled truths.
    pub supersample: u32,
    /// Timed host runs per row.
    pub host_runs: usize,
    /// Size of the precision scene (`marble`) and of the contact sheet's images.
    pub precision_scene: (u16, u16),
    /// Size of the seascape for flicker.
    pub flicker_scene: (u16, u16),
    /// Frames of the flicker measurement.
    pub flicker_frames: u32,
}

impl Settings {
    /// The full run.
    pub const FULL: Settings = Settings {
        plane_size: 256,
        supersample: 8,
        host_runs: 9,
        precision_scene: (320, 240),
        flicker_scene: (160, 120),
        flicker_frames: 8,
    };
    /// `--quick`.
    pub const QUICK: Settings = Settings {
        plane_size: 64,
        supersample: 2,
        host_runs: 3,
        precision_scene: (80, 60),
        flicker_scene: (80, 60),
        flicker_frames: 3,
    };
}

/// Errors of an image against one reference, in the report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ErrorSummary {
    /// PSNR in dB (capped at 100).
    pub psnr: f64,
    /// Largest channel error, 8-bit units.
    pub max_error: f64,
    /// Mean channel error.
    pub mean_error: f64,
    /// Fraction of pixels within one 8-bit step.
    pub within_one_step: f64,
}

impl From<&Metrics> for ErrorSummary {
    fn from(m: &Metrics) -> Self {
        ErrorSummary {
            psnr: m.psnr,
            max_error: m.max_error,
            mean_error: m.mean_error,
            within_one_step: m.within_one_step,
        }
    }
}

/// Flicker near the seascape's horizon.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Flicker {
    /// Mean absolute frame-to-frame difference of texcore's frames (8-bit units, RGB).
    pub texcore: f64,
    /// The same for the supersampled truth.
    pub reference: f64,
    /// `texcore - reference`.
    pub excess: f64,
}

/// One row of the report (the JSON schema of `--json`).
#[derive(Clone, Debug, Serialize)]
pub struct RowReport {
    /// The knob (`coordinate_bits`, `value_bits`, `interpolation`, `evaluation`, `octaves`,
    /// `table_size`, `antialiasing`, `gradient_norm`, `perspective`, `basis`, `hash`, and
    /// `shading` ([`shading`]) and `gradient_blend` ([`blend`])).
    pub knob: &'static str,
    /// The setting.
    pub setting: &'static str,
    /// The device job name.
    pub id: &'static str,
    /// A combination of knobs (a Pareto-front candidate) rather than a single knob.
    pub combination: bool,
    /// The configuration is the baseline.
    pub baseline: bool,
    /// The configuration in words.
    pub config: String,
    /// What `psnr`, `max_error` and `within_one_step` are measured against.
    pub reference: &'static str,
    /// PSNR (dB) against the reference.
    pub psnr: f64,
    /// Largest channel error (8-bit units).
    pub max_error: f64,
    /// Mean channel error.
    pub mean_error: f64,
    /// Fraction of pixels within one 8-bit step.
    pub within_one_step: f64,
    /// Against the baseline's f64 reference image (rows rendering the baseline's texture).
    pub base: Option<ErrorSummary>,
    /// Against the supersampled truth of the baseline's texture.
    pub supersampled: Option<ErrorSummary>,
    /// Precision rows: the `marble` scene against its f64 reference.
    pub scene: Option<ErrorSummary>,
    /// Antialiasing and band-limiting rows: the seascape against its supersampled truth.
    pub scene_supersampled: Option<ErrorSummary>,
    /// Antialiasing and band-limiting rows: flicker near the seascape's horizon.
    pub flicker: Option<Flicker>,
    /// Antialiasing rows: the same with octave culling off (the papers' unit has none).
    pub flicker_nocull: Option<Flicker>,
    /// Host ns per pixel, median of `host_runs`.
    pub host_ns_per_pixel: f64,
    /// Fastest host run.
    pub host_ns_min: f64,
    /// Slowest host run.
    pub host_ns_max: f64,
    /// Timed host runs.
    pub host_runs: usize,
    /// Device instructions per pixel by target triple (empty without QEMU).
    pub device_instructions_per_pixel: BTreeMap<String, f64>,
    /// Device instructions of building the texture (not per pixel) by target triple.
    pub device_setup_instructions: BTreeMap<String, u64>,
    /// Whether the device's checksum equals the host's, by target triple.
    pub device_checksum_match: BTreeMap<String, bool>,
    /// texcore's code size for the features this configuration needs, and the RAM of a
    /// texture-unit instance, by target triple; `None` when not measured (`--no-device`, or a
    /// feature set outside `--quick`'s).
    pub code_size: Option<BTreeMap<String, codesize::CodeSize>>,
    /// The feature set this configuration needs ([`codesize::feature_set`]), measured or not.
    pub code_features: String,
    /// The job's checksum computed on the host.
    pub checksum: String,
    /// On the Pareto front (base error against M4F instructions).
    pub pareto: bool,
    /// `shading` rows drawn from atlases: atlas texels baked (all objects).
    pub atlas_texels_baked: Option<u64>,
    /// `shading` rows drawn from atlases: host milliseconds to lay out and bake the atlases
    /// (median), not part of `host_ns_per_pixel`.
    pub host_bake_ms: Option<f64>,
    /// `gradient_blend` rows ([`blend`]): the samples' error in units of `2^-16`.
    pub value_error: Option<blend::ValueError>,
}

impl RowReport {
    /// The row's device instructions per unit on `triple` as a table cell (`-` when not
    /// measured).
    pub fn device_cell(&self, triple: &str) -> String {
        self.device_instructions_per_pixel
            .get(triple)
            .map_or("-".to_string(), |v| format!("{v:.1}"))
    }

    /// Whether every device checksum equals the host's, as a table cell (`-`: no device run).
    pub fn device_match_cell(&self) -> &'static str {
        if self.device_checksum_match.is_empty() {
            "-"
        } else if self.device_checksum_match.values().all(|&m| m) {
            "yes"
        } else {
            "**no**"
        }
    }

    /// A row of `knob = setting` (device job `id`) with nothing measured yet: no errors, no
    /// timings, no device counts, not a combination, not the baseline.
    pub fn unmeasured(
        knob: &'static str,
        setting: &'static str,
        id: &'static str,
        config: String,
        code_features: String,
    ) -> RowReport {
        RowReport {
            knob,
            setting,
            id,
            combination: false,
            baseline: false,
            config,
            reference: "",
            psnr: 0.0,
            max_error: 0.0,
            mean_error: 0.0,
            within_one_step: 0.0,
            base: None,
            supersampled: None,
            scene: None,
            scene_supersampled: None,
            flicker: None,
            flicker_nocull: None,
            host_ns_per_pixel: 0.0,
            host_ns_min: 0.0,
            host_ns_max: 0.0,
            host_runs: 0,
            device_instructions_per_pixel: BTreeMap::new(),
            device_setup_instructions: BTreeMap::new(),
            device_checksum_match: BTreeMap::new(),
            code_size: None,
            code_features,
            checksum: String::new(),
            pareto: false,
            atlas_texels_baked: None,
            host_bake_ms: None,
            value_error: None,
        }
    }
}

/// The whole report.
#[derive(Clone, Debug)]
pub struct Report {
    /// The rows, in [`ROWS`] order.
    pub rows: Vec<RowReport>,
    /// Settings used.
    pub settings: Settings,
    /// `--quick`.
    pub quick: bool,
    /// Targets not measured and why.
    pub device_skipped: Vec<String>,
    /// Seconds: total, device part (QEMU runs and their builds).
    pub seconds: (f64, f64),
    /// Seconds of building the probe for the code sizes.
    pub code_seconds: f64,
    /// The marble scene at each coordinate precision (for the contact sheet): bits, image.
    pub precision_images: Vec<(u8, Vec<[u8; 4]>)>,
}

/// The baseline in words.
pub const BASELINE_TEXT: &str = "marble preset (f = r + sum_{i<4} 2^-i n(2^i s), trilinear value \
noise, permutation hash), 4 octaves, 256-entry table, nearest look-up, csat filter, L2 norm, \
auto evaluation, culling on, 16/16 precision";

/// A configuration in words.
pub fn describe(c: &Config) -> String {
    let mut s = format!(
        "F={} V={} {} {} {} {} oct, N={} {} {} {} {}{}",
        c.coord_bits,
        c.value_bits,
        c.fade,
        c.basis,
        measure::hash_name(c.hash),
        c.octaves,
        c.table_size,
        c.lookup,
        c.aa,
        c.norm,
        crate::multipass::mode_name(c.mode),
        if c.cull { "" } else { " no-cull" }
    );
    if c.cull && c.band_limit != texcore::bandlimit::BandLimit::DEFAULT {
        s.push_str(&format!(" band-limit {}", c.band_limit));
    }
    if let Some(p) = c.perspective {
        s.push_str(&format!(" seascape {p}"));
    }
    s.to_lowercase()
}

fn err(e: UnitError) -> String {
    e.to_string()
}

/// Runs the report: every row's host measurements, the device runs, the Pareto front.
pub fn run(quick: bool, policy: DevicePolicy, log: &mut dyn FnMut(&str)) -> Result<Report, String> {
    let start = Instant::now();
    let settings = if quick {
        Settings::QUICK
    } else {
        Settings::FULL
    };
    let rows: Vec<&Row> = ROWS.iter().filter(|r| !quick || r.quick).collect();
    log(&format!(
        "accuracy: {} rows, {}x{} check plane",
        rows.len(),
        settings.plane_size,
        settings.plane_size
    ));
    let size = settings.plane_size;
    let mut refs = References::default();

    // Shared truths.
    let base_ref = refs.plane(&BASELINE, size).map_err(err)?.clone();
    log("accuracy: supersampled truth of the check plane");
    let ss_truth =
        measure::plane_supersampled(&BASELINE, size, settings.supersample).map_err(err)?;

    // Precision scene (marble) and its reference.
    let (pw, ph) = settings.precision_scene;
    let marble_scene = texcore::scene::by_name("marble").ok_or("no marble scene")?;
    let marble_scene = measure::resized(&marble_scene, pw, ph);
    let marble_still = marble_scene.still();
    let marble_ref =
        measure::scene_reference(&marble_scene, marble_still, &BASELINE).map_err(err)?;

    // Flicker scene (seascape, animated) and its supersampled truth per frame.
    let (fw_, fh) = settings.flicker_scene;
    let sea = measure::resized(
        &texcore::scene::by_name("seascape").ok_or("no seascape scene")?,
        fw_,
        fh,
    );
    let band = (u32::from(fh) / 2 - u32::from(fh) / 8)..(u32::from(fh) / 2 + u32::from(fh) / 8);
    let mut sea_truth: Vec<Vec<[f64; 4]>> = Vec::new();
    if rows
        .iter()
        .any(|r| matches!(r.knob, Knob::Antialiasing | Knob::BandLimit))
    {
        log("accuracy: supersampled seascape frames");
        for t in 0..settings.flicker_frames {
            sea_truth.push(
                measure::scene_supersampled(&sea, t, &BASELINE, settings.supersample as u16)
                    .map_err(err)?,
            );
        }
    }
    let truth_flicker = measure::flicker(&sea_truth, u32::from(fw_), band.clone());

    // Perspective reference: the seascape with exact perspective.
    let persp_ref = {
        let s = measure::static_scene(Perspective::Exact).ok_or("no seascape")?;
        measure::scene_reference(&s, 0, &BASELINE).map_err(err)?
    };

    // The rows' own plane references (distinct ones computed once, in parallel), then every
    // row's images and errors in parallel (rayon); the host timings run afterwards, one row at a
    // time, so that they are not measured on a loaded machine.
    let plane_cfgs: Vec<&Config> = rows
        .iter()
        .filter(|r| r.cfg.perspective.is_none())
        .map(|r| &r.cfg)
        .collect();
    refs.fill_planes(&plane_cfgs, size).map_err(err)?;
    log(&format!(
        "accuracy: errors of {} rows on {} threads",
        rows.len(),
        rayon::current_num_threads()
    ));
    let measured = rows
        .par_iter()
        .map(|row| -> Result<_, String> {
            let cfg = &row.cfg;
            let mut precision_image = None;
            let mut r = RowReport::unmeasured(
                row.knob.name(),
                row.setting,
                row.id,
                describe(cfg),
                codesize::feature_set(cfg),
            );
            r.combination = row.combination;
            r.baseline = *cfg == BASELINE;
            if let Some(mode) = cfg.perspective {
                let scene = measure::static_scene(mode).ok_or("no seascape")?;
                let img = measure::scene_image(cfg, &scene).ok_or("seascape render failed")?;
                let m = measure::errors(&img, &persp_ref).map_err(err)?;
                r.reference = "f64 reference of the seascape with exact perspective";
                set_primary(&mut r, &m);
                let sum = measure::scene_device_checksum(cfg, mode).ok_or("scene checksum")?;
                r.checksum = format!("{sum:08x}");
            } else {
                let img = measure::plane_image(cfg, size).map_err(err)?;
                let own = refs.cached_plane(cfg, size).ok_or("no plane reference")?;
                let m = measure::errors(&img, own).map_err(err)?;
                r.reference = "f64 reference with the row's table, filter, norm and culling \
                           (ideal precision, exact evaluation)";
                set_primary(&mut r, &m);
                // The device computes the top-left 64x64 of this very image.
                let sum = measure::plane_device_checksum(cfg).ok_or("plane checksum")?;
                let side = u32::from(device_jobs::SIDE);
                let window = measure::window_checksum(&img, size, side.min(size), cfg.aa);
                if size >= side && window != sum {
                    return Err(format!(
                        "{}: the device job's code and the host's pixel path disagree \
                     ({sum:08x} vs {window:08x})",
                        row.id
                    ));
                }
                r.checksum = format!("{sum:08x}");
                if measure::same_texture(cfg) {
                    r.base = Some((&measure::errors(&img, &base_ref).map_err(err)?).into());
                    r.supersampled = Some((&measure::errors(&img, &ss_truth).map_err(err)?).into());
                }
                if matches!(row.knob, Knob::CoordinateBits | Knob::ValueBits) && !row.combination {
                    let img = crate::scenes::render_frame(
                        &marble_scene,
                        marble_still,
                        &measure::unit_config(cfg),
                        cfg.hash,
                        texcore::render::Output::Color,
                    )
                    .map_err(err)?
                    .frame
                    .pixels;
                    r.scene = Some((&measure::errors(&img, &marble_ref).map_err(err)?).into());
                    if row.knob == Knob::CoordinateBits {
                        precision_image = Some((cfg.coord_bits, img));
                    }
                }
            }
            // The seascape's animation near its horizon: the filters (with culling on and off)
            // and the band-limiting settings (as the row sets culling).
            let flicker_culls: &[bool] = match row.knob {
                _ if row.combination => &[],
                Knob::Antialiasing => &[true, false],
                Knob::BandLimit => &[cfg.cull],
                _ => &[],
            };
            for &cull in flicker_culls {
                let c = Config { cull, ..*cfg };
                let mut frames = Vec::new();
                for t in 0..settings.flicker_frames {
                    let f = crate::scenes::render_frame(
                        &sea,
                        t,
                        &measure::unit_config(&c),
                        c.hash,
                        texcore::render::Output::Color,
                    )
                    .map_err(err)?
                    .frame
                    .pixels;
                    if t == 0 && cull == cfg.cull {
                        r.scene_supersampled =
                            Some((&measure::errors(&f, &sea_truth[0]).map_err(err)?).into());
                    }
                    frames.push(measure::to_f64(&f));
                }
                let fl = measure::flicker(&frames, u32::from(fw_), band.clone());
                let f = Some(Flicker {
                    texcore: fl,
                    reference: truth_flicker,
                    excess: fl - truth_flicker,
                });
                if cull == cfg.cull {
                    r.flicker = f;
                } else {
                    r.flicker_nocull = f;
                }
            }
            Ok((r, precision_image))
        })
        .collect::<Result<Vec<_>, String>>()?;
    let mut out = Vec::new();
    let mut precision_images = Vec::new();
    for (row, (mut r, image)) in rows.iter().zip(measured) {
        let cfg = &row.cfg;
        log(&format!("accuracy: {} (host timing)", row.id));
        let timing = if let Some(mode) = cfg.perspective {
            let scene = measure::static_scene(mode).ok_or("no seascape")?;
            measure::scene_time(cfg, &scene, settings.host_runs).ok_or("scene timing")?
        } else {
            measure::plane_time(cfg, size as u16, settings.host_runs).ok_or("plane timing")?
        };
        r.host_ns_per_pixel = timing.median;
        r.host_ns_min = timing.min;
        r.host_ns_max = timing.max;
        r.host_runs = timing.runs;
        out.push(r);
        precision_images.extend(image);
    }

    log("accuracy: device runs (QEMU)");
    let dev = device::measure(&rows, policy)?;
    apply_device(&mut out, &rows, &dev);
    let code = if policy == DevicePolicy::Off {
        codesize::CodeSizes::default()
    } else {
        log("accuracy: code size (texcore-probe builds)");
        codesize::measure(&rows, quick, log)?
    };
    for (r, row) in out.iter_mut().zip(&rows) {
        r.code_size = code.of(&row.cfg);
    }
    mark_pareto(&mut out, &rows);

    // The `shading` knob: the marble scene from atlases against its procedural frame.
    log("accuracy: shading (the marble scene from atlases)");
    let mut shading_rows = shading::host_rows(&settings, quick, &marble_ref)?;
    let mut device_skipped = dev.skipped.clone();
    device_skipped.extend(shading::apply_device(&mut shading_rows, policy)?);
    if policy != DevicePolicy::Off && !quick {
        shading::apply_code_size(&mut shading_rows, log)?;
    }
    out.extend(shading_rows);

    // The `gradient_blend` knob: gradient noise exact or fused, on the peers' plane.
    log("accuracy: gradient_blend (gradient noise exact or fused)");
    let mut blend_rows = blend::host_rows(&settings)?;
    if !quick {
        device_skipped.extend(blend::apply_device(&mut blend_rows, policy)?);
    }
    out.extend(blend_rows);
    Ok(Report {
        rows: out,
        settings,
        quick,
        device_skipped,
        seconds: (start.elapsed().as_secs_f64(), dev.seconds),
        code_seconds: code.seconds,
        precision_images,
    })
}

/// Sets a row's primary errors (`psnr`, `max_error`, `mean_error`, `within_one_step`).
fn set_primary(r: &mut RowReport, m: &Metrics) {
    r.psnr = m.psnr;
    r.max_error = m.max_error;
    r.mean_error = m.mean_error;
    r.within_one_step = m.within_one_step;
}

fn apply_device(out: &mut [RowReport], rows: &[&Row], dev: &DeviceResults) {
    for (r, row) in out.iter_mut().zip(rows) {
        for (triple, map) in &dev.rows {
            if let Some(m) = map.get(row.id) {
                r.device_instructions_per_pixel
                    .insert(triple.to_string(), m.render() as f64 / device::pixels(row));
                r.device_setup_instructions
                    .insert(triple.to_string(), m.setup);
                r.device_checksum_match.insert(
                    triple.to_string(),
                    format!("{:08x}", m.checksum) == r.checksum,
                );
            }
        }
    }
}

/// The cost axis of the front: M4F instructions per pixel, else host ns.
pub fn cost(r: &RowReport) -> f64 {
    r.device_instructions_per_pixel
        .get("thumbv7em-none-eabihf")
        .copied()
        .unwrap_or(r.host_ns_per_pixel)
}

/// PSNR differences below this (dB) are noise for the Pareto front: a configuration that is
/// cheaper and at most this much less accurate dominates.
pub const PSNR_TOLERANCE: f64 = 0.1;

/// Marks the rows whose configuration is on the Pareto front of error against the baseline's
/// reference (`base.psnr`, higher is better, up to [`PSNR_TOLERANCE`]) and cost ([`cost`],
/// lower is better), among the rows that render the baseline's texture.
fn mark_pareto(out: &mut [RowReport], rows: &[&Row]) {
    let cands: Vec<usize> = (0..out.len()).filter(|&i| out[i].base.is_some()).collect();
    let mut front: Vec<Config> = Vec::new();
    for &i in &cands {
        let (ci, pi) = (cost(&out[i]), out[i].base.map_or(0.0, |b| b.psnr));
        let dominated = cands.iter().any(|&j| {
            let (cj, pj) = (cost(&out[j]), out[j].base.map_or(0.0, |b| b.psnr));
            (cj < ci && pj >= pi - PSNR_TOLERANCE) || (cj == ci && pj > pi + PSNR_TOLERANCE)
        });
        if !dominated {
            front.push(rows[i].cfg);
        }
    }
    for (r, row) in out.iter_mut().zip(rows) {
        r.pareto = front.contains(&row.cfg);
    }
}

/// Runs `texsim report accuracy`.
pub fn cli(a: &AccuracyArgs) -> std::process::ExitCode {
    use std::io::Write;
    let ci = std::env::var_os("CI").is_some();
    if a.no_device && ci {
        return crate::cli::bad_input("--no-device is not allowed when CI is set");
    }
    let policy = if a.no_device {
        DevicePolicy::Off
    } else if ci || !a.quick {
        DevicePolicy::Required
    } else {
        DevicePolicy::IfAvailable
    };
    let mut log = |m: &str| eprintln!("{m}");
    let report = match run(a.quick, policy, &mut log) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("texsim: error: {e}");
            return std::process::ExitCode::from(1);
        }
    };
    let root = crate::device::workspace_root();
    let (out_dir, readme) = if a.write_docs {
        (
            Some(a.out.clone().unwrap_or_else(|| root.join("docs"))),
            Some(a.readme.clone().unwrap_or_else(|| root.join("README.md"))),
        )
    } else {
        (a.out.clone(), a.readme.clone())
    };
    if let Some(dir) = &out_dir {
        if let Err(e) = output::write_docs(&report, dir) {
            eprintln!("texsim: error: {e}");
            return std::process::ExitCode::from(1);
        }
    }
    if let Some(p) = &readme {
        if let Err(e) = output::update_readme(&report, p) {
            eprintln!("texsim: error: {e}");
            return std::process::ExitCode::from(1);
        }
    }
    let mut stdout = std::io::stdout().lock();
    if a.json {
        let _ = serde_json::to_writer_pretty(&mut stdout, &report.rows);
        let _ = writeln!(stdout);
    } else {
        let _ = write!(stdout, "{}", output::text_summary(&report));
    }
    std::process::ExitCode::SUCCESS
}
