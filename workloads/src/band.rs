//! The evaluation modes over one renderer band: 8 rows of 320 pixels of the 4-octave value-noise
//! plane, the workload on which multipass corner-by-corner noise (`EvalMode::Multipass`,
//! `docs/multipass.md`) is priced against `Direct` and `Fd` (shared with the host, like
//! `stages`; the criterion bench `texcore/benches/multipass.rs`, group `band320_4oct`, runs the
//! same band on the host).
//!
//! The model is `texcore::texture::workload::value_fbm(4, hash)` (trilinear value noise, `mod`
//! wrap, octave 0 at 16 cells across the 320 pixels: `plane_span(CELLS_8 / 2, y, 320)`), filter
//! width gradients and culling on, one span per row: the band is [`ROWS`] spans of [`WIDTH`]
//! pixels. Every sample is folded into an FNV-1a checksum (`workload::fold_sample`: `f`, then `gx`
//! and `gy`, low word then high word; five folds a pixel, the same for every mode and part of the
//! figure).
//!
//! Every workload `f(hash, work)` first builds its model; with `work == false` it stops there
//! (keeping the model alive with `black_box`) and returns a checksum of it, so the host's
//! difference of the two counts is the band's evaluation alone.
//!
//! Memory: nothing but the model and the span evaluator on the stack; the multipass modes add
//! their band buffers (`texcore::multipass::Band<16>` and five 16-entry sums, about 2 KB, inside
//! the texture-unit RAM budget of 4 KB).
//!
//! | workload | mode |
//! |---|---|
//! | `direct` | `EvalMode::Direct` |
//! | `fd` | `EvalMode::Fd` |
//! | `multipass-native` | `EvalMode::Multipass`, native precision, texcore's hash (bit-identical to `direct`) |
//! | `multipass-16.8` | `EvalMode::Multipass`, the 16.8 format |
//! | `multipass-8` | `EvalMode::Multipass`, 8-bit passes |
//!
//! The multipass workloads exist with feature `multipass` only (the job-suite firmware's default).

use texcore::hash::HashKind;
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::texture::workload;

/// Pixels per row of the band (the width of the display the renderer bands).
pub const WIDTH: u16 = 320;
/// Rows of the band (`texcore`'s renderer band height).
pub const ROWS: u16 = 8;
/// Octave-0 lattice step of the band: 16 cells across its 320 pixels (raw 16.16).
pub const STEP: i32 = workload::CELLS_8 / 2;

/// One evaluation mode over the band.
#[derive(Clone, Copy, Debug)]
pub struct BandWorkload {
    /// Name (the device job is `band:<name>`).
    pub name: &'static str,
    /// The evaluation mode.
    pub mode: EvalMode,
}

impl BandWorkload {
    /// Pixels evaluated (the units of the per-pixel figure).
    pub const fn pixels(&self) -> u32 {
        WIDTH as u32 * ROWS as u32
    }

    /// Runs the workload with `hash` (`work == false`: builds the model only).
    pub fn run(&self, hash: HashKind, work: bool) -> u32 {
        band_checksum(self.mode, hash, work)
    }
}

#[cfg(feature = "multipass")]
const fn multipass(p: texcore::multipass::PassPrecision) -> EvalMode {
    EvalMode::Multipass(texcore::multipass::MultipassConfig::with_precision(p))
}

/// Every workload, in firmware order.
pub const BANDS: &[BandWorkload] = &[
    BandWorkload {
        name: "direct",
        mode: EvalMode::Direct,
    },
    BandWorkload {
        name: "fd",
        mode: EvalMode::Fd,
    },
    #[cfg(feature = "multipass")]
    BandWorkload {
        name: "multipass-native",
        mode: multipass(texcore::multipass::PassPrecision::Native),
    },
    #[cfg(feature = "multipass")]
    BandWorkload {
        name: "multipass-16.8",
        mode: multipass(texcore::multipass::PassPrecision::Fixed16_8),
    },
    #[cfg(feature = "multipass")]
    BandWorkload {
        name: "multipass-8",
        mode: multipass(texcore::multipass::PassPrecision::Bits8),
    },
];

/// The workload named `name` (without the `band:` prefix).
pub fn band(name: &str) -> Option<&'static BandWorkload> {
    BANDS.iter().find(|b| b.name == name)
}

/// The body of every band workload (one copy of the evaluator in flash): the band's checksum,
/// rows top to bottom.
#[inline(never)]
pub fn band_checksum(mode: EvalMode, hash: HashKind, work: bool) -> u32 {
    let model = workload::value_fbm(4, hash);
    let model = core::hint::black_box(&model);
    if !work {
        return workload::fold(workload::FNV_OFFSET, model.terms().len() as u32);
    }
    let mut ev = SpanEvaluator::new(
        model,
        EvalOptions {
            mode: core::hint::black_box(mode),
            gradients: true,
            cull: true,
        },
    );
    let mut acc = workload::FNV_OFFSET;
    for y in 0..ROWS {
        ev.eval(&workload::plane_span(STEP, y, WIDTH), |s| {
            acc = workload::fold_sample(acc, &s)
        });
    }
    acc
}
