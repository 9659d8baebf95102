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
//!
//! # Carried lanes
//!
//! Through a [`FaceCache`](super::FaceCache) with room for the span's lanes, the lanes live in
//! the cache and stay there after the span, each lattice start moved on to the pixel after
//! the span. The next span takes them as they are when, term by term, they are what its own
//! set-up would build: the same moving axis and step, the same lattice point at pixel 0, the
//! same cell and fractions on the two other axes, hash, amplitude, noise fraction bits and
//! value precision (`Carried::resumes`). A lane's state is a function of exactly these: `v`
//! and `s` are the cell polynomial at the current fraction (the same sum modulo 2^64 whether
//! stepped or set up), `left` counts the pixels to the cell's end either way, and the face
//! blends are the cell's. A lane that ended on its cell's last pixel moves into the next cell
//! first, as an event at pixel 0 (a cell set-up, counted as such). So a row handed over in
//! short spans, one after the other, sets up the cells the whole row in one span does (tested:
//! the same values as each span on its own and as `Direct`, and the same `cell_setups` as the
//! whole row), while any other span is set up from scratch. Nothing is carried past a span
//! that was not walked to its end.

use super::face_cache::{cached_phi, fill, FaceEntry, FaceKey, Faces};
use super::*;

/// One term of the lane kernel.
#[derive(Clone, Copy, Debug)]
pub(super) struct ValueLane {
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
    /// The term's set-up the lane was made for: its lattice point at pixel 0 (moved on to the
    /// pixel after the span once the span is walked) and its lattice step.
    at: [i32; 3],
    du: [i32; 3],
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

/// What the lane slots of a [`FaceCache`] hold: the `n` lanes of the last span, made for `fv`
/// noise fraction bits and value precision `vb` (`n = 0`: none).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Carried {
    n: u8,
    fv: u32,
    vb: u32,
}

impl Carried {
    /// Nothing carried.
    pub(super) const NONE: Carried = Carried { n: 0, fv: 0, vb: 0 };

    /// Whether the carried `lanes` are the lanes of a span set up as `setup` (with
    /// `strategies`, for `model`): for every active term in order, the same lattice point at
    /// pixel 0 (the lane's `at`, moved on to the pixel after its span), lattice step,
    /// amplitude and hash, and the same noise fraction bits and value precision. A lane's
    /// state (moving axis, `v`, `s`, `left`, the cell and its blends, the cache key) is a
    /// function of these alone (the cache key's share too: the steps of all the lanes), so
    /// such a lane is the fresh one, except when it has walked to the end of its cell
    /// (`left = 0`): the caller then moves it into the next cell.
    #[inline(always)]
    fn resumes<const T: usize>(
        &self,
        lanes: &[ValueLane],
        model: &TextureModel<T>,
        strategies: &[Strategy; T],
        setup: &Setup<T>,
        fv: u32,
        vb: u32,
    ) -> bool {
        if usize::from(self.n) != lanes.len() || self.fv != fv || self.vb != vb {
            return false;
        }
        let mut lanes = lanes.iter();
        for ((term, st), ts) in model.terms().iter().zip(strategies).zip(setup.terms.iter()) {
            if *st == Strategy::Off {
                continue;
            }
            let Some(t) = lanes.next() else {
                return false;
            };
            // Word by word (an array comparison is a library call on the devices).
            let (u, d) = (&ts.u0, &ts.du);
            let differ = (u[0] ^ t.at[0])
                | (u[1] ^ t.at[1])
                | (u[2] ^ t.at[2])
                | (d[0] ^ t.du[0])
                | (d[1] ^ t.du[1])
                | (d[2] ^ t.du[2])
                | (ts.amp ^ t.amp);
            if differ != 0 || t.hash != term.basis.hash {
                return false;
            }
        }
        lanes.next().is_none()
    }
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
    if faces.is_empty() {
        return face_phi(k, hash, cell, frac, b, amp, fv, vb);
    }
    let face = cell[k.min(2)].wrapping_add(b as u16);
    let miss = |w| fill(w, k, hash, cell, b, amp, fv, vb);
    match cached_phi(faces, key, face, miss) {
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

/// Pushes [`ValueLane::fresh`] onto `lanes` (the lanes of a span that are not carried; at most
/// `T` terms: never full). Out of line, as [`ValueLane::start`].
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn push_fresh<const T: usize>(
    lanes: &mut heapless::Vec<ValueLane, T>,
    k: usize,
    ts: &TermSetup,
    hash: HashKind,
    base: usize,
    share: usize,
    fv: u32,
    vb: u32,
    faces: &mut [FaceEntry],
) {
    let _ = lanes.push(ValueLane::fresh(k, ts, hash, base, share, fv, vb, faces));
}

impl ValueLane {
    /// A slot that holds no lane.
    pub(super) const IDLE: ValueLane = ValueLane {
        left: 0,
        v: 0,
        s: 0,
        k: 0,
        u0: 0,
        d: 0,
        at: [0; 3],
        du: [0; 3],
        cell: [0; 3],
        frac: [0; 3],
        phi: [0; 2],
        hash: HashKind::Integer,
        amp: 0,
        key: FaceKey::NONE,
    };

    /// The fresh lane of a term set up as `ts` (`hash`), moving along `k`, with the face
    /// cache's share `base .. base + share` (`faces`: empty for none).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn fresh(
        k: usize,
        ts: &TermSetup,
        hash: HashKind,
        base: usize,
        share: usize,
        fv: u32,
        vb: u32,
        faces: &mut [FaceEntry],
    ) -> ValueLane {
        let k = k.min(2);
        let (cell, frac) = split(ts.u0);
        let d = ts.du[k];
        let amp = ts.amp;
        let key = FaceKey::new(base, share, k, hash, cell, frac, amp, fv, vb);
        let phi = [
            lane_phi(faces, &key, k, hash, cell, frac, 0, amp, fv, vb),
            lane_phi(faces, &key, k, hash, cell, frac, 1, amp, fv, vb),
        ];
        let (v, s) = value_and_step(phi, frac[k], d);
        ValueLane {
            left: pixels_in_cell_axis(frac[k], d),
            v,
            s,
            k,
            u0: ts.u0[k],
            d,
            at: ts.u0,
            du: ts.du,
            cell,
            frac,
            phi,
            hash,
            amp,
            key,
        }
    }

    /// Becomes [`ValueLane::fresh`] (a carried lane's slot). Out of line: one copy, with
    /// registers of its own, that writes the lane in place.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn start(
        &mut self,
        k: usize,
        ts: &TermSetup,
        hash: HashKind,
        base: usize,
        share: usize,
        fv: u32,
        vb: u32,
        faces: &mut [FaceEntry],
    ) {
        *self = ValueLane::fresh(k, ts, hash, base, share, fv, vb, faces);
    }

    /// The blend of face `b` of the current cell, whose coordinate along the moving axis is
    /// `cell` (through `faces` when it has entries: a hit reads only the key and the entry).
    #[inline(always)]
    fn blend(&self, cell: u16, b: usize, fv: u32, vb: u32, faces: &mut [FaceEntry]) -> i64 {
        let (k, h, a) = (self.k, self.hash, self.amp);
        if faces.is_empty() {
            return face_phi(k, h, self.cell, self.frac, b, a, fv, vb);
        }
        let face = cell.wrapping_add(b as u16);
        let miss = |w| fill(w, k, h, self.cell, b, a, fv, vb);
        match cached_phi(faces, &self.key, face, miss) {
            Some(phi) => phi,
            None => face_phi(k, h, self.cell, self.frac, b, a, fv, vb),
        }
    }

    /// [`ValueLane::event`] out of line: for the events of one-lane spans and of carried lanes
    /// that ended on their cell's last pixel (one copy; the shared walk keeps its own inline).
    #[inline(never)]
    fn event_apart(&mut self, i: u32, fv: u32, vb: u32, faces: &mut [FaceEntry]) {
        self.event(i, fv, vb, faces);
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
            1 => [self.phi[1], self.blend(cell, 1, fv, vb, faces)],
            0xFFFF => [self.blend(cell, 0, fv, vb, faces), self.phi[0]],
            _ => [
                self.blend(cell, 0, fv, vb, faces),
                self.blend(cell, 1, fv, vb, faces),
            ],
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
    /// The first of several with the quadric folded into the accumulators ([`fold_quadric`]).
    FirstFolded,
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

/// `run` pixels of the first lane from `(v, s)` into the accumulators `acc`, each with the folded
/// affine quadric `qf = [Q, dQ]` added (`Q` the quadric shifted left by the value shift, stepped
/// with it; see [`fold_quadric`]). The sum of two affine sequences is one: the run stores
/// `y = v + Q` stepped by `s + dQ` (a store a pixel, as [`Role::First`]), then moves `Q` on by
/// `run dQ` and takes `v` back as `y - Q`, every step wrapping modulo 2^64 as the two walks'
/// (the same accumulators, `v` and `Q`).
#[inline(always)]
fn walk_acc_folded(acc: &mut [i64], v: &mut i64, s: i64, qf: &mut [i64; 2]) {
    let [q, dq] = *qf;
    let mut y = v.wrapping_add(q);
    walk_acc::<false>(acc, &mut y, s.wrapping_add(dq));
    let q = q.wrapping_add(dq.wrapping_mul(acc.len() as i64));
    *v = y.wrapping_sub(q);
    qf[0] = q;
}

/// Whether the affine quadric `q = [q0, dq, 0]` (48 fraction bits, wrapping i64) of a span of
/// `len` pixels can be folded into the first lane's accumulators, shifted left by the value
/// shift `fv` (`4 <= fv <= 16`, the model's noise fraction bits), so that the last lane writes
/// `f = ((A >> 32) as i32) >> fv` from their sum `A = (q << fv) + N` (wrapping) instead of
/// `f = (q + (N >> fv)) >> 32`: the fast shape's last lane then holds no quadric and shifts one
/// word. Both give bits 32.. of `B = q + (N >> fv)` (mod 2^64), the first sign-extended from bit
/// `63 - fv`, so they agree exactly when `B` lies in `[-2^(63 - fv), 2^(63 - fv))`. The noise
/// sum is bounded by the model (`|N >> fv| <= sumA 2^48 <= 2^(61 - fv)`, `docs/model.md` 4.4),
/// and the quadric is checked at both ends of the span (an affine quadric lies between them):
/// `|q| <= 2^(62 - fv)` gives `|B| <= 3 2^(61 - fv)`. Never in the size-lean shape.
#[inline(always)]
fn fold_quadric(q: &[i64; 3], quad: u8, len: u32, fv: u32) -> bool {
    if cfg!(texcore_lean) || quad != 1 || !(4..=16).contains(&fv) || len == 0 {
        return false;
    }
    let limit = 1i128 << (62 - fv);
    let first = i128::from(q[0]);
    let last = first + i128::from(q[1]) * i128::from(len - 1);
    first.abs() <= limit && last.abs() <= limit
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
    if ADD && NOQ {
        // The last lane without a quadric (or with it folded into the first lane's
        // accumulators): the samples and the accumulators zipped, one counter.
        for (o, a) in out.iter_mut().zip(acc.iter_mut()) {
            let n = a.wrapping_add(x);
            if CLEAR {
                *a = 0;
            }
            *o = TexValue::from_bits(((n >> 32) as i32) >> fvs);
            x = x.wrapping_add(s);
        }
        *v = x;
        return;
    }
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

/// `run` pixels of a lane that writes the samples: the only lane (`last` false) or the last of
/// several (`last`: plus the accumulators; `clear`: zeroing them as it reads them), `quad` the
/// quadric's kind (zero, affine, curved). The accumulating roles have their own run loops in
/// [`walk_lanes`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn walk_samples(
    clear: bool,
    last: bool,
    quad: u8,
    acc: &mut [i64],
    out: &mut [TexValue],
    fvs: u32,
    v: &mut i64,
    s: i64,
    q: &mut [i64; 3],
) {
    match (last, quad) {
        (false, 0) => walk_out::<false, false, true, true>(out, acc, fvs, v, s, q),
        (false, 1) => walk_out::<false, false, false, true>(out, acc, fvs, v, s, q),
        (false, _) => walk_out::<false, false, false, false>(out, acc, fvs, v, s, q),
        (true, 0) if clear => walk_out::<true, true, true, true>(out, acc, fvs, v, s, q),
        (true, 1) if clear => walk_out::<true, true, false, true>(out, acc, fvs, v, s, q),
        (true, _) if clear => walk_out::<true, true, false, false>(out, acc, fvs, v, s, q),
        (true, 0) => walk_out::<true, false, true, true>(out, acc, fvs, v, s, q),
        (true, 1) => walk_out::<true, false, false, true>(out, acc, fvs, v, s, q),
        (true, _) => walk_out::<true, false, false, false>(out, acc, fvs, v, s, q),
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
        self.run_lanes::<false>(
            len,
            setup,
            strategies,
            &mut LaneOut::Chunk(sink),
            &mut Faces::none(),
        );
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

/// The walk of a span's `lanes` over `len` pixels into `sink` (the quadric stepped from `q`,
/// `quad` its kind: 0 zero, 1 affine, 2 curved), each lane's cell events through `faces`.
/// Returns the pixels walked and the cell events. Out of line: one copy for the kernel with a
/// cache and the one without.
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn walk_lanes(
    lanes: &mut [ValueLane],
    len: u32,
    mut q: [i64; 3],
    quad: u8,
    fv: u32,
    vb: u32,
    sink: &mut LaneOut<'_, '_, '_>,
    faces: &mut [FaceEntry],
) -> (u32, u32) {
    let nl = lanes.len();
    let fvs = fv & 31;
    // At most a lane's pixels times the lanes (`len < 2^16`): a word.
    let mut events = 0u32;
    let clear = sink.clears();
    // The affine quadric folded into the first lane's accumulators where a bound allows it
    // (`fold_quadric`): the last lane then writes as without a quadric.
    let folded = nl > 1 && fold_quadric(&q, quad, len, fv);
    let mut qf = [q[0].wrapping_shl(fvs), q[1].wrapping_shl(fvs)];
    let quad = if folded { 0 } else { quad };
    let mut i = 0u32;
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
                (true, false) if folded => Role::FirstFolded,
                (true, false) => Role::First,
                (false, true) => Role::Last,
                (false, false) => Role::Add,
            };
            let ev = (i, len, fv, vb);
            // The accumulating roles and the usual last one each with a loop of its own (the
            // role known in it); the other writing ones through the dispatch of `walk_samples`.
            match (role, quad, clear) {
                (Role::FirstFolded, _, _) => lane_runs(t, out, acc, ev, faces, &mut events, {
                    let qf = &mut qf;
                    move |a, _, v, s| walk_acc_folded(a, v, s, qf)
                }),
                (Role::First, _, _) => {
                    lane_runs(t, out, acc, ev, faces, &mut events, |a, _, v, s| {
                        walk_acc::<false>(a, v, s)
                    })
                }
                (Role::Add, _, _) => {
                    lane_runs(t, out, acc, ev, faces, &mut events, |a, _, v, s| {
                        walk_acc::<true>(a, v, s)
                    })
                }
                (Role::Last, 0, false) => {
                    lane_runs(t, out, acc, ev, faces, &mut events, |a, o, v, s| {
                        walk_out::<true, false, true, true>(o, a, fvs, v, s, &mut [0; 3])
                    })
                }
                _ => {
                    let last = role == Role::Last;
                    lane_runs(t, out, acc, ev, faces, &mut events, |a, o, v, s| {
                        walk_samples(clear, last, quad, a, o, fvs, v, s, &mut q)
                    })
                }
            }
        }
        sink.advance(n);
        i += n as u32;
    }
    (i, events)
}

/// One lane's runs over a chunk of `out.len()` pixels starting at span pixel `i` of `len`
/// (`ev = (i, len, fv, vb)`): `w` walks each run of the lane's cell (the accumulators, the
/// samples, `v` and `s`), and the lane's cell events between runs go through `faces`, counted
/// in `events`.
#[inline(always)]
fn lane_runs(
    t: &mut ValueLane,
    out: &mut [TexValue],
    acc: &mut [i64],
    ev: (u32, u32, u32, u32),
    faces: &mut [FaceEntry],
    events: &mut u32,
    mut w: impl FnMut(&mut [i64], &mut [TexValue], &mut i64, i64),
) {
    let (i, len, fv, vb) = ev;
    let n = out.len();
    let mut j = 0usize;
    loop {
        let run = (n - j).min(t.left as usize);
        if let Some(o) = out.get_mut(j..j + run) {
            let a = acc.get_mut(j..j + run).unwrap_or_default();
            w(a, o, &mut t.v, t.s);
        }
        j += run;
        t.left -= run as u32;
        if t.left == 0 && i + (j as u32) < len {
            t.event(i + j as u32, fv, vb, faces);
            *events += 1;
        }
        if j >= n {
            break;
        }
    }
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// The axial kernel without gradients, lane by lane (see the module documentation); the
    /// span must have been accepted by `merged_takes` and `axial_takes`.
    #[inline(never)]
    pub(super) fn run_lanes<const CACHE: bool>(
        &mut self,
        len: u16,
        setup: &Setup<T>,
        strategies: &[Strategy; T],
        sink: &mut LaneOut<'_, '_, '_>,
        faces: &mut Faces<'_>,
    ) {
        let m = self.model;
        let fv = m.noise_frac_bits();
        let vb = m.precision().value_bits();
        let len = u32::from(len);
        // 0: zero quadric, 1: affine, 2: curved.
        let q = QuadStep::value_kind(setup);

        let Faces {
            entries,
            lanes: slots,
            carried,
            ..
        } = faces;
        // Without a cache (`CACHE` false: the chunk path) the set-up is compiled for empty
        // entries and no lane slots (no look-ups, no shares, no carrying).
        let (faces, slots, carried): (&mut [FaceEntry], &mut [ValueLane], _) = if CACHE {
            (entries, slots, carried.as_deref_mut())
        } else {
            (&mut [], &mut [], None)
        };
        // The lanes live in the cache's slots when it has room for them all (and are then
        // carried to the next span), otherwise here.
        let nl = strategies.iter().filter(|st| **st != Strategy::Off).count();
        let mut local: heapless::Vec<ValueLane, T> = heapless::Vec::new();
        let (slots, carried) = match (slots.get_mut(..nl), carried) {
            (Some(sl), Some(c)) => (sl, Some(c)),
            _ => (&mut [][..], None),
        };
        // At most the lanes' pixels and starts (`len < 2^16`, `T` lanes): a word.
        let mut setups = 0u32;
        let resumed = carried
            .as_deref()
            .is_some_and(|c| c.resumes(slots, m, strategies, setup, fv, vb));
        let lanes: &mut [ValueLane] = if resumed {
            // The span goes on from where the last one ended: each lane is in the state a
            // fresh one would be in, but for a cell it has yet to enter (`left = 0`: that
            // lane's cell event at pixel 0).
            for t in slots.iter_mut().filter(|t| t.left == 0) {
                t.event_apart(0, fv, vb, faces);
                setups += 1;
            }
            slots
        } else {
            let carrying = carried.is_some();
            // The face cache's shares: in proportion to the terms' steps ([`FaceKey::share`]).
            // (Without a cache every share is 1: no sum.)
            let steps: u64 = if faces.is_empty() {
                0
            } else {
                strategies
                    .iter()
                    .zip(setup.terms.iter())
                    .filter(|(st, _)| **st != Strategy::Off)
                    .filter_map(|(_, ts)| single_axis(ts.du).map(|k| ts.du[k.min(2)]))
                    .map(|d| u64::from(d.unsigned_abs()))
                    .sum()
            };
            let mut base = 0usize;
            let mut li = 0usize;
            for ((term, st), ts) in m.terms().iter().zip(strategies).zip(setup.terms.iter()) {
                if *st == Strategy::Off {
                    continue;
                }
                let Some(k) = single_axis(ts.du) else {
                    continue;
                };
                let k = k.min(2);
                let share = FaceKey::share(faces.len(), ts.du[k].unsigned_abs(), steps);
                let hash = term.basis.hash;
                if carrying {
                    if let Some(slot) = slots.get_mut(li) {
                        slot.start(k, ts, hash, base, share, fv, vb, faces);
                    }
                } else {
                    push_fresh(&mut local, k, ts, hash, base, share, fv, vb, faces);
                }
                base = base.wrapping_add(share);
                li += 1;
                setups += 1;
            }
            if carrying {
                slots.get_mut(..li).unwrap_or_default()
            } else {
                &mut local
            }
        };
        let nl = lanes.len();
        // One lane, room for the whole span (the caller's slice of values or a chunk): one walk
        // a cell, straight into the output (inline in each kernel: the spans of one octave);
        // any other span through the shared walk. Without a quadric, or (without a cache: the
        // chunk path's shading) with an affine one; more forms would not fit the Cortex-M4F
        // job-suite firmware's flash.
        let mut one = None;
        let inline = q.1 == 0 || (!CACHE && q.1 == 1);
        if let ([t], true, true) = (&mut *lanes, inline, sink.room(1) >= len as usize) {
            if let Some((out, _)) = sink.slots(len as usize) {
                let fvs = fv & 31;
                let mut qs = q.0;
                let mut j = 0usize;
                let mut rest = out;
                loop {
                    let (r, tail) = rest.split_at_mut((t.left as usize).min(rest.len()));
                    match q.1 {
                        0 => walk_out::<false, false, true, true>(
                            r,
                            &mut [],
                            fvs,
                            &mut t.v,
                            t.s,
                            &mut qs,
                        ),
                        _ => walk_out::<false, false, false, true>(
                            r,
                            &mut [],
                            fvs,
                            &mut t.v,
                            t.s,
                            &mut qs,
                        ),
                    }
                    j += r.len();
                    t.left -= r.len() as u32;
                    if tail.is_empty() {
                        break;
                    }
                    rest = tail;
                    t.event_apart(j as u32, fv, vb, faces);
                    setups += 1;
                }
                sink.advance(len as usize);
                one = Some(len);
            }
        }
        let i = match one {
            Some(i) => i,
            None => {
                // The faces hidden from the optimiser: one copy of the walk for both kernels.
                let faces = core::hint::black_box(&mut *faces);
                let (i, events) = walk_lanes(lanes, len, q.0, q.1, fv, vb, sink, faces);
                setups += events;
                i
            }
        };

        // Carried to the next span: every lane's `u0` moved on to the pixel after this span
        // (only when the whole span was walked).
        if let Some(c) = carried {
            let done = i >= len;
            if done {
                for t in lanes.iter_mut() {
                    t.u0 = t.u0.wrapping_add(t.d.wrapping_mul(len as i32));
                    for (a, d) in t.at.iter_mut().zip(t.du) {
                        *a = a.wrapping_add(d.wrapping_mul(len as i32));
                    }
                }
            }
            *c = Carried {
                n: if done { nl as u8 } else { 0 },
                fv,
                vb,
            };
        }

        let px = u64::from(len);
        let st = &mut self.stats;
        st.cell_setups += u64::from(setups);
        st.noise_evaluations += px * nl as u64;
        st.fd_pixels += px;
        #[cfg(test)]
        {
            self.axial_spans += 1;
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    extern crate std;
    use std::vec;

    use super::*;
    use crate::format::{Amplitude, MatrixEntry};
    use crate::model::Octaves;
    use crate::noise::NoiseBasis;
    use crate::quadric::Quadric;
    use crate::span::FaceCache;
    use crate::transform::Affine3;

    /// `octaves` trilinear value-noise octaves scaled by `2^zoom` (no rotation, no quadric), of
    /// amplitude `amp` and `hash`: the single-axis models of the lane and axial kernels' tests.
    pub(in crate::span) fn model(
        octaves: u8,
        zoom: u32,
        amp: f64,
        hash: HashKind,
        wrap: TableWrap,
    ) -> TextureModel<8> {
        let mut m: TextureModel<8> = TextureModel::new(Quadric::ZERO, wrap);
        m.push_octaves(&Octaves {
            count: octaves,
            base: Affine3::scale(MatrixEntry::from_num(1u32 << zoom)),
            amplitude: Amplitude::from_num(amp),
            rotate: false,
            basis: NoiseBasis::trilinear(hash),
            turbulence: false,
        })
        .unwrap();
        m
    }

    fn opts(mode: EvalMode) -> EvalOptions {
        EvalOptions {
            mode,
            gradients: false,
            cull: true,
            ..Default::default()
        }
    }

    /// `len` pixels of the row through `s0` with step `ds`, starting `x` pixels in.
    fn piece(s0: [i32; 3], ds: [i32; 3], x: u16, len: u16) -> Span {
        let at = |i: usize| s0[i].wrapping_add(ds[i].wrapping_mul(i32::from(x)));
        Span {
            s0: TexPoint::from_bits(at(0), at(1), at(2)),
            ds: TexPoint::from_bits(ds[0], ds[1], ds[2]),
            dsdy: TexPoint::from_bits(0, 0, 0),
            len,
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        /// A row cut into pieces of random lengths and evaluated piece after piece through a
        /// face cache (the lanes carried from piece to piece) gives every piece's values as
        /// evaluated on its own and by `Direct`, whatever comes in between (a span elsewhere,
        /// another model through the same cache); and, the pieces being contiguous, it sets up
        /// as many cells as the whole row in one span (so the lanes were carried, not rebuilt).
        #[test]
        fn carried_lanes_are_fresh_lanes(
            s0 in proptest::array::uniform3(-4_000_000i32..4_000_000),
            step in 1i32..40_000,
            negative: bool,
            axis in 0usize..3,
            across in 1usize..3,
            row in -9_000i32..9_000,
            octaves in 1u8..7,
            zoom in 0u32..3,
            cuts in proptest::collection::vec(1u16..40, 1..12),
            interleave: bool,
            clamp: bool,
        ) {
            let wrap = if clamp { TableWrap::Clamp } else { TableWrap::Mod };
            let m = model(octaves, zoom, 0.6, HashKind::Integer, wrap);
            let other_m = model(3, 1, -0.35, HashKind::default(), TableWrap::Mod);
            let mut ds = [0; 3];
            let d = step >> (2 * zoom) | 1;
            ds[axis] = if negative { -d } else { d };
            let mut c4 = FaceCache::<64>::new();
            let mut c8 = FaceCache::<64, 8>::new();
            let mut fd4 = SpanEvaluator::new(&m, opts(EvalMode::Fd));
            let mut fd8 = SpanEvaluator::new(&m, opts(EvalMode::Fd));
            let mut plain = SpanEvaluator::new(&m, opts(EvalMode::Fd));
            let mut direct = SpanEvaluator::new(&m, opts(EvalMode::Direct));
            let mut other = SpanEvaluator::new(&other_m, opts(EvalMode::Fd));
            let total: u16 = cuts.iter().sum();
            for y in 0..3 {
                let mut s = s0;
                let o = (axis + across) % 3;
                s[o] = s[o].wrapping_add(row.wrapping_mul(y));
                let (before4, before8) = (fd4.stats().cell_setups, fd8.stats().cell_setups);
                let mut x = 0u16;
                for (i, &n) in cuts.iter().enumerate() {
                    let sp = piece(s, ds, x, n);
                    let k = usize::from(n);
                    let mut want = vec![TexValue::ZERO; k];
                    let mut d_ = vec![TexValue::ZERO; k];
                    plain.eval_values(&sp, &mut want);
                    direct.eval_values(&sp, &mut d_);
                    proptest::prop_assert_eq!(&want, &d_);
                    let (mut a, mut b) = (vec![TexValue::ZERO; k], vec![TexValue::ZERO; k]);
                    fd4.eval_values_cached(&sp, &mut a, &mut c4);
                    fd8.eval_values_cached(&sp, &mut b, &mut c8);
                    proptest::prop_assert_eq!(&a, &want, "row {} piece {}", y, i);
                    proptest::prop_assert_eq!(&b, &want, "row {} piece {}", y, i);
                    if interleave && i % 3 == 1 {
                        // Something else through the same caches in between.
                        let away = piece([s[0] ^ 0x5_0000, s[1], s[2]], ds, 7, 9);
                        let mut e = [TexValue::ZERO; 9];
                        let mut f = [TexValue::ZERO; 9];
                        other.eval_values_cached(&away, &mut e, &mut c4);
                        SpanEvaluator::new(&other_m, opts(EvalMode::Direct)).eval_values(&away, &mut f);
                        proptest::prop_assert_eq!(e, f);
                        fd8.eval_values_cached(&away, &mut e, &mut c8);
                        SpanEvaluator::new(&m, opts(EvalMode::Direct)).eval_values(&away, &mut f);
                        proptest::prop_assert_eq!(e, f);
                    }
                    x += n;
                }
                if !interleave {
                    // The whole row in one span sets up the same cells (the lane kernel takes
                    // the pieces whenever it takes the row).
                    let mut whole = SpanEvaluator::new(&m, opts(EvalMode::Fd));
                    let mut w = vec![TexValue::ZERO; usize::from(total)];
                    whole.eval_values(&piece(s, ds, 0, total), &mut w);
                    let cells = whole.stats().cell_setups;
                    if whole.core.axial_spans == 1 && fd8.core.axial_spans > 0 {
                        proptest::prop_assert_eq!(fd8.stats().cell_setups - before8, cells);
                        if octaves <= 4 {
                            proptest::prop_assert_eq!(fd4.stats().cell_setups - before4, cells);
                        }
                    }
                }
            }
        }
    }

    /// The folded first lane's run is the two walks it replaces: the lane `v + i s` and the
    /// quadric `Q + i dQ` added pixel by pixel, and both moved on by the run, modulo 2^64.
    #[test]
    fn folded_walk_is_the_two_walks() {
        let mut rng = crate::test_rng::XorShift64::new(0x5eed_f01d);
        for round in 0..2_000 {
            let mut r = || rng.next_u64() as i64;
            let (v0, s, q0, dq) = (r(), r(), r(), r());
            let n = round % 70;
            let mut acc = vec![0i64; n];
            let (mut v, mut qf) = (v0, [q0, dq]);
            walk_acc_folded(&mut acc, &mut v, s, &mut qf);
            let (mut x, mut q) = (v0, q0);
            for (i, &a) in acc.iter().enumerate() {
                assert_eq!(a, x.wrapping_add(q), "round {round}, pixel {i}");
                x = x.wrapping_add(s);
                q = q.wrapping_add(dq);
            }
            assert_eq!((v, qf), (x, [q, dq]), "round {round}");
        }
    }

    /// A face cache's accumulators serve every span of the rows, not only the first: they are
    /// back in the cache after each span (short, long and past their length), and the values
    /// are those without a cache. (Without forward differencing, crate feature `fd`, no span
    /// takes the lane kernel and nothing takes the accumulators.)
    #[test]
    fn face_cache_accumulators_serve_every_span() {
        let m = model(4, 0, 0.5, HashKind::Integer, TableWrap::Mod);
        let mut cache = FaceCache::<64, 8>::new();
        let mut faces = cache.parts();
        for (row, len) in [(0, 10u16), (1, 64), (2, 150), (3, 7), (4, 65)] {
            let s0 = [123_456, 40_000 + 3_000 * row, -77_777];
            let span = piece(s0, [5_000, 0, 0], 0, len);
            let mut with = vec![TexValue::ZERO; usize::from(len)];
            let mut without = with.clone();
            let mut ev = SpanEvaluator::new(&m, opts(EvalMode::Fd));
            ev.values_through(&span, &mut with, &mut faces);
            assert_eq!(
                ev.core.axial_spans > 0,
                super::super::plan::FD,
                "row {row}: the lane kernel took the span exactly with forward differencing"
            );
            assert_eq!(
                faces.acc.len(),
                VALUE_RUN,
                "row {row}: the accumulators are back"
            );
            SpanEvaluator::new(&m, opts(EvalMode::Fd)).eval_values(&span, &mut without);
            assert_eq!(with, without, "row {row}");
        }
    }

    /// With no cache, or one with fewer lane slots than the span has lanes, nothing is carried:
    /// every piece is set up on its own.
    #[test]
    fn lanes_past_the_slots_are_not_carried() {
        let m = model(6, 0, 0.5, HashKind::Integer, TableWrap::Mod);
        let ds = [2048, 0, 0];
        let s0 = [12_345, 67_890, 24_248];
        let setups = |cache: Option<&mut FaceCache<64>>| {
            let mut ev = SpanEvaluator::new(&m, opts(EvalMode::Fd));
            let mut out = [TexValue::ZERO; 16];
            let mut c = cache;
            for x in (0..256).step_by(16) {
                match c.as_deref_mut() {
                    Some(c) => ev.eval_values_cached(&piece(s0, ds, x, 16), &mut out, c),
                    None => ev.eval_values(&piece(s0, ds, x, 16), &mut out),
                };
            }
            ev.stats().cell_setups
        };
        let alone = setups(None);
        assert_eq!(setups(Some(&mut FaceCache::new())), alone);
        let m4 = model(4, 0, 0.5, HashKind::Integer, TableWrap::Mod);
        let mut ev = SpanEvaluator::new(&m4, opts(EvalMode::Fd));
        let mut c = FaceCache::<64>::new();
        let mut out = [TexValue::ZERO; 16];
        for x in (0..256).step_by(16) {
            ev.eval_values_cached(&piece(s0, ds, x, 16), &mut out, &mut c);
        }
        let mut whole = SpanEvaluator::new(&m4, opts(EvalMode::Fd));
        whole.eval_values(&piece(s0, ds, 0, 256), &mut [TexValue::ZERO; 256]);
        assert_eq!(ev.stats().cell_setups, whole.stats().cell_setups);
        assert!(whole.stats().cell_setups < alone);
    }
}
