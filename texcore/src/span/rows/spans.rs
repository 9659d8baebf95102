//! A plane's rows handed over a span at a time: [`PlaneSpans`].
//!
//! A rasteriser or a tiled fill draws a plane in short spans (16 pixels, a tile's width), left
//! to right along each row. Evaluated on its own, every such span sets its terms up and enters
//! its cells again; [`PlaneRows`] serves whole rows from a cell schedule kept across rows, at a
//! few additions a pixel and two products a cell event. [`PlaneSpans`] serves the spans of a
//! [`PlaneSetup`]'s plane from the same schedule: each row `y` is set up once as the span
//! `(0, y)` across the plane's whole width, and its walk (the merged value, slope and derivative
//! across the rows, the schedule entry, the quadric's differences) is kept between the spans. A span that starts
//! where the last one of its row ended goes on from there; one further along the row moves the
//! walk on (a product per entry passed, no pixel written); any other span starts its row again.
//!
//! The set-up of span `(x, y)` is that of span `(0, y)` moved on by `x` pixels exactly when each
//! term's step along a span has no bits below the lattice's raw 16.16 units (`M ds`: the plane's
//! set-up keeps it with 32 fraction bits; [`PlaneSetup`]'s `whole_steps`): the rounded start of
//! `(x, y)` is then the rounded start of `(0, y)` plus `x` rounded steps, modulo 2^32, and the
//! quadric's polynomial along the row is the span's, shifted, as an identity of integers. Planes
//! of such steps (power-of-two octaves of a step that is a whole number of raw units, as every
//! axis-aligned fill of the peers' workloads) are walked; any other plane, model or span is
//! evaluated span by span.
//!
//! # Guarantees
//!
//! - **Exact**: every span's values and facts are those of
//!   [`SpanEvaluator::eval_plane_values`] of the same span, its samples (gradients included)
//!   those of [`SpanEvaluator::eval_plane_chunks`], and its colours through
//!   [`TextureEvaluator::plane_spans`](crate::texture::TextureEvaluator::plane_spans) those of
//!   `shade_plane`, bit for bit, in every mode, for any order of spans (the unit tests compare
//!   them, and with `Direct`, on random planes, models, cuts of the rows into pieces, gaps and
//!   spans out of order).
//! - **Counters**: a walked span counts its span, pixels, band-limited terms and samples as the
//!   span evaluated on its own (with gradients, its gradient samples too); its cell set-ups are
//!   the cells it enters, as through a [`FaceCache`] whose lanes are carried from span to span:
//!   a span that goes on from the last one counts the cell events at its pixels, any other span
//!   one cell a term plus the events after its first pixel (a row cut into contiguous spans
//!   sets up exactly the cells of the whole row). "Goes on" is the carried lanes' own test:
//!   every term's lattice point at the span's first pixel is where the last walked span left
//!   it, so a span on another row that starts there (rows of the same points, no step across
//!   them) is counted as going on too, a cell for each term whose first pixel leaves the cell
//!   of the pixel before. The row's plan decides the terms' strategies, so in [`EvalMode::Auto`] a
//!   walked span counts the row's forward-differenced pixels.
//! - Nothing is assumed about the spans: a span outside the plane's rectangle is not evaluated
//!   (the default facts are returned, as `eval_plane_values` does), and a row the schedule does
//!   not serve (a model the row schedule does not take, a schedule longer than the cache, the
//!   size-lean code shape) has its spans evaluated one by one.
//! - Capacity in the type: the entries are the caller's [`RowCache<N>`]; no allocation, never
//!   panics.

use super::*;

/// The row being walked and where its walk stands.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(texcore_lean, allow(dead_code))]
struct Cursor<const T: usize> {
    /// The row set up last (`None`: none yet).
    row: Option<u16>,
    /// The schedule serves that row (otherwise its spans are evaluated one by one).
    served: bool,
    /// The row was set up for samples with their gradients (the entries' derivative parts).
    grads: bool,
    /// The next pixel of the row.
    x: u16,
    /// The quadric's kind (`QuadStep::value_kind`: 0 zero, 1 affine, 2 curved).
    kind: u8,
    /// The served row's lanes' terms (bit `t` for term `t`) and each one's lattice point at the
    /// row's pixel 0 and amplitude (`[u0, amp]`): where a face cache's carried lanes stand after
    /// a span of the row, for the counters.
    #[cfg(not(texcore_lean))]
    terms: u32,
    #[cfg(not(texcore_lean))]
    starts: [[i32; 4]; T],
    /// The walk at pixel `x` (fast shape only).
    #[cfg(not(texcore_lean))]
    walk: RowWalk<T>,
}

/// The state of a plane's spans walked from its rows' schedule, apart from the evaluator that
/// walks them: [`PlaneSpans`] and the texture evaluator's spans hold one with their evaluator.
#[derive(Debug)]
#[cfg_attr(texcore_lean, allow(dead_code))]
pub(crate) struct PlaneWalk<'c, 'm, const T: usize> {
    plane: &'c PlaneSetup<'m, T>,
    events: &'c mut [RowEvent],
    state: RowsState<T>,
    cursor: Cursor<T>,
    /// The chunk the walked spans' samples are handed over in, kept from span to span (not
    /// cleared for each: every slot handed over is written first; an evaluator's options do not
    /// change, so samples without gradients find the gradient slots as made, zero).
    chunk: SampleChunk,
}

impl<'c, 'm, const T: usize> PlaneWalk<'c, 'm, T> {
    /// No row set up yet, the schedule's entries in `cache`.
    pub(crate) fn new<const N: usize, const W: usize>(
        plane: &'c PlaneSetup<'m, T>,
        cache: &'c mut RowCache<N, W>,
    ) -> Self {
        PlaneWalk {
            plane,
            events: &mut cache.events,
            state: RowsState {
                used: 0,
                len: 0,
                grads: false,
                weights: 0,
                lanes: heapless::Vec::new(),
            },
            chunk: SampleChunk::new(),
            cursor: Cursor {
                row: None,
                served: false,
                grads: false,
                x: 0,
                kind: 0,
                #[cfg(not(texcore_lean))]
                terms: 0,
                #[cfg(not(texcore_lean))]
                starts: [[0; 4]; T],
                #[cfg(not(texcore_lean))]
                walk: RowWalk::new(QuadStep {
                    q: 0,
                    dq: 0,
                    ddq: 0,
                    gx: 0,
                    dgx: 0,
                    gy: 0,
                    dgy: 0,
                }),
            },
        }
    }

    /// The plane.
    pub(crate) fn plane(&self) -> &'c PlaneSetup<'m, T> {
        self.plane
    }

    /// Whether the span at `(x, y)` is walked (the row set up first when the walk does not
    /// stand at or before `x` on row `y`, for samples with gradients when `grads`).
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    fn walks(&mut self, ev: &mut SpanEvaluator<'m, T>, x: u16, y: u16, grads: bool) -> bool {
        let c = &self.cursor;
        if c.row != Some(y) || c.x > x || c.grads != grads {
            self.start_row(ev, x, y, grads);
        }
        self.cursor.served
    }

    /// [`PlaneSpans::values`] by `ev`.
    pub(crate) fn values(
        &mut self,
        ev: &mut SpanEvaluator<'m, T>,
        x: u16,
        y: u16,
        out: &mut [TexValue],
    ) -> SpanInfo {
        let Ok(len) = u16::try_from(out.len()) else {
            return SpanInfo::default();
        };
        let Some(span) = self.plane.plane().span(x, y, len) else {
            return SpanInfo::default();
        };
        #[cfg(not(texcore_lean))]
        if len > 0 && self.walks(ev, x, y, false) {
            return self.walk(ev, x, len, false, |w, events, fvs, kind, _, _| match kind {
                // An affine quadric is stepped as curved (it adds zeros: one code shape fewer).
                0 => walk_part::<true, true, T>(w, events, fvs, out),
                _ => walk_part::<false, false, T>(w, events, fvs, out),
            });
        }
        let core = &mut ev.core;
        let grads = core.opts.gradients;
        core.opts.gradients = false;
        let from = SetupFrom::Plane(self.plane, x, y);
        let info = core.eval_values_from(&span, from, out, &mut super::face_cache::Faces::none());
        core.opts.gradients = grads;
        info
    }

    /// [`PlaneSpans::chunks`] by `ev`.
    pub(crate) fn chunks(
        &mut self,
        ev: &mut SpanEvaluator<'m, T>,
        x: u16,
        y: u16,
        len: u16,
        out: &mut dyn FnMut(&SampleChunk),
    ) -> SpanInfo {
        let Some(span) = self.plane.plane().span(x, y, len) else {
            return SpanInfo::default();
        };
        #[cfg(not(texcore_lean))]
        if len > 0 && self.walks(ev, x, y, GRADIENTS && ev.core.opts.gradients) {
            let (_, _, extra_width48) = self.plane.span_facts();
            self.chunk.len = 0;
            self.chunk.extra_width48 = extra_width48;
            let n = usize::from(len);
            return self.walk(ev, x, len, true, |w, events, fvs, _, grads, chunk| {
                let mut sink = ChunkSink { chunk, out };
                walk_chunks(w, events, fvs, n, grads, &mut sink);
                sink.finish();
            });
        }
        ev.eval_chunks_from(&span, SetupFrom::Plane(self.plane, x, y), out)
    }

    /// Sets row `y` up across the plane's width (`(0, y)`, gradients when `grads`) for the
    /// span at `x` and makes the schedule serve it when the plane, the evaluator and the row
    /// allow it: the cursor at its pixel 0. The row's set-up is not counted (its spans are).
    #[cfg(not(texcore_lean))]
    #[inline(never)]
    fn start_row(&mut self, ev: &mut SpanEvaluator<'m, T>, x: u16, y: u16, grads: bool) {
        // The last walked span (its row served): its row's terms and its end.
        let c = &mut self.cursor;
        let (last, last_x) = (c.served.then_some(c.terms), c.x);
        // Not served until the schedule is made: every span of the row is then evaluated on
        // its own, without trying again (the cursor at pixel 0, before every span).
        (c.row, c.served, c.grads, c.x) = (Some(y), false, grads, 0);
        let core = &mut ev.core;
        let plane = self.plane;
        // `Direct` never forward differences: its rows are never served (not even tried).
        let walkable = FD
            && !core.lean()
            && !core.multipass()
            && compiled_mode(core.opts.mode) != EvalMode::Direct
            && plane.serves(core)
            && plane.whole_steps()
            && core.model.precision().coord_bits() >= 16;
        let Some(span) = plane.plane().span(0, y, plane.plane().width()) else {
            return;
        };
        if !walkable {
            return;
        }
        let (stats, opt) = (core.stats, core.opts.gradients);
        core.opts.gradients = grads;
        let mut setup = Setup::empty();
        let from = SetupFrom::Plane(plane, 0, y);
        let (_, _, served) =
            core.row_begin(&span, from, &mut setup, &mut self.state, self.events, false);
        core.opts.gradients = opt;
        core.stats = stats;
        // Smooth-fade and gradient-noise terms are never served without `smooth`.
        if !served {
            return;
        }
        // The walk at the row's pixel 0, made in place.
        let (_, kind) = QuadStep::value_kind(&setup);
        let c = &mut self.cursor;
        c.walk = RowWalk::new(QuadStep::new(&setup));
        row_weights(&setup, &self.state, c.walk.weights_mut());
        (c.served, c.kind) = (true, kind);
        // The span resumes the last one when every term starts where that one's left off
        // (`Carried::resumes`): a term then sets up a cell at its first pixel only when that
        // pixel leaves the cell of the pixel before (the carried lane's event at pixel 0). The
        // span's walk counts one cell a term at its first pixel (a span that does not go on,
        // or the entries at a row's pixel 0): those are taken back here, so that the walk's
        // code is the same for every span.
        // Each term's lattice point at the span's first pixel against the last span's end
        // (`u0 + x du` on both rows: a term's step along the rows is the plane's), compared
        // until one differs; the row's own kept for the next row.
        let (n, m) = (i32::from(x), i32::from(last_x));
        let mut resumes = last.is_some();
        let (mut terms, mut entering) = (0u32, 0u8);
        for l in self.state.lanes.iter() {
            let (Some(ts), Some(kept)) = (setup.terms.get(l.term), c.starts.get_mut(l.term)) else {
                resumes = false;
                continue;
            };
            let (u, d) = (ts.u0, ts.du);
            if resumes {
                let at = |i: usize, p: i32| u[i].wrapping_add(d[i].wrapping_mul(p));
                let end = |i: usize| kept[i].wrapping_add(d[i].wrapping_mul(m));
                let differ = (at(0, n) ^ end(0)) | (at(1, n) ^ end(1)) | (at(2, n) ^ end(2));
                resumes = differ == 0 && kept[3] == ts.amp;
                let k = l.k.min(2);
                entering += u8::from((at(k, n) as u32 >> 16) != (at(k, n - 1) as u32 >> 16));
            }
            *kept = [u[0], u[1], u[2], ts.amp];
            // A term past the mask's 32 bits is never resumed (no model has that many).
            match 1u32.checked_shl(l.term as u32) {
                Some(b) => terms |= b,
                None => resumes = false,
            }
        }
        c.terms = terms;
        let lanes = &self.state.lanes;
        if resumes && last == Some(terms) {
            let st = &mut ev.core.stats;
            st.cell_setups = st
                .cell_setups
                .wrapping_add(u64::from(entering))
                .wrapping_sub(lanes.len() as u64);
        }
    }

    /// Span `x` (`len > 0` pixels) of the row the cursor stands on (`x` at or after the
    /// cursor, inside the row), walked from the schedule by `part` (given the walk, the
    /// entries, the noise fraction bits, the quadric's kind, whether the row has its gradients
    /// and the walk's chunk), and its counters (`samples`: the span's samples are handed over, with their
    /// gradients when the row has them). One copy per `part`: a values-only user links no
    /// sample code.
    #[cfg(not(texcore_lean))]
    #[inline(never)]
    fn walk(
        &mut self,
        ev: &mut SpanEvaluator<'m, T>,
        x: u16,
        len: u16,
        samples: bool,
        part: impl FnOnce(&mut RowWalk<T>, &[RowEvent], u32, u8, bool, &mut SampleChunk),
    ) -> SpanInfo {
        let events = self.events.get(..self.state.used).unwrap_or_default();
        let fvs = ev.core.model.noise_frac_bits() & 31;
        let c = &mut self.cursor;
        let fresh = c.x != x;
        let w = &mut c.walk;
        if fresh {
            w.skip(events, x.wrapping_sub(c.x));
        }
        let first = w.entry();
        let grads = c.grads;
        part(w, events, fvs, c.kind, grads, &mut self.chunk);
        let walked = w.entry() - first;
        c.x = x.wrapping_add(len);
        // Counters: as the span on its own, its cells as the module documentation states.
        let lanes = self.state.lanes.len() as u64;
        let entered = walked as u64 + if fresh { lanes } else { 0 };
        let (culled, faded, extra_width48) = self.plane.span_facts();
        let px = u64::from(len);
        let st = &mut ev.core.stats;
        st.spans += 1;
        st.pixels += px;
        st.culled_octaves += u64::from(culled);
        st.faded_octaves += u64::from(faded);
        st.cell_setups += entered;
        st.noise_evaluations += px * lanes;
        if samples && grads {
            st.gradient_evaluations += px * (1 + lanes);
        }
        if self.state.lanes.iter().any(|l| l.fd) {
            st.fd_pixels += px;
        }
        #[cfg(test)]
        {
            ev.core.row_spans += 1;
        }
        SpanInfo { extra_width48 }
    }
}

/// The spans of one plane, evaluated from its rows' cell schedule (see the module
/// documentation): made by [`SpanEvaluator::plane_spans`].
///
/// A 64 x 32 field of four octaves of value noise in 16-pixel spans:
///
/// ```
/// use texcore::format::{Amplitude, MatrixEntry, TexPoint, TexValue};
/// use texcore::hash::HashKind;
/// use texcore::model::{Octaves, TextureModel};
/// use texcore::noise::NoiseBasis;
/// use texcore::quadric::Quadric;
/// use texcore::span::{EvalMode, EvalOptions, RowCache, SpanEvaluator, SpanPlane};
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
/// let plane = SpanPlane::new(
///     TexPoint::from_f64(0.0, 0.0, 0.5),
///     TexPoint::from_f64(1.0 / 8.0, 0.0, 0.0),
///     TexPoint::from_f64(0.0, 1.0 / 8.0, 0.0),
///     64,
///     32,
/// )?;
/// let setup = ev.plane_setup(&plane);
/// let mut cache = RowCache::<64>::new();
/// let mut field = [[TexValue::ZERO; 64]; 32];
/// let mut spans = ev.plane_spans(&setup, &mut cache);
/// for (y, row) in (0u16..).zip(field.iter_mut()) {
///     for (x, tile) in (0u16..).step_by(16).zip(row.chunks_mut(16)) {
///         spans.values(x, y, tile);
///     }
/// }
/// // The same values as each span set up on its own.
/// let mut tile = [TexValue::ZERO; 16];
/// let span = plane.span(16, 5, 16).unwrap();
/// SpanEvaluator::new(&model, opts).eval_values(&span, &mut tile);
/// assert_eq!(tile, field[5][16..32]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct PlaneSpans<'e, 'm, 'c, const T: usize> {
    ev: &'e mut SpanEvaluator<'m, T>,
    walk: PlaneWalk<'c, 'm, T>,
}

impl<'m, const T: usize> SpanEvaluator<'m, T> {
    /// The spans of `plane` (made by [`SpanEvaluator::plane_setup`]), served from its rows' cell
    /// schedule in `cache` (see [`PlaneSpans`]): the same values and samples as
    /// [`SpanEvaluator::eval_plane_values`] and [`SpanEvaluator::eval_plane_chunks`] of each
    /// span, bit for bit.
    pub fn plane_spans<'e, 'c, const N: usize, const W: usize>(
        &'e mut self,
        plane: &'c PlaneSetup<'m, T>,
        cache: &'c mut RowCache<N, W>,
    ) -> PlaneSpans<'e, 'm, 'c, T> {
        PlaneSpans {
            ev: self,
            walk: PlaneWalk::new(plane, cache),
        }
    }
}

impl<const T: usize> PlaneSpans<'_, '_, '_, T> {
    /// The evaluator's counters so far.
    pub fn stats(&self) -> &SpanStats {
        self.ev.stats()
    }

    /// The span of `out.len()` pixels at `(x, y)` of the plane into `out`, as
    /// [`SpanEvaluator::eval_plane_values`] gives it (see [`PlaneSpans`] for the counters).
    /// Nothing is evaluated (and the default facts are returned) when the span is not inside
    /// the plane's rectangle or is longer than `u16::MAX`.
    pub fn values(&mut self, x: u16, y: u16, out: &mut [TexValue]) -> SpanInfo {
        self.walk.values(self.ev, x, y, out)
    }

    /// The samples of the span of `len` pixels at `(x, y)` of the plane, with their gradients
    /// when the evaluator's options ask for them, handed to `out` in chunks of at most
    /// [`SAMPLE_CHUNK`], as [`SpanEvaluator::eval_plane_chunks`] gives them (see [`PlaneSpans`]
    /// for the counters). Nothing is evaluated (and the default facts are returned) when the
    /// span is not inside the plane's rectangle.
    pub fn chunks(
        &mut self,
        x: u16,
        y: u16,
        len: u16,
        out: &mut dyn FnMut(&SampleChunk),
    ) -> SpanInfo {
        self.walk.chunks(self.ev, x, y, len, out)
    }
}
#[cfg(test)]
mod tests {
    use std::vec::Vec;

    use super::*;
    use crate::format::{Amplitude, MatrixEntry};
    use crate::model::Octaves;
    use crate::noise::NoiseBasis;
    use crate::span::Sample;
    use crate::transform::Affine3;

    /// `model` of the rows' tests, or (`odd`) its octaves at a zoom of 1.3 (steps with bits
    /// below the lattice's units: never walked).
    fn model(
        octaves: u8,
        zoom: u32,
        quadric: u32,
        clamp: bool,
        basis: u8,
        odd: bool,
    ) -> TextureModel<8> {
        let hash = HashKind::Integer;
        let mut m = super::super::tests::model(octaves, zoom, quadric, clamp, hash, basis);
        if odd {
            let mut o: TextureModel<8> = TextureModel::new(*m.quadric(), m.wrap());
            o.push_octaves(&Octaves {
                count: octaves,
                base: Affine3::scale(MatrixEntry::from_num(1.3)),
                amplitude: Amplitude::from_num(0.6),
                rotate: false,
                basis: NoiseBasis::trilinear(hash),
                turbulence: false,
            })
            .unwrap();
            m = o;
        }
        m
    }

    /// The spans asked for: every row of `height` cut at `cuts` (pixels, any order), every
    /// `gap`-th piece left out, and (`back`) an earlier piece of the row asked for again after
    /// its last one.
    fn pieces(
        width: u16,
        height: u16,
        cuts: &[u16],
        gap: usize,
        back: bool,
    ) -> Vec<(u16, u16, u16)> {
        let mut at: Vec<u16> = cuts.iter().map(|c| c % width.max(1)).collect();
        at.push(0);
        at.push(width);
        at.sort_unstable();
        at.dedup();
        let mut out = Vec::new();
        for y in 0..height {
            let row: Vec<(u16, u16, u16)> = at.windows(2).map(|w| (w[0], y, w[1] - w[0])).collect();
            for (i, p) in row.iter().enumerate() {
                if gap == 0 || (i + usize::from(y)) % gap != gap - 1 {
                    out.push(*p);
                }
            }
            if back && row.len() > 1 {
                out.push(row[row.len() / 2]);
            }
        }
        out
    }

    /// Three evaluators of `m` with `opts`: the spans', the reference's and (in `Direct`) the
    /// model's own.
    fn evaluators(m: &TextureModel<8>, opts: EvalOptions) -> [SpanEvaluator<'_, 8>; 3] {
        let direct = EvalOptions {
            mode: EvalMode::Direct,
            ..opts
        };
        [opts, opts, direct].map(|o| SpanEvaluator::new(m, o))
    }

    /// The counters' changes of a walked span (`got` from `got0`) are the span's on its own
    /// (`want` from `want0`), its cell set-ups too when `cells`.
    fn same_counters(
        got: &SpanStats,
        got0: &SpanStats,
        want: &SpanStats,
        want0: &SpanStats,
        cells: bool,
    ) -> Result<(), proptest::test_runner::TestCaseError> {
        let delta = |a: &SpanStats, b: &SpanStats| {
            [
                a.pixels - b.pixels,
                a.spans - b.spans,
                if cells {
                    a.cell_setups - b.cell_setups
                } else {
                    0
                },
                a.noise_evaluations - b.noise_evaluations,
                a.culled_octaves - b.culled_octaves,
                a.faded_octaves - b.faded_octaves,
                a.gradient_evaluations - b.gradient_evaluations,
                a.fd_pixels - b.fd_pixels,
            ]
        };
        proptest::prop_assert_eq!(delta(got, got0), delta(want, want0));
        Ok(())
    }

    /// Every piece through [`PlaneSpans`] against `eval_plane_values` (through a face cache
    /// carrying lanes, values, facts and, where the span was walked in `Fd`, the counters'
    /// changes) and `Direct`; the number of spans walked.
    fn compare(
        m: &TextureModel<8>,
        opts: EvalOptions,
        plane: &SpanPlane,
        pieces: &[(u16, u16, u16)],
    ) -> Result<u64, proptest::test_runner::TestCaseError> {
        let [mut ev, mut reference, mut direct] = evaluators(m, opts);
        let setup = ev.plane_setup(plane);
        let ref_setup = reference.plane_setup(plane);
        let mut faces = FaceCache::<64, 8>::new();
        let mut cache = RowCache::<400>::new();
        let mut spans = ev.plane_spans(&setup, &mut cache);
        let marker = TexValue::from_bits(0x5A5A_5A5A);
        for (i, &(x, y, len)) in pieces.iter().enumerate() {
            let n = usize::from(len);
            let mut got = std::vec![marker; n + 1];
            let (before, walked) = (*spans.stats(), spans.ev.core.row_spans);
            let info = spans.values(x, y, &mut got[..n]);
            let mut want = std::vec![marker; n + 1];
            let ref_before = *reference.stats();
            let want_info =
                reference.eval_plane_values(&ref_setup, x, y, &mut want[..n], &mut faces);
            proptest::prop_assert_eq!(&got, &want, "span {:?}", (x, y, len));
            proptest::prop_assert_eq!(info, want_info);
            if i % 3 == 0 {
                let mut d = std::vec![marker; n + 1];
                direct.eval_values(&plane.span(x, y, len).unwrap(), &mut d[..n]);
                proptest::prop_assert_eq!(&got, &d, "span {:?} against Direct", (x, y, len));
            }
            if spans.ev.core.row_spans > walked && opts.mode == EvalMode::Fd {
                same_counters(spans.stats(), &before, reference.stats(), &ref_before, true)?;
            }
        }
        let walked = spans.ev.core.row_spans;
        drop(spans);
        proptest::prop_assert_eq!(ev.options(), opts, "the options are restored");
        Ok(walked)
    }

    /// A span's samples as its chunks: each chunk's length, samples and culled width.
    type Chunks = Vec<(usize, Vec<Sample>, i64)>;

    /// Collects the chunks handed to it into `v`.
    fn collect(v: &mut Chunks) -> impl FnMut(&SampleChunk) + '_ {
        |c: &SampleChunk| v.push((c.len(), c.iter().collect(), c.extra_width48()))
    }

    /// Every piece's samples through [`PlaneSpans::chunks`] against `eval_plane_chunks` (and
    /// `Direct`'s), chunk by chunk, and in `Fd` the counters' changes of every walked span but
    /// its cells (the values' test counts those) against the span on its own; the number of
    /// spans walked.
    fn compare_chunks(
        m: &TextureModel<8>,
        opts: EvalOptions,
        plane: &SpanPlane,
        pieces: &[(u16, u16, u16)],
    ) -> Result<u64, proptest::test_runner::TestCaseError> {
        let [mut ev, mut reference, mut direct] = evaluators(m, opts);
        let setup = ev.plane_setup(plane);
        let ref_setup = reference.plane_setup(plane);
        let mut cache = RowCache::<400>::new();
        let mut spans = ev.plane_spans(&setup, &mut cache);
        for (i, &(x, y, len)) in pieces.iter().enumerate() {
            let (mut got, mut want): (Chunks, Chunks) = (Vec::new(), Vec::new());
            let (before, walked) = (*spans.stats(), spans.ev.core.row_spans);
            let info = spans.chunks(x, y, len, &mut collect(&mut got));
            let ref_before = *reference.stats();
            let want_info =
                reference.eval_plane_chunks(&ref_setup, x, y, len, &mut collect(&mut want));
            proptest::prop_assert_eq!(&got, &want, "span {:?}", (x, y, len));
            proptest::prop_assert_eq!(info, want_info);
            if i % 3 == 0 {
                let mut d = Vec::new();
                direct.eval_chunks(&plane.span(x, y, len).unwrap(), &mut collect(&mut d));
                proptest::prop_assert_eq!(&got, &d, "span {:?} against Direct", (x, y, len));
            }
            if spans.ev.core.row_spans > walked && opts.mode == EvalMode::Fd {
                same_counters(
                    spans.stats(),
                    &before,
                    reference.stats(),
                    &ref_before,
                    false,
                )?;
            }
        }
        let walked = spans.ev.core.row_spans;
        drop(spans);
        proptest::prop_assert_eq!(ev.options(), opts, "the options are restored");
        Ok(walked)
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(96))]
        /// The spans of a plane through [`PlaneSpans`] are `eval_plane_values`' and `Direct`'s
        /// (values and facts; in `Fd` the counters of every walked span), for planes anywhere in
        /// the coordinate range stepping along any axis (short and long cells, both signs), rows
        /// stepping along another axis or none, rows cut into pieces of any lengths, with gaps
        /// and pieces asked for again out of order, any quadric, `mod` and `clamp`, every mode,
        /// gradients asked for or not, 1 to 5 octaves, the smooth fade and gradient noise (never
        /// walked), octaves whose steps have bits below the lattice's units (never walked); and
        /// every span of a walkable plane in `Fd` is walked when the schedule holds its rows.
        #[test]
        fn plane_spans_are_their_spans(
            origin in proptest::array::uniform3(-2_000_000_000i32..2_000_000_000),
            step in -90_000i32..90_000,
            axis in 0usize..3,
            across: bool,
            dyv in -30_000i32..30_000,
            width in 1u16..300,
            height in 1u16..5,
            cuts in proptest::collection::vec(0u16..300, 0..12),
            gap in 0usize..4,
            back: bool,
            clamp: bool,
            quadric in 0u32..3,
            gradients: bool,
            octaves in 1u8..6,
            zoom in 0u32..3,
            mode in 0usize..3,
            basis in 0u8..4,
            odd: bool,
        ) {
            let m = model(octaves, zoom, quadric, clamp, basis, odd);
            let mut ds = [0; 3];
            ds[axis] = (step >> (2 * zoom)) | 1;
            let mut dy = [0; 3];
            if across {
                dy[(axis + 1) % 3] = dyv;
            }
            let bits = |v: [i32; 3]| TexPoint::from_bits(v[0], v[1], v[2]);
            let plane = SpanPlane::new(bits(origin), bits(ds), bits(dy), width, height);
            proptest::prop_assume!(plane.is_ok());
            let plane = plane.unwrap();
            let mode = [EvalMode::Fd, EvalMode::Auto, EvalMode::Direct][mode];
            let opts = EvalOptions { mode, gradients, cull: true, ..Default::default() };
            let pieces = pieces(width, height, &cuts, gap, back);
            let walked = compare(&m, opts, &plane, &pieces)?;
            let walked_chunks = compare_chunks(&m, opts, &plane, &pieces)?;
            if !(GRADIENTS && gradients) {
                // Without gradients the samples' rows are the values'.
                proptest::prop_assert_eq!(walked_chunks, walked);
            }
            // Every span walked: trilinear octaves of whole steps (powers of two), resolved
            // cells, `Fd`, a `mod` table (a `clamp` one needs the row's quadric in range), in
            // the fast shape.
            let resolved = (ds[axis] << (zoom + u32::from(octaves) - 1)).unsigned_abs() < NYQUIST_STEP as u32;
            if FD && !cfg!(texcore_lean) && mode == EvalMode::Fd && basis == 0 && !odd && !clamp && resolved {
                proptest::prop_assert_eq!(walked, pieces.len() as u64);
            }
            if odd || super::super::tests::per_pixel_basis(basis) {
                proptest::prop_assert_eq!((walked, walked_chunks), (0, 0));
            }
        }
    }

    /// Four octaves on a 256-pixel plane in 16-pixel spans, as a tiled fill hands them over:
    /// every span walked, the values of the whole rows, and the rows' cell set-ups.
    #[test]
    fn sixteen_pixel_spans_are_the_rows() {
        let m = model(4, 0, 0, false, 0, false);
        let opts = EvalOptions {
            mode: EvalMode::Fd,
            gradients: false,
            ..Default::default()
        };
        let step = 65536 / 32;
        let plane = SpanPlane::new(
            TexPoint::from_bits(0, 0, 24_248),
            TexPoint::from_bits(step, 0, 0),
            TexPoint::from_bits(0, step, 0),
            256,
            6,
        )
        .unwrap();
        let mut ev = SpanEvaluator::new(&m, opts);
        let setup = ev.plane_setup(&plane);
        let mut cache = RowCache::<128>::new();
        let mut spans = ev.plane_spans(&setup, &mut cache);
        let mut rows_ev = SpanEvaluator::new(&m, opts);
        for y in 0..6 {
            let mut got = [TexValue::ZERO; 256];
            let before = spans.stats().cell_setups;
            for (x, tile) in (0u16..).step_by(16).zip(got.chunks_mut(16)) {
                spans.values(x, y, tile);
            }
            let mut want = [TexValue::ZERO; 256];
            let rb = rows_ev.stats().cell_setups;
            rows_ev.eval_values(&plane.span(0, y, 256).unwrap(), &mut want);
            assert_eq!(got, want, "row {y}");
            // Walked (the fast shape with forward differencing), the spans set up the cells of
            // the whole row; otherwise each span sets up its own.
            if FD && !cfg!(texcore_lean) {
                assert_eq!(
                    spans.stats().cell_setups - before,
                    rows_ev.stats().cell_setups - rb,
                    "row {y}: the cells of the whole row"
                );
            }
        }
        let walked = spans.ev.core.row_spans;
        if FD && !cfg!(texcore_lean) {
            assert_eq!(walked, 6 * 16);
        }
    }

    /// A plane whose rows are the same points (no step across them), handed over in 16-pixel
    /// spans that take turns between two rows: each span starts where the last one left off,
    /// on the other row. Through [`PlaneSpans`] every span is walked and counts the cells a face
    /// cache's carried lanes set up, a cell a term only where its first pixel leaves the cell
    /// of the pixel before: the cells of the whole row once, as the row in one span.
    #[test]
    fn spans_that_resume_on_another_row_count_the_carried_lanes() {
        let m = model(3, 0, 0, false, 0, false);
        let opts = EvalOptions {
            mode: EvalMode::Fd,
            gradients: false,
            ..Default::default()
        };
        // 1/24 of a cell a pixel at the first octave: pieces that end inside cells and at
        // their ends.
        let plane = SpanPlane::new(
            TexPoint::from_bits(-40_000, 1_000, 24_248),
            TexPoint::from_bits(65536 / 24, 0, 0),
            TexPoint::from_bits(0, 0, 0),
            192,
            2,
        )
        .unwrap();
        let [mut ev, mut reference, mut direct] = evaluators(&m, opts);
        let mut whole = SpanEvaluator::new(&m, opts);
        let setup = ev.plane_setup(&plane);
        let ref_setup = reference.plane_setup(&plane);
        let mut faces = FaceCache::<64, 8>::new();
        let mut cache = RowCache::<128>::new();
        let mut spans = ev.plane_spans(&setup, &mut cache);
        let mut got = [TexValue::ZERO; 192];
        let mut want = [TexValue::ZERO; 192];
        for (i, x) in (0u16..192).step_by(16).enumerate() {
            let y = (i % 2) as u16;
            let r = usize::from(x)..usize::from(x) + 16;
            let (before, ref_before) = (*spans.stats(), *reference.stats());
            spans.values(x, y, &mut got[r.clone()]);
            reference.eval_plane_values(&ref_setup, x, y, &mut want[r.clone()], &mut faces);
            assert_eq!(got[r.clone()], want[r], "span {x}");
            if FD && !cfg!(texcore_lean) {
                let cells = |a: &SpanStats, b: &SpanStats| a.cell_setups - b.cell_setups;
                assert_eq!(
                    cells(spans.stats(), &before),
                    cells(reference.stats(), &ref_before),
                    "span {x}: the carried lanes' cells"
                );
            }
        }
        let mut row = [TexValue::ZERO; 192];
        whole.eval_values(&plane.span(0, 1, 192).unwrap(), &mut row);
        assert_eq!(got, row);
        direct.eval_values(&plane.span(0, 0, 192).unwrap(), &mut row);
        assert_eq!(got, row, "Direct");
        if FD && !cfg!(texcore_lean) {
            assert_eq!(spans.ev.core.row_spans, 12, "every span walked");
            let cells = spans.stats().cell_setups;
            assert_eq!(cells, whole.stats().cell_setups, "the whole row's cells");
            assert_eq!(cells, reference.stats().cell_setups);
        }
    }

    /// The same with gradients, the marble preset's model (a quadric along `r`, the rows
    /// stepping along it) on its own plane: every span walked, the samples of the whole rows
    /// through [`PlaneRows`], and the rows' cell set-ups and gradient samples.
    #[test]
    fn sixteen_pixel_spans_with_gradients_are_the_rows() {
        let preset = crate::presets::marble(HashKind::Integer);
        let m = preset.model;
        let opts = EvalOptions {
            mode: EvalMode::Fd,
            gradients: true,
            ..Default::default()
        };
        let plane = SpanPlane::new(
            TexPoint::from_bits(0, 32_768, 0),
            TexPoint::from_bits(512, 0, 0),
            TexPoint::from_bits(0, 0, 512),
            128,
            5,
        )
        .unwrap();
        let mut ev = SpanEvaluator::new(&m, opts);
        let setup = ev.plane_setup(&plane);
        let mut cache = RowCache::<128>::new();
        let mut spans = ev.plane_spans(&setup, &mut cache);
        let mut rows_ev = SpanEvaluator::new(&m, opts);
        let mut rows_cache = RowCache::<128>::new();
        let mut rows = rows_ev.rows(&plane.span(0, 0, 128).unwrap(), &mut rows_cache);
        for y in 0..5 {
            let before = *spans.stats();
            let mut got = Vec::new();
            for x in (0u16..128).step_by(16) {
                spans.chunks(x, y, 16, &mut |c: &SampleChunk| got.extend(c.iter()));
            }
            let rb = *rows.stats();
            let mut want = Vec::new();
            rows.next(|s| want.push(s));
            assert_eq!(got, want, "row {y}");
            if FD && GRADIENTS && !cfg!(texcore_lean) {
                let (a, b) = (spans.stats(), rows.stats());
                assert_eq!(
                    a.cell_setups - before.cell_setups,
                    b.cell_setups - rb.cell_setups
                );
                assert_eq!(
                    a.gradient_evaluations - before.gradient_evaluations,
                    b.gradient_evaluations - rb.gradient_evaluations
                );
            }
        }
        let walked = spans.ev.core.row_spans;
        if FD && !cfg!(texcore_lean) {
            assert_eq!(walked, 5 * 8);
        }
    }

    /// A 4000-pixel plane in 16-pixel spans, its rows' schedule held by the cache (about 940
    /// entries: walked) or not (64 entries: every span on its own), near the top of the
    /// coordinate range with negative steps along `t`: the same values either way.
    #[test]
    fn long_rows_past_the_cache_are_evaluated_span_by_span() {
        let m = model(4, 0, 1, false, 0, false);
        let opts = EvalOptions {
            mode: EvalMode::Fd,
            gradients: false,
            ..Default::default()
        };
        let plane = SpanPlane::new(
            TexPoint::from_bits(-5, i32::MAX - 70_000, 1 << 30),
            TexPoint::from_bits(0, -1024, 0),
            TexPoint::from_bits(3, 0, 0),
            4000,
            2,
        )
        .unwrap();
        fn field<const N: usize>(
            m: &TextureModel<8>,
            opts: EvalOptions,
            plane: &SpanPlane,
        ) -> (Vec<TexValue>, u64) {
            let mut ev = SpanEvaluator::new(m, opts);
            let setup = ev.plane_setup(plane);
            let mut cache = RowCache::<N>::new();
            let mut spans = ev.plane_spans(&setup, &mut cache);
            let mut out = std::vec![TexValue::ZERO; 8000];
            for (i, tile) in out.chunks_mut(16).enumerate() {
                let (x, y) = ((i % 250 * 16) as u16, (i / 250) as u16);
                spans.values(x, y, tile);
            }
            (out, spans.ev.core.row_spans)
        }
        let (big, walked) = field::<2048>(&m, opts, &plane);
        let (small, none) = field::<64>(&m, opts, &plane);
        let mut want = std::vec![TexValue::ZERO; 4000];
        let mut direct = SpanEvaluator::new(
            &m,
            EvalOptions {
                mode: EvalMode::Direct,
                ..opts
            },
        );
        for y in 0..2u16 {
            direct.eval_values(&plane.span(0, y, 4000).unwrap(), &mut want);
            let row = usize::from(y) * 4000..usize::from(y + 1) * 4000;
            assert_eq!(big[row.clone()], want[..], "row {y}, walked");
            assert_eq!(small[row], want[..], "row {y}, span by span");
        }
        assert_eq!(none, 0);
        if FD && !cfg!(texcore_lean) {
            assert_eq!(walked, 500);
        }
    }

    /// A span outside the plane's rectangle is not evaluated: the default facts, its output
    /// untouched, no counter moved; the spans around it are.
    #[test]
    fn spans_outside_the_plane_are_not_evaluated() {
        let m = model(2, 0, 2, false, 0, false);
        let opts = EvalOptions::default();
        let plane = SpanPlane::new(
            TexPoint::from_f64(1.0, 2.0, 0.5),
            TexPoint::from_f64(1.0 / 16.0, 0.0, 0.0),
            TexPoint::from_f64(0.0, 1.0 / 16.0, 0.0),
            40,
            3,
        )
        .unwrap();
        let mut ev = SpanEvaluator::new(&m, opts);
        let setup = ev.plane_setup(&plane);
        let mut cache = RowCache::<32>::new();
        let mut spans = ev.plane_spans(&setup, &mut cache);
        let marker = TexValue::from_bits(0x1234_5678);
        let mut out = [TexValue::ZERO; 16];
        spans.values(0, 1, &mut out);
        for (x, y, n) in [(30, 1, 16), (0, 3, 4), (40, 0, 1), (u16::MAX, 0, 2)] {
            let mut o = [marker; 16];
            let before = *spans.stats();
            let info = spans.values(x, y, &mut o[..n]);
            assert_eq!(info, SpanInfo::default());
            assert_eq!(o, [marker; 16], "{x} {y} {n}");
            assert_eq!(*spans.stats(), before);
        }
        // The row goes on where it stood.
        let mut next = [TexValue::ZERO; 16];
        spans.values(16, 1, &mut next);
        let mut want = [TexValue::ZERO; 16];
        SpanEvaluator::new(&m, opts).eval_values(&plane.span(16, 1, 16).unwrap(), &mut want);
        assert_eq!(next, want);
    }
}
