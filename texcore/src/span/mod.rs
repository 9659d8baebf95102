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
//! Three cheaper, approximate modes trade accuracy for time: [`EvalMode::Fd32`] (32-bit
//! accumulators), [`EvalMode::Reanchored`] (piecewise cubic forward differencing of the
//! higher-degree bases) and [`EvalMode::Fused`] (gradient-noise rows interpolated with one
//! rounding); their error bounds are documented on the variants and priced in the
//! accuracy report.
//!
//! How much of this is compiled in follows the crate features: `fd` carries forward differencing
//! itself (without it every mode evaluates per pixel, the smallest code), `gradients` the
//! filter-width gradients, `fd32`, `reanchor` and `fused` carry the
//! three approximate modes, `turbulence-fd` the general loop's per-term forward differencing
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
//! - this module: the public types, the evaluator and its entry points (`EvalCore::eval_inner`,
//!   `EvalCore::eval_values`);
//! - `setup`: the per-span set-up (`EvalCore::setup`: per-term lattice start and steps, **the
//!   per-span band-limiting decision**, made there per term from `lattice_steps` and
//!   [`crate::bandlimit::term_band`], and the quadric along the span);
//! - `plan`: one strategy per term, decided once per span from the mode as compiled in;
//! - `chunk`: [`SampleChunk`], how samples are handed over;
//! - `merged`: the merged forward-difference loop (every forward-differenced term trilinear and
//!   not turbulent), its cell events and the segment loop;
//! - `general`: the general loop, one strategy per term;
//! - `passes`: the pixel kernels of the merged loop, short loops over registers specialised per
//!   segment (linear or cubic merged state, zero or affine or curved quadric, gradients on or
//!   off); **the per-sample gradient output** is written by `passes::grad_pass` (the merged
//!   path) and at the end of the general loop's pixel;
//! - `cubic`: the exact cell polynomial of a trilinear term and its forward-difference states
//!   (exact, 32-bit, Hermite segments);
//! - `axis`: the cell set-up of terms whose lattice step has one nonzero axis (a linear cell
//!   polynomial from two face blends, the shared face kept from the previous cell);
//! - `axial` (fast shape only): the kernel of spans whose terms are all single-axis trilinear
//!   terms, forward differenced (per-term countdowns to the cell events, coinciding events in one
//!   pass);
//! - `lanes` (fast shape only): the axial kernel without gradients, one term at a time over each
//!   chunk of samples (no merged state, no segment loop);
//! - `direct`: trilinear terms evaluated per pixel inside the merged loop (one cell set-up per
//!   cell, then the cell's monomial form, or the face blends of a single-axis term);
//! - `face_cache` (fast shape only): [`FaceCache`], face blends and the lane kernel's lanes
//!   kept across spans;
//! - `rows` (fast shape only; a row at a time otherwise): [`PlaneRows`], the rows of a plane
//!   with their cell schedule kept across rows (values, gradients, the smooth fade, gradient
//!   noise's corner gradients), and [`PlaneSpans`], the short spans of a plane served from the
//!   same schedule, each row's walk kept from span to span;
//! - `quad`: the quadric along the span;
//! - `plane`: [`SpanPlane`] and [`PlaneSetup`], the spans of one plane with their terms and
//!   quadric set up once.
//!
//! # Planes
//!
//! A caller filling a plane (a background, a framebuffer, an atlas) row after row should use
//! [`SpanEvaluator::rows`]: on an axis-aligned plane every row crosses the same cells at the
//! same pixels, and [`PlaneRows`] keeps that schedule and each cell's start and slope as
//! functions of the row, so a row costs one multiplication pair per cell it crosses and an
//! addition a pixel; any other plane is evaluated span by span, with the same values.
//!
//! A caller handing a plane over in short spans (tiles, a display driver's line buffer of 16
//! pixels) should set the plane's terms up once ([`SpanEvaluator::plane_setup`]) and evaluate
//! its spans through [`SpanEvaluator::eval_plane_values`], [`SpanEvaluator::eval_plane_chunks`]
//! or [`crate::texture::TextureEvaluator::shade_plane`]: each span's set-up is then a few
//! products a term instead of the terms' transforms and the band decision (the same values).
//! Handed over left to right through a [`FaceCache`], the spans of a row also go on from the
//! cells the span before ended in (`lanes`, "Carried lanes": the lane kernel's state kept in
//! the cache) instead of setting up every term's cell again.

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
mod chunk;
mod cubic;
mod direct;
mod face_cache;
mod general;
#[cfg(not(texcore_lean))]
mod lanes;
mod merged;
mod options;
mod passes;
mod plan;
mod plane;
mod quad;
mod rows;
mod setup;
mod stats;

pub use chunk::{SampleChunk, SAMPLE_CHUNK};
pub use face_cache::FaceCache;
pub(crate) use face_cache::Faces;
pub use options::{EvalMode, EvalOptions};
pub use plan::AUTO_FD_PIXELS;
pub(crate) use plan::GRADIENTS;
pub use plane::{PlaneSetup, SpanPlane, SpanPlaneError};
pub(crate) use rows::PlaneWalk;
pub use rows::{PlaneRows, PlaneSpans, RowCache};
pub(crate) use setup::{Setup, TermSetup};
pub use stats::{Sample, SpanInfo, SpanStats};

use axis::*;
use chunk::*;
use cubic::*;
use direct::*;
use passes::*;
use plan::*;
pub(crate) use plane::SetupFrom;
use quad::*;
use setup::*;

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
        self.rows_down(1)
    }

    /// The span one row up (`s0` less `dsdy`, wrapping): [`Span::next_row`] undone.
    pub(crate) fn prev_row(&self) -> Span {
        self.rows_down(-1)
    }

    /// The span `n` rows below (`s0` advanced by `n dsdy`, wrapping).
    #[inline(always)]
    fn rows_down(&self, n: i32) -> Span {
        let b = self.s0.to_bits();
        let d = self.dsdy.to_bits();
        let at = |k: usize| b[k].wrapping_add(d[k].wrapping_mul(n));
        Span {
            s0: TexPoint::from_bits(at(0), at(1), at(2)),
            ..*self
        }
    }
}

/// Shortest segment (pixels between two cell events) that the merged loop evaluates in component
/// passes; shorter ones take one fused per-pixel pass (each pass has a fixed start-up cost).
const PASS_MIN: u32 = 4;

/// Half a cell per pixel (raw 16.16): the Nyquist limit of a lattice noise.
pub const NYQUIST_STEP: i32 = 1 << 15;

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

impl TermRun {
    /// A run of `strategy` from lattice point `u` with `remaining` pixels before its first
    /// anchor, no cell cached and zero states: one literal, so that it is written straight into
    /// its slot.
    #[inline(always)]
    const fn start(strategy: Strategy, u: [i32; 3], remaining: u32) -> TermRun {
        TermRun {
            strategy,
            data: CellData::Value([0; 8]),
            cell: [0; 3],
            cached: false,
            remaining,
            u,
            #[cfg(texcore_fd_state)]
            fd: Cubic::ZERO,
            #[cfg(feature = "fd32")]
            fd32: Cubic32::ZERO,
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
    /// Tests only: spans the axial kernel evaluated (never in the size-lean shape, which has no
    /// axial kernel).
    #[cfg(test)]
    #[cfg_attr(texcore_lean, allow(dead_code))]
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
    #[inline(always)]
    pub fn eval_chunks(&mut self, span: &Span, out: &mut dyn FnMut(&SampleChunk)) -> SpanInfo {
        self.eval_chunks_from(span, SetupFrom::Span, out)
    }

    /// [`SpanEvaluator::eval_chunks`] with the set-up from `from`.
    #[inline(never)]
    pub(crate) fn eval_chunks_from(
        &mut self,
        span: &Span,
        from: SetupFrom<'_, '_, T>,
        out: &mut dyn FnMut(&SampleChunk),
    ) -> SpanInfo {
        let mut chunk = SampleChunk::new();
        let mut sink = ChunkSink {
            chunk: &mut chunk,
            out,
        };
        let info = self.core.eval_inner(span, from, &mut sink);
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
        self.values_through(span, out, &mut face_cache::Faces::none())
    }

    /// [`SpanEvaluator::eval_values`] with the face blends of single-axis trilinear terms kept
    /// in `cache` across calls ([`FaceCache`]): the same values, bit for bit; the rows of an
    /// axis-aligned plane after the first read the faces they share with the rows before
    /// instead of hashing and blending them again, and a span that goes on along the row of the
    /// span before it (the next pixels of the same row, through the same cache) starts from
    /// the cells that span ended in when the cache has a lane slot for each of its terms
    /// (`FaceCache<N, L>`, `L` slots). Spans the lane kernel does not take (and the size-lean
    /// code shape) do not use the cache. The counters count what was done: a span that goes
    /// on counts only the cells it enters.
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
    pub fn eval_values_cached<const N: usize, const L: usize>(
        &mut self,
        span: &Span,
        out: &mut [TexValue],
        cache: &mut FaceCache<N, L>,
    ) -> SpanInfo {
        self.values_through(span, out, &mut cache.parts())
    }

    /// [`SpanEvaluator::eval_values`] through the face cache entries `faces` (none: no cache).
    pub(crate) fn values_through(
        &mut self,
        span: &Span,
        out: &mut [TexValue],
        faces: &mut face_cache::Faces<'_>,
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
        let info = self
            .core
            .eval_values_from(&span, SetupFrom::Span, out, faces);
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
    #[inline(never)]
    fn eval_values_from(
        &mut self,
        span: &Span,
        from: SetupFrom<'_, '_, T>,
        out: &mut [TexValue],
        faces: &mut face_cache::Faces<'_>,
    ) -> SpanInfo {
        // Only the forward-differencing modes can take the lane kernel (fast shape only).
        #[cfg(not(texcore_lean))]
        if FD && !self.lean() && !self.multipass() {
            let mut setup = Setup::empty();
            let (info, strategies) = self.begin_planned(span, from, &mut setup);
            let Some(strategies) = strategies else {
                return info;
            };
            self.values_planned(span.len, &setup, &strategies, out, faces);
            return info;
        }
        let mut info = SpanInfo::default();
        copy_values(out, |sink| info = self.eval_inner(span, from, sink));
        info
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
        faces: &mut face_cache::Faces<'_>,
    ) {
        let merged = self.merged_takes(u32::from(len), setup, strategies);
        if merged && self.axial_takes(setup, strategies) {
            // Accumulators only for several lanes, no longer than the span needs (each array
            // is cleared only on its own branch).
            let lanes = strategies.iter().filter(|s| **s != Strategy::Off).count();
            // The accumulators from the face cache when it has them (no array cleared a span:
            // the first lane writes them before any is read; a span longer than them is
            // walked in runs as long), taken for the span and handed back after it.
            let cached = core::mem::take(&mut faces.acc);
            let mut go = |acc: &mut [i64]| {
                let mut values = lanes::LaneOut::Values(lanes::ValuesOut::new(out, acc));
                self.run_lanes::<true>(len, setup, strategies, &mut values, &mut *faces);
            };
            if lanes <= 1 {
                go(&mut []);
            } else if !cached.is_empty() {
                go(&mut *cached);
            } else if len <= SAMPLE_CHUNK as u16 {
                go(&mut [0i64; SAMPLE_CHUNK]);
            } else {
                go(&mut [0i64; lanes::VALUE_RUN]);
            }
            faces.acc = cached;
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
    fn begin(&mut self, span: &Span, from: SetupFrom<'_, '_, T>, setup: &mut Setup<T>) -> SpanInfo {
        self.setup_from(span, from, setup);
        self.stats.spans += 1;
        self.stats.pixels += u64::from(span.len);
        SpanInfo {
            extra_width48: setup.extra_width48,
        }
    }

    /// The evaluation proper.
    fn eval_inner(
        &mut self,
        span: &Span,
        from: SetupFrom<'_, '_, T>,
        sink: &mut ChunkSink<'_, '_>,
    ) -> SpanInfo {
        let mut setup = Setup::empty();
        let info = self.begin(span, from, &mut setup);
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

    pub(super) fn marble() -> TextureModel<8> {
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

    // The lists grow with the basis features.
    #[allow(clippy::single_element_loop)]
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
        let mut r = || (crate::test_rng::lcg64(&mut st) >> 32) as i32;
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
