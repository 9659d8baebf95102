//! The axial kernel lane by lane: the spans of the axial kernel (`axial`) without gradients,
//! evaluated one term at a time over each chunk of samples instead of through one merged state.
//!
//! On such a span every term is linear inside its cell (`axis`): its value at the next pixel
//! `v` and its slope `s` are two words, and a pixel is one 64-bit addition `v += s`. Each term
//! (a *lane*) walks the chunk on its own: the first lane stores its values to a chunk of
//! accumulators, the next ones add theirs, and the last one adds its values and writes the
//! sample (`f = (q + (N >> fv)) >> 32`, the quadric `q` stepped in the same loop; with a zero
//! quadric `f = (N >> 32) >> fv`); a span of one lane writes its samples directly. The
//! accumulators are the chunk's gradient slots (zero without gradients), zeroed again as they
//! are read, so the span clears no scratch array of its own. A lane's cell event happens
//! inside its own walk, so there is no segment loop over the lanes at every event, and nothing
//! is subtracted at an exit: the new cell's polynomial simply replaces the lane's `(v, s)`.
//!
//! Exactness: a lane's `v` at pixel `j` of its cell is `g0 + j g1` of the cell polynomial
//! (`axis::poly`), the term's value in the merged loop, and every sum is wrapping modulo 2^64
//! as the merged state's, so the sums (in any order of the terms) and the samples are the
//! merged loop's, and so are the counters (tested against `Direct`, the merged loop of the
//! size-lean shape and the axial kernel with gradients).

use super::face_cache::{cached_phi, FaceEntry, FaceKey};
use super::*;

/// One term of the lane kernel.
#[derive(Clone, Copy, Debug)]
struct ValueLane {
    /// Pixels before the term's next cell event.
    left: u32,
    /// The term's value at the next pixel, and its step a pixel.
    v: i64,
    s: i64,
    /// The moving axis (0..=2).
    k: usize,
    /// The lattice coordinate along `k` at pixel 0 of the span, and its step a pixel.
    u0: i32,
    d: i32,
    /// The current cell and fractions (the two axes other than `k` never change).
    cell: [u16; 3],
    frac: [u32; 3],
    /// The blends `Phi` of the current cell's faces `c_k = 0` and `c_k = 1`.
    phi: [i64; 2],
    hash: HashKind,
    amp: i32,
    /// The constant part of the face cache's keys.
    key: FaceKey,
}

/// The blend `Phi` of face `b` of `cell` for a lane moving along `k` (constant fractions `frac`
/// on the two other axes). Out of line: a span's lanes blend faces at five places (two at the
/// start, three kinds of cell event), and with a face cache most blends are read back.
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn face_phi(
    k: usize,
    hash: HashKind,
    cell: [u16; 3],
    frac: [u32; 3],
    b: usize,
    amp: i32,
    fv: u32,
    vb: u32,
) -> i64 {
    let k = k.min(2); // always 0..=2: lets the compiler drop the bounds checks
    let w = face_bits(k, hash, cell, b, amp, fv, vb);
    face(&w, k, frac, [0; 3], false).phi()
}

/// [`face_phi`] through the face cache `faces` when it has entries ([`cached_phi`]: the same
/// value).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn lane_phi(
    faces: &mut [FaceEntry],
    key: &FaceKey,
    k: usize,
    hash: HashKind,
    cell: [u16; 3],
    frac: [u32; 3],
    b: usize,
    amp: i32,
    fv: u32,
    vb: u32,
) -> i64 {
    match cached_phi(faces, key, k, hash, cell, b, amp, fv, vb) {
        Some(phi) => phi,
        None => face_phi(k, hash, cell, frac, b, amp, fv, vb),
    }
}

/// The cell polynomial at its local pixel 0 and its step from the face blends (`axis::poly`'s
/// `g[0]` and `g[1]`), `fk` the fraction along the moving axis, `d` its step.
#[inline(always)]
fn value_and_step(phi: [i64; 2], fk: u32, d: i32) -> (i64, i64) {
    let [p0, p1] = phi;
    let dphi = wsub(p1, p0);
    (
        wadd(p0 << 16, wmul(dphi, i64::from(fk))),
        wmul(dphi, i64::from(d)),
    )
}

impl ValueLane {
    /// The blend of face `b` of the current cell (through `faces` when it has entries).
    #[inline(always)]
    fn blend(&self, b: usize, fv: u32, vb: u32, faces: &mut [FaceEntry]) -> i64 {
        let (k, h, c, f, a) = (self.k, self.hash, self.cell, self.frac, self.amp);
        lane_phi(faces, &self.key, k, h, c, f, b, a, fv, vb)
    }

    /// The cell event at span pixel `i`: into the next cell along `k` (the shared face kept).
    #[inline(always)]
    fn event(&mut self, i: u32, fv: u32, vb: u32, faces: &mut [FaceEntry]) {
        let k = self.k.min(2);
        let uk = self.u0.wrapping_add(self.d.wrapping_mul(i as i32));
        let cell = (uk >> 16) as u16;
        let step = match self.cell.get(k) {
            Some(&c) => cell.wrapping_sub(c),
            None => 0,
        };
        let fk = (uk & 0xFFFF) as u32;
        if let (Some(c), Some(f)) = (self.cell.get_mut(k), self.frac.get_mut(k)) {
            *c = cell;
            *f = fk;
        }
        self.phi = match step {
            1 => [self.phi[1], self.blend(1, fv, vb, faces)],
            0xFFFF => [self.blend(0, fv, vb, faces), self.phi[0]],
            _ => [self.blend(0, fv, vb, faces), self.blend(1, fv, vb, faces)],
        };
        (self.v, self.s) = value_and_step(self.phi, fk, self.d);
        self.left = pixels_in_cell_axis(fk, self.d);
    }
}

/// What a lane does with its values over a chunk.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    /// The only lane: writes the samples.
    Only,
    /// The first of several: stores to the accumulators.
    First,
    /// A middle one: adds to the accumulators.
    Add,
    /// The last of several: adds to the accumulators and writes the samples.
    Last,
}

/// `run` pixels of a lane from `(v, s)` into the accumulators `acc`.
#[inline(always)]
fn walk_acc<const ADD: bool>(acc: &mut [i64], v: &mut i64, s: i64) {
    let mut x = *v;
    for a in acc.iter_mut() {
        *a = if ADD { a.wrapping_add(x) } else { x };
        x = x.wrapping_add(s);
    }
    *v = x;
}

/// `run` pixels of a lane from `(v, s)` written as samples (`ADD`: plus the accumulators, which
/// are zeroed as they are read when `CLEAR`; without `ADD` the accumulators are not read):
/// `f = (q + (N >> fv)) >> 32`, `q` the quadric (`NOQ`: zero, `f = (N >> 32) >> fv`; `AFFINE`:
/// a constant step).
#[inline(always)]
pub(super) fn walk_out<const ADD: bool, const CLEAR: bool, const NOQ: bool, const AFFINE: bool>(
    out: &mut [TexValue],
    acc: &mut [i64],
    fvs: u32,
    v: &mut i64,
    s: i64,
    q: &mut [i64; 3],
) {
    let mut x = *v;
    let [mut qq, mut dq, ddq] = *q;
    let mut acc = acc.iter_mut();
    for o in out.iter_mut() {
        let n = if ADD {
            let Some(a) = acc.next() else {
                break;
            };
            let n = a.wrapping_add(x);
            if CLEAR {
                *a = 0;
            }
            n
        } else {
            x
        };
        let f = if NOQ {
            ((n >> 32) as i32) >> fvs
        } else {
            let f = (qq.wrapping_add(n >> fvs) >> 32) as i32;
            qq = qq.wrapping_add(dq);
            if !AFFINE {
                dq = dq.wrapping_add(ddq);
            }
            f
        };
        *o = TexValue::from_bits(f);
        x = x.wrapping_add(s);
    }
    *v = x;
    *q = [qq, dq, ddq];
}

/// One lane's `run` pixels in its role (`quad`: zero quadric, affine, curved; `clear`: the last
/// lane zeroes the accumulators it reads).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn walk(
    clear: bool,
    role: Role,
    quad: u8,
    acc: &mut [i64],
    out: &mut [TexValue],
    fvs: u32,
    v: &mut i64,
    s: i64,
    q: &mut [i64; 3],
) {
    match (role, quad) {
        (Role::First, _) => walk_acc::<false>(acc, v, s),
        (Role::Add, _) => walk_acc::<true>(acc, v, s),
        (Role::Only, 0) => walk_out::<false, false, true, true>(out, acc, fvs, v, s, q),
        (Role::Only, 1) => walk_out::<false, false, false, true>(out, acc, fvs, v, s, q),
        (Role::Only, _) => walk_out::<false, false, false, false>(out, acc, fvs, v, s, q),
        (Role::Last, 0) if clear => walk_out::<true, true, true, true>(out, acc, fvs, v, s, q),
        (Role::Last, 1) if clear => walk_out::<true, true, false, true>(out, acc, fvs, v, s, q),
        (Role::Last, _) if clear => walk_out::<true, true, false, false>(out, acc, fvs, v, s, q),
        (Role::Last, 0) => walk_out::<true, false, true, true>(out, acc, fvs, v, s, q),
        (Role::Last, 1) => walk_out::<true, false, false, true>(out, acc, fvs, v, s, q),
        (Role::Last, _) => walk_out::<true, false, false, false>(out, acc, fvs, v, s, q),
    }
}

/// Where the lane kernel and the per-pixel axial kernel write: a chunk handed to a consumer
/// when full, or the caller's slice of values; filled a run of slots at a time. One type (not a
/// trait): the kernels are large, and are compiled once for both.
pub(super) enum LaneOut<'a, 'o, 'c> {
    /// A chunk of samples; the accumulators are its gradient slots, zero without gradients,
    /// which the last lane zeroes again as it reads them.
    Chunk(&'a mut ChunkSink<'o, 'c>),
    /// The caller's slice of values.
    Values(ValuesOut<'a>),
}

impl LaneOut<'_, '_, '_> {
    /// Whether the last lane zeroes the accumulators it reads.
    #[inline(always)]
    fn clears(&self) -> bool {
        matches!(self, LaneOut::Chunk(_))
    }

    /// Free slots for a span of `lanes` lanes (at least 1 while the output has room).
    #[inline(always)]
    pub(super) fn room(&self, lanes: usize) -> usize {
        match self {
            LaneOut::Chunk(c) => c.room(),
            LaneOut::Values(v) => v.room(lanes),
        }
    }

    /// The next `n <= room(lanes)` slots of `f` and of the accumulators (the accumulators are
    /// only read for a span of several lanes); `None` when there are none.
    #[inline(always)]
    pub(super) fn slots(&mut self, n: usize) -> Option<(&mut [TexValue], &mut [i64])> {
        match self {
            LaneOut::Chunk(c) => {
                let c = &mut *c.chunk;
                let at = c.len;
                Some((c.f.get_mut(at..at + n)?, c.gx.get_mut(at..at + n)?))
            }
            LaneOut::Values(v) => v.slots(n),
        }
    }

    /// Marks `n` slots as filled.
    #[inline(always)]
    pub(super) fn advance(&mut self, n: usize) {
        match self {
            LaneOut::Chunk(c) => c.advance(n),
            LaneOut::Values(v) => v.at += n,
        }
    }
}

/// Accumulators of [`ValuesOut`] for a span longer than [`SAMPLE_CHUNK`]: a span of several
/// lanes is walked in runs of this many pixels.
pub(super) const VALUE_RUN: usize = 64;

/// The caller's slice of values ([`SpanEvaluator::eval_values`](crate::span::SpanEvaluator::eval_values)): a span of one lane is written
/// in one run, a span of several in runs as long as the accumulators it is given.
pub(super) struct ValuesOut<'o> {
    out: &'o mut [TexValue],
    at: usize,
    acc: &'o mut [i64],
}

impl<'o> ValuesOut<'o> {
    /// Slots `out`, from its start, with accumulators `acc` (empty for a span of one lane).
    pub(super) fn new(out: &'o mut [TexValue], acc: &'o mut [i64]) -> ValuesOut<'o> {
        ValuesOut { out, at: 0, acc }
    }
}

impl ValuesOut<'_> {
    #[inline(always)]
    fn room(&self, lanes: usize) -> usize {
        let left = self.out.len().saturating_sub(self.at);
        if lanes > 1 {
            left.min(self.acc.len())
        } else {
            left
        }
    }

    #[inline(always)]
    fn slots(&mut self, n: usize) -> Option<(&mut [TexValue], &mut [i64])> {
        let at = self.at;
        let acc = self.acc.get_mut(..n.min(self.acc.len()))?;
        Some((self.out.get_mut(at..at + n)?, acc))
    }
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// [`Self::run_lanes`] into a chunk sink, without a face cache. Out of line, so that the
    /// merged loop's code around the call stays as it is without the kernel's output type.
    #[inline(never)]
    pub(super) fn run_lanes_into(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        sink: &mut ChunkSink<'_, '_>,
    ) {
        self.run_lanes(len, setup, strategies, &mut LaneOut::Chunk(sink), &mut []);
    }

    /// [`Self::run_axial_direct`] into a chunk sink (out of line, as [`Self::run_lanes_into`]).
    #[inline(never)]
    pub(super) fn run_axial_direct_into(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        sink: &mut ChunkSink<'_, '_>,
    ) {
        self.run_axial_direct(len, setup, strategies, &mut LaneOut::Chunk(sink));
    }
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// The axial kernel without gradients, lane by lane (see the module documentation); the
    /// span must have been accepted by `merged_takes` and `axial_takes`.
    #[inline(never)]
    pub(super) fn run_lanes(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        sink: &mut LaneOut<'_, '_, '_>,
        faces: &mut [FaceEntry],
    ) {
        let m = self.model;
        let fv = m.noise_frac_bits();
        let fvs = fv & 31;
        let vb = m.precision().value_bits();
        let len = u32::from(len);
        // 0: zero quadric, 1: affine, 2: curved.
        let (mut q, quad) = QuadStep::value_kind(setup);

        let mut lanes: heapless::Vec<ValueLane, T> = heapless::Vec::new();
        // The face cache's shares: in proportion to the terms' steps ([`FaceKey::share`]).
        let steps: u64 = strategies
            .iter()
            .zip(setup.terms.iter())
            .filter(|(st, _)| **st != Strategy::Off)
            .filter_map(|(_, ts)| single_axis(ts.du).map(|k| ts.du[k.min(2)]))
            .map(|d| u64::from(d.unsigned_abs()))
            .sum();
        let mut base = 0usize;
        for ((term, st), ts) in m.terms().iter().zip(strategies).zip(setup.terms.iter()) {
            if *st == Strategy::Off {
                continue;
            }
            let Some(k) = single_axis(ts.du) else {
                continue;
            };
            let k = k.min(2);
            let (cell, frac) = split(ts.u0);
            let d = ts.du[k];
            let (hash, amp) = (term.basis.hash, ts.amp);
            let share = FaceKey::share(faces.len(), d.unsigned_abs(), steps);
            let key = FaceKey::new(base, share, k, hash, cell, frac, amp, fv, vb);
            base = base.wrapping_add(share);
            let phi = [
                lane_phi(faces, &key, k, hash, cell, frac, 0, amp, fv, vb),
                lane_phi(faces, &key, k, hash, cell, frac, 1, amp, fv, vb),
            ];
            let (v, s) = value_and_step(phi, frac[k], d);
            let lane = ValueLane {
                left: pixels_in_cell_axis(frac[k], d),
                v,
                s,
                k,
                u0: ts.u0[k],
                d,
                cell,
                frac,
                phi,
                hash,
                amp,
                key,
            };
            // At most T terms: never full.
            let _ = lanes.push(lane);
        }
        let nl = lanes.len();
        let mut setups = nl as u64;
        let clear = sink.clears();

        let mut i = 0u32;
        // One lane, no quadric, room for the whole span (the caller's slice of values): one walk
        // a cell, straight into the output.
        if let ([t], 0, true) = (lanes.as_mut_slice(), quad, sink.room(1) >= len as usize) {
            if let Some((out, _)) = sink.slots(len as usize) {
                let mut j = 0usize;
                let mut rest = out;
                loop {
                    let (r, tail) = rest.split_at_mut((t.left as usize).min(rest.len()));
                    walk_out::<false, false, true, true>(r, &mut [], fvs, &mut t.v, t.s, &mut q);
                    j += r.len();
                    if tail.is_empty() {
                        break;
                    }
                    rest = tail;
                    t.event(j as u32, fv, vb, faces);
                    setups += 1;
                }
                sink.advance(len as usize);
                i = len;
            }
        }
        while i < len {
            let n = ((len - i) as usize).min(sink.room(nl));
            // A chunk's accumulators are its gradient slots, zero without gradients: they are
            // zeroed again as they are read, before the chunk is handed over.
            let Some((out, acc)) = sink.slots(n) else {
                break;
            };
            if n == 0 {
                break;
            }
            for (li, t) in lanes.iter_mut().enumerate() {
                let role = match (li == 0, li + 1 == nl) {
                    (true, true) => Role::Only,
                    (true, false) => Role::First,
                    (false, true) => Role::Last,
                    (false, false) => Role::Add,
                };
                let mut j = 0usize;
                loop {
                    let run = (n - j).min(t.left as usize);
                    if let Some(o) = out.get_mut(j..j + run) {
                        let a = acc.get_mut(j..j + run).unwrap_or_default();
                        walk(clear, role, quad, a, o, fvs, &mut t.v, t.s, &mut q);
                    }
                    j += run;
                    t.left -= run as u32;
                    if t.left == 0 && i + (j as u32) < len {
                        t.event(i + j as u32, fv, vb, faces);
                        setups += 1;
                    }
                    if j >= n {
                        break;
                    }
                }
            }
            sink.advance(n);
            i += n as u32;
        }

        let px = u64::from(len);
        let st = &mut self.stats;
        st.cell_setups += setups;
        st.noise_evaluations += px * nl as u64;
        st.fd_pixels += px;
        #[cfg(test)]
        {
            self.axial_spans += 1;
        }
    }
}
