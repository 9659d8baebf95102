//! Workloads of the accuracy report (`texsim report accuracy`, `docs/accuracy.md`): one texture
//! unit configuration per job, so that every row of the report has exact device instruction
//! counts on both targets.
//!
//! This file is the single definition of the report's configurations. It uses only `core` and
//! `texcore`, so `host-sim` includes it verbatim (`host_sim::accuracy::device_jobs`) to know the
//! rows and to recompute every job's checksum with the very same code; only the job glue at the
//! end (the `JOBS` list) is device-only.
//!
//! - **Baseline** ([`BASELINE`]): the `marble` preset, `f = r + sum_{i<4} 2^-i n(2^i s)`
//!   (trilinear value noise, permutation hash, `mod` table), 256-entry colour table, nearest
//!   look-up, summed-area table filter (`csat`), L2 gradient norm, `auto` evaluation, culling on,
//!   16/16 precision.
//! - **Rows** ([`ROWS`]): each knob varied alone from the baseline, plus a few combinations
//!   (fewer octaves with cheaper filters) that are candidates for the Pareto front.
//! - **Plane jobs**: the first [`SIDE`] x [`SIDE`] pixels of the marble check plane at its
//!   256-pixel scale (1/128 per pixel), in [`SEGMENT`]-pixel spans like `texsim check`; each
//!   pixel's colour (`Rgba8888::to_u32`) folded into an FNV-1a checksum, row-major.
//! - **Scene jobs** (the `perspective` rows): the `seascape` scene at its still frame,
//!   [`SCENE_W`] x [`SCENE_H`], every object drawn in the row's perspective mode, streamed into a
//!   `ChecksumSink` (FNV-1a over RGB565 in drawing order).
//!
//! Each row is two jobs that call the same function (`device::row_job`): `acc:<knob>=<setting>/setup`
//! only builds the texture (tables, filters, scene), `acc:<knob>=<setting>` builds it and
//! renders. The rendering's count is the difference of the two (exact up to the few instructions
//! of the branch between them); building on the job's own stack keeps the firmware's context
//! small (a 1024-entry texture with its filter is 29 KB).
//! Only the firmware built with feature `accuracy` runs them (instead of the default jobs); that
//! feature also enables the texcore features the rows need (fades, gradient noise, mNoise, MIP,
//! and the permutation hash on both targets).

use texcore::bandlimit::{BandLimit, FadeWeight, FADED_PART, FADE_FLOOR};
use texcore::color::Rgba8888;
use texcore::filter::{Antialias, ColorStage, GradientNorm, WidthSource};
use texcore::format::{Amplitude, QuadricCoeff, TexPoint, TexValue};
use texcore::hash::HashKind;
use texcore::model::{Octaves, Precision, TextureModel};
use texcore::multipass::{MultipassConfig, PassPrecision};
use texcore::noise::{BasisKind, Fade, NoiseBasis};
use texcore::presets::{CheckPlane, Key};
use texcore::quadric::Quadric;
use texcore::raster::Perspective;
use texcore::render::Renderer;
use texcore::scene::Scene;
use texcore::sink::ChecksumSink;
use texcore::span::{EvalMode, Span};
use texcore::table::{ColorTable, TableLookup, TableWrap};
use texcore::texture::{Shader, Texture};
use texcore::transform::Affine3;

/// Noise-term capacity of the configurations' models.
pub const TERMS: usize = 8;
/// Side of the device's check-plane window, in pixels.
pub const SIDE: u16 = 64;
/// Span length of the check planes (`host_sim::unit::PLANE_SEGMENT`).
pub const SEGMENT: u16 = 16;
/// Width of the scene jobs' image.
pub const SCENE_W: u16 = 160;
/// Height of the scene jobs' image.
pub const SCENE_H: u16 = 120;
/// The scene of the perspective rows.
pub const SCENE: &str = "seascape";

/// The marble preset's check plane (`presets::marble(..).plane`).
pub const PLANE: CheckPlane = CheckPlane {
    origin: [0, 32768, 0],
    step_x: [512, 0, 0],
    step_y: [0, 0, 512],
};

/// A knob of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Knob {
    /// Lattice-coordinate fraction bits.
    CoordinateBits,
    /// Lattice value bits.
    ValueBits,
    /// The fade of the noise basis.
    Interpolation,
    /// Span evaluation mode and octave culling.
    Evaluation,
    /// Number of octaves.
    Octaves,
    /// Colour-table size and look-up.
    TableSize,
    /// Colour-table filter.
    Antialiasing,
    /// Gradient norm of the filter width.
    GradientNorm,
    /// Perspective interpolation of the rasterizer.
    Perspective,
    /// Noise basis.
    Basis,
    /// Lattice hash.
    Hash,
    /// Band-limiting of the octaves past the Nyquist limit (the seascape's horizon).
    BandLimit,
    /// Where the filter widths come from: the analytic gradients or the differences of
    /// neighbouring values.
    FilterWidths,
}

impl Knob {
    /// Every knob, in report order.
    pub const ALL: [Knob; 13] = [
        Knob::CoordinateBits,
        Knob::ValueBits,
        Knob::Interpolation,
        Knob::Evaluation,
        Knob::Octaves,
        Knob::TableSize,
        Knob::Antialiasing,
        Knob::GradientNorm,
        Knob::Perspective,
        Knob::Basis,
        Knob::Hash,
        Knob::BandLimit,
        Knob::FilterWidths,
    ];

    /// The knob's name in the report's JSON.
    pub const fn name(self) -> &'static str {
        match self {
            Knob::CoordinateBits => "coordinate_bits",
            Knob::ValueBits => "value_bits",
            Knob::Interpolation => "interpolation",
            Knob::Evaluation => "evaluation",
            Knob::Octaves => "octaves",
            Knob::TableSize => "table_size",
            Knob::Antialiasing => "antialiasing",
            Knob::GradientNorm => "gradient_norm",
            Knob::Perspective => "perspective",
            Knob::Basis => "basis",
            Knob::Hash => "hash",
            Knob::BandLimit => "band_limit",
            Knob::FilterWidths => "filter_widths",
        }
    }
}

/// The fade of a configuration (texcore's [`Fade`] has the smooth fades only with its
/// `smooth-fade` feature, which only the firmware part that needs them enables).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FadeSel {
    /// Trilinear.
    Linear,
    /// `3a^2 - 2a^3`.
    Smooth,
    /// `6a^5 - 15a^4 + 10a^3`.
    Quintic,
}

/// The basis of a configuration (gradient noise and mNoise are texcore features too).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BasisSel {
    /// Value noise.
    Value,
    /// Perlin's gradient noise.
    Gradient,
    /// Olano's mNoise.
    MNoise,
}

/// `linear`, `smooth`, `quintic` (report labels).
impl core::fmt::Display for FadeSel {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            FadeSel::Linear => "linear",
            FadeSel::Smooth => "smooth",
            FadeSel::Quintic => "quintic",
        })
    }
}

/// `value`, `gradient`, `mnoise` (report labels).
impl core::fmt::Display for BasisSel {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            BasisSel::Value => "value",
            BasisSel::Gradient => "gradient",
            BasisSel::MNoise => "mnoise",
        })
    }
}

impl FadeSel {
    /// texcore's fade (`None` where this build of texcore lacks it).
    pub fn fade(self) -> Option<Fade> {
        match self {
            FadeSel::Linear => Some(Fade::Linear),
            #[cfg(any(not(target_os = "none"), feature = "accuracy-planes"))]
            FadeSel::Smooth => Some(Fade::Smooth),
            #[cfg(any(not(target_os = "none"), feature = "accuracy-planes"))]
            FadeSel::Quintic => Some(Fade::Quintic),
            #[allow(unreachable_patterns)]
            _ => None,
        }
    }
}

impl BasisSel {
    /// texcore's basis kind (`None` where this build of texcore lacks it).
    pub fn kind(self) -> Option<BasisKind> {
        match self {
            BasisSel::Value => Some(BasisKind::Value),
            #[cfg(any(not(target_os = "none"), feature = "accuracy-planes"))]
            BasisSel::Gradient => Some(BasisKind::Gradient),
            #[cfg(any(not(target_os = "none"), feature = "accuracy-planes"))]
            BasisSel::MNoise => Some(BasisKind::Modified),
            #[allow(unreachable_patterns)]
            _ => None,
        }
    }
}

/// One configuration of the texture unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Config {
    /// Lattice-coordinate fraction bits (1..=16).
    pub coord_bits: u8,
    /// Lattice value bits (1..=16).
    pub value_bits: u8,
    /// Fade of every octave.
    pub fade: FadeSel,
    /// Basis of every octave.
    pub basis: BasisSel,
    /// Lattice hash.
    pub hash: HashKind,
    /// Octaves (1..=8).
    pub octaves: u8,
    /// Colour-table entries.
    pub table_size: u16,
    /// Table look-up.
    pub lookup: TableLookup,
    /// Filter.
    pub aa: Antialias,
    /// Gradient norm.
    pub norm: GradientNorm,
    /// Span evaluation.
    pub mode: EvalMode,
    /// Octave culling past Nyquist.
    pub cull: bool,
    /// How culling fades and spreads the octaves past Nyquist.
    pub band_limit: BandLimit,
    /// `Some`: a scene job (the perspective rows) with every object in this mode.
    pub perspective: Option<Perspective>,
    /// Where the filter widths come from (the plane jobs; differences through
    /// `texcore::texture::DifferenceSpans`).
    pub widths: WidthSource,
}

/// The documented baseline.
pub const BASELINE: Config = Config {
    coord_bits: 16,
    value_bits: 16,
    fade: FadeSel::Linear,
    basis: BasisSel::Value,
    hash: HashKind::Permutation,
    octaves: 4,
    table_size: 256,
    lookup: TableLookup::Nearest,
    aa: Antialias::Csat,
    norm: GradientNorm::L2,
    mode: EvalMode::Auto,
    cull: true,
    band_limit: BandLimit::DEFAULT,
    perspective: None,
    widths: WidthSource::Gradients,
};

/// A band-limiting setting of the table below (the defaults where one is out of range, which a
/// test rules out).
const fn band(weight: FadeWeight, floor: u32, faded_part: u32) -> BandLimit {
    match BandLimit::new(weight, floor, faded_part) {
        Some(b) => b,
        None => BandLimit::DEFAULT,
    }
}

/// One row of the report: a knob setting (or a combination) and its configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Row {
    /// The knob varied (for combinations: the first knob that differs from the baseline).
    pub knob: Knob,
    /// The setting, as the report prints it.
    pub setting: &'static str,
    /// Name of the measured job.
    pub id: &'static str,
    /// Name of the set-up job.
    pub setup: &'static str,
    /// Part of `--quick`.
    pub quick: bool,
    /// A combination of several knobs (a Pareto-front candidate), not a single-knob row.
    pub combination: bool,
    /// The configuration.
    pub cfg: Config,
}

macro_rules! row {
    ($knob:ident, $kname:literal, $setting:literal, $quick:expr, $cfg:expr) => {
        Row {
            knob: Knob::$knob,
            setting: $setting,
            id: concat!("acc:", $kname, "=", $setting),
            setup: concat!("acc:", $kname, "=", $setting, "/setup"),
            quick: $quick,
            combination: false,
            cfg: $cfg,
        }
    };
}

macro_rules! combo {
    ($knob:ident, $setting:literal, $quick:expr, $cfg:expr) => {
        Row {
            knob: Knob::$knob,
            setting: $setting,
            id: concat!("acc:combo=", $setting),
            setup: concat!("acc:combo=", $setting, "/setup"),
            quick: $quick,
            combination: true,
            cfg: $cfg,
        }
    };
}

const B: Config = BASELINE;

/// Number of rows.
pub const N_ROWS: usize = 70;

/// Every row, in report order (knobs in [`Knob::ALL`] order, combinations last).
pub const ROWS: [Row; N_ROWS] = [
    row!(
        CoordinateBits,
        "coordinate_bits",
        "4",
        true,
        Config { coord_bits: 4, ..B }
    ),
    row!(
        CoordinateBits,
        "coordinate_bits",
        "8",
        false,
        Config { coord_bits: 8, ..B }
    ),
    row!(
        CoordinateBits,
        "coordinate_bits",
        "12",
        false,
        Config {
            coord_bits: 12,
            ..B
        }
    ),
    row!(CoordinateBits, "coordinate_bits", "16", true, B),
    row!(
        ValueBits,
        "value_bits",
        "4",
        true,
        Config { value_bits: 4, ..B }
    ),
    row!(
        ValueBits,
        "value_bits",
        "8",
        false,
        Config { value_bits: 8, ..B }
    ),
    row!(
        ValueBits,
        "value_bits",
        "12",
        false,
        Config {
            value_bits: 12,
            ..B
        }
    ),
    row!(ValueBits, "value_bits", "16", true, B),
    row!(Interpolation, "interpolation", "linear", true, B),
    row!(
        Interpolation,
        "interpolation",
        "smooth",
        true,
        Config {
            fade: FadeSel::Smooth,
            ..B
        }
    ),
    row!(
        Interpolation,
        "interpolation",
        "quintic",
        false,
        Config {
            fade: FadeSel::Quintic,
            ..B
        }
    ),
    row!(
        Evaluation,
        "evaluation",
        "direct",
        true,
        Config {
            mode: EvalMode::Direct,
            ..B
        }
    ),
    row!(
        Evaluation,
        "evaluation",
        "fd",
        false,
        Config {
            mode: EvalMode::Fd,
            ..B
        }
    ),
    row!(
        Evaluation,
        "evaluation",
        "fd32",
        false,
        Config {
            mode: EvalMode::Fd32,
            ..B
        }
    ),
    row!(
        Evaluation,
        "evaluation",
        "reanchored",
        false,
        Config {
            mode: EvalMode::Reanchored,
            ..B
        }
    ),
    row!(Evaluation, "evaluation", "auto", true, B),
    row!(
        Evaluation,
        "evaluation",
        "multipass-native",
        false,
        Config {
            mode: EvalMode::Multipass(MultipassConfig::with_precision(PassPrecision::Native)),
            ..B
        }
    ),
    row!(
        Evaluation,
        "evaluation",
        "multipass-16.8",
        false,
        Config {
            mode: EvalMode::Multipass(MultipassConfig::with_precision(PassPrecision::Fixed16_8)),
            ..B
        }
    ),
    row!(
        Evaluation,
        "evaluation",
        "multipass-8",
        false,
        Config {
            mode: EvalMode::Multipass(MultipassConfig::with_precision(PassPrecision::Bits8)),
            ..B
        }
    ),
    row!(
        Evaluation,
        "evaluation",
        "auto-nocull",
        false,
        Config { cull: false, ..B }
    ),
    row!(Octaves, "octaves", "1", true, Config { octaves: 1, ..B }),
    row!(Octaves, "octaves", "2", false, Config { octaves: 2, ..B }),
    row!(Octaves, "octaves", "3", false, Config { octaves: 3, ..B }),
    row!(Octaves, "octaves", "4", true, B),
    row!(Octaves, "octaves", "5", false, Config { octaves: 5, ..B }),
    row!(Octaves, "octaves", "6", false, Config { octaves: 6, ..B }),
    row!(Octaves, "octaves", "7", false, Config { octaves: 7, ..B }),
    row!(Octaves, "octaves", "8", false, Config { octaves: 8, ..B }),
    row!(
        TableSize,
        "table_size",
        "16",
        false,
        Config {
            table_size: 16,
            ..B
        }
    ),
    row!(
        TableSize,
        "table_size",
        "32",
        false,
        Config {
            table_size: 32,
            ..B
        }
    ),
    row!(
        TableSize,
        "table_size",
        "64",
        false,
        Config {
            table_size: 64,
            ..B
        }
    ),
    row!(
        TableSize,
        "table_size",
        "128",
        false,
        Config {
            table_size: 128,
            ..B
        }
    ),
    row!(TableSize, "table_size", "256", true, B),
    row!(
        TableSize,
        "table_size",
        "512",
        false,
        Config {
            table_size: 512,
            ..B
        }
    ),
    row!(
        TableSize,
        "table_size",
        "1024",
        false,
        Config {
            table_size: 1024,
            ..B
        }
    ),
    row!(
        TableSize,
        "table_size",
        "256-linear",
        true,
        Config {
            lookup: TableLookup::Linear,
            ..B
        }
    ),
    row!(
        Antialiasing,
        "antialiasing",
        "none",
        true,
        Config {
            aa: Antialias::None,
            ..B
        }
    ),
    row!(
        Antialiasing,
        "antialiasing",
        "mip",
        false,
        Config {
            aa: Antialias::Mip,
            ..B
        }
    ),
    row!(Antialiasing, "antialiasing", "csat", true, B),
    row!(
        Antialiasing,
        "antialiasing",
        "csat3",
        false,
        Config {
            aa: Antialias::Csat3,
            ..B
        }
    ),
    row!(
        Antialiasing,
        "antialiasing",
        "ramp",
        false,
        Config {
            aa: Antialias::Ramp,
            ..B
        }
    ),
    row!(GradientNorm, "gradient_norm", "l2", true, B),
    row!(
        GradientNorm,
        "gradient_norm",
        "l1",
        false,
        Config {
            norm: GradientNorm::L1,
            ..B
        }
    ),
    row!(
        GradientNorm,
        "gradient_norm",
        "max",
        true,
        Config {
            norm: GradientNorm::Max,
            ..B
        }
    ),
    row!(
        Perspective,
        "perspective",
        "exact",
        false,
        Config {
            perspective: Some(Perspective::Exact),
            ..B
        }
    ),
    row!(
        Perspective,
        "perspective",
        "every8",
        false,
        Config {
            perspective: Some(Perspective::Every8),
            ..B
        }
    ),
    row!(
        Perspective,
        "perspective",
        "every16",
        true,
        Config {
            perspective: Some(Perspective::Every16),
            ..B
        }
    ),
    row!(
        Perspective,
        "perspective",
        "affine",
        true,
        Config {
            perspective: Some(Perspective::Affine),
            ..B
        }
    ),
    row!(Basis, "basis", "value", true, B),
    row!(
        Basis,
        "basis",
        "gradient",
        true,
        Config {
            basis: BasisSel::Gradient,
            ..B
        }
    ),
    row!(
        Basis,
        "basis",
        "mnoise",
        false,
        Config {
            basis: BasisSel::MNoise,
            ..B
        }
    ),
    row!(Hash, "hash", "perm", true, B),
    row!(
        Hash,
        "hash",
        "int",
        true,
        Config {
            hash: HashKind::Integer,
            ..B
        }
    ),
    row!(
        BandLimit,
        "band_limit",
        "footprint",
        true,
        Config {
            perspective: Some(Perspective::Every16),
            ..B
        }
    ),
    row!(
        BandLimit,
        "band_limit",
        "reach",
        true,
        Config {
            band_limit: band(FadeWeight::Reach, FADE_FLOOR, FADED_PART),
            perspective: Some(Perspective::Every16),
            ..B
        }
    ),
    row!(
        BandLimit,
        "band_limit",
        "floor=1/8",
        false,
        Config {
            band_limit: band(FadeWeight::Footprint, 1 << 13, FADED_PART),
            perspective: Some(Perspective::Every16),
            ..B
        }
    ),
    row!(
        BandLimit,
        "band_limit",
        "floor=1/2",
        false,
        Config {
            band_limit: band(FadeWeight::Footprint, 1 << 15, FADED_PART),
            perspective: Some(Perspective::Every16),
            ..B
        }
    ),
    row!(
        BandLimit,
        "band_limit",
        "share=1/2",
        false,
        Config {
            band_limit: band(FadeWeight::Footprint, FADE_FLOOR, 1 << 15),
            perspective: Some(Perspective::Every16),
            ..B
        }
    ),
    row!(
        BandLimit,
        "band_limit",
        "share=1",
        false,
        Config {
            band_limit: band(FadeWeight::Footprint, FADE_FLOOR, 1 << 16),
            perspective: Some(Perspective::Every16),
            ..B
        }
    ),
    row!(
        BandLimit,
        "band_limit",
        "off",
        false,
        Config {
            cull: false,
            perspective: Some(Perspective::Every16),
            ..B
        }
    ),
    row!(FilterWidths, "filter_widths", "gradients", true, B),
    row!(
        FilterWidths,
        "filter_widths",
        "differences",
        true,
        Config {
            widths: WidthSource::Differences,
            ..B
        }
    ),
    combo!(
        Octaves,
        "1oct+none",
        false,
        Config {
            octaves: 1,
            aa: Antialias::None,
            ..B
        }
    ),
    combo!(
        Octaves,
        "2oct+none",
        false,
        Config {
            octaves: 2,
            aa: Antialias::None,
            ..B
        }
    ),
    combo!(
        Octaves,
        "3oct+none",
        false,
        Config {
            octaves: 3,
            aa: Antialias::None,
            ..B
        }
    ),
    combo!(
        Octaves,
        "1oct+mip",
        false,
        Config {
            octaves: 1,
            aa: Antialias::Mip,
            ..B
        }
    ),
    combo!(
        Octaves,
        "2oct+mip",
        false,
        Config {
            octaves: 2,
            aa: Antialias::Mip,
            ..B
        }
    ),
    combo!(
        Octaves,
        "3oct+mip",
        true,
        Config {
            octaves: 3,
            aa: Antialias::Mip,
            ..B
        }
    ),
    combo!(
        TableSize,
        "linear+none",
        false,
        Config {
            lookup: TableLookup::Linear,
            aa: Antialias::None,
            ..B
        }
    ),
    combo!(
        Antialiasing,
        "ramp+differences",
        true,
        Config {
            aa: Antialias::Ramp,
            widths: WidthSource::Differences,
            ..B
        }
    ),
];

/// The model of a plane configuration: the marble preset's quadric (`f = r + ...`, `mod`) and
/// `cfg.octaves` octaves of `2^-i n(2^i s)` with the configuration's basis, fade and hash, at its
/// precision. Built without floating point; with the baseline's basis and four octaves it equals
/// `presets::marble(hash).model` (tested on the host).
pub fn model(cfg: &Config) -> Option<TextureModel<TERMS>> {
    let (kind, fade) = (cfg.basis.kind()?, cfg.fade.fade()?);
    let mut c = [QuadricCoeff::ZERO; 10];
    c[8] = QuadricCoeff::from_bits(1 << 15); // I = 1/2: q = 2 I r = r
    let mut m = TextureModel::new(Quadric::from_coefficients(c), TableWrap::Mod);
    // At most eight octaves of amplitude sum < 2: this cannot fail.
    let _ = m.push_octaves(&Octaves {
        count: cfg.octaves.clamp(1, TERMS as u8),
        base: Affine3::IDENTITY,
        amplitude: Amplitude::ONE,
        rotate: false,
        basis: NoiseBasis {
            kind,
            fade,
            hash: cfg.hash,
        },
        turbulence: false,
    });
    if let Ok(p) = Precision::new(u32::from(cfg.coord_bits), u32::from(cfg.value_bits)) {
        m.set_precision(p);
    }
    Some(m)
}

/// A colour table of `N` entries from key colours (`None` if the keys are invalid).
pub fn table<const N: usize>(keys: &[Key]) -> Option<ColorTable<N>> {
    texcore::ready::key_table(keys, texcore::table::KeySpacing::Linear).ok()
}

/// The marble keys as table keys, at compile time.
const fn marble_keys() -> [(TexValue, Rgba8888); 7] {
    let k = &texcore::presets::MARBLE_KEYS;
    let mut out = [(TexValue::ZERO, Rgba8888::BLACK); 7];
    let mut i = 0;
    while i < 7 {
        let c = k[i].1;
        out[i] = (
            TexValue::from_bits(k[i].0 as i32),
            Rgba8888::new(c[0], c[1], c[2], c[3]),
        );
        i += 1;
    }
    out
}

/// Compile-time marble colour stages (`mod`, nearest look-up, summed-area filter), equal to what
/// [`table`] and `ColorStage::new` build at run time (tested on the host).
pub struct Stages<const N: usize>;

impl<const N: usize> Stages<N> {
    /// The stage (a compile-time error for a table size that is not a power of two in
    /// `2..=1024`).
    pub const CSAT: ColorStage<N> = match ColorTable::<N>::from_keys(&marble_keys()) {
        Ok(t) => match ColorStage::new(t, TableWrap::Mod, TableLookup::Nearest, Antialias::Csat) {
            Ok(s) => s,
            Err(_) => panic!("marble colour stage"),
        },
        Err(_) => panic!("marble colour table"),
    };
}

/// A texture for `shader` with the configuration's colour stage (`keys`, `wrap`) and options.
pub fn texture<const N: usize>(
    cfg: &Config,
    shader: Shader<TERMS>,
    keys: &[Key],
    wrap: TableWrap,
) -> Option<Texture<TERMS, N>> {
    let opts = texcore::ready::TextureOptions {
        lookup: cfg.lookup,
        norm: cfg.norm,
        mode: cfg.mode,
        cull: cfg.cull,
        band_limit: cfg.band_limit,
    };
    texcore::ready::Material::new(shader, wrap, keys)
        .texture_with(cfg.aa, opts)
        .ok()
}

/// The texture of a plane configuration: [`model`] with the marble keys.
pub fn plane_texture<const N: usize>(cfg: &Config) -> Option<Texture<TERMS, N>> {
    texture(
        cfg,
        Shader::Model(model(cfg)?),
        &texcore::presets::MARBLE_KEYS,
        TableWrap::Mod,
    )
}

/// Pixels `x0 .. x0 + len` of row `y` of the check plane (`host_sim::unit::plane_span`).
pub fn plane_span(x0: u16, y: u16, len: u16) -> Span {
    let at = |k: usize| {
        let v = i64::from(PLANE.origin[k])
            + (i64::from(PLANE.step_x[k]) * (2 * i64::from(x0) + 1)) / 2
            + (i64::from(PLANE.step_y[k]) * (2 * i64::from(y) + 1)) / 2;
        v as i32
    };
    let (sx, sy) = (PLANE.step_x, PLANE.step_y);
    Span {
        s0: TexPoint::from_bits(at(0), at(1), at(2)),
        ds: TexPoint::from_bits(sx[0], sx[1], sx[2]),
        dsdy: TexPoint::from_bits(sy[0], sy[1], sy[2]),
        len,
    }
}

/// FNV-1a 32-bit offset basis.
pub const FNV_OFFSET: u32 = 0x811C_9DC5;

/// Folds one word into an FNV-1a checksum.
#[inline(always)]
pub fn fold(acc: u32, word: u32) -> u32 {
    (acc ^ word).wrapping_mul(0x0100_0193)
}

/// Shades the first `side x side` pixels of the check plane, row by row in [`SEGMENT`]-pixel
/// spans, calling `emit(x, y, colour)`.
#[inline(always)]
pub fn shade_plane<const N: usize>(
    tex: &Texture<TERMS, N>,
    side: u16,
    mut emit: impl FnMut(u16, u16, Rgba8888),
) {
    let mut ev = tex.evaluator();
    for y in 0..side {
        let mut x0 = 0u16;
        while x0 < side {
            let len = SEGMENT.min(side - x0);
            let mut x = x0;
            ev.shade(&plane_span(x0, y, len), |c| {
                emit(x, y, c);
                x = x.wrapping_add(1);
            });
            x0 += len;
        }
    }
}

/// The plane job's checksum: every colour of [`shade_plane`] (`side x side`) folded, row-major.
/// A texture with the ramp filter (`antialiasing=ramp`) is shaded straight to RGB565, as a
/// display would take it (`TextureEvaluator::shade565`: the ramp's own path, one read a pixel),
/// and its RGB565 words are folded ([`fold_colour`]). With `widths` the differences, the same
/// spans are shaded through `DifferenceSpans` ([`differences_checksum`]).
#[inline(never)]
pub fn plane_checksum<const N: usize>(
    tex: &Texture<TERMS, N>,
    widths: WidthSource,
    side: u16,
) -> u32 {
    if widths == WidthSource::Differences {
        return differences_checksum(tex, side);
    }
    let mut acc = FNV_OFFSET;
    #[cfg(any(not(target_os = "none"), feature = "accuracy-planes"))]
    if tex.stage().antialias() == Antialias::Ramp {
        let mut ev = tex.evaluator();
        for y in 0..side {
            let mut x0 = 0u16;
            while x0 < side {
                let len = SEGMENT.min(side - x0);
                ev.shade565(&plane_span(x0, y, len), |c| {
                    acc = fold(acc, u32::from(c.to_bits()));
                });
                x0 += len;
            }
        }
        return acc;
    }
    shade_plane(tex, side, |_, _, c| acc = fold(acc, c.to_u32()));
    acc
}

/// The widest window [`differences_checksum`] takes: the device's [`SIDE`] on a device, 4096
/// pixels on the host (the memory of two rows is on the stack).
#[cfg(target_os = "none")]
pub const DIFFERENCES_MAX_SIDE: usize = SIDE as usize;
/// The widest window [`differences_checksum`] takes: the device's [`SIDE`] on a device, 4096
/// pixels on the host (the memory of two rows is on the stack).
#[cfg(not(target_os = "none"))]
pub const DIFFERENCES_MAX_SIDE: usize = 4096;

/// [`plane_checksum`] with the filter widths from the differences of neighbouring values: the
/// window as a `SpanPlane` whose spans are [`plane_span`]'s, shaded in [`SEGMENT`]-pixel spans
/// row by row through `DifferenceSpans` (straight to RGB565 with the ramp, as
/// [`plane_checksum`]). 0 when the window is wider than [`DIFFERENCES_MAX_SIDE`] or the texture
/// is not a model.
#[inline(never)]
pub fn differences_checksum<const N: usize>(tex: &Texture<TERMS, N>, side: u16) -> u32 {
    use texcore::span::{RowCache, SpanPlane};
    use texcore::texture::DifferenceMemory;
    let first = plane_span(0, 0, side);
    let Ok(plane) = SpanPlane::new(first.s0, first.ds, first.dsdy, side, side) else {
        return 0;
    };
    let mut ev = tex.evaluator();
    let Some(setup) = ev.plane_setup(&plane) else {
        return 0;
    };
    let mut cache = RowCache::<{ texcore::texture::workload::peers::ROW_EVENTS }>::new();
    let mut mem = DifferenceMemory::<DIFFERENCES_MAX_SIDE>::new();
    let Some(mut spans) = ev.difference_spans(&setup, &mut cache, &mut mem) else {
        return 0;
    };
    #[cfg(any(not(target_os = "none"), feature = "accuracy-planes"))]
    let ramp = tex.stage().antialias() == Antialias::Ramp;
    #[cfg(not(any(not(target_os = "none"), feature = "accuracy-planes")))]
    let ramp = false;
    let mut acc = FNV_OFFSET;
    for y in 0..side {
        let mut x0 = 0u16;
        while x0 < side {
            let len = SEGMENT.min(side - x0);
            if ramp {
                spans.shade565(x0, y, len, |c| acc = fold(acc, u32::from(c.to_bits())));
            } else {
                spans.shade(x0, y, len, |c| acc = fold(acc, c.to_u32()));
            }
            x0 += len;
        }
    }
    acc
}

/// The word [`plane_checksum`] folds for a colour of a plane with filter `aa`: its RGB565 bits
/// for the ramp (whose colours are RGB565 expanded, so this loses nothing), else its
/// `Rgba8888` word.
pub fn fold_colour(aa: Antialias, c: Rgba8888) -> u32 {
    if aa == Antialias::Ramp {
        u32::from(c.to_rgb565().to_bits())
    } else {
        c.to_u32()
    }
}

/// The scene of a perspective row: [`SCENE`] at its still frame, [`SCENE_W`] x [`SCENE_H`],
/// every object in `mode`.
pub fn scene(mode: Perspective) -> Option<Scene> {
    // The builder itself, not `scene::by_name` (which would link every scene's builder).
    let s = texcore::scene::builtin::seascape().ok()?;
    let mut f = s.at_frame(s.still());
    f.camera.width = SCENE_W;
    f.camera.height = SCENE_H;
    for o in f.objects.iter_mut() {
        o.perspective = mode;
    }
    Some(f)
}

/// The textures of the scene's slots (presets as they are: the seascape's slots change no
/// amplitude, phase or keys) with the configuration's colour stage and options.
pub fn scene_textures(cfg: &Config, scene: &Scene) -> Option<[Texture<TERMS, 256>; 2]> {
    let slot = |k: usize| -> Option<Texture<TERMS, 256>> {
        // The seascape's slots, by their builders (`presets::by_name` would link every preset).
        let p = match scene.slots.get(k)?.material {
            "clouds" => texcore::presets::clouds(cfg.hash),
            "water" => texcore::presets::water(cfg.hash),
            _ => return None,
        };
        let mut m = p.model;
        if let Ok(pr) = Precision::new(u32::from(cfg.coord_bits), u32::from(cfg.value_bits)) {
            m.set_precision(pr);
        }
        let wrap = m.wrap();
        texture(cfg, Shader::Model(m), p.keys, wrap)
    };
    Some([slot(0)?, slot(1)?])
}

/// The scene job's checksum: the scene streamed into a [`ChecksumSink`] (0 if it cannot be
/// rendered streamed).
#[inline(never)]
pub fn scene_checksum(scene: &Scene, textures: &[Texture<TERMS, 256>]) -> u32 {
    let r = Renderer::new(textures);
    let mut sink = ChecksumSink::new();
    match r.needs_bands(scene) {
        Ok(false) => match r.render_streamed(scene, &mut sink) {
            Ok(_) => sink.checksum(),
            Err(_) => 0,
        },
        _ => 0,
    }
}

/// Which firmware build runs a row. One build with every row does not fit the devices' flash
/// (each table size instantiates the whole pixel path, about 38 KB of rv32imc code), so the
/// rows are split over four builds, each with its own cargo feature; `host_sim::accuracy` builds
/// and runs each part it needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Part {
    /// Plane rows with a 256-entry table (most knobs).
    Planes,
    /// Plane rows with 16, 32 or 64 entries.
    SmallTables,
    /// Plane rows with 128, 512 or 1024 entries.
    LargeTables,
    /// Scene rows (perspective).
    Scenes,
}

impl Part {
    /// Every part.
    pub const ALL: [Part; 4] = [
        Part::Planes,
        Part::SmallTables,
        Part::LargeTables,
        Part::Scenes,
    ];

    /// The part of a configuration.
    pub const fn of(cfg: &Config) -> Part {
        if cfg.perspective.is_some() {
            return Part::Scenes;
        }
        match cfg.table_size {
            16 | 32 | 64 => Part::SmallTables,
            128 | 512 | 1024 => Part::LargeTables,
            _ => Part::Planes,
        }
    }

    /// The firmware feature that selects this part.
    pub const fn feature(self) -> &'static str {
        match self {
            Part::Planes => "accuracy-planes",
            Part::SmallTables => "accuracy-small-tables",
            Part::LargeTables => "accuracy-large-tables",
            Part::Scenes => "accuracy-scenes",
        }
    }
}

#[cfg(target_os = "none")]
pub use device::JOBS;

/// The job glue (firmware only).
#[cfg(target_os = "none")]
#[allow(dead_code)]
mod device {
    use super::*;
    use crate::job::{Ctx, Job};

    /// A plane configuration's job with table size `N`: builds the texture (always) and, with
    /// `render`, renders the plane window and returns its checksum (else returns 1 when the texture
    /// could be built, 0 otherwise). The set-up and measured jobs of a row both call this one
    /// function, so the difference of their counts is the rendering alone.
    ///
    /// Written to hold as few copies of the texture on the stack as possible (a 1024-entry texture
    /// is 29 KB; the Cortex-M4F's 128 KB of RAM also holds the harness's context).
    /// Tables of 512 and more entries (nearest, `csat`, culling on: the only such rows) take their
    /// colour stage
    /// from a compile-time constant ([`Stages`]) copied straight into the texture, instead of
    /// building it next to the texture (two 29 KB copies do not fit beside the harness's context).
    #[inline(never)]
    pub fn plane_job<const N: usize>(cfg: &Config, render: bool) -> u32 {
        if N >= 512 {
            // (Only culling on: `with_culling` would copy the texture once more.)
            if !cfg.cull
                || !matches!(
                    (cfg.lookup, cfg.aa),
                    (TableLookup::Nearest, Antialias::Csat)
                )
            {
                return 0;
            }
            let Some(m) = model(cfg) else {
                return 0;
            };
            let tex = Texture::new(Shader::Model(m), Stages::<N>::CSAT, cfg.norm, cfg.mode);
            return finish_plane(&tex, cfg.widths, render);
        }
        let Some(table) = table::<N>(&texcore::presets::MARBLE_KEYS) else {
            return 0;
        };
        let Ok(stage) = ColorStage::new(table, TableWrap::Mod, cfg.lookup, cfg.aa) else {
            return 0;
        };
        let Some(m) = model(cfg) else {
            return 0;
        };
        let tex = Texture::new(Shader::Model(m), stage, cfg.norm, cfg.mode);
        if cfg.cull {
            finish_plane(&tex, cfg.widths, render)
        } else {
            finish_plane(&tex.with_culling(false), cfg.widths, render)
        }
    }

    #[inline(always)]
    fn finish_plane<const N: usize>(
        tex: &Texture<TERMS, N>,
        widths: WidthSource,
        render: bool,
    ) -> u32 {
        if render {
            plane_checksum(tex, widths, SIDE)
        } else {
            core::hint::black_box(tex);
            1
        }
    }

    /// A scene configuration's job, like [`plane_job`]: builds the scene and its textures and, with
    /// `render`, renders it and returns the checksum.
    #[inline(never)]
    pub fn scene_job(cfg: &Config, mode: Perspective, render: bool) -> u32 {
        let Some(s) = scene(mode) else {
            return 0;
        };
        let Some(t) = scene_textures(cfg, &s) else {
            return 0;
        };
        if render {
            scene_checksum(&s, &t)
        } else {
            core::hint::black_box((&s, &t));
            1
        }
    }

    /// Row `i`'s job ([`plane_job`] or [`scene_job`]); 0 for an unknown row or table size.
    #[inline(never)]
    pub fn row_job(i: usize, render: bool) -> u32 {
        let Some(r) = ROWS.get(i) else {
            return 0;
        };
        let cfg = &r.cfg;
        if Some(Part::of(cfg)) != ACTIVE {
            return 0;
        }
        if let Some(mode) = cfg.perspective {
            #[cfg(feature = "accuracy-scenes")]
            return scene_job(cfg, mode, render);
            #[cfg(not(feature = "accuracy-scenes"))]
            {
                let _ = mode;
                return 0;
            }
        }
        // Only the active part's table sizes are instantiated (flash).
        match cfg.table_size {
            #[cfg(feature = "accuracy-small-tables")]
            16 => plane_job::<16>(cfg, render),
            #[cfg(feature = "accuracy-small-tables")]
            32 => plane_job::<32>(cfg, render),
            #[cfg(feature = "accuracy-small-tables")]
            64 => plane_job::<64>(cfg, render),
            #[cfg(feature = "accuracy-large-tables")]
            128 => plane_job::<128>(cfg, render),
            #[cfg(feature = "accuracy-planes")]
            256 => plane_job::<256>(cfg, render),
            #[cfg(feature = "accuracy-large-tables")]
            512 => plane_job::<512>(cfg, render),
            #[cfg(feature = "accuracy-large-tables")]
            1024 => plane_job::<1024>(cfg, render),
            _ => 0,
        }
    }

    /// The part this firmware runs.
    const ACTIVE: Option<Part> = if cfg!(feature = "accuracy-planes") {
        Some(Part::Planes)
    } else if cfg!(feature = "accuracy-small-tables") {
        Some(Part::SmallTables)
    } else if cfg!(feature = "accuracy-large-tables") {
        Some(Part::LargeTables)
    } else if cfg!(feature = "accuracy-scenes") {
        Some(Part::Scenes)
    } else {
        None
    };

    fn setup<const I: usize>(_: &mut Ctx) -> u32 {
        row_job(I, false)
    }

    fn run<const I: usize>(_: &mut Ctx) -> u32 {
        row_job(I, true)
    }

    macro_rules! jobs {
        ($($i:literal)*) => {
            [$(
                (Job { name: ROWS[$i].setup, run: setup::<$i> }, $i),
                (Job { name: ROWS[$i].id, run: run::<$i> }, $i),
            )*]
        };
    }

    const ALL_JOBS: [(Job, usize); 2 * N_ROWS] = jobs!(
        0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32
        33 34 35 36 37 38 39 40 41 42 43 44 45 46 47 48 49 50 51 52 53 54 55 56 57 58 59 60 61 62 63 64
        65 66 67 68 69
    );

    const fn in_part(i: usize) -> bool {
        match ACTIVE {
            Some(p) => {
                let q = Part::of(&ROWS[i].cfg);
                q as u8 == p as u8
            }
            None => false,
        }
    }

    /// The active part's jobs first (in [`ROWS`] order), then unused slots.
    const PART_JOBS: ([Job; 2 * N_ROWS], usize) = {
        let empty = Job {
            name: "",
            run: setup::<0>,
        };
        let mut out = [empty; 2 * N_ROWS];
        let mut n = 0;
        let mut k = 0;
        while k < ALL_JOBS.len() {
            if in_part(ALL_JOBS[k].1) {
                out[n] = ALL_JOBS[k].0;
                n += 1;
            }
            k += 1;
        }
        (out, n)
    };

    const PART_ARRAY: [Job; 2 * N_ROWS] = PART_JOBS.0;
    static PART_STATIC: [Job; 2 * N_ROWS] = PART_ARRAY;

    /// The accuracy jobs of this firmware's part (set-up then measurement, per row), in [`ROWS`]
    /// order.
    pub static JOBS: &[Job] = PART_STATIC.split_at(PART_JOBS.1).0;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_limit_rows_are_distinct_settings_of_the_seascape() {
        let mut rows: heapless::Vec<&Row, 16> = heapless::Vec::new();
        for r in ROWS.iter().filter(|r| r.knob == Knob::BandLimit) {
            assert!(rows.push(r).is_ok());
        }
        assert_eq!(rows.len(), 7);
        for (i, r) in rows.iter().enumerate() {
            assert_eq!(r.cfg.perspective, Some(Perspective::Every16), "{}", r.id);
            // Only the band-limiting differs from the baseline.
            let plain = Config {
                band_limit: BandLimit::DEFAULT,
                cull: true,
                perspective: None,
                ..r.cfg
            };
            assert_eq!(plain, BASELINE, "{}", r.id);
            // No setting fell back to the default (`band` on an out-of-range value), and no two
            // rows are the same setting.
            let default = r.cfg.band_limit == BandLimit::DEFAULT && r.cfg.cull;
            assert_eq!(default, r.setting == "footprint", "{}", r.id);
            for q in &rows[..i] {
                assert!(
                    (q.cfg.band_limit, q.cfg.cull) != (r.cfg.band_limit, r.cfg.cull),
                    "{} and {}",
                    q.id,
                    r.id
                );
            }
        }
    }
}
