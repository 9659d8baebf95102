//! The rows of a plane: [`PlaneRows`] evaluates row after row of a plane (each row a span, the
//! next one `dsdy` further), keeping each row's cell schedule and the cells' polynomials as
//! functions of the row across rows.
//!
//! On an axis-aligned plane (the lane kernel's spans, `lanes`: every term trilinear, forward
//! differenced, stepping along one lattice axis `k` along the row) whose rows step along at
//! most one other axis `m` and not along `k`, every row crosses the same cells along `k` at the
//! same pixels: the *schedule* (which term enters a new cell at which pixel) is the same for
//! every row. Inside a cell a term is linear, `v(j) = g0 + g1 j` (`axis::poly`), and the face
//! blends are `Phi = A + B f_m` in the ring of 64-bit integers, `f_m` the fraction along `m` (the
//! face cache's identity, `face_cache`), so `g0` and `g1` are `A + B f_m` too, with `A` and `B`
//! fixed while the term stays in the same cells along the two other axes. A row's samples are
//! then one merged value `V` and slope `S` (the sum of the terms' `v` and `g1`) stepped a pixel
//! at a time, and at each entry of the schedule `V` and `S` change by the entering cell's start
//! less the leaving cell's end, itself `A + B f_m` ([`RowEvent`]): two multiplications an event,
//! no hashing, no blending, no division. A term's `A` and `B` are made again only when the rows
//! reach its next cell along `m` (once every `1 / dsdy_m` rows).
//!
//! Value noise with the smooth fade and Perlin's gradient noise are not linear in a cell: their
//! entries hold what stays fixed across the rows (the smooth fade's `G` and `D`; gradient
//! noise's corners blended along the fixed axis with their gradient components, `fused`), and
//! their pixels are interpolated one by one, the fade along the row read from the cache's
//! weights when the row has one such term. Along the lattice's x axis a gradient-noise pixel
//! steps two exact sums and makes one product (`docs/model.md` 4.3, `fused`); along y or z it
//! steps its eight dot products and blends them (`gradient`).
//!
//! The spans of a plane handed over a few pixels at a time (a rasteriser's or a tiled fill's)
//! are served from the same schedule by [`PlaneSpans`] (`spans`): each row is set up once across
//! the plane, and its walk (`walk::RowWalk`) is kept from span to span.
//!
//! # Guarantees
//!
//! - **Exact**: every sample is the one [`SpanEvaluator::eval_values`] gives for the row's span,
//!   bit for bit (the same ring identities; the unit tests compare them row by row with the lane
//!   kernel and with `Direct`, on random planes, cache sizes and models), and so are the
//!   counters.
//! - Any plane and model is accepted: a row the schedule does not serve (a model or plane the
//!   lane kernel does not take, a rotated plane, a schedule longer than the cache, the size-lean
//!   code shape, a build without forward differencing) is evaluated by
//!   [`SpanEvaluator::eval_values`]. Each row is set up as a span of its own and checked against
//!   the schedule, so nothing about the plane is assumed.
//! - Capacity in the type: [`RowCache<N>`] holds `N` schedule entries of 56 bytes, given by the
//!   caller; no allocation, never panics.

#[cfg(not(texcore_lean))]
use super::face_cache::blend_ab;
use super::*;

#[cfg(all(feature = "gradient-noise", not(texcore_lean)))]
mod fused;
#[cfg(all(feature = "gradient-noise", not(texcore_lean)))]
mod gradient;
#[cfg(not(texcore_lean))]
mod schedule;
mod spans;
#[cfg(not(texcore_lean))]
mod walk;
#[cfg(not(texcore_lean))]
use schedule::*;
#[cfg(not(texcore_lean))]
use walk::*;

pub use spans::PlaneSpans;
pub(crate) use spans::PlaneWalk;

/// One entry of a row schedule: at pixel `at`, term `lane` enters a new cell, and the row's
/// value and slope change by `dv[0] + dv[1] f_m` and `ds[0] + ds[1] f_m` (`f_m` that term's
/// fraction along its row axis in the current row). The first entry of each term (at pixel 0)
/// is its first cell's start.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct RowEvent {
    at: u16,
    /// Pixels from `at` to the next entry (to the end of the row for the last).
    run: u16,
    lane: u16,
    dv: [i64; 2],
    ds: [i64; 2],
    /// The change of the derivative across the rows and of its slope (constants: with the rows
    /// stepping along `m` only, a face's derivative across them does not depend on `f_m`).
    dg: [i64; 2],
}

/// The schedule entries of [`PlaneRows`]: `N` entries of 56 bytes, given by the caller so that
/// a device keeps them where it wants (see the module documentation of `texcore::span::rows`).
///
/// Size it to the cells one row crosses, over all terms: a term of `c` cells across the row
/// needs `c + 1` entries (four octaves of 8, 16, 32 and 64 cells: 124). `W` fade weights keep
/// the fades along the row of a row of one smooth-fade term (`W` at least its pixels) or of the
/// terms of a row of gradient noise (`W` at least its pixels times its terms); with fewer the
/// fades are computed per pixel (the same values).
#[derive(Clone, Debug)]
pub struct RowCache<const N: usize, const W: usize = 0> {
    events: [RowEvent; N],
    weights: [u32; W],
}

impl<const N: usize, const W: usize> RowCache<N, W> {
    /// An empty cache.
    pub const fn new() -> Self {
        RowCache {
            events: [RowEvent {
                at: 0,
                run: 0,
                lane: 0,
                dv: [0; 2],
                ds: [0; 2],
                dg: [0; 2],
            }; N],
            weights: [0; W],
        }
    }

    /// Number of entries.
    pub const fn capacity(&self) -> usize {
        N
    }

    /// Number of pixel weights (a row of one smooth-fade term keeps its fades in them when it
    /// has at most `W` pixels; a row of gradient noise when its pixels times its terms are at
    /// most `W`).
    pub const fn weight_capacity(&self) -> usize {
        W
    }
}

impl<const N: usize, const W: usize> Default for RowCache<N, W> {
    fn default() -> Self {
        Self::new()
    }
}

/// One term of a row schedule: what the schedule and the term's `A`, `B` were made for.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(texcore_lean, allow(dead_code))]
struct RowLane {
    /// The term's index in the model.
    term: usize,
    /// The axis along the row, the row axis and the fixed axis.
    k: usize,
    m: usize,
    o: usize,
    /// The lattice step along the row and the coordinate along `k` at pixel 0.
    du: [i32; 3],
    u0k: i32,
    /// The lattice step to the next row (the derivative across the rows).
    dy: [i32; 3],
    /// The cells along `m` and `o`, the fraction along `o` and the amplitude the term's entries
    /// were made for (`made`: they are).
    cm: u16,
    co: u16,
    fo: u32,
    amp: i32,
    made: bool,
    /// The weight along `o`: `fo`, or its fade (smooth-fade value noise, gradient noise).
    wo: u32,
    /// The basis has the smooth fade (`3u^2 - 2u^3`): the cell is not linear in the pixel.
    smooth: bool,
    /// The basis is gradient noise (`gradient`): its entries are the cells' corner gradients,
    /// interpolated per pixel.
    grad: bool,
    /// The basis's fade (of the fades along the row that the weights keep, `row_fades`).
    fade: crate::noise::Fade,
    /// The term is forward differenced (`Fd`, `Fd32`; otherwise `Cached`): counted in
    /// `SpanStats::fd_pixels`.
    fd: bool,
}

/// The rows of a plane, evaluated one after the other with their schedule kept (see the module
/// documentation): made by [`SpanEvaluator::rows`].
///
/// A 64 x 64 field of four octaves of value noise:
///
/// ```
/// use texcore::format::{Amplitude, MatrixEntry, TexPoint, TexValue};
/// use texcore::hash::HashKind;
/// use texcore::model::{Octaves, TextureModel};
/// use texcore::noise::NoiseBasis;
/// use texcore::quadric::Quadric;
/// use texcore::span::{EvalMode, EvalOptions, RowCache, Span, SpanEvaluator};
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
/// let first = Span {
///     s0: TexPoint::from_f64(0.0, 0.0, 0.5),
///     ds: TexPoint::from_f64(1.0 / 8.0, 0.0, 0.0),
///     dsdy: TexPoint::from_f64(0.0, 1.0 / 8.0, 0.0),
///     len: 64,
/// };
/// let mut ev = SpanEvaluator::new(&model, opts);
/// let mut cache = RowCache::<64>::new();
/// let mut field = [[TexValue::ZERO; 64]; 64];
/// let mut rows = ev.rows(&first, &mut cache);
/// for row in field.iter_mut() {
///     rows.next_values(row);
/// }
/// // Row 5 is the span five rows down, as any evaluation of it gives.
/// let mut direct = SpanEvaluator::new(&model, EvalOptions { mode: EvalMode::Direct, ..opts });
/// let mut row = [TexValue::ZERO; 64];
/// let s0 = TexPoint::from_f64(0.0, 5.0 / 8.0, 0.5);
/// direct.eval_values(&Span { s0, ..first }, &mut row);
/// assert_eq!(row, field[5]);
/// # Ok::<(), texcore::model::ModelError>(())
/// ```
#[derive(Debug)]
pub struct PlaneRows<'e, 'm, 'c, const T: usize> {
    ev: &'e mut SpanEvaluator<'m, T>,
    events: &'c mut [RowEvent],
    weights: &'c mut [u32],
    state: RowsState<T>,
    span: Span,
}

/// The schedule's description: its entries in use, its length and terms.
#[derive(Debug)]
#[cfg_attr(texcore_lean, allow(dead_code))]
struct RowsState<const T: usize> {
    used: usize,
    len: u16,
    /// The entries have their derivative parts (`RowEvent::dg`).
    grads: bool,
    /// The weights in use (the fades of a row of one smooth-fade term, or of every term of a
    /// row of gradient noise; 0: none).
    weights: usize,
    lanes: heapless::Vec<RowLane, T>,
}

impl<'m, const T: usize> SpanEvaluator<'m, T> {
    /// The rows of a plane from `first` (each next row's span is the last one's with `s0`
    /// advanced by `dsdy`, wrapping), evaluated through `cache` (see [`PlaneRows`]): the same
    /// values as [`SpanEvaluator::eval_values`] of each row's span, bit for bit.
    pub fn rows<'e, 'c, const N: usize, const W: usize>(
        &'e mut self,
        first: &Span,
        cache: &'c mut RowCache<N, W>,
    ) -> PlaneRows<'e, 'm, 'c, T> {
        PlaneRows {
            ev: self,
            events: &mut cache.events,
            weights: &mut cache.weights,
            state: RowsState {
                used: 0,
                len: 0,
                grads: false,
                weights: 0,
                lanes: heapless::Vec::new(),
            },
            span: *first,
        }
    }
}

impl<const T: usize> PlaneRows<'_, '_, '_, T> {
    /// The span of the next row.
    pub fn span(&self) -> &Span {
        &self.span
    }

    /// The evaluator's counters so far.
    pub fn stats(&self) -> &SpanStats {
        self.ev.stats()
    }

    /// The span of the next row, and moves to the row after it.
    fn advance(&mut self) -> Span {
        let span = self.span;
        self.span = span.next_row();
        span
    }

    /// Evaluates the next row with its gradients when the evaluator's options ask for them (as
    /// [`SpanEvaluator::eval_chunks`]: the samples handed to `out` in chunks of at most
    /// [`SAMPLE_CHUNK`]) and moves to the row after it. Returns the row's facts.
    #[inline(never)]
    pub fn next_chunks(&mut self, out: &mut dyn FnMut(&SampleChunk)) -> SpanInfo {
        let span = self.advance();
        let mut chunk = SampleChunk::new();
        let mut sink = ChunkSink {
            chunk: &mut chunk,
            out,
        };
        let info = self
            .ev
            .core
            .eval_row_chunks(&span, &mut sink, &mut self.state, self.events);
        sink.finish();
        info
    }

    /// [`PlaneRows::next_chunks`] sample by sample: `emit` is called once per pixel in order.
    #[inline]
    pub fn next<F: FnMut(Sample)>(&mut self, mut emit: F) -> SpanInfo {
        self.next_chunks(&mut |chunk: &SampleChunk| {
            for s in chunk.iter() {
                emit(s);
            }
        })
    }

    /// Evaluates the next row into `out` (as [`SpanEvaluator::eval_values`]: its first
    /// `min(len, out.len())` values) and moves to the row after it. Returns the row's facts.
    pub fn next_values(&mut self, out: &mut [TexValue]) -> SpanInfo {
        let span = self.advance();
        let n = usize::from(span.len).min(out.len());
        let span = Span {
            len: n as u16,
            ..span
        };
        let Some(out) = out.get_mut(..n) else {
            return SpanInfo::default();
        };
        let core = &mut self.ev.core;
        let grads = core.opts.gradients;
        core.opts.gradients = false;
        let info = core.eval_row(&span, out, &mut self.state, self.events, self.weights);
        core.opts.gradients = grads;
        info
    }
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// Whether the rows of gradient noise are fused ([`EvalMode::Fused`], compiled in).
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn fused_rows(&self) -> bool {
        compiled_mode(self.opts.mode) == EvalMode::Fused
    }

    /// Whether the gradient-noise lanes `lanes` take `fused`'s stepped sums: in every mode when
    /// each runs along the lattice's x axis, where the sums' last product is the blend's of
    /// `docs/model.md` 4.3 (exact), and in [`EvalMode::Fused`]; otherwise `gradient`'s blends of
    /// stepped dot products.
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn fused_form(&self, lanes: &[RowLane]) -> bool {
        self.fused_rows() || lanes.iter().all(|l| !l.grad || l.k == 0)
    }

    /// A row of [`PlaneRows`] (gradients off, `out` exactly `span.len` long): through the
    /// schedule `state` / `events` where it serves the row, otherwise as
    /// [`SpanEvaluator::eval_values`].
    #[cfg_attr(texcore_lean, allow(unused_variables))]
    fn eval_row(
        &mut self,
        span: &Span,
        out: &mut [TexValue],
        state: &mut RowsState<T>,
        events: &mut [RowEvent],
        weights: &mut [u32],
    ) -> SpanInfo {
        #[cfg(not(texcore_lean))]
        if FD && !self.lean() && !self.multipass() {
            let mut setup = Setup::empty();
            let (info, strategies, served) =
                self.row_begin(span, SetupFrom::Span, &mut setup, state, events, true);
            let Some(strategies) = strategies else {
                return info;
            };
            if !served {
                self.values_planned(
                    span.len,
                    &setup,
                    &strategies,
                    out,
                    &mut super::face_cache::Faces::none(),
                );
                return info;
            }
            self.run_row(span.len, &setup, state, events, weights, out);
            return info;
        }
        #[cfg(texcore_lean)]
        let _ = weights;
        self.eval_values_from(
            span,
            SetupFrom::Span,
            out,
            &mut super::face_cache::Faces::none(),
        )
    }

    /// The set-up of the row `span` (from `from`) into `setup` (empty), its plan, and whether
    /// the schedule `state` / `events` serves it (`row_schedule`; `smooth` as there). A row it
    /// does not serve leaves no entries in use. Out of line: the rows of values and
    /// [`PlaneSpans`] share it.
    #[cfg(not(texcore_lean))]
    #[inline(never)]
    fn row_begin(
        &mut self,
        span: &Span,
        from: SetupFrom<'_, '_, T>,
        setup: &mut Setup<T>,
        state: &mut RowsState<T>,
        events: &mut [RowEvent],
        smooth: bool,
    ) -> (SpanInfo, Option<[Strategy; T]>, bool) {
        let (info, strategies) = self.begin_planned(span, from, setup);
        let served = match &strategies {
            Some(st) => self.row_schedule(span, setup, st, state, events, smooth),
            None => false,
        };
        if !served {
            state.used = 0;
        }
        (info, strategies, served)
    }

    /// A row of [`PlaneRows::next_chunks`]: through the schedule `state` / `events` where it
    /// serves the row, otherwise as [`SpanEvaluator::eval_chunks`].
    fn eval_row_chunks(
        &mut self,
        span: &Span,
        sink: &mut ChunkSink<'_, '_>,
        state: &mut RowsState<T>,
        events: &mut [RowEvent],
    ) -> SpanInfo {
        #[cfg(not(texcore_lean))]
        if FD && !self.lean() && !self.multipass() {
            let mut setup = Setup::empty();
            let (info, strategies) = self.begin_planned(span, SetupFrom::Span, &mut setup);
            sink.chunk.extra_width48 = info.extra_width48;
            let Some(strategies) = strategies else {
                return info;
            };
            if !self.row_schedule(span, &setup, &strategies, state, events, false) {
                state.used = 0;
                self.run(span.len, &setup, sink);
                return info;
            }
            self.run_row_chunks(span.len, &setup, state, events, sink);
            return info;
        }
        #[cfg(texcore_lean)]
        let _ = (state, events);
        self.eval_inner(span, SetupFrom::Span, sink)
    }

    /// Whether the row schedule can serve a span of `len` pixels set up as `setup` with
    /// `strategies`: every active term a non-turbulent value-noise term stepping along one
    /// lattice axis, forward differenced exactly (`Fd`, `Fd32` of a trilinear term: the merged
    /// loop's) or, with `smooth` and the smooth fade, cached (`Cached`: per pixel, exact); with a
    /// `clamp` table (or gradients) the quadric's sums in range (`merged_takes`'s `fits`).
    #[cfg(not(texcore_lean))]
    fn rows_take(
        &self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        smooth: bool,
    ) -> bool {
        let m = self.model;
        let mut any = false;
        let mut grad_terms = false;
        let mut grads_n = 0usize;
        // The gradient-noise terms' amplitudes (raw), summed.
        #[cfg(feature = "gradient-noise")]
        let mut amps = 0u64;
        for ((term, st), ts) in m.terms().iter().zip(strategies).zip(setup.terms.iter()) {
            let b = &term.basis;
            let taken = match st {
                Strategy::Off => continue,
                Strategy::Fd | Strategy::Fd32 => b.is_cubic(),
                Strategy::Cached => smooth && (is_smooth_value(b) || is_gradient_basis(b)),
                _ => false,
            };
            if !taken || term.turbulence || single_axis(ts.du).is_none() {
                return false;
            }
            // Gradient-noise terms are walked on their own (`gradient`): not mixed with others.
            if any && is_gradient_basis(b) != grad_terms {
                return false;
            }
            grad_terms = is_gradient_basis(b);
            grads_n += usize::from(grad_terms);
            #[cfg(feature = "gradient-noise")]
            if grad_terms {
                amps += u64::from(ts.amp.unsigned_abs());
            }
            any = true;
        }
        if grads_n > GRADIENT_TERMS {
            return false;
        }
        // Gradient-noise rows sum the terms' values unscaled (`gradient::small_amps`: what the
        // model's noise fraction bits keep).
        #[cfg(feature = "gradient-noise")]
        if grads_n > 0 && !gradient::small_amps(amps, m.noise_frac_bits()) {
            return false;
        }
        let grads = GRADIENTS && self.opts.gradients;
        let len = u32::from(len);
        any && (m.wrap() != TableWrap::Clamp || fits(&setup.quadric().quad.c, len))
            && (!grads || (fits(&setup.quadric().gqx, len) && fits(&setup.quadric().gqy, len)))
    }

    /// Makes `state` and `events` serve the row `span` (set up as `setup`, planned as
    /// `strategies`): keeps the schedule when the row's terms cross the same cells along their
    /// row axis at the same pixels, remakes it otherwise, and remakes the entries of each term
    /// whose cells along the two other axes (or fixed fraction, or amplitude) changed. `false`
    /// when the schedule cannot serve the row (a span the lane kernel does not take, a term whose
    /// rows step along its row axis or along both other axes, too many entries).
    #[cfg(not(texcore_lean))]
    #[allow(clippy::too_many_arguments)]
    fn row_schedule(
        &mut self,
        span: &Span,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        state: &mut RowsState<T>,
        events: &mut [RowEvent],
        smooth_ok: bool,
    ) -> bool {
        let len = span.len;
        let grads = GRADIENTS && self.opts.gradients;
        if !self.rows_take(len, setup, strategies, smooth_ok && !grads) {
            return false;
        }
        // The row's terms: the same terms, axes, steps and starts along the row as the
        // schedule's make the same schedule.
        let mut fresh: heapless::Vec<RowLane, T> = heapless::Vec::new();
        let model_terms = self.model.terms();
        for (i, (st, ts)) in strategies.iter().zip(setup.terms.iter()).enumerate() {
            if *st == Strategy::Off {
                continue;
            }
            let Some(k) = single_axis(ts.du) else {
                return false;
            };
            // Every term's gradient, or the general loop's.
            if grads && !ts.gradient {
                return false;
            }
            let k = k.min(2);
            let (a, c) = others(k);
            // The row axis: the other axis the rows step along (either when neither).
            let (m, o) = match (ts.dy[k] != 0, ts.dy[a] != 0, ts.dy[c] != 0) {
                (false, _, false) => (a, c),
                (false, false, true) => (c, a),
                _ => return false,
            };
            let basis = model_terms.get(i).map(|t| t.basis).unwrap_or_default();
            let lane = RowLane {
                term: i,
                k,
                m,
                o,
                du: ts.du,
                u0k: ts.u0[k],
                dy: ts.dy,
                cm: 0,
                co: 0,
                fo: 0,
                amp: 0,
                made: false,
                wo: 0,
                smooth: is_smooth_value(&basis),
                grad: is_gradient_basis(&basis),
                fade: basis.fade,
                fd: matches!(st, Strategy::Fd | Strategy::Fd32),
            };
            // At most T terms: never full.
            let _ = fresh.push(lane);
        }
        // Word by word (an array comparison is a library call on the devices).
        let eq3 = |a: [i32; 3], b: [i32; 3]| ((a[0] ^ b[0]) | (a[1] ^ b[1]) | (a[2] ^ b[2])) == 0;
        let same = state.used != 0
            && state.len == len
            && state.lanes.len() == fresh.len()
            && state.lanes.iter().zip(fresh.iter()).all(|(l, f)| {
                l.term == f.term && eq3(l.du, f.du) && eq3(l.dy, f.dy) && l.u0k == f.u0k
            });
        if !same {
            state.used = 0;
            state.lanes = fresh;
            let Some(used) = schedule(len, &state.lanes, events) else {
                return false;
            };
            state.used = used;
            state.len = len;
            state.grads = grads;
            state.weights = 0;
        }
        // Entries made without their derivative parts are made again for a row that needs them.
        if grads && !state.grads {
            for lane in state.lanes.iter_mut() {
                lane.made = false;
            }
            state.grads = true;
        }
        let grads = state.grads;
        // Each term's entries, for the cells of this row along the other axes.
        let m = self.model;
        let (fv, vb) = (m.noise_frac_bits(), m.precision().value_bits());
        let used = state.used;
        // Gradient-noise entries as `fused` or `gradient` takes them (`fused_form`).
        let fused = self.fused_form(&state.lanes);
        for (li, lane) in state.lanes.iter_mut().enumerate() {
            let (Some(ts), Some(term)) = (setup.terms.get(lane.term), m.terms().get(lane.term))
            else {
                return false;
            };
            let (cell, frac) = split(ts.u0);
            let (mi, oi) = (lane.m.min(2), lane.o.min(2)); // always 0..=2: no bounds checks
            let (cm, co, fo) = (cell[mi], cell[oi], frac[oi]);
            if lane.made && lane.cm == cm && lane.co == co && lane.fo == fo && lane.amp == ts.amp {
                continue;
            }
            (lane.cm, lane.co, lane.fo, lane.amp) = (cm, co, fo, ts.amp);
            // `fo` or its fade (the lanes' fades are the linear one, the smooth one of value
            // noise, or any of gradient noise).
            lane.wo = lane.fade.apply(fo) as u32;
            let events = events.get_mut(..used).unwrap_or_default();
            let hash = term.basis.hash;
            if lane.grad && fused {
                #[cfg(feature = "gradient-noise")]
                fused::fused_entries(li, lane, hash, events);
            } else if lane.grad {
                #[cfg(feature = "gradient-noise")]
                gradient::gradient_entries(li, lane, hash, events);
            } else {
                let cells = schedule::Cells {
                    li,
                    lane,
                    hash,
                    fv,
                    vb,
                    grads: GRADIENTS && grads,
                };
                if lane.smooth {
                    smooth_entries(cells, events);
                } else {
                    lane_entries(cells, events);
                }
            }
            lane.made = true;
        }
        true
    }

    /// The samples of a row that `state` / `events` serve (`row_schedule`), and its counters.
    #[cfg(not(texcore_lean))]
    fn run_row(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        state: &mut RowsState<T>,
        events: &[RowEvent],
        weights: &mut [u32],
        out: &mut [TexValue],
    ) {
        let (mut q, quad) = QuadStep::value_kind(setup);
        let events = events.get(..state.used).unwrap_or_default();
        #[cfg(feature = "gradient-noise")]
        if state.lanes.iter().any(|l| l.grad) {
            let form = (self.fused_form(&state.lanes), self.fused_rows());
            gradient::gradient_row(events, state, weights, setup, out, &mut q, form);
            self.count_row(len, state, false);
            return;
        }
        let fvs = self.model.noise_frac_bits() & 31;
        let mut w = RowWalk::new(QuadStep::new(setup));
        if row_weights(setup, state, w.weights_mut()) {
            // One smooth term: its fades along the row (the same in every row the schedule
            // serves) kept in the weights when they hold the row.
            let table = if state.lanes.len() == 1 {
                state.weights =
                    row_fades(&state.lanes, state.weights, weights, usize::from(len), 0);
                weights.get(..state.weights).filter(|w| !w.is_empty())
            } else {
                None
            };
            smooth_walk(events, &state.lanes, w.weights(), fvs, out, &mut q, table);
        } else {
            // An affine quadric is stepped as curved (it adds zeros: one code shape fewer).
            match quad {
                0 => walk_part::<true, true, T>(&mut w, events, fvs, out),
                _ => walk_part::<false, false, T>(&mut w, events, fvs, out),
            }
        }
        self.count_row(len, state, false);
    }

    /// The counters of a row that the schedule `state` served (`grads`: with its gradients), as
    /// the span path counts them: a cell set-up an entry, a sample a term a pixel, the pixels of
    /// forward-differenced terms.
    #[cfg(not(texcore_lean))]
    fn count_row(&mut self, len: u16, state: &RowsState<T>, grads: bool) {
        let px = u64::from(len);
        let lanes = state.lanes.len() as u64;
        let st = &mut self.stats;
        st.cell_setups += state.used as u64;
        st.noise_evaluations += px * lanes;
        if grads {
            st.gradient_evaluations += px * (1 + lanes);
        }
        if state.lanes.iter().any(|l| l.fd) {
            st.fd_pixels += px;
        }
        #[cfg(test)]
        {
            self.row_spans += 1;
        }
    }

    /// The samples of a row that `state` / `events` serve (`row_schedule`) into `sink`, with
    /// their gradients when the options ask for them (`row_schedule` made the entries' parts),
    /// and its counters.
    #[cfg(not(texcore_lean))]
    fn run_row_chunks(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        state: &RowsState<T>,
        events: &[RowEvent],
        sink: &mut ChunkSink<'_, '_>,
    ) {
        let grads = GRADIENTS && self.opts.gradients;
        let fvs = self.model.noise_frac_bits() & 31;
        let mut fm = [0i64; T];
        row_weights(setup, state, &mut fm);
        let mut quad = QuadStep::new(setup);
        let q = &quad;
        let noq = (q.q | q.dq | q.ddq | q.gx | q.dgx | q.gy | q.dgy) == 0;
        let events = events.get(..state.used).unwrap_or_default();
        let fm = &fm;
        let qs = &mut quad;
        // A quadric is stepped as curved (an affine one adds zeros: one code shape fewer).
        match (grads, noq) {
            (true, true) => row_chunks::<true, true, true, T>(events, fm, fvs, sink, qs),
            (true, false) => row_chunks::<true, false, false, T>(events, fm, fvs, sink, qs),
            (false, true) => row_chunks::<false, true, true, T>(events, fm, fvs, sink, qs),
            (false, false) => row_chunks::<false, false, false, T>(events, fm, fvs, sink, qs),
        }
        self.count_row(len, state, grads);
    }
}

#[cfg(test)]
mod tests {
    use std::vec::Vec;

    use super::*;
    use crate::format::{Amplitude, MatrixEntry, QuadricCoeff};
    use crate::model::Octaves;
    use crate::noise::NoiseBasis;
    use crate::quadric::Quadric;
    use crate::transform::Affine3;

    /// Whether [`model`]'s `basis` is one evaluated per pixel where it is compiled in (the
    /// smooth fade, gradient noise; trilinear value noise otherwise).
    pub(super) fn per_pixel_basis(basis: u8) -> bool {
        match basis {
            0 => false,
            1 => cfg!(feature = "smooth-fade"),
            _ => cfg!(feature = "gradient-noise"),
        }
    }

    /// A model of `octaves` unrotated trilinear octaves (zoom `2^zoom`) with quadric kind
    /// `quadric` (zero, affine, curved).
    pub(super) fn model(
        octaves: u8,
        zoom: u32,
        quadric: u32,
        clamp: bool,
        hash: HashKind,
        basis: u8,
    ) -> TextureModel<8> {
        let q = match quadric {
            0 => Quadric::ZERO,
            1 => Quadric::linear(
                QuadricCoeff::ONE,
                QuadricCoeff::ZERO,
                QuadricCoeff::from_num(0.5),
                QuadricCoeff::ZERO,
            ),
            _ => Quadric::from_f64([0.7, 0.1, 0.0, -0.2, 0.3, 0.0, 0.05, 1.1, 0.25, 0.4]).unwrap(),
        };
        let wrap = if clamp {
            TableWrap::Clamp
        } else {
            TableWrap::Mod
        };
        let mut m: TextureModel<8> = TextureModel::new(q, wrap);
        m.push_octaves(&Octaves {
            count: octaves,
            base: Affine3::scale(MatrixEntry::from_num(1u32 << zoom)),
            amplitude: Amplitude::from_num(0.6),
            rotate: false,
            basis: match basis {
                0 => NoiseBasis::trilinear(hash),
                1 => smooth_basis(hash),
                b => gradient_basis(hash, b == 2),
            },
            turbulence: false,
        })
        .unwrap();
        m
    }

    /// Value noise with the smooth fade (trilinear without the feature).
    fn smooth_basis(hash: HashKind) -> NoiseBasis {
        #[cfg(feature = "smooth-fade")]
        return NoiseBasis {
            kind: crate::noise::BasisKind::Value,
            fade: crate::noise::Fade::Smooth,
            hash,
        };
        #[cfg(not(feature = "smooth-fade"))]
        NoiseBasis::trilinear(hash)
    }

    /// Gradient noise, with the quintic fade (`quintic`, when compiled in) or the linear one
    /// (trilinear value noise without the feature).
    fn gradient_basis(hash: HashKind, quintic: bool) -> NoiseBasis {
        #[cfg(feature = "gradient-noise")]
        {
            #[cfg(feature = "smooth-fade")]
            let fade = if quintic {
                crate::noise::Fade::Quintic
            } else {
                crate::noise::Fade::Linear
            };
            #[cfg(not(feature = "smooth-fade"))]
            let fade = {
                let _ = quintic;
                crate::noise::Fade::Linear
            };
            NoiseBasis {
                kind: crate::noise::BasisKind::Gradient,
                fade,
                hash,
            }
        }
        #[cfg(not(feature = "gradient-noise"))]
        {
            let _ = quintic;
            NoiseBasis::trilinear(hash)
        }
    }

    /// Row `y` of the plane `first` (`s0 + y dsdy`, wrapping).
    fn row(first: &Span, y: i32) -> Span {
        let b = first.s0.to_bits();
        let d = first.dsdy.to_bits();
        Span {
            s0: TexPoint::from_bits(
                b[0].wrapping_add(d[0].wrapping_mul(y)),
                b[1].wrapping_add(d[1].wrapping_mul(y)),
                b[2].wrapping_add(d[2].wrapping_mul(y)),
            ),
            ..*first
        }
    }

    /// `rows` rows of `first` through a [`RowCache<N>`] and through `eval_values` (and `Direct`
    /// every third row), compared row by row, and the counters; then the samples through
    /// [`PlaneRows::next`] and [`SpanEvaluator::eval`] (a values row every fourth); returns the
    /// rows the schedule served in each pass.
    fn compare<const N: usize, const W: usize>(
        m: &TextureModel<8>,
        opts: EvalOptions,
        first: &Span,
        rows: i32,
        out_len: usize,
    ) -> Result<(u64, u64), proptest::test_runner::TestCaseError> {
        let mut cache = RowCache::<N, W>::new();
        let mut ev = SpanEvaluator::new(m, opts);
        let mut plain = SpanEvaluator::new(m, opts);
        let mut direct = SpanEvaluator::new(
            m,
            EvalOptions {
                mode: EvalMode::Direct,
                ..opts
            },
        );
        let marker = TexValue::from_bits(0x5A5A_5A5A);
        let n = usize::from(first.len).min(out_len);
        let mut pr = ev.rows(first, &mut cache);
        for y in 0..rows {
            let sp = row(first, y);
            proptest::prop_assert_eq!(pr.span(), &sp);
            let mut got = std::vec![marker; out_len + 2];
            let info = pr.next_values(&mut got[..out_len]);
            let mut want = std::vec![marker; out_len + 2];
            let want_info = plain.eval_values(&sp, &mut want[..out_len]);
            proptest::prop_assert_eq!(&got, &want, "row {}", y);
            proptest::prop_assert_eq!(info, want_info);
            proptest::prop_assert_eq!(&got[n..], &std::vec![marker; out_len + 2 - n][..]);
            if y % 3 == 0 {
                let mut d = std::vec![marker; out_len + 2];
                direct.eval_values(&sp, &mut d[..out_len]);
                proptest::prop_assert_eq!(&got, &d, "row {} against Direct", y);
            }
            proptest::prop_assert_eq!(pr.stats(), plain.stats(), "row {}", y);
        }
        drop(pr);
        proptest::prop_assert_eq!(ev.options(), opts, "the options are restored");
        // The samples, gradients included when asked for, through `next` and `eval`.
        let mut cache = RowCache::<N, W>::new();
        let mut ev2 = SpanEvaluator::new(m, opts);
        let mut plain = SpanEvaluator::new(m, opts);
        let mut pr = ev2.rows(first, &mut cache);
        let mut y = 0;
        while y < rows {
            let sp = row(first, y);
            proptest::prop_assert_eq!(pr.span(), &sp);
            let mut got = Vec::new();
            let info = pr.next(|s| got.push(s));
            let mut want = Vec::new();
            let want_info = plain.eval(&sp, |s| want.push(s));
            proptest::prop_assert_eq!(&got, &want, "samples, row {}", y);
            proptest::prop_assert_eq!(info, want_info);
            proptest::prop_assert_eq!(pr.stats(), plain.stats(), "row {}", y);
            y += 1;
            if y % 4 == 2 {
                // A values row in between (the entries are kept or made again as needed).
                let mut a = std::vec![TexValue::ZERO; usize::from(first.len)];
                let mut b = a.clone();
                pr.next_values(&mut a);
                plain.eval_values(&row(first, y), &mut b);
                proptest::prop_assert_eq!(a, b, "values row {}", y);
                y += 1;
            }
        }
        Ok((ev.core.row_spans, ev2.core.row_spans))
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(96))]
        /// The rows of a plane through the schedule are `eval_values`' and `Direct`'s, with the
        /// same counters, for any start, step along any axis (short and long cells), row step
        /// (along another axis, none, along the row's own axis or along two axes: the last two
        /// never served by the schedule), length, output length, quadric, `mod` and `clamp`,
        /// mode, gradients asked for or not, octaves, zoom, the linear and the smooth fade,
        /// gradient noise with the linear and the quintic fade; and
        /// the schedule serves every row of an axis-aligned plane of resolved cells when the
        /// cache holds it (with gradients, every row of linear-fade terms whose gradients are
        /// all needed).
        #[test]
        fn rows_are_eval_values(
            s0 in proptest::array::uniform3(-4_000_000i32..4_000_000),
            step in -90_000i32..90_000,
            axis in 0usize..3,
            across in 0usize..4,
            dyv in -30_000i32..30_000,
            len in 0u16..300,
            short in 0usize..3,
            clamp: bool,
            quadric in 0u32..3,
            gradients: bool,
            octaves in 1u8..6,
            zoom in 0u32..3,
            mode in 0usize..3,
            hash: bool,
            basis in 0u8..4,
        ) {
            let hash = if hash { HashKind::Integer } else { HashKind::default() };
            let m = model(octaves, zoom, quadric, clamp, hash, basis);
            // Bases other than trilinear value noise: their rows' gradients are the span path's.
            let per_pixel = per_pixel_basis(basis);
            let mut ds = [0; 3];
            ds[axis] = (step >> (2 * zoom)) | 1;
            let mut dy = [0; 3];
            match across {
                // None, another axis, the row's own axis, two axes.
                0 => {}
                1 => dy[(axis + 1) % 3] = dyv,
                2 => dy[axis] = dyv | 1,
                _ => {
                    dy[(axis + 1) % 3] = dyv | 1;
                    dy[(axis + 2) % 3] = 77;
                }
            }
            let first = Span {
                s0: TexPoint::from_bits(s0[0], s0[1], s0[2]),
                ds: TexPoint::from_bits(ds[0], ds[1], ds[2]),
                dsdy: TexPoint::from_bits(dy[0], dy[1], dy[2]),
                len,
            };
            let mode = [EvalMode::Fd, EvalMode::Auto, EvalMode::Direct][mode];
            let opts = EvalOptions { mode, gradients, cull: true, ..Default::default() };
            let out_len = match short {
                0 => usize::from(len),
                1 => usize::from(len) / 2,
                _ => usize::from(len) + 5,
            };
            let served = compare::<256, 300>(&m, opts, &first, 10, out_len)?;
            let small = compare::<3, 0>(&m, opts, &first, 4, out_len)?;
            // Fewer weights than pixels: the fades computed as the row goes.
            compare::<256, 40>(&m, opts, &first, 3, out_len)?;
            // The schedule serves an axis-aligned plane of resolved cells (`Fd`) that the lane
            // kernel takes, whatever the octaves (at most 5 x ~150 entries of 256 here would
            // not always fit: only when it does).
            let resolved = (ds[axis] << zoom).unsigned_abs() < NYQUIST_STEP as u32;
            let n = usize::from(len).min(out_len);
            let cells: u64 = (0..octaves)
                .map(|i| 2 + ((n as u64 * u64::from(ds[axis].unsigned_abs())) << (zoom + u32::from(i))) / 65536)
                .sum();
            // With gradients every term's gradient is needed: its steps within half a cell.
            let top = zoom + u32::from(octaves) - 1;
            let reach = |d: i32| (i64::from(d).abs() << top) <= i64::from(NYQUIST_STEP);
            let gradients_served = !(GRADIENTS && gradients) || (reach(ds[axis]) && reach(dyv));
            // The size-lean shape has no schedule.
            let fast = FD && !cfg!(texcore_lean);
            if fast && mode == EvalMode::Fd && n > 0 && across < 2 && !clamp && resolved && cells <= 256 {
                proptest::prop_assert_eq!(served.0, 10);
                if gradients_served && n == usize::from(len) && !per_pixel {
                    proptest::prop_assert!(served.1 >= 10, "{:?}", served);
                }
            }
            if across >= 2 {
                proptest::prop_assert_eq!(served, (0, 0));
                proptest::prop_assert_eq!(small, (0, 0));
            }
        }
    }

    /// A hard plane: `(s0, ds, dsdy, len)`, raw.
    type Case = ([i32; 3], [i32; 3], [i32; 3], u16);

    /// Hard planes: coordinates at the ends of the 16.16 range whose rows and spans wrap, a
    /// 4000-pixel span (thousands of entries), steps of a whole cell a pixel and of one raw
    /// unit, negative steps, along every axis.
    const EXTREME: [Case; 5] = [
        (
            [i32::MAX - 9_000, i32::MIN + 5, -7],
            [4099, 0, 0],
            [0, 30_000, 0],
            4000,
        ),
        (
            [i32::MIN + 1, 123, i32::MAX - 77],
            [0, 0, -65_536],
            [70_000, 0, 0],
            300,
        ),
        ([5, -5, 0], [1, 0, 0], [0, 0, 1], 2000),
        (
            [-1_000_000, 2_000_000, -3],
            [0, -32_768, 0],
            [0, 0, -1],
            1000,
        ),
        (
            [i32::MAX, i32::MAX, i32::MAX],
            [65_535, 0, 0],
            [0, i32::MIN, 0],
            64,
        ),
    ];

    /// The first row's span of a hard plane.
    fn case_span(&(s0, ds, dy, len): &Case) -> Span {
        Span {
            s0: TexPoint::from_bits(s0[0], s0[1], s0[2]),
            ds: TexPoint::from_bits(ds[0], ds[1], ds[2]),
            dsdy: TexPoint::from_bits(dy[0], dy[1], dy[2]),
            len,
        }
    }

    /// Hard cases ([`EXTREME`]): every row the span path's, through caches large and too small.
    #[test]
    fn extreme_planes_are_exact() {
        for (octaves, basis) in [(1, 0), (4, 0), (1, 1), (3, 1), (1, 2), (3, 2), (2, 3)] {
            let m = model(octaves, 0, 1, false, HashKind::Integer, basis);
            for gradients in [false, true] {
                let opts = EvalOptions {
                    mode: EvalMode::Fd,
                    gradients,
                    cull: true,
                    ..Default::default()
                };
                for case in &EXTREME {
                    let first = case_span(case);
                    let n = usize::from(first.len);
                    compare::<4096, 4096>(&m, opts, &first, 5, n).unwrap();
                    compare::<16, 0>(&m, opts, &first, 3, n).unwrap();
                }
            }
        }
    }

    /// A row of more gradient-noise terms than the schedule serves (`GRADIENT_TERMS`) is
    /// evaluated span by span, and a row of as many through the schedule: both `Direct`'s.
    #[test]
    #[cfg(all(feature = "gradient-noise", not(texcore_lean)))]
    fn gradient_rows_up_to_their_term_limit() {
        for (count, served) in [(GRADIENT_TERMS, true), (GRADIENT_TERMS + 1, false)] {
            let mut m: TextureModel<16> = TextureModel::new(Quadric::ZERO, TableWrap::Mod);
            m.push_octaves(&Octaves {
                count: count as u8,
                base: Affine3::scale(MatrixEntry::from_num(1)),
                amplitude: Amplitude::from_num(0.5),
                rotate: false,
                basis: gradient_basis(HashKind::Integer, true),
                turbulence: false,
            })
            .unwrap();
            let opts = EvalOptions {
                mode: EvalMode::Fd,
                gradients: false,
                cull: false,
                ..Default::default()
            };
            let first = Span {
                s0: TexPoint::from_bits(-70_000, 12_345, 99_999),
                ds: TexPoint::from_bits(3_000, 0, 0),
                dsdy: TexPoint::from_bits(0, 0, 2_500),
                len: 40,
            };
            let spans = rows_against_direct::<16, 512, 512>(&m, opts, &first, 6, "gradient");
            assert_eq!(spans, if served { 6 } else { 0 }, "{count} terms");
        }
    }

    #[test]
    fn peers_plane_rows_take_the_schedule() {
        use crate::texture::workload::peers;
        for w in [
            peers::Workload::Value1,
            peers::Workload::Value4,
            peers::Workload::Smooth1,
            peers::Workload::Perlin1,
            peers::Workload::Perlin4,
        ] {
            let Some(m) = peers::model(w, HashKind::Integer) else {
                continue;
            };
            let opts = EvalOptions {
                mode: EvalMode::Fd,
                gradients: false,
                cull: true,
                ..Default::default()
            };
            let first = peers::span(0, 0, peers::SIZE);
            let spans = rows_against_direct::<8, 128, 0>(&m, opts, &first, 70, "peers");
            let fast = FD && !cfg!(texcore_lean);
            assert_eq!(spans, if fast { 70 } else { 0 }, "{w:?}");
        }
    }

    /// `rows` rows of `first` in `EvalMode::Fused` through a [`RowCache<N, W>`], each sample
    /// within `ceil(2 sum |a_i| / 2^16)` plus one per term (raw) of `Direct`'s (the mode's bound,
    /// `a_i` the terms' raw amplitudes); returns the rows the schedule served and the samples that differ
    /// from `Direct`'s.
    #[cfg(feature = "fused")]
    fn fused_against_direct<const T: usize, const N: usize, const W: usize>(
        m: &TextureModel<T>,
        gradients: bool,
        first: &Span,
        rows: i32,
        out_len: usize,
    ) -> Result<(u64, usize), proptest::test_runner::TestCaseError> {
        let opts = EvalOptions {
            mode: EvalMode::Fused,
            gradients,
            cull: true,
            ..Default::default()
        };
        let amps: i64 = m
            .terms()
            .iter()
            .map(|t| i64::from(t.amplitude.to_bits()).abs())
            .sum();
        let bound = (2 * amps + 65_535) / 65_536 + m.terms().len() as i64;
        let mut cache = RowCache::<N, W>::new();
        let mut ev = SpanEvaluator::new(m, opts);
        let direct_opts = EvalOptions {
            mode: EvalMode::Direct,
            ..opts
        };
        let mut direct = SpanEvaluator::new(m, direct_opts);
        let mut differ = 0;
        let mut pr = ev.rows(first, &mut cache);
        for y in 0..rows {
            let mut got = std::vec![TexValue::ZERO; out_len];
            let mut want = got.clone();
            pr.next_values(&mut got);
            direct.eval_values(&row(first, y), &mut want);
            for (x, (g, w)) in got.iter().zip(&want).enumerate() {
                let e = (i64::from(g.to_bits()) - i64::from(w.to_bits())).abs();
                proptest::prop_assert!(e <= bound, "row {} pixel {}: {:?} {:?}", y, x, g, w);
                differ += usize::from(e != 0);
            }
        }
        drop(pr);
        Ok((ev.core.row_spans, differ))
    }

    #[cfg(feature = "fused")]
    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(96))]
        /// `EvalMode::Fused` rows are within the mode's bound of `Direct` for any start, step
        /// along any axis, row step, length, quadric, octaves, zoom, fade, cache (weights holding
        /// the fades or not); value-noise rows are `Fd`'s exactly; an axis-aligned plane of one
        /// or more octaves is served by the schedule.
        #[test]
        fn fused_rows_are_within_their_bound(
            s0 in proptest::array::uniform3(-4_000_000i32..4_000_000),
            step in -90_000i32..90_000,
            axis in 0usize..3,
            across: bool,
            dyv in -30_000i32..30_000,
            len in 0u16..300,
            quadric in 0u32..3,
            octaves in 1u8..6,
            zoom in 0u32..3,
            basis in 0u8..4,
        ) {
            let m = model(octaves, zoom, quadric, false, HashKind::Integer, basis);
            let mut ds = [0; 3];
            ds[axis] = (step >> (2 * zoom)) | 1;
            let mut dy = [0; 3];
            if across {
                dy[(axis + 1) % 3] = dyv;
            }
            let first = Span {
                s0: TexPoint::from_bits(s0[0], s0[1], s0[2]),
                ds: TexPoint::from_bits(ds[0], ds[1], ds[2]),
                dsdy: TexPoint::from_bits(dy[0], dy[1], dy[2]),
                len,
            };
            let n = usize::from(len);
            let (served, differ) = fused_against_direct::<8, 512, 2048>(&m, false, &first, 6, n)?;
            fused_against_direct::<8, 512, 0>(&m, false, &first, 3, n)?;
            fused_against_direct::<8, 512, 0>(&m, true, &first, 3, n)?;
            if basis < 2 {
                // Not gradient noise: `Fd`'s samples.
                proptest::prop_assert_eq!(differ, 0);
            }
            let resolved = (ds[axis] << zoom).unsigned_abs() < NYQUIST_STEP as u32;
            let cells: u64 = (0..octaves)
                .map(|i| 2 + ((n as u64 * u64::from(ds[axis].unsigned_abs())) << (zoom + u32::from(i))) / 65536)
                .sum();
            if n > 0 && resolved && cells <= 512 && !cfg!(texcore_lean) {
                proptest::prop_assert_eq!(served, 6);
            }
        }
    }

    /// The fused rows of the peers' Perlin planes and of the extreme planes: within the bound and
    /// served by the schedule. On the peers' planes (rows along x) one octave is `Direct`'s
    /// exactly, and four octaves are not everywhere (their floored products added term after
    /// term: the approximate path ran).
    #[test]
    #[cfg(all(feature = "fused", not(texcore_lean)))]
    fn fused_rows_of_hard_planes() {
        use crate::texture::workload::peers;
        for w in [peers::Workload::Perlin1, peers::Workload::Perlin4] {
            let m = peers::model(w, HashKind::Integer).unwrap();
            let first = peers::span(0, 0, peers::SIZE);
            let n = usize::from(peers::SIZE);
            let (served, differ) =
                fused_against_direct::<8, 128, 1024>(&m, false, &first, 40, n).unwrap();
            assert_eq!(served, 40, "{w:?}");
            if w == peers::Workload::Perlin1 {
                assert_eq!(differ, 0);
            } else {
                assert!(differ > 0, "{w:?}");
            }
        }
        // The hard planes (`EXTREME`).
        for (octaves, basis) in [(1, 2), (3, 2), (1, 3), (5, 3)] {
            let m = model(octaves, 0, 1, false, HashKind::Integer, basis);
            for (i, case) in EXTREME.iter().enumerate() {
                let first = case_span(case);
                let n = usize::from(first.len);
                let (served, _) =
                    fused_against_direct::<8, 4096, 8192>(&m, false, &first, 4, n).unwrap();
                // Five octaves of the long rows need more entries than the cache holds.
                assert!(
                    served == 4 || (octaves == 5 && i != 2 && i != 4),
                    "{case:?}"
                );
                fused_against_direct::<8, 16, 0>(&m, false, &first, 2, n).unwrap();
            }
        }
    }

    /// `rows` rows of `first` through a [`RowCache<N, W>`], each against `Direct`'s evaluation of
    /// its span; returns the rows the schedule served.
    fn rows_against_direct<const T: usize, const N: usize, const W: usize>(
        m: &TextureModel<T>,
        opts: EvalOptions,
        first: &Span,
        rows: i32,
        what: &str,
    ) -> u64 {
        let mut cache = RowCache::<N, W>::new();
        let mut ev = SpanEvaluator::new(m, opts);
        let direct_opts = EvalOptions {
            mode: EvalMode::Direct,
            ..opts
        };
        let mut direct = SpanEvaluator::new(m, direct_opts);
        let n = usize::from(first.len);
        let mut pr = ev.rows(first, &mut cache);
        for y in 0..rows {
            let mut got = std::vec![TexValue::ZERO; n];
            let mut want = got.clone();
            pr.next_values(&mut got);
            direct.eval_values(&row(first, y), &mut want);
            assert_eq!(got, want, "{what} row {y}");
        }
        drop(pr);
        ev.core.row_spans
    }

    #[test]
    #[cfg(not(texcore_lean))]
    fn face_ab_is_the_blend() {
        let mut rng = crate::test_rng::XorShift64::new(0x9E37_79B9_7F4A_7C15);
        let mut next = || rng.next_u64();
        for _ in 0..3000 {
            let k = (next() % 3) as usize;
            let (a, c) = others(k);
            let (m, o) = if next() & 1 == 0 { (a, c) } else { (c, a) };
            let fo = (next() & 0xFFFF) as u32;
            let fm = (next() & 0xFFFF) as u32;
            let lane = RowLane {
                term: 0,
                k,
                m,
                o,
                du: [0; 3],
                u0k: 0,
                dy: {
                    let mut dy = [0; 3];
                    dy[m] = (next() as i32) >> 15;
                    dy
                },
                cm: 0,
                co: 0,
                fo,
                amp: (next() as i32) >> 14,
                made: true,
                wo: fo,
                smooth: false,
                grad: false,
                fade: crate::noise::Fade::Linear,
                fd: true,
            };
            let cell = [next() as u16, next() as u16, next() as u16];
            let hash = if next() & 1 == 0 {
                HashKind::Integer
            } else {
                HashKind::default()
            };
            let b = (next() & 1) as usize;
            let [fa_, fb_, h] = face_ab(&lane, hash, cell, b, 8, 16, true);
            let w = face_bits(k, hash, cell, b, lane.amp, 8, 16);
            let mut frac = [0u32; 3];
            frac[o] = fo;
            frac[m] = fm;
            frac[k] = (next() & 0xFFFF) as u32;
            let want = face(&w, k, frac, lane.dy, true);
            assert_eq!(
                wadd(fa_, wmul(fb_, i64::from(fm))),
                want.phi(),
                "k {k} m {m}"
            );
            if GRADIENTS {
                assert_eq!(h, want.h(), "k {k} m {m}");
            }
        }
    }

    #[test]
    #[cfg(all(feature = "smooth-fade", not(texcore_lean)))]
    fn smooth_fade_is_the_fade() {
        for a in 0..=0xFFFFu32 {
            let want = crate::noise::Fade::Smooth.apply(a);
            assert_eq!(smooth_fade(a), want, "{a}");
            assert_eq!(smooth_fade(a | 0x7_0000), want, "{a}");
            assert_eq!(weight(true, a), want as u32);
        }
    }

    #[test]
    fn cache_capacity() {
        assert_eq!(RowCache::<7>::new().capacity(), 7);
        assert_eq!(RowCache::<7, 9>::new().weight_capacity(), 9);
        assert_eq!(RowCache::<0>::default().capacity(), 0);
        assert_eq!(core::mem::size_of::<RowEvent>(), 56);
    }
}
