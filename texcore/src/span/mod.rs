//! The span evaluator: the texture function along a scanline span, by direct evaluation or by
//! forward differencing (Kameya & Hart), with the filter-width gradients.
//!
//! A [`Span`] is `len` pixels with solid coordinates `s(i) = s0 + i ds`; the lattice point of noise
//! term `k` at pixel `i` is `U0_k + i DU_k` (`docs/model.md` section 3). Three evaluation modes give
//! **bit-identical** [`Sample`]s:
//!
//! - [`EvalMode::Direct`]: every pixel hashes its cell corners and interpolates (the reference
//!   path of the fixed-point model).
//! - [`EvalMode::Fd`]: trilinear value-noise terms are cubics in `i` inside a cell; they are set up
//!   once per cell and stepped with three wrapping i64 additions a pixel (the value) plus two each
//!   for the two gradient components. Wrapping arithmetic is exact here: every forward difference
//!   is an integer polynomial value, and the true result fits in i64, so the sum modulo 2^64 *is*
//!   the result. Cell exits are found once per cell (one division per axis), never per pixel.
//!   Other bases (smooth fades, gradient noise, mNoise) are degree 9 or more along a span; they keep
//!   their hashed cell cached and interpolate per pixel, which is exactly the direct computation.
//!   The quadric is a quadratic in `i`: two additions a pixel.
//!   All non-turbulent trilinear terms share **one** merged forward-difference state (a sum of
//!   cubics is a cubic while no term changes cell): the pixel loop costs the same for one octave
//!   or eight, and a cell change subtracts the leaving term's state and adds the new cell's
//!   (`docs/performance.md`).
//! - [`EvalMode::Auto`]: per span and per term, forward differencing where the span leaves each
//!   cell set-up more than [`AUTO_FD_PIXELS`] pixels, direct where cells or the span are shorter
//!   (set-up would cost more than it saves). Per-pixel trilinear terms hash their corners once
//!   per cell and evaluate the cell's monomial form (`noise::value`), bit-identical to the lerps.
//!
//! Two cheaper, approximate modes trade accuracy for time: [`EvalMode::Fd32`] (32-bit
//! accumulators) and [`EvalMode::Reanchored`] (piecewise cubic forward differencing of the
//! higher-degree bases); their error bounds are documented on the variants and priced in the
//! accuracy report.
//!
//! How much of this is compiled in follows the crate features: `fd` carries forward differencing
//! itself (without it every mode evaluates per pixel, the smallest code), `gradients` the
//! filter-width gradients, `fd32` and `reanchor` carry the
//! two approximate modes, `turbulence-fd` the general loop's per-term forward differencing
//! (turbulent terms; terms of spans the merged path does not take). A mode or strategy that is
//! not compiled in falls back to an exact one (documented on the variants), so every feature
//! combination gives the samples described here.
//!
//! Octaves whose cells are smaller than a pixel are band-limited when [`EvalOptions::cull`] is set
//! ([`crate::bandlimit`]): per span, a term reaching more than one cell a pixel enters `f` with a
//! faded amplitude (every mode uses the same faded amplitude, so the modes stay bit-identical),
//! a negligible one is culled, and the spread they lose goes to the span's extra filter width,
//! [`SpanInfo::extra_width48`]. Nothing here panics, for any span (any coordinates, any `ds`, any
//! length up to 65535).
//!
//! # Structure
//!
//! - this module: the public types, the per-span set-up (`EvalCore::setup`: per-term
//!   lattice start and steps; **the per-span
//!   band-limiting decision** is made there, per term, from `lattice_steps` and
//!   [`crate::bandlimit::term_band`]) and the plan
//!   (`EvalCore::eval_inner`: one strategy per term, decided once per span);
//! - `merged`: the merged forward-difference loop (every forward-differenced term trilinear and
//!   not turbulent), its cell events and the segment loop;
//! - `general`: the general loop, one strategy per term;
//! - `passes`: the pixel kernels of the merged loop, short loops over registers specialised per
//!   segment (linear or cubic merged state, zero or affine or curved quadric, gradients on or
//!   off); **the per-sample gradient output** is written by `passes::grad_pass` (the merged
//!   path) and at the end of the general loop's pixel;
//! - `cubic`: the exact cell polynomial of a trilinear term and its forward-difference states;
//! - `axis`: the cell set-up of terms whose lattice step has one nonzero axis (a linear cell
//!   polynomial from two face blends, the shared face kept from the previous cell);
//! - `axial` (fast shape only): the kernel of spans whose terms are all single-axis trilinear
//!   terms, forward differenced (per-term countdowns to the cell events, coinciding events in one
//!   pass);
//! - `lanes` (fast shape only): the axial kernel without gradients, one term at a time over each
//!   chunk of samples (no merged state, no segment loop);
//! - `direct`: trilinear terms evaluated per pixel inside the merged loop (one cell set-up per
//!   cell, then the cell's monomial form, or the face blends of a single-axis term);
//! - `face_cache` (fast shape only): [`FaceCache`], face blends kept across spans;
//! - `rows` (fast shape only; a row at a time otherwise): [`PlaneRows`], the rows of a plane
//!   with their cell schedule kept across rows (values, gradients, the smooth fade);
//! - `quad`: the quadric along the span.
//!
//! # Planes
//!
//! A caller filling a plane (a background, a framebuffer, an atlas) row after row should use
//! [`SpanEvaluator::rows`]: on an axis-aligned plane every row crosses the same cells at the
//! same pixels, and [`PlaneRows`] keeps that schedule and each cell's start and slope as
//! functions of the row, so a row costs one multiplication pair per cell it crosses and an
//! addition a pixel; any other plane is evaluated span by span, with the same values.

use crate::bandlimit::{build_spread_width48, term_band, BandLimit};
use crate::format::{TexPoint, TexValue};
use crate::hash::HashKind;
use crate::model::{quantize_coord, NoiseTerm, TextureModel};
use crate::noise::value::{scaled_corners_bits, scaled_face_bits, CellDirection, CellPoly};
use crate::noise::{split, CellData};
use crate::quadric::QuadraticSpan;
use crate::table::TableWrap;

#[cfg(not(texcore_lean))]
mod axial;
mod axis;
mod cubic;
mod direct;
mod face_cache;
mod general;
#[cfg(not(texcore_lean))]
mod lanes;
mod merged;
mod passes;
mod quad;
mod rows;

pub use face_cache::FaceCache;
pub use rows::{PlaneRows, RowCache};

use axis::*;
use cubic::*;
use direct::*;
use passes::*;
use quad::*;

/// A span of pixels: `s(i) = s0 + i ds`, with the second screen direction `dsdy` for the filter
/// width (zero if unknown).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    /// Solid coordinates of pixel 0.
    pub s0: TexPoint,
    /// Step per pixel along the span (`ds/dx`).
    pub ds: TexPoint,
    /// Step per pixel in the other screen direction (`ds/dy`).
    pub dsdy: TexPoint,
    /// Number of pixels.
    pub len: u16,
}

impl Span {
    /// The span one row below: `s0` advanced by `dsdy` (the raw 16.16 bits, wrapping), the steps
    /// and the length kept ([`PlaneRows`] and the texture's rows step so).
    #[cfg_attr(texcore_lean, allow(dead_code))]
    pub(crate) fn next_row(&self) -> Span {
        let b = self.s0.to_bits();
        let d = self.dsdy.to_bits();
        Span {
            s0: TexPoint::from_bits(
                b[0].wrapping_add(d[0]),
                b[1].wrapping_add(d[1]),
                b[2].wrapping_add(d[2]),
            ),
            ..*self
        }
    }
}

/// How a span is evaluated; every mode gives identical samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EvalMode {
    /// Per-pixel evaluation.
    Direct,
    /// Exact forward differencing (crate feature `fd`; without it, per pixel as `Direct`).
    Fd,
    /// Forward differencing where cells and spans are long, direct where they are short
    /// ([`AUTO_FD_PIXELS`]; without the crate feature `fd`, per pixel as `Direct`).
    #[default]
    Auto,
    /// Cheaper forward differencing of the cubic terms with 32-bit accumulators, re-anchored to
    /// the exact polynomial every [`FD32_ANCHOR`] pixels: **not** bit-identical; the error of `f` is
    /// at most `5489 * 2^-(16 + fv)` (one anchor interval's truncation drift, `1 + 32 + C(32,2) +
    /// C(32,3)` units) plus one unit of the final floor, per cubic term. Other terms as `Fd`.
    /// Since the exact merged accumulators of `Fd` (one set for all cubic terms) cost less than
    /// per-term 32-bit ones, non-turbulent cubic terms take the exact merged path here too (error
    /// zero, within the bound); the 32-bit accumulators remain for turbulent cubic terms.
    ///
    /// The 32-bit accumulators are compiled in with the crate feature `fd32`; without it this mode
    /// is [`EvalMode::Fd`] (exact, so within the bound above).
    Fd32,
    /// Terms that are not cubics along a span (smooth and quintic fades, gradient noise, mNoise:
    /// degree 9 or more) forward-differenced as cubic Hermite segments through exact values and
    /// exact derivatives at both ends of each segment (piecewise re-anchoring): approximate between
    /// anchors, exact at them. A segment covers at most [`HERMITE_SEGMENT`] pixels and at most a
    /// quarter of a cell along the span (the Hermite error grows with the fourth power of the
    /// segment's length in cells), so it pays only where cells span many pixels. Cubic terms as
    /// `Fd`.
    ///
    /// The Hermite segments are compiled in with the crate feature `reanchor` together with a
    /// basis that is not a cubic (`smooth-fade`, `gradient-noise` or `mnoise`); otherwise this mode
    /// is [`EvalMode::Fd`] (exact).
    Reanchored,
    /// Multipass corner-by-corner noise (Hart 2001, [`crate::multipass`], crate feature
    /// `multipass`): value-noise terms evaluated a band of pixels at a time, one pass per corner.
    /// With [`crate::multipass::MultipassConfig::EXACT`] bit-identical to `Direct`; the reduced
    /// precisions are approximate (their error is in `texsim report accuracy`).
    #[cfg(feature = "multipass")]
    Multipass(crate::multipass::MultipassConfig),
}

/// Options of the span evaluator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EvalOptions {
    /// Evaluation strategy.
    pub mode: EvalMode,
    /// Compute the filter-width gradients `gx`, `gy` (off: they are zero and cost nothing).
    /// Needs the crate feature `gradients` (enabled by `csat` and `mip`); without it this has no
    /// effect and the gradients are always zero.
    pub gradients: bool,
    /// Band-limit octaves past the Nyquist limit: fade them, cull the negligible ones and widen
    /// the filter by what they lose ([`crate::bandlimit`]).
    pub cull: bool,
    /// How band-limiting fades and spreads (when `cull` is on): an accuracy knob, the measured
    /// best by default.
    pub band_limit: BandLimit,
}

impl EvalOptions {
    /// The band-limiting setting in force: `None` when `cull` is off.
    #[inline(always)]
    pub fn band(&self) -> Option<&BandLimit> {
        self.cull.then_some(&self.band_limit)
    }
}

impl Default for EvalOptions {
    fn default() -> Self {
        EvalOptions {
            mode: EvalMode::Auto,
            gradients: true,
            cull: true,
            band_limit: BandLimit::DEFAULT,
        }
    }
}

/// The texture function and its screen gradient at one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sample {
    /// `f`.
    pub f: TexValue,
    /// `df/dx` with 48 fraction bits (saturating); zero when gradients are off or not compiled
    /// in (crate feature `gradients`).
    pub gx: i64,
    /// `df/dy` with 48 fraction bits (saturating); zero when gradients are off or not compiled
    /// in.
    pub gy: i64,
}

/// Per-span facts the shading stage needs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpanInfo {
    /// Extra filter width from culled or aliasing octaves, in `f` units with 48 fraction bits
    /// (always 0 in builds without feature `gradients`: they have no filter to widen).
    pub extra_width48: i64,
}

/// Activity counters (pixels, set-ups, evaluations), for `--stats` and cost accounting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SpanStats {
    /// Pixels evaluated.
    pub pixels: u64,
    /// Spans evaluated.
    pub spans: u64,
    /// Lattice cell set-ups (corner hashing), per term.
    pub cell_setups: u64,
    /// Noise term samples produced (per term per pixel).
    pub noise_evaluations: u64,
    /// Octaves culled by band-limiting (per term per span; [`crate::bandlimit`]).
    pub culled_octaves: u64,
    /// Octaves faded by band-limiting (per term per span; [`crate::bandlimit`]).
    pub faded_octaves: u64,
    /// Gradient samples (per pixel, counting the quadric and each term).
    pub gradient_evaluations: u64,
    /// Pixels produced by forward differencing of at least one term.
    pub fd_pixels: u64,
}

impl SpanStats {
    /// Adds another set of counters.
    pub fn add(&mut self, o: &SpanStats) {
        self.pixels += o.pixels;
        self.spans += o.spans;
        self.cell_setups += o.cell_setups;
        self.noise_evaluations += o.noise_evaluations;
        self.culled_octaves += o.culled_octaves;
        self.faded_octaves += o.faded_octaves;
        self.gradient_evaluations += o.gradient_evaluations;
        self.fd_pixels += o.fd_pixels;
    }
}

/// Samples handed over per call by [`SpanEvaluator::eval_chunks`].
pub const SAMPLE_CHUNK: usize = 16;

/// Up to [`SAMPLE_CHUNK`] consecutive samples of a span, stored by component (`f`, `gx`, `gy`
/// arrays), as [`SpanEvaluator::eval_chunks`] hands them over. The forward-differencing fast path
/// fills each component in its own pass over the chunk, so the state of each pass fits a 32-bit
/// core's registers. The gradient arrays hold zeros when gradients are off.
#[derive(Clone, Debug)]
pub struct SampleChunk {
    f: [TexValue; SAMPLE_CHUNK],
    gx: [i64; SAMPLE_CHUNK],
    gy: [i64; SAMPLE_CHUNK],
    /// Samples held, `<= SAMPLE_CHUNK`.
    len: usize,
    /// The span's [`SpanInfo::extra_width48`].
    extra_width48: i64,
}

impl SampleChunk {
    const fn new() -> Self {
        SampleChunk {
            f: [TexValue::ZERO; SAMPLE_CHUNK],
            gx: [0; SAMPLE_CHUNK],
            gy: [0; SAMPLE_CHUNK],
            len: 0,
            extra_width48: 0,
        }
    }

    /// The extra filter width of the chunk's span from octaves culled past the Nyquist limit
    /// ([`SpanInfo::extra_width48`]; the same for every chunk of a span), known before the first
    /// chunk is handed over, so a consumer need not ask [`SpanEvaluator::extra_width48`] first.
    pub const fn extra_width48(&self) -> i64 {
        self.extra_width48
    }

    /// Number of samples.
    pub const fn len(&self) -> usize {
        self.len
    }

    /// Whether the chunk holds no sample.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// `f` of each sample.
    pub fn f(&self) -> &[TexValue] {
        self.f.get(..self.len).unwrap_or(&[])
    }

    /// `gx` of each sample.
    pub fn gx(&self) -> &[i64] {
        self.gx.get(..self.len).unwrap_or(&[])
    }

    /// `gy` of each sample.
    pub fn gy(&self) -> &[i64] {
        self.gy.get(..self.len).unwrap_or(&[])
    }

    /// The samples in order.
    pub fn iter(&self) -> impl Iterator<Item = Sample> + '_ {
        self.f()
            .iter()
            .zip(self.gx())
            .zip(self.gy())
            .map(|((&f, &gx), &gy)| Sample { f, gx, gy })
    }
}

/// A chunk being filled and the consumer it goes to when full (and at the end of the span).
struct ChunkSink<'o, 'c> {
    chunk: &'o mut SampleChunk,
    out: &'o mut (dyn FnMut(&SampleChunk) + 'c),
}

impl ChunkSink<'_, '_> {
    /// Appends one sample.
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn push(&mut self, s: Sample) {
        let c = &mut self.chunk;
        let i = c.len;
        if let (Some(f), Some(gx), Some(gy)) = (c.f.get_mut(i), c.gx.get_mut(i), c.gy.get_mut(i)) {
            *f = s.f;
            *gx = s.gx;
            *gy = s.gy;
        }
        self.advance(1);
    }

    /// Free slots before the chunk is handed over (at least 1).
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn room(&self) -> usize {
        SAMPLE_CHUNK - self.chunk.len
    }

    /// Marks `k <= room()` more slots as filled, handing the chunk over when it is full.
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn advance(&mut self, k: usize) {
        self.chunk.len += k;
        if self.chunk.len >= SAMPLE_CHUNK {
            self.chunk.len = SAMPLE_CHUNK;
            (self.out)(self.chunk);
            self.chunk.len = 0;
        }
    }

    /// Hands over what is left.
    fn finish(&mut self) {
        if self.chunk.len > 0 {
            (self.out)(self.chunk);
            self.chunk.len = 0;
        }
    }
}

/// Shortest segment (pixels between two cell events) that the merged loop evaluates in component
/// passes; shorter ones take one fused per-pixel pass (each pass has a fixed start-up cost).
const PASS_MIN: u32 = 4;

/// Half a cell per pixel (raw 16.16): the Nyquist limit of a lattice noise.
pub const NYQUIST_STEP: i32 = 1 << 15;

/// A term's span set-up (read by the multipass evaluator too).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct TermSetup {
    /// Lattice point of pixel 0 (rounded to the model's coordinate precision).
    pub(crate) u0: [i32; 3],
    /// Lattice step along the span (rounded as `u0`).
    pub(crate) du: [i32; 3],
    /// Lattice step to the next row (unrounded).
    pub(crate) dy: [i32; 3],
    /// Evaluate the value.
    pub(crate) active: bool,
    /// Evaluate the gradient (false past one cell a pixel: the term's spread goes to
    /// `extra_width48`, [`crate::bandlimit`]).
    pub(crate) gradient: bool,
    /// The amplitude of this span (raw 16.16): the term's own, or faded
    /// ([`crate::bandlimit::term_band`]).
    pub(crate) amp: i32,
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn exact(p: TexPoint) -> [i64; 3] {
    let b = p.to_bits();
    [i64::from(b[0]), i64::from(b[1]), i64::from(b[2])]
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn sat_i64(x: i128) -> i64 {
    crate::noise::saturate_i64(x)
}

/// Combines the exact quadric (48 fraction bits) and the noise sum (`48 + fv`) into `f`
/// (`docs/model.md` section 6): wrapping for `mod`, saturating for `clamp`.
#[cfg_attr(not(texcore_lean), inline(always))]
fn combine(wrap: TableWrap, q48: i128, n: i64, fv: u32) -> TexValue {
    let f48 = match wrap {
        TableWrap::Mod => (q48 as i64).wrapping_add(n >> fv),
        TableWrap::Clamp => sat_i64(q48).saturating_add(n >> fv),
    };
    TexValue::from_bits((f48 >> 32) as i32)
}

/// Pixels from fraction `f` (0..65535) until the lattice coordinate leaves the cell, stepping `d`.
#[cfg_attr(not(texcore_lean), inline(always))]
fn pixels_in_cell_axis(f: u32, d: i32) -> u32 {
    if d > 0 {
        (0xFFFF - f) / d as u32 + 1
    } else if d < 0 {
        f / d.unsigned_abs() + 1
    } else {
        u32::MAX
    }
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn pixels_in_cell(frac: [u32; 3], d: [i32; 3]) -> u32 {
    pixels_in_cell_axis(frac[0], d[0])
        .min(pixels_in_cell_axis(frac[1], d[1]))
        .min(pixels_in_cell_axis(frac[2], d[2]))
}

/// Break-even of [`EvalMode::Auto`] in pixels a cell set-up: forward differencing a trilinear
/// term costs a cell set-up (corner hashing, the cubic and its forward differences, the exit
/// pixel, and at the exit the subtraction of its state) per cell it visits, and little per
/// pixel; per-pixel evaluation costs a cheaper cell set-up (corner hashing, the monomial form)
/// per cell and the polynomial per pixel. Forward differencing pays when a span gives each of
/// its cell set-ups more than this many pixels (measured on the devices, `docs/performance.md`).
pub const AUTO_FD_PIXELS: u32 = 2;

/// Whether forward differencing a trilinear term with lattice step `du` pays over a span of
/// `len` pixels: the span visits about `1 + len sum|du| / 2^16` cells, and forward differencing
/// pays when that leaves more than [`AUTO_FD_PIXELS`] pixels to each.
#[cfg_attr(not(texcore_lean), inline(always))]
fn fd_pays(len: u16, du: [i32; 3]) -> bool {
    let sum: u64 = du.iter().map(|d| u64::from(d.unsigned_abs())).sum();
    let len = u64::from(len);
    // len / (1 + len sum / 2^16) > P  <=>  2^16 len > P (2^16 + len sum)
    (len << 16) > u64::from(AUTO_FD_PIXELS) * ((1 << 16) + len * sum)
}

/// The per-span part of the model evaluation shared by every mode (multipass included).
pub(crate) struct Setup<const T: usize> {
    /// One per model term, in order (inactive where culled).
    pub(crate) terms: heapless::Vec<TermSetup, T>,
    /// The quadric along the span (48 fraction bits).
    pub(crate) quad: QuadraticSpan,
    /// The quadric's x-gradient along the span: `gqx[0] + i gqx[1]` (zero without gradients).
    pub(crate) gqx: [i128; 2],
    /// The quadric's y-gradient along the span, as `gqx`.
    pub(crate) gqy: [i128; 2],
    extra_width48: i64,
}

impl<const T: usize> Setup<T> {
    /// No terms, a zero quadric (built in place: the term slots stay unwritten).
    #[cfg_attr(not(texcore_lean), inline(always))]
    fn empty() -> Self {
        Setup {
            terms: heapless::Vec::new(),
            quad: QuadraticSpan { c: [0; 3] },
            gqx: [0; 2],
            gqy: [0; 2],
            extra_width48: 0,
        }
    }
}

/// Forward-difference state of a cubic term inside one cell (exact, 64-bit).
#[derive(Clone, Copy, Debug, Default)]
struct Cubic {
    p: [i64; 4],
    gx: [i64; 3],
    gy: [i64; 3],
}

/// Forward-difference state with 32-bit accumulators (the exact state's top 32 bits at the anchor).
#[cfg(feature = "fd32")]
#[derive(Clone, Copy, Debug, Default)]
struct Cubic32 {
    p: [i32; 4],
    gx: [i32; 3],
    gy: [i32; 3],
}

/// How one term is evaluated along the current span.
///
/// Which strategies the general loop ([`SpanEvaluator::run`]) carries depends on the features:
/// `Direct` always; `Fd` (for terms the merged fast path does not take) with `turbulence-fd`;
/// `Cached` with a basis that is not a cubic (`smooth-fade`, `gradient-noise`, `mnoise`); `Fd32`
/// with `fd32`; `Hermite` with `reanchor` and a basis that is not a cubic. A strategy that is
/// not compiled in is never chosen (see [`SpanEvaluator::eval_inner`] and
/// [`SpanEvaluator::run`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Strategy {
    Off,
    /// Per-pixel hashing and interpolation.
    Direct,
    /// Cached cell, per-pixel interpolation (exact).
    #[cfg_attr(
        not(any(
            feature = "smooth-fade",
            feature = "gradient-noise",
            feature = "mnoise"
        )),
        allow(dead_code)
    )]
    Cached,
    /// Exact 64-bit forward differencing of the cubic.
    Fd,
    /// 32-bit forward differencing, re-anchored every [`FD32_ANCHOR`] pixels.
    #[cfg_attr(not(feature = "fd32"), allow(dead_code))]
    Fd32,
    /// Cubic Hermite segments of at most [`HERMITE_SEGMENT`] pixels (approximate).
    #[cfg_attr(not(texcore_hermite), allow(dead_code))]
    Hermite,
}

/// Whether the general loop forward-differences cubic terms itself (`Strategy::Fd`); without it
/// they are evaluated per pixel there (identical samples) and turbulent cubic terms go through
/// the merged loop's per-pixel path.
const GENERAL_FD: bool = cfg!(feature = "turbulence-fd");

/// Whether forward differencing is compiled in (crate feature `fd`); without it every mode
/// evaluates per pixel (see [`compiled_mode`]).
const FD: bool = cfg!(feature = "fd");

/// Whether the filter-width gradients are compiled in (crate feature `gradients`, enabled by the
/// colour-table filters); without it [`EvalOptions::gradients`] has no effect and every gradient
/// is zero.
pub(crate) const GRADIENTS: bool = cfg!(feature = "gradients");

/// The size-lean code shape (built at `opt-level = "s"` or `"z"`, `cfg(texcore_lean)`): the
/// merged loop runs one pixel loop that tests the span's shape (gradients, affine quadric) per
/// pixel, instead of its eight specialisations and the component passes over long cells; with
/// [`GENERAL_FD`] the merged loop is not used at all (the general loop forward-differences every
/// term). The samples are identical (unit tests compare both shapes in every build).
const LEAN: bool = cfg!(texcore_lean);

/// Whether any strategy of the general loop keeps per-term state across pixels (cell caches,
/// forward differences, segments); without one it only evaluates per pixel.
const GENERAL_ANCHORS: bool = cfg!(any(
    feature = "turbulence-fd",
    feature = "fd32",
    feature = "smooth-fade",
    feature = "gradient-noise",
    feature = "mnoise"
));

/// The evaluation mode actually run for `mode`: a mode whose code is not compiled in is
/// [`EvalMode::Fd`] (see the variants' documentation), and without the crate feature `fd` every
/// mode is [`EvalMode::Direct`].
#[cfg_attr(not(texcore_lean), inline(always))]
const fn compiled_mode(mode: EvalMode) -> EvalMode {
    if !FD {
        return EvalMode::Direct;
    }
    match mode {
        #[cfg(not(feature = "fd32"))]
        EvalMode::Fd32 => EvalMode::Fd,
        #[cfg(not(texcore_hermite))]
        EvalMode::Reanchored => EvalMode::Fd,
        m => m,
    }
}

/// Re-anchoring interval of [`EvalMode::Fd32`], in pixels.
pub const FD32_ANCHOR: u32 = 32;
/// Longest Hermite segment of [`EvalMode::Reanchored`], in pixels.
pub const HERMITE_SEGMENT: u32 = 16;

#[derive(Clone, Copy, Debug)]
struct TermRun {
    strategy: Strategy,
    data: CellData,
    cell: [u16; 3],
    cached: bool,
    remaining: u32,
    u: [i32; 3],
    /// The forward-difference state of `Fd` and of a `Hermite` segment (whose y-gradient is
    /// linear: `gy[2]` stays zero).
    #[cfg(texcore_fd_state)]
    fd: Cubic,
    #[cfg(feature = "fd32")]
    fd32: Cubic32,
}

impl Default for TermRun {
    fn default() -> Self {
        TermRun {
            strategy: Strategy::Off,
            data: CellData::Value([0; 8]),
            cell: [0; 3],
            cached: false,
            remaining: 0,
            u: [0; 3],
            #[cfg(texcore_fd_state)]
            fd: Cubic::default(),
            #[cfg(feature = "fd32")]
            fd32: Cubic32::default(),
        }
    }
}

/// Evaluates spans of one model.
#[derive(Debug)]
pub struct SpanEvaluator<'m, const T: usize> {
    core: EvalCore<'m, T>,
}

/// The evaluator's state: the model, the options and the counters (the plan and the loops are
/// its methods; the sample chunk of a span is borrowed beside it).
#[derive(Debug)]
struct EvalCore<'m, const T: usize> {
    model: &'m TextureModel<T>,
    opts: EvalOptions,
    /// The nonzero entries of the quadric's matrix (bit `4 r + c`), found once.
    qmask: u16,
    stats: SpanStats,
    /// Tests only: run the size-lean loop shape ([`LEAN`]) whatever the build.
    #[cfg(test)]
    lean: bool,
    /// Tests only: spans the axial kernel evaluated.
    #[cfg(test)]
    axial_spans: u64,
    /// Tests only: rows the row schedule evaluated (`rows`).
    #[cfg(test)]
    row_spans: u64,
}

impl<'m, const T: usize> SpanEvaluator<'m, T> {
    /// An evaluator for `model` with `opts`.
    pub fn new(model: &'m TextureModel<T>, opts: EvalOptions) -> Self {
        SpanEvaluator {
            core: EvalCore::new(model, opts),
        }
    }

    /// Whether the merged loop takes its size-lean shape ([`LEAN`]; tests choose either).
    #[inline(always)]
    fn lean(&self) -> bool {
        self.core.lean()
    }

    /// The counters so far.
    pub fn stats(&self) -> &SpanStats {
        &self.core.stats
    }

    /// The options.
    pub fn options(&self) -> EvalOptions {
        self.core.opts
    }

    /// The extra filter width of `span` from octaves past the Nyquist limit (what
    /// [`SpanInfo::extra_width48`] of [`SpanEvaluator::eval`] will be), without evaluating it.
    pub fn extra_width48(&self, span: &Span) -> i64 {
        let mut each = |_: &NoiseTerm, _: &[i32; 3], _: &[i32; 3], _: Option<(i32, bool)>| {};
        band_terms(
            self.core.model,
            span,
            self.core.opts.band(),
            each_term(&mut each),
        )
    }

    /// Evaluates `span`, calling `emit` once per pixel in order. Returns the span's facts.
    ///
    /// Only this thin loop is generic over `emit`: the evaluator itself is compiled once per model
    /// capacity `T` and hands its samples over in chunks of [`SAMPLE_CHUNK`], so a program with
    /// many call sites carries one copy of the evaluator (code size on the device).
    ///
    /// In the size-lean shape (`opt-level = "s"` or `"z"`, crate documentation, "Code size")
    /// the loop over a chunk's samples is compiled once and calls `emit` through a trait object,
    /// instead of once per `emit`.
    #[inline]
    pub fn eval<F: FnMut(Sample)>(&mut self, span: &Span, mut emit: F) -> SpanInfo {
        if self.lean() {
            return self.eval_dyn(span, &mut emit);
        }
        self.eval_chunks(span, &mut |chunk: &SampleChunk| {
            for s in chunk.iter() {
                emit(s);
            }
        })
    }

    /// [`SpanEvaluator::eval`] with `emit` as a trait object (the size-lean shape).
    #[inline(never)]
    fn eval_dyn(&mut self, span: &Span, emit: &mut dyn FnMut(Sample)) -> SpanInfo {
        self.eval_chunks(span, &mut |chunk: &SampleChunk| {
            for s in chunk.iter() {
                emit(s);
            }
        })
    }

    /// Evaluates `span`, handing the samples to `out` in order, in chunks of at most
    /// [`SAMPLE_CHUNK`] (every chunk but the last of a span is full).
    #[inline(never)]
    pub fn eval_chunks(&mut self, span: &Span, out: &mut dyn FnMut(&SampleChunk)) -> SpanInfo {
        let mut chunk = SampleChunk::new();
        let mut sink = ChunkSink {
            chunk: &mut chunk,
            out,
        };
        let info = self.core.eval_inner(span, &mut sink);
        sink.finish();
        info
    }
    /// Evaluates the values `f` of `span` into `out`, pixel `i` into `out[i]`: the `f` of the
    /// samples of [`SpanEvaluator::eval`], bit for bit, without their gradients (whatever
    /// [`EvalOptions::gradients`] says) and without handing samples over. The shortest way to a
    /// row of values: the forward-differenced single-axis spans (a row across an axis-aligned
    /// plane) are written straight into `out`.
    ///
    /// Writes `min(span.len, out.len())` values (a shorter `out` takes the start of the span,
    /// and the counters count what was evaluated); the rest of `out` is left as it is. Returns
    /// the span's facts.
    pub fn eval_values(&mut self, span: &Span, out: &mut [TexValue]) -> SpanInfo {
        self.values_through(span, out, &mut [])
    }

    /// [`SpanEvaluator::eval_values`] with the face blends of single-axis trilinear terms kept
    /// in `cache` across calls ([`FaceCache`]): the same values, bit for bit; the rows of an
    /// axis-aligned plane after the first read the faces they share with the rows before
    /// instead of hashing and blending them again. Spans the lane kernel does not take (and the
    /// size-lean code shape) do not use the cache.
    ///
    /// A 64 x 64 field of four octaves of value noise, row by row (8 lattice cells across):
    ///
    /// ```
    /// use texcore::format::{Amplitude, MatrixEntry, TexPoint, TexValue};
    /// use texcore::hash::HashKind;
    /// use texcore::model::{Octaves, TextureModel};
    /// use texcore::noise::NoiseBasis;
    /// use texcore::quadric::Quadric;
    /// use texcore::span::{EvalMode, EvalOptions, FaceCache, Span, SpanEvaluator};
    /// use texcore::table::TableWrap;
    /// use texcore::transform::Affine3;
    ///
    /// let mut model: TextureModel<4> = TextureModel::new(Quadric::ZERO, TableWrap::Mod);
    /// model.push_octaves(&Octaves {
    ///     count: 4,
    ///     base: Affine3::scale(MatrixEntry::ONE),
    ///     amplitude: Amplitude::ONE,
    ///     rotate: false,
    ///     basis: NoiseBasis::trilinear(HashKind::Integer),
    ///     turbulence: false,
    /// })?;
    /// let opts = EvalOptions { mode: EvalMode::Fd, gradients: false, ..Default::default() };
    /// let mut ev = SpanEvaluator::new(&model, opts);
    /// let mut faces = FaceCache::<128>::new();
    /// let mut field = [[TexValue::ZERO; 64]; 64];
    /// for (y, row) in field.iter_mut().enumerate() {
    ///     let span = Span {
    ///         s0: TexPoint::from_f64(0.0, y as f64 / 8.0, 0.5),
    ///         ds: TexPoint::from_f64(1.0 / 8.0, 0.0, 0.0),
    ///         dsdy: TexPoint::from_f64(0.0, 1.0 / 8.0, 0.0),
    ///         len: 64,
    ///     };
    ///     ev.eval_values_cached(&span, row, &mut faces);
    /// }
    /// // The same values as without the cache, and as per-pixel evaluation.
    /// let mut direct = SpanEvaluator::new(&model, EvalOptions { mode: EvalMode::Direct, ..opts });
    /// let mut row = [TexValue::ZERO; 64];
    /// direct.eval_values(
    ///     &Span {
    ///         s0: TexPoint::from_f64(0.0, 5.0 / 8.0, 0.5),
    ///         ds: TexPoint::from_f64(1.0 / 8.0, 0.0, 0.0),
    ///         dsdy: TexPoint::from_f64(0.0, 1.0 / 8.0, 0.0),
    ///         len: 64,
    ///     },
    ///     &mut row,
    /// );
    /// assert_eq!(row, field[5]);
    /// # Ok::<(), texcore::model::ModelError>(())
    /// ```
    pub fn eval_values_cached<const N: usize>(
        &mut self,
        span: &Span,
        out: &mut [TexValue],
        cache: &mut FaceCache<N>,
    ) -> SpanInfo {
        self.values_through(span, out, cache.entries())
    }

    /// [`SpanEvaluator::eval_values`] through the face cache entries `faces` (none: no cache).
    fn values_through(
        &mut self,
        span: &Span,
        out: &mut [TexValue],
        faces: &mut [face_cache::FaceEntry],
    ) -> SpanInfo {
        let n = usize::from(span.len).min(out.len());
        let span = Span {
            len: n as u16,
            ..*span
        };
        let Some(out) = out.get_mut(..n) else {
            return SpanInfo::default();
        };
        let grads = self.core.opts.gradients;
        self.core.opts.gradients = false;
        let info = self.core.eval_values(&span, out, faces);
        self.core.opts.gradients = grads;
        info
    }
}

impl<'m, const T: usize> EvalCore<'m, T> {
    fn new(model: &'m TextureModel<T>, opts: EvalOptions) -> Self {
        EvalCore {
            model,
            opts,
            qmask: quadric_mask(&quadric_matrix(model.quadric())),
            stats: SpanStats::default(),
            #[cfg(test)]
            lean: LEAN,
            #[cfg(test)]
            axial_spans: 0,
            #[cfg(test)]
            row_spans: 0,
        }
    }

    /// [`SpanEvaluator::eval_values`] (gradients off, `out` exactly `span.len` long): the lane
    /// kernel straight into `out` where it takes the span, otherwise the chunks' `f` copied.
    #[cfg_attr(texcore_lean, allow(unused_variables))]
    fn eval_values(
        &mut self,
        span: &Span,
        out: &mut [TexValue],
        faces: &mut [face_cache::FaceEntry],
    ) -> SpanInfo {
        // Only the forward-differencing modes can take the lane kernel (fast shape only).
        #[cfg(not(texcore_lean))]
        if FD && !self.lean() && !self.multipass() {
            let mut setup = Setup::empty();
            let (info, strategies) = self.begin_planned(span, &mut setup);
            let Some(strategies) = strategies else {
                return info;
            };
            self.values_planned(span.len, &setup, &strategies, out, faces);
            return info;
        }
        let mut info = SpanInfo::default();
        copy_values(out, |sink| info = self.eval_inner(span, sink));
        info
    }

    /// The span's set-up into `setup` (empty), its counters and facts ([`Self::begin`]), and its
    /// plan ([`Self::plan_span`]; `None` for an empty span, which sets nothing up).
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn begin_planned(
        &mut self,
        span: &Span,
        setup: &mut Setup<T>,
    ) -> (SpanInfo, Option<[Strategy; T]>) {
        let info = self.begin(span, setup);
        if span.len == 0 {
            return (info, None);
        }
        (info, Some(self.plan_span(span.len, setup)))
    }

    /// The plan of a span of `len` pixels with set-up `setup` under the evaluator's mode.
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn plan_span(&self, len: u16, setup: &Setup<T>) -> [Strategy; T] {
        let mode = compiled_mode(self.opts.mode);
        let choose = |ts: &TermSetup, cubic| strategy(mode, ts, cubic, len);
        plan(setup, self.model.terms(), choose)
    }

    /// The values of a span of `len` pixels (`out` exactly that long, gradients off) that has
    /// been set up and planned: the lane kernel straight into `out` where it takes the span,
    /// otherwise the chunks' `f` copied (fast shape only).
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn values_planned(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        out: &mut [TexValue],
        faces: &mut [face_cache::FaceEntry],
    ) {
        let merged = self.merged_takes(u32::from(len), setup, strategies);
        if merged && self.axial_takes(setup, strategies) {
            // Accumulators only for several lanes, no longer than the span needs (each array
            // is cleared only on its own branch).
            let lanes = strategies.iter().filter(|s| **s != Strategy::Off).count();
            let mut go = |acc: &mut [i64]| {
                let mut values = lanes::LaneOut::Values(lanes::ValuesOut::new(out, acc));
                self.run_lanes(len, setup, strategies, &mut values, faces);
            };
            if lanes <= 1 {
                go(&mut []);
            } else if len <= SAMPLE_CHUNK as u16 {
                go(&mut [0i64; SAMPLE_CHUNK]);
            } else {
                go(&mut [0i64; lanes::VALUE_RUN]);
            }
        } else if merged && self.axial_direct_takes(setup, strategies) {
            let mut values = lanes::LaneOut::Values(lanes::ValuesOut::new(out, &mut []));
            self.run_axial_direct(len, setup, strategies, &mut values);
        } else {
            copy_values(out, |sink| self.run(len, setup, sink));
        }
    }

    /// Whether the merged loop takes its size-lean shape ([`LEAN`]; tests choose either).
    #[inline(always)]
    fn lean(&self) -> bool {
        #[cfg(test)]
        return self.lean;
        #[cfg(not(test))]
        LEAN
    }

    /// Fills `out` (empty, as [`Setup::empty`]) for `span`; in place, as the set-up is large.
    fn setup(&mut self, span: &Span, out: &mut Setup<T>) {
        let m = self.model;
        let s0 = exact(span.s0);
        let ds = exact(span.ds);
        let dy = exact(span.dsdy);
        // The quadric along the span from two matrix-vector products, `Q x` and `Q d` (entries
        // 32 x 32 -> 64-bit, zero entries skipped), and five dot products: the same values mod
        // 2^128 as `Quadric::along` / `derivative_along` (`x^T Q d = d^T Q x`).
        let grads = GRADIENTS && self.opts.gradients;
        if self.qmask != 0 {
            let qm = quadric_matrix(m.quadric());
            let xh = [s0[0], s0[1], s0[2], 1 << 16];
            let dh = [ds[0], ds[1], ds[2], 0];
            let qx = mat_vec(&qm, self.qmask, &xh);
            let qd = mat_vec(&qm, self.qmask, &dh);
            let c1 = dot(&dh, &qx).wrapping_mul(2);
            let c2 = dot(&dh, &qd);
            out.quad = QuadraticSpan {
                c: [dot(&xh, &qx), c1, c2],
            };
            if grads {
                let yh = [dy[0], dy[1], dy[2], 0];
                out.gqx = [c1, c2.wrapping_mul(2)];
                out.gqy = [dot(&yh, &qx).wrapping_mul(2), dot(&yh, &qd).wrapping_mul(2)];
            }
        }
        // A vector, not an array: nothing is written for the slots past the model's terms.
        let terms = &mut out.terms;
        let stats = &mut self.stats;
        // Coordinate precision (`docs/model.md` 3.2): `U0` and `DU` rounded to `F` fraction bits,
        // so `u(i) = U0 + i DU` stays linear in `i`; band-limiting uses the unrounded step.
        let cb = m.precision().coord_bits();
        let mut each =
            |term: &NoiseTerm, du: &[i32; 3], dyl: &[i32; 3], band: Option<(i32, bool)>| {
                let Some((amp, gradient)) = band else {
                    stats.culled_octaves += 1;
                    // At most T terms: never full.
                    let _ = terms.push(TermSetup::default());
                    return;
                };
                if amp != term.amplitude.to_bits() {
                    stats.faded_octaves += 1;
                }
                let mut u0 = term.transform.apply_point(span.s0);
                let mut du = *du;
                if cb < 16 {
                    u0 = u0.map(|c| quantize_coord(c, cb));
                    du = du.map(|c| quantize_coord(c, cb));
                }
                let _ = terms.push(TermSetup {
                    u0,
                    du,
                    dy: *dyl,
                    active: true,
                    gradient: grads && gradient,
                    amp,
                });
            };
        out.extra_width48 = band_terms(m, span, self.opts.band(), each_term(&mut each));
    }

    /// Whether the mode is the multipass evaluator (which has its own loop).
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn multipass(&self) -> bool {
        #[cfg(feature = "multipass")]
        return matches!(self.opts.mode, EvalMode::Multipass(_));
        #[cfg(not(feature = "multipass"))]
        false
    }

    /// The span's set-up into `setup` (empty, as [`Setup::empty`]) and its counters, and the
    /// span's facts: what every evaluation of a span starts with.
    #[inline(always)]
    fn begin(&mut self, span: &Span, setup: &mut Setup<T>) -> SpanInfo {
        self.setup(span, setup);
        self.stats.spans += 1;
        self.stats.pixels += u64::from(span.len);
        SpanInfo {
            extra_width48: setup.extra_width48,
        }
    }

    /// The evaluation proper.
    fn eval_inner(&mut self, span: &Span, sink: &mut ChunkSink<'_, '_>) -> SpanInfo {
        let mut setup = Setup::empty();
        let info = self.begin(span, &mut setup);
        sink.chunk.extra_width48 = setup.extra_width48;
        // An empty span sets nothing up (in either loop).
        if span.len == 0 {
            return info;
        }
        #[cfg(feature = "multipass")]
        if let EvalMode::Multipass(cfg) = self.opts.mode {
            let (m, o, st) = (self.model, self.opts, &mut self.stats);
            crate::multipass::eval_span(m, o, cfg, &setup, span.len, st, &mut |s| sink.push(s));
            return info;
        }
        self.run(span.len, &setup, sink);
        info
    }
}

/// The plan: each term's strategy for a span, decided once per span by `choose(term set-up,
/// is_cubic)` (`Off` for the terms the set-up culled), as the general loop makes it.
#[cfg(not(texcore_lean))]
#[inline(always)]
fn plan<const T: usize>(
    setup: &Setup<T>,
    terms: &[NoiseTerm],
    choose: impl Fn(&TermSetup, bool) -> Strategy,
) -> [Strategy; T] {
    let mut strategies = [Strategy::Off; T];
    for ((st, ts), term) in strategies.iter_mut().zip(setup.terms.iter()).zip(terms) {
        if ts.active {
            *st = choose(ts, term.basis.is_cubic());
            // Without the general loop's forward differencing, turbulent cubic terms are
            // evaluated per pixel, which the merged loop does (identical samples).
            if !GENERAL_FD && *st == Strategy::Fd && term.turbulence {
                *st = Strategy::Direct;
            }
        }
    }
    strategies
}

/// The strategy of an active term (`cubic`: a trilinear basis) with set-up `ts` in a span of
/// `len` pixels under `mode` (as compiled, [`compiled_mode`]).
#[inline(always)]
fn strategy(mode: EvalMode, ts: &TermSetup, cubic: bool, len: u16) -> Strategy {
    match mode {
        EvalMode::Direct => Strategy::Direct,
        EvalMode::Fd => {
            if cubic {
                Strategy::Fd
            } else {
                Strategy::Cached
            }
        }
        EvalMode::Auto => {
            if ts.du.iter().any(|d| d.unsigned_abs() > NYQUIST_STEP as u32) {
                Strategy::Direct
            } else if cubic {
                if fd_pays(len, ts.du) {
                    Strategy::Fd
                } else {
                    Strategy::Direct
                }
            } else {
                Strategy::Cached
            }
        }
        EvalMode::Fd32 => {
            if cubic {
                Strategy::Fd32
            } else {
                Strategy::Cached
            }
        }
        EvalMode::Reanchored => {
            if cubic {
                Strategy::Fd
            } else {
                Strategy::Hermite
            }
        }
        #[cfg(feature = "multipass")]
        EvalMode::Multipass(_) => Strategy::Direct,
    }
}

/// Runs `eval` with a chunk sink that copies each chunk's `f` into `out`, in order.
fn copy_values(out: &mut [TexValue], eval: impl FnOnce(&mut ChunkSink<'_, '_>)) {
    let mut chunk = SampleChunk::new();
    let mut at = 0usize;
    let mut copy = |c: &SampleChunk| {
        if let Some(dst) = out.get_mut(at..at + c.len()) {
            // Element by element: `copy_from_slice` keeps a length-mismatch panic.
            for (d, v) in dst.iter_mut().zip(c.f()) {
                *d = *v;
            }
        }
        at += c.len();
    };
    let mut sink = ChunkSink {
        chunk: &mut chunk,
        out: &mut copy,
    };
    eval(&mut sink);
    sink.finish();
}

/// Amplitude used for the corner values and the sign applied afterwards (turbulence).
#[cfg_attr(not(texcore_lean), inline(always))]
fn amp_and_sign(term: &NoiseTerm, ts: &TermSetup) -> (i32, bool) {
    let a = ts.amp;
    if term.turbulence {
        (a.wrapping_abs(), a < 0)
    } else {
        (a, false)
    }
}

/// The top 32 bits (floor) of an exact forward-difference state.
#[cfg(feature = "fd32")]
fn narrow(c: &Cubic) -> Cubic32 {
    let h = |x: i64| (x >> 32) as i32;
    Cubic32 {
        p: [h(c.p[0]), h(c.p[1]), h(c.p[2]), h(c.p[3])],
        gx: [h(c.gx[0]), h(c.gx[1]), h(c.gx[2])],
        gy: [h(c.gy[0]), h(c.gy[1]), h(c.gy[2])],
    }
}

/// Division of an i128 by a positive divisor, rounded to nearest (ties away from zero), saturated.
#[cfg(texcore_hermite)]
fn div_round(x: i128, d: i128) -> i64 {
    // `(x + d/2) / d` for x >= 0 and `(x - d/2) / d` (truncating) for x < 0, i.e. the rounded
    // magnitude with x's sign; the division is the crate's shared one (code size).
    let (q, _) = crate::wide::div_rem_euclid_i128(x.unsigned_abs() as i128 + d / 2, d);
    sat_i64(if x < 0 { q.wrapping_neg() } else { q })
}

/// Cubic Hermite segment over pixels `0..l` through the exact values and derivatives at pixels
/// `0` and `l - 1` (both inside the current cell), as a forward-difference state: the value is
/// cubic, the x-gradient its derivative, the y-gradient linear between the anchors (`gy[2] = 0`).
#[cfg(texcore_hermite)]
#[allow(clippy::too_many_arguments)]
fn hermite_setup(
    term: &NoiseTerm,
    data: &CellData,
    u: [i32; 3],
    ts: &TermSetup,
    l: u32,
    amp: i32,
    fv: u32,
    grads: bool,
) -> Cubic {
    let (_, f0) = split(u);
    let b = &term.basis;
    let p0 = b.sample(data, f0, amp, fv);
    let g0 = b.derivative(data, f0, ts.du, amp, fv);
    let y0 = if grads {
        b.derivative(data, f0, ts.dy, amp, fv)
    } else {
        0
    };
    if l <= 1 {
        return Cubic {
            p: [p0, 0, 0, 0],
            gx: [g0, 0, 0],
            gy: [y0, 0, 0],
        };
    }
    let mm = l - 1;
    let (_, fm) = split([
        u[0].wrapping_add(ts.du[0].wrapping_mul(mm as i32)),
        u[1].wrapping_add(ts.du[1].wrapping_mul(mm as i32)),
        u[2].wrapping_add(ts.du[2].wrapping_mul(mm as i32)),
    ]);
    let pm = b.sample(data, fm, amp, fv);
    let gm = b.derivative(data, fm, ts.du, amp, fv);
    let ym = if grads {
        b.derivative(data, fm, ts.dy, amp, fv)
    } else {
        0
    };
    let m = i128::from(mm);
    let (p0w, pmw, g0w, gmw) = (
        i128::from(p0),
        i128::from(pm),
        i128::from(g0),
        i128::from(gm),
    );
    let c2 = div_round(3 * (pmw - p0w) - (2 * g0w + gmw) * m, m * m);
    let c3 = div_round(2 * (p0w - pmw) + (g0w + gmw) * m, m * m * m);
    let c1 = g0;
    Cubic {
        p: [
            p0,
            c1.wrapping_add(c2).wrapping_add(c3),
            c2.wrapping_mul(2).wrapping_add(c3.wrapping_mul(6)),
            c3.wrapping_mul(6),
        ],
        gx: [
            g0,
            c2.wrapping_mul(2).wrapping_add(c3.wrapping_mul(3)),
            c3.wrapping_mul(6),
        ],
        gy: [y0, div_round(i128::from(ym) - i128::from(y0), m), 0],
    }
}

/// The per-term band-limiting of `span` ([`crate::bandlimit::term_band`]), the one loop behind
/// the span set-up, [`SpanEvaluator::extra_width48`] and the multipass evaluator (which takes the
/// span set-up), band-limited by `rule` (`None`: the unfaded contract): calls
/// `each(term, du, dy, band)` for every term of `model` in order, with the
/// term's unrounded lattice steps along and across the span and `band` its amplitude for the
/// span and whether its gradient widens the filter ([`crate::bandlimit::TermBand`]; `None`:
/// culled), and returns the span's extra filter width ([`SpanInfo::extra_width48`]) from the
/// summed variances (the callback does not see them: builds without filter widths drop them).
///
/// In the size-lean shape with filter widths (feature `gradients`, where both callers are
/// linked) the callers hand `each` over as an [`EachTerm`] trait object: one out-of-line copy.
/// Elsewhere it is inlined with `each` (the fast shape; the lean builds without filter widths,
/// whose only caller is the span set-up and which drop the variances).
#[cfg_attr(not(all(texcore_lean, feature = "gradients")), inline(always))]
fn band_terms<const T: usize, F>(
    model: &TextureModel<T>,
    span: &Span,
    rule: Option<&BandLimit>,
    each: &mut F,
) -> i64
where
    F: FnMut(&NoiseTerm, &[i32; 3], &[i32; 3], Option<(i32, bool)>) + ?Sized,
{
    let mut variance: u64 = 0;
    for term in model.terms().iter().take(T) {
        let (du, dy) = lattice_steps(term, span);
        let band = term_band(term, du, dy, rule);
        // Summed only where filter widths exist (`build_spread_width48`).
        if cfg!(feature = "gradients") {
            variance = variance.saturating_add(band.variance);
        }
        each(
            term,
            &du,
            &dy,
            band.active.then_some((band.amplitude, band.gradient)),
        );
    }
    build_spread_width48(variance)
}

/// The callback of [`band_terms`] as a trait object (the size-lean shape with filter widths).
#[cfg(all(texcore_lean, feature = "gradients"))]
type EachTerm<'a> = dyn FnMut(&NoiseTerm, &[i32; 3], &[i32; 3], Option<(i32, bool)>) + 'a;

/// A callback as [`band_terms`] takes it: a trait object in the size-lean shape with filter
/// widths (one copy of the loop for every caller), itself elsewhere (inlined with the loop).
#[cfg(all(texcore_lean, feature = "gradients"))]
fn each_term<'a>(each: &'a mut EachTerm<'a>) -> &'a mut EachTerm<'a> {
    each
}

/// See the size-lean version.
#[cfg(not(all(texcore_lean, feature = "gradients")))]
#[inline(always)]
fn each_term<F>(each: &mut F) -> &mut F {
    each
}

/// A term's lattice steps along the span and across it (raw 16.16 cells a pixel).
#[inline]
fn lattice_steps(term: &NoiseTerm, span: &Span) -> ([i32; 3], [i32; 3]) {
    let du = term.transform.apply_vector(span.ds);
    let dy = term.transform.apply_vector(span.dsdy);
    (du, dy)
}

/// Value and gradients of one term at a fraction of its cached cell.
#[cfg_attr(not(texcore_lean), inline(always))]
fn eval_term(
    term: &NoiseTerm,
    data: &CellData,
    frac: [u32; 3],
    ts: &TermSetup,
    amp: i32,
    fv: u32,
    want_g: bool,
) -> (i64, i64, i64) {
    let b = &term.basis;
    let v = b.sample(data, frac, amp, fv);
    if want_g {
        (
            v,
            b.derivative(data, frac, ts.du, amp, fv),
            b.derivative(data, frac, ts.dy, amp, fv),
        )
    } else {
        (v, 0, 0)
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for Sample {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "Sample(f raw {=i32}, gx {=i64}, gy {=i64})",
            self.f.to_bits(),
            self.gx,
            self.gy
        );
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for Span {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "Span(s0 {}, ds {}, dsdy {}, len {=u16})",
            self.s0,
            self.ds,
            self.dsdy,
            self.len
        );
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::format::{Amplitude, MatrixEntry, QuadricCoeff};
    use crate::model::{NoiseTerm, Octaves};
    use crate::noise::{BasisKind, Fade, NoiseBasis};
    use crate::quadric::Quadric;
    use crate::transform::Affine3;

    fn marble() -> TextureModel<8> {
        TextureModel::new(
            Quadric::linear(
                QuadricCoeff::ZERO,
                QuadricCoeff::ZERO,
                QuadricCoeff::ONE,
                QuadricCoeff::ZERO,
            ),
            TableWrap::Mod,
        )
        .with_octaves(&Octaves {
            count: 4,
            base: Affine3::scale(MatrixEntry::from_num(4)),
            amplitude: Amplitude::ONE,
            rotate: true,
            basis: NoiseBasis::trilinear(HashKind::Integer),
            turbulence: false,
        })
        .unwrap()
    }

    fn run<const T: usize>(m: &TextureModel<T>, mode: EvalMode, span: &Span) -> Vec<Sample> {
        let mut ev = SpanEvaluator::new(
            m,
            EvalOptions {
                mode,
                gradients: true,
                cull: true,
                ..Default::default()
            },
        );
        let mut out = Vec::new();
        ev.eval(span, |s| out.push(s));
        out
    }

    #[test]
    fn fd_equals_direct_on_marble() {
        let m = marble();
        let span = Span {
            s0: TexPoint::from_f64(0.1, 0.2, 0.3),
            ds: TexPoint::from_f64(0.0031, -0.0007, 0.0019),
            dsdy: TexPoint::from_f64(0.0005, 0.003, -0.0001),
            len: 600,
        };
        let d = run(&m, EvalMode::Direct, &span);
        let f = run(&m, EvalMode::Fd, &span);
        let a = run(&m, EvalMode::Auto, &span);
        assert_eq!(d.len(), 600);
        assert_eq!(d, f);
        assert_eq!(d, a);
    }

    #[test]
    fn all_bases_identical_across_modes() {
        let kinds = [
            BasisKind::Value,
            #[cfg(feature = "gradient-noise")]
            BasisKind::Gradient,
            #[cfg(feature = "mnoise")]
            BasisKind::Modified,
        ];
        for kind in kinds {
            for fade in [
                Fade::Linear,
                #[cfg(feature = "smooth-fade")]
                Fade::Smooth,
            ] {
                let mut m: TextureModel<4> = TextureModel::new(
                    Quadric::from_f64([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap(),
                    TableWrap::Clamp,
                );
                let mut t = NoiseTerm::new(
                    Amplitude::from_num(-0.75),
                    Affine3::scale(MatrixEntry::from_num(3)),
                    NoiseBasis {
                        kind,
                        fade,
                        hash: HashKind::Integer,
                    },
                );
                m.push(t).unwrap();
                t.turbulence = true;
                t.transform = Affine3::scale(MatrixEntry::from_num(7));
                m.push(t).unwrap();
                let span = Span {
                    s0: TexPoint::from_f64(-1.3, 0.7, 2.1),
                    ds: TexPoint::from_f64(0.01, 0.004, -0.002),
                    dsdy: TexPoint::from_f64(0.0, 0.01, 0.0),
                    len: 400,
                };
                let d = run(&m, EvalMode::Direct, &span);
                assert_eq!(d, run(&m, EvalMode::Fd, &span), "{kind:?} {fade:?}");
                assert_eq!(d, run(&m, EvalMode::Auto, &span), "{kind:?} {fade:?}");
            }
        }
    }

    #[test]
    fn every_band_limit_setting_is_exact_and_changes_only_faded_octaves() {
        use crate::bandlimit::FadeWeight;
        let m = marble();
        // A receding row: the octaves reach about 1.5, 3, 6 and 12 cells a pixel across the
        // span and a quarter of that along it (a long, narrow footprint).
        let span = Span {
            s0: TexPoint::from_f64(0.1, 0.2, 0.3),
            ds: TexPoint::from_f64(0.09, 0.0, 0.0),
            dsdy: TexPoint::from_f64(0.0, 0.0, 0.37),
            len: 300,
        };
        let go = |opts: EvalOptions| {
            let mut ev = SpanEvaluator::new(&m, opts);
            let mut out = Vec::new();
            let info = ev.eval(&span, |s| out.push(s));
            (out, info)
        };
        let with = |mode, band_limit| {
            go(EvalOptions {
                mode,
                band_limit,
                ..Default::default()
            })
        };
        let default = with(EvalMode::Direct, BandLimit::DEFAULT);
        let mut distinct = 0;
        for weight in [FadeWeight::Footprint, FadeWeight::Reach] {
            for (floor, part) in [(1 << 12, 0), (1 << 14, 3 << 14), (1 << 15, 1 << 16)] {
                let Some(b) = BandLimit::new(weight, floor, part) else {
                    panic!("{weight:?} {floor} {part}");
                };
                let d = with(EvalMode::Direct, b);
                assert_eq!(d, with(EvalMode::Fd, b), "{b:?}");
                assert_eq!(d, with(EvalMode::Auto, b), "{b:?}");
                distinct += usize::from(d != default);
            }
        }
        // Every setting but the default's own changes the row.
        assert_eq!(distinct, 5);
        // With culling off the setting plays no part.
        let Some(reach) = BandLimit::new(FadeWeight::Reach, 1 << 12, 0) else {
            panic!("reach rule");
        };
        let off = |band_limit| {
            go(EvalOptions {
                cull: false,
                band_limit,
                ..Default::default()
            })
        };
        assert_eq!(off(BandLimit::DEFAULT), off(reach));
    }

    #[test]
    fn band_limiting_counts_fades_and_widens() {
        let m = marble();
        let spread = |span: &Span, cull: bool| -> i64 {
            let mut var = 0u64;
            for t in m.terms() {
                let (du, dy) = lattice_steps(t, span);
                var += crate::bandlimit::term_band(t, du, dy, cull.then_some(&BandLimit::DEFAULT))
                    .variance;
            }
            crate::bandlimit::build_spread_width48(var)
        };
        // A far-away span: the octaves reach about 2, 4, 8 and 16 cells a pixel.
        let span = Span {
            s0: TexPoint::from_f64(0.0, 0.0, 0.0),
            ds: TexPoint::from_f64(0.5, 0.0, 0.0),
            dsdy: TexPoint::ZERO,
            len: 10,
        };
        let mut ev = SpanEvaluator::new(&m, EvalOptions::default());
        let mut faded = Vec::new();
        let info = ev.eval(&span, |s| faded.push(s.f));
        let bands: Vec<_> = m
            .terms()
            .iter()
            .map(|t| {
                let (du, dy) = lattice_steps(t, &span);
                crate::bandlimit::term_band(t, du, dy, Some(&BandLimit::DEFAULT))
            })
            .collect();
        let n_faded = bands
            .iter()
            .zip(m.terms())
            .filter(|(b, t)| b.active && b.amplitude != t.amplitude.to_bits())
            .count() as u64;
        let n_active = bands.iter().filter(|b| b.active).count() as u64;
        assert!(n_faded >= 2, "{bands:?}");
        assert_eq!(ev.stats().culled_octaves, 4 - n_active);
        assert_eq!(ev.stats().faded_octaves, n_faded);
        assert_eq!(ev.stats().noise_evaluations, 10 * n_active);
        assert_eq!(info.extra_width48 > 0, GRADIENTS);
        assert_eq!(info.extra_width48, spread(&span, true));
        assert_eq!(ev.extra_width48(&span), info.extra_width48);
        // Without band-limiting every octave enters at full amplitude and the two far ones add
        // their whole variance.
        let opts = EvalOptions {
            cull: false,
            ..EvalOptions::default()
        };
        let mut full_ev = SpanEvaluator::new(&m, opts);
        let mut full = Vec::new();
        let info_full = full_ev.eval(&span, |s| full.push(s.f));
        assert_eq!(full_ev.stats().faded_octaves, 0);
        assert_eq!(info_full.extra_width48, spread(&span, false));
        assert!(info_full.extra_width48 > info.extra_width48 || !GRADIENTS);
        assert_ne!(faded, full);
        // Every mode gives the same faded samples.
        for mode in [
            EvalMode::Direct,
            EvalMode::Fd,
            EvalMode::Fd32,
            EvalMode::Reanchored,
        ] {
            let o = EvalOptions {
                mode,
                ..EvalOptions::default()
            };
            let mut e = SpanEvaluator::new(&m, o);
            let mut got = Vec::new();
            e.eval(&span, |s| got.push(s.f));
            assert_eq!(got, faded, "{mode:?}");
        }
        // Every chunk carries its span's spread: a span of 3 chunks whose finer octaves reach
        // past one cell a pixel, then one with every octave resolved.
        let near = Span {
            ds: TexPoint::from_f64(1.0 / 16.0, 0.0, 0.0),
            len: 3 * SAMPLE_CHUNK as u16 - 5,
            ..span
        };
        let mut got = Vec::new();
        let info = ev.eval_chunks(&near, &mut |c: &SampleChunk| {
            got.push((c.len(), c.extra_width48()))
        });
        assert_eq!(info.extra_width48 > 0, GRADIENTS);
        assert_eq!(info.extra_width48, spread(&near, true));
        assert_eq!(ev.extra_width48(&near), info.extra_width48);
        let lens: Vec<usize> = got.iter().map(|g| g.0).collect();
        assert_eq!(lens, [SAMPLE_CHUNK, SAMPLE_CHUNK, SAMPLE_CHUNK - 5]);
        assert!(got.iter().all(|g| g.1 == info.extra_width48));
        let none = Span {
            ds: TexPoint::from_f64(1.0 / 256.0, 0.0, 0.0),
            ..near
        };
        let info = ev.eval_chunks(&none, &mut |c: &SampleChunk| {
            assert_eq!(c.extra_width48(), 0)
        });
        assert_eq!(info.extra_width48, 0);
    }

    #[test]
    fn merged_path_exact_without_gradients_and_with_quadrics() {
        // Gradients on and off, mod and clamp, affine and curved quadrics, terms forward
        // differenced and (past Nyquist, culling off) per pixel in the same span.
        for wrap in [TableWrap::Mod, TableWrap::Clamp] {
            for curved in [false, true] {
                let q = test_quadric(curved);
                let mut m: TextureModel<8> = TextureModel::new(q, wrap);
                m.push_octaves(&Octaves {
                    count: 6,
                    base: Affine3::scale(MatrixEntry::from_num(3)),
                    amplitude: Amplitude::from_num(0.6),
                    rotate: true,
                    basis: NoiseBasis::trilinear(HashKind::Integer),
                    turbulence: false,
                })
                .unwrap();
                let span = Span {
                    s0: TexPoint::from_f64(-0.37, 1.21, 0.55),
                    ds: TexPoint::from_f64(0.0082, 0.0026, -0.0014),
                    dsdy: TexPoint::from_f64(-0.0011, 0.0037, 0.0002),
                    len: 700,
                };
                for gradients in [true, false] {
                    for cull in [true, false] {
                        let go = |mode| {
                            let mut ev = SpanEvaluator::new(
                                &m,
                                EvalOptions {
                                    mode,
                                    gradients,
                                    cull,
                                    ..Default::default()
                                },
                            );
                            let mut out = Vec::new();
                            ev.eval(&span, |s| out.push(s));
                            out
                        };
                        let d = go(EvalMode::Direct);
                        let ctx = (wrap, curved, gradients, cull);
                        assert_eq!(d, go(EvalMode::Fd), "{ctx:?}");
                        assert_eq!(d, go(EvalMode::Auto), "{ctx:?}");
                        assert_eq!(d, go(EvalMode::Fd32), "{ctx:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn sparse_quadric_is_the_quadric() {
        let mut st = 99u64;
        let mut r = || {
            st = st
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (st >> 32) as i32
        };
        for case in 0..400 {
            let mut c = [QuadricCoeff::ZERO; 10];
            for k in c.iter_mut() {
                // Sparse and dense quadrics, small and extreme entries.
                let v = r();
                *k = QuadricCoeff::from_bits(match (v as u32) % 4 {
                    0 | 1 => 0,
                    2 => v >> 12,
                    _ => v,
                });
            }
            let q = Quadric::from_coefficients(c);
            let pt = |r: &mut dyn FnMut() -> i32, big: bool| {
                let mut v = [0i64; 3];
                for x in v.iter_mut() {
                    let a = r();
                    *x = i64::from(if big || a % 3 == 0 { a } else { a >> 14 });
                }
                v
            };
            let s0 = pt(&mut r, case % 2 == 0);
            let ds = pt(&mut r, case % 5 == 0);
            let dy = pt(&mut r, false);
            let qm = quadric_matrix(&q);
            let mask = quadric_mask(&qm);
            assert_eq!(
                mask.count_ones() as usize,
                qm.iter().flatten().filter(|&&e| e != 0).count()
            );
            let h = |v: [i64; 3], w: i64| [v[0], v[1], v[2], w];
            let (xh, dh, yh) = (h(s0, 1 << 16), h(ds, 0), h(dy, 0));
            let (qx, qd) = (mat_vec(&qm, mask, &xh), mat_vec(&qm, mask, &dh));
            let want = q.along(s0, ds).c;
            let got = [dot(&xh, &qx), dot(&dh, &qx).wrapping_mul(2), dot(&dh, &qd)];
            assert_eq!(got, want);
            for (dir, vh) in [(ds, dh), (dy, yh)] {
                let want = q.derivative_along(s0, ds, dir);
                let got = [dot(&vh, &qx).wrapping_mul(2), dot(&vh, &qd).wrapping_mul(2)];
                assert_eq!(got, want);
            }
        }
    }

    /// Samples and counters of `span` with the merged loop in its size-lean or fast shape.
    fn run_shape<const T: usize>(
        m: &TextureModel<T>,
        opts: EvalOptions,
        span: &Span,
        lean: bool,
    ) -> (Vec<Sample>, SpanStats) {
        let mut ev = SpanEvaluator::new(m, opts);
        ev.core.lean = lean;
        let mut out = Vec::new();
        ev.eval(span, |s| out.push(s));
        (out, *ev.stats())
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(96))]
        /// The size-lean loop shape (`opt-level = "s"`/`"z"`) and the fast one give the same
        /// samples and counters: long cells (the fast shape's component passes), short cells,
        /// per-pixel terms mixed in (culling off past Nyquist), gradients on and off, `mod` and
        /// `clamp`, affine and curved quadrics, plain and turbulent terms (with `turbulence-fd`
        /// the lean shape leaves the merged loop out).
        #[test]
        fn lean_shape_equals_fast_shape(
            s0 in proptest::array::uniform3(-4_000_000i32..4_000_000),
            ds in proptest::array::uniform3(-40_000i32..40_000),
            dy in proptest::array::uniform3(-9_000i32..9_000),
            len in 0u16..300,
            clamp: bool,
            curved: bool,
            gradients: bool,
            cull: bool,
            zoom in 0u32..4,
            mode in 0usize..3,
            turbulent: bool,
        ) {
            let q = test_quadric(curved);
            let wrap = if clamp { TableWrap::Clamp } else { TableWrap::Mod };
            let mut m: TextureModel<8> = TextureModel::new(q, wrap);
            m.push_octaves(&Octaves {
                count: 5,
                base: Affine3::scale(MatrixEntry::from_num(1u32 << zoom)),
                amplitude: Amplitude::from_num(0.6),
                rotate: true,
                basis: NoiseBasis::trilinear(HashKind::Integer),
                turbulence: turbulent,
            })
            .unwrap();
            let span = Span {
                s0: TexPoint::from_bits(s0[0], s0[1], s0[2]),
                ds: TexPoint::from_bits(ds[0] >> (2 * zoom), ds[1] >> (2 * zoom), ds[2]),
                dsdy: TexPoint::from_bits(dy[0], dy[1], dy[2]),
                len,
            };
            let opts = EvalOptions {
                mode: [EvalMode::Direct, EvalMode::Fd, EvalMode::Auto][mode],
                gradients,
                cull,
                ..Default::default()
            };
            let fast = run_shape(&m, opts, &span, false);
            let lean = run_shape(&m, opts, &span, true);
            proptest::prop_assert_eq!(fast, lean);
        }
    }

    /// The merged-path tests' quadric: a curved one, or the linear `s + r/2`.
    fn test_quadric(curved: bool) -> Quadric {
        if curved {
            Quadric::from_f64([0.7, 0.1, 0.0, -0.2, 0.3, 0.0, 0.05, 1.1, 0.25, 0.4]).unwrap()
        } else {
            Quadric::linear(
                QuadricCoeff::ONE,
                QuadricCoeff::ZERO,
                QuadricCoeff::from_num(0.5),
                QuadricCoeff::ZERO,
            )
        }
    }

    /// A span of `len` pixels with step `ds` for the feature tests (rows one 0.003 apart).
    fn feature_span(ds: [f64; 3], len: u16) -> Span {
        Span {
            s0: TexPoint::from_f64(0.1, 0.2, 0.3),
            ds: TexPoint::from_f64(ds[0], ds[1], ds[2]),
            dsdy: TexPoint::from_f64(0.0, 0.003, 0.0),
            len,
        }
    }

    #[test]
    fn forward_differencing_follows_the_feature() {
        // `Fd` and `Auto` forward-difference exactly when the crate feature `fd` is on; without
        // it they evaluate per pixel. The samples are the same either way.
        let m = marble();
        let span = feature_span([0.003, 0.001, 0.002], 200);
        let direct = run(&m, EvalMode::Direct, &span);
        for mode in [EvalMode::Fd, EvalMode::Auto] {
            let opts = EvalOptions {
                mode,
                ..EvalOptions::default()
            };
            let (out, st) = run_shape(&m, opts, &span, LEAN);
            assert_eq!(out, direct, "{mode:?}");
            if cfg!(feature = "fd") {
                assert_eq!(st.fd_pixels, 200, "{mode:?}");
                assert!(st.cell_setups < 200, "{mode:?}: {st:?}");
            } else {
                assert_eq!(st.fd_pixels, 0, "{mode:?}");
                assert_eq!(st.cell_setups, 800, "{mode:?}: {st:?}");
            }
        }
    }

    /// `Auto` forward-differences a term when the span leaves each of its cell set-ups more
    /// than `AUTO_FD_PIXELS` pixels, and evaluates it per pixel otherwise (short spans, short
    /// cells); the samples are `Direct`'s either way.
    #[test]
    fn auto_sends_short_spans_and_cells_to_direct_evaluation() {
        assert!(fd_pays(200, [200, 100, 0]));
        assert!(!fd_pays(AUTO_FD_PIXELS as u16, [0, 0, 0]));
        assert!(fd_pays(AUTO_FD_PIXELS as u16 + 1, [0, 0, 0]));
        // Cells of 2 pixels: every set-up gets at most 2 pixels, however long the span.
        assert!(!fd_pays(1000, [1 << 15, 0, 0]));
        // 3 pixels over cells of 4: two set-ups.
        assert!(!fd_pays(3, [1 << 14, 0, 0]));
        assert!(!fd_pays(0, [0; 3]));
        let m = marble();
        for (len, ds, fd) in [
            (200, [0.003, 0.001, 0.002], true),
            (2, [0.003, 0.001, 0.002], false),
            (3, [0.06, 0.0, 0.0], false),
            (30, [0.06, 0.0, 0.0], true),
        ] {
            let span = feature_span(ds, len);
            let direct = run(&m, EvalMode::Direct, &span);
            let (out, st) = run_shape(&m, EvalOptions::default(), &span, LEAN);
            assert_eq!(out, direct);
            let expect = if fd && cfg!(feature = "fd") {
                u64::from(len)
            } else {
                0
            };
            assert_eq!(st.fd_pixels, expect, "{len} {ds:?}: {st:?}");
        }
    }

    #[test]
    fn gradients_follow_the_feature() {
        // Asked for, the gradients are computed exactly when the crate feature `gradients` is
        // on; without it they are zero and nothing counts as a gradient evaluation. (CI runs
        // these unit tests with and without features.)
        let m = marble();
        let span = feature_span([0.003, 0.001, 0.002], 100);
        for mode in [EvalMode::Direct, EvalMode::Fd, EvalMode::Auto] {
            let opts = EvalOptions {
                mode,
                ..EvalOptions::default()
            };
            let (out, st) = run_shape(&m, opts, &span, LEAN);
            let nonzero = out.iter().filter(|s| s.gx != 0 || s.gy != 0).count();
            if cfg!(feature = "gradients") {
                assert!(nonzero > 90, "{mode:?}: {nonzero}");
                assert!(st.gradient_evaluations > 0);
            } else {
                assert_eq!(nonzero, 0, "{mode:?}");
                assert_eq!(st.gradient_evaluations, 0);
            }
        }
    }

    #[test]
    fn gradients_off_costs_nothing() {
        let m = marble();
        let span = feature_span([0.003, 0.0, 0.0], 100);
        let mut ev = SpanEvaluator::new(
            &m,
            EvalOptions {
                gradients: false,
                ..EvalOptions::default()
            },
        );
        ev.eval(&span, |s| assert_eq!((s.gx, s.gy), (0, 0)));
        assert_eq!(ev.stats().gradient_evaluations, 0);
        assert_eq!(ev.stats().noise_evaluations, 400);
    }

    /// `P(j)` from the coefficients `g` (wrapping).
    fn poly_at(g: &[i64], j: i64) -> i64 {
        g.iter()
            .rev()
            .fold(0i64, |acc, &c| acc.wrapping_mul(j).wrapping_add(c))
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
        /// The cell polynomials equal direct evaluation at `w = f + j d`: `P(j)` the
        /// interpolation, `h(j)` the derivative across (any steps, inside and past the cell).
        #[test]
        fn cubic_poly_equals_direct_evaluation(
            v in proptest::array::uniform8(-(1i32 << 20)..(1 << 20)),
            frac in proptest::array::uniform3(0u32..65536),
            du in proptest::array::uniform3(proptest::prelude::any::<i32>()),
            small in proptest::array::uniform3(-70_000i32..70_000),
            dy in proptest::array::uniform3(proptest::prelude::any::<i32>()),
            use_small: bool,
            grads: bool,
        ) {
            let du = if use_small { small } else { du };
            let a = cubic_poly(&v, frac, du, dy, grads);
            for j in [0i64, 1, 2, 3, 7, 100] {
                let w = [0, 1, 2].map(|k| i64::from(frac[k]) + j * i64::from(du[k]));
                proptest::prop_assert_eq!(
                    poly_at(&a.g, j),
                    crate::noise::value::interpolate(&v, w)
                );
                if grads && GRADIENTS {
                    proptest::prop_assert_eq!(
                        poly_at(&a.h, j),
                        crate::noise::value::directional(&v, w, dy.map(i64::from))
                    );
                }
            }
        }
    }
}
