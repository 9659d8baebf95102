//! The evaluation modes over one renderer band: 8 rows of 320 pixels of the 4-octave value-noise
//! plane, the workload on which multipass corner-by-corner noise (`EvalMode::Multipass`,
//! `docs/multipass.md`) is priced against `Direct` and `Fd` (shared with the host, like
//! `stages`; the criterion bench `texcore/benches/multipass.rs`, group `band320_4oct`, runs the
//! same band on the host).
//!
//! The model is `texcore::texture::workload::value_fbm(4, hash)` (trilinear value noise, `mod`
//! wrap, octave 0 at 64 pixels per cell: `plane_span(CELLS_8 / 2, y, 320)`), filter-width
//! gradients and culling on (the `-1oct` rows: one octave, no gradients), one span per row: the
//! band is [`ROWS`] spans of [`WIDTH`]
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
//! | `direct-1oct`, `fd-1oct`, `multipass-native-1oct` | the same modes on one octave without gradients: the single noise of the paper's Table 1 |
//!
//! The multipass workloads exist with feature `multipass` only (the job-suite firmware's default).

use texcore::hash::HashKind;
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::texture::workload;

/// Pixels per row of the band (the width of the display the renderer bands).
pub const WIDTH: u16 = 320;
/// Rows of the band (`texcore`'s renderer band height).
pub const ROWS: u16 = 8;
/// Octave-0 lattice step of the band: 1/64 cell per pixel, 5 cells across its 320 pixels (raw
/// 16.16).
pub const STEP: i32 = workload::CELLS_8 / 2;

/// One evaluation mode over the band.
#[derive(Clone, Copy, Debug)]
pub struct BandWorkload {
    /// Name (the device job is `band:<name>`).
    pub name: &'static str,
    /// The evaluation mode.
    pub mode: EvalMode,
    /// Octaves of the model (4; 1 for the paper's single noise).
    pub octaves: u8,
    /// Filter-width gradients on.
    pub gradients: bool,
}

impl BandWorkload {
    /// Pixels evaluated (the units of the per-pixel figure).
    pub const fn pixels(&self) -> u32 {
        WIDTH as u32 * ROWS as u32
    }

    /// Runs the workload with `hash` (`work == false`: builds the model only).
    pub fn run(&self, hash: HashKind, work: bool) -> u32 {
        band_checksum(self.mode, self.octaves, self.gradients, hash, work)
    }
}

#[cfg(feature = "multipass")]
const fn multipass(p: texcore::multipass::PassPrecision) -> EvalMode {
    EvalMode::Multipass(texcore::multipass::MultipassConfig::with_precision(p))
}

/// The 4-octave workload with gradients in `mode`.
const fn four(name: &'static str, mode: EvalMode) -> BandWorkload {
    BandWorkload {
        name,
        mode,
        octaves: 4,
        gradients: true,
    }
}

/// One octave without gradients (the paper's single noise, its Table 1 workload) in `mode`.
const fn one(name: &'static str, mode: EvalMode) -> BandWorkload {
    BandWorkload {
        name,
        mode,
        octaves: 1,
        gradients: false,
    }
}

/// Every workload, in firmware order.
pub const BANDS: &[BandWorkload] = &[
    four("direct", EvalMode::Direct),
    four("fd", EvalMode::Fd),
    #[cfg(feature = "multipass")]
    four(
        "multipass-native",
        multipass(texcore::multipass::PassPrecision::Native),
    ),
    #[cfg(feature = "multipass")]
    four(
        "multipass-16.8",
        multipass(texcore::multipass::PassPrecision::Fixed16_8),
    ),
    #[cfg(feature = "multipass")]
    four(
        "multipass-8",
        multipass(texcore::multipass::PassPrecision::Bits8),
    ),
    one("direct-1oct", EvalMode::Direct),
    one("fd-1oct", EvalMode::Fd),
    #[cfg(feature = "multipass")]
    one(
        "multipass-native-1oct",
        multipass(texcore::multipass::PassPrecision::Native),
    ),
];

/// The workload named `name` (without the `band:` prefix).
pub fn band(name: &str) -> Option<&'static BandWorkload> {
    BANDS.iter().find(|b| b.name == name)
}

/// The body of every band workload (one copy of the evaluator in flash): the band's checksum,
/// rows top to bottom.
#[inline(never)]
pub fn band_checksum(
    mode: EvalMode,
    octaves: u8,
    gradients: bool,
    hash: HashKind,
    work: bool,
) -> u32 {
    let model = workload::value_fbm(octaves, hash);
    let model = core::hint::black_box(&model);
    if !work {
        return workload::fold(workload::FNV_OFFSET, model.terms().len() as u32);
    }
    let mut ev = SpanEvaluator::new(
        model,
        EvalOptions {
            mode: core::hint::black_box(mode),
            gradients,
            cull: true,
            ..Default::default()
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
