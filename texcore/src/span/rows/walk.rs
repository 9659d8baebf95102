//! The row kernels: a row's samples from its schedule (the merged value and slope stepped a
//! pixel at a time, changed at each event by `A + B w_m`), and the smooth fade's rows (the
//! fade weight per row, the non-linear cells walked per pixel).
//!
//! Guarantees: the samples are the lane kernel's, bit for bit (wrapping sums in the ring of
//! 64-bit integers, as the module `rows` states); nothing here panics.

use super::*;

/// Each term's weight along its row axis `m` in the row set up as `setup` (the fraction, or
/// its smooth fade) into `wm` (lane by lane; the others untouched): what the entries'
/// `A + B w_m` take; and whether a term has the smooth fade. Out of line: once a row, for the
/// rows and the spans of a plane.
#[cfg(not(texcore_lean))]
#[inline(never)]
pub(super) fn row_weights<const T: usize>(
    setup: &Setup<T>,
    state: &RowsState<T>,
    wm: &mut [i64; T],
) -> bool {
    let mut smooth = false;
    // Over the lanes in use (a loop, not unrolled over the `T` slots).
    for (i, lane) in state.lanes.iter().enumerate() {
        if let (Some(w), Some(ts)) = (wm.get_mut(i), setup.terms.get(lane.term)) {
            *w = i64::from(weight(lane.smooth, split(ts.u0).1[lane.m.min(2)]));
        }
        smooth |= lane.smooth;
    }
    smooth
}

/// Where the walk of a row stands between two of its pixels: the next schedule entry, the
/// pixels left in the run of the last entry applied, the merged value and slope, the merged
/// derivative across the rows and its slope, the quadric's forward differences and gradients,
/// and each term's `f_m` (fixed along the row). A row is walked from pixel 0 in one piece
/// ([`PlaneRows`]) or span by span ([`PlaneSpans`]).
#[cfg(not(texcore_lean))]
#[derive(Clone, Copy)]
pub(super) struct RowWalk<const T: usize> {
    entry: usize,
    left: u16,
    v: i64,
    s: i64,
    g: i64,
    gs: i64,
    q: QuadStep,
    fm: [i64; T],
}

#[cfg(not(texcore_lean))]
impl<const T: usize> core::fmt::Debug for RowWalk<T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("RowWalk")
            .field("entry", &self.entry)
            .field("left", &self.left)
            .finish_non_exhaustive()
    }
}

#[cfg(not(texcore_lean))]
impl<const T: usize> RowWalk<T> {
    /// The walk at pixel 0 of a row (no entry applied yet), with the quadric `q` there and
    /// every term's `f_m` zero ([`RowWalk::weights_mut`] sets them).
    #[inline(always)]
    pub(super) fn new(q: QuadStep) -> Self {
        RowWalk {
            entry: 0,
            left: 0,
            v: 0,
            s: 0,
            g: 0,
            gs: 0,
            q,
            fm: [0; T],
        }
    }

    /// Whether the quadric and its gradients are zero along the row (word by word).
    #[inline(always)]
    pub(super) fn quadric_is_zero(&self) -> bool {
        let q = &self.q;
        (q.q | q.dq | q.ddq | q.gx | q.dgx | q.gy | q.dgy) == 0
    }

    /// The next entry's index.
    #[inline(always)]
    pub(super) fn entry(&self) -> usize {
        self.entry
    }

    /// Each term's `f_m` ([`row_weights`]).
    #[inline(always)]
    pub(super) fn weights(&self) -> &[i64; T] {
        &self.fm
    }

    /// Each term's `f_m`, to be set.
    #[inline(always)]
    pub(super) fn weights_mut(&mut self) -> &mut [i64; T] {
        &mut self.fm
    }

    /// Applies the next entry: the merged value, slope and derivative across the rows change
    /// by its parts, and its run begins. `false` past the last entry.
    #[inline(always)]
    fn apply(&mut self, events: &[RowEvent]) -> bool {
        let Some(e) = events.get(self.entry) else {
            return false;
        };
        let f = self.fm.get(usize::from(e.lane)).copied().unwrap_or(0);
        self.v = wadd(self.v, wadd(e.dv[0], wmul(e.dv[1], f)));
        self.s = wadd(self.s, wadd(e.ds[0], wmul(e.ds[1], f)));
        self.g = wadd(self.g, e.dg[0]);
        self.gs = wadd(self.gs, e.dg[1]);
        self.left = e.run;
        self.entry += 1;
        true
    }

    /// Moves on by `n` pixels without writing them, and applies the entries at the pixel it
    /// reaches (the cells that pixel starts in). Every step is the walk's own sum in the ring of
    /// 64-bit integers: `m` pixels of a run add `m s` to the value and `m g_s` to the
    /// derivative across the rows, and the quadric moves on by its closed form
    /// (`q + m dq + m (m - 1) / 2 ddq`, `dq + m ddq`, each gradient `+ m` its step).
    #[inline(never)]
    pub(super) fn skip(&mut self, events: &[RowEvent], mut n: u16) {
        loop {
            while self.left == 0 {
                if !self.apply(events) {
                    return;
                }
            }
            if n == 0 {
                return;
            }
            let m = self.left.min(n);
            let mi = i64::from(m);
            self.v = wadd(self.v, wmul(self.s, mi));
            self.g = wadd(self.g, wmul(self.gs, mi));
            let q = &mut self.q;
            let tri = i64::from(u32::from(m) * u32::from(m.saturating_sub(1)) / 2);
            q.q = wadd(q.q, wadd(wmul(q.dq, mi), wmul(q.ddq, tri)));
            q.dq = wadd(q.dq, wmul(q.ddq, mi));
            q.gx = wadd(q.gx, wmul(q.dgx, mi));
            q.gy = wadd(q.gy, wmul(q.dgy, mi));
            self.left -= m;
            n -= m;
        }
    }
}

/// The next `out.len()` samples of a row from its schedule's `events` (`lanes::walk_out`, the
/// lane kernel's pixel loop, between the entries; the quadric `NOQ` zero, `AFFINE` a constant
/// step), leaving the entries at the pixel after them to the next part. Out of line: the rows
/// and the spans of a plane share it.
#[cfg(not(texcore_lean))]
#[inline(never)]
pub(super) fn walk_part<const NOQ: bool, const AFFINE: bool, const T: usize>(
    w: &mut RowWalk<T>,
    events: &[RowEvent],
    fvs: u32,
    out: &mut [TexValue],
) {
    // The walk in registers (written back at the end): the rest of the run in progress, then
    // entry after entry.
    let (entry, mut left, mut v, mut s) = (w.entry, w.left, w.v, w.s);
    let mut q = [w.q.q, w.q.dq, w.q.ddq];
    let fm = &w.fm;
    let mut rest = out;
    let mut next = events.get(entry..).unwrap_or_default().iter();
    loop {
        let n = usize::from(left).min(rest.len());
        let (run, tail) = core::mem::take(&mut rest).split_at_mut(n);
        lanes::walk_out::<false, false, NOQ, AFFINE>(run, &mut [], fvs, &mut v, s, &mut q);
        left -= n as u16;
        rest = tail;
        if rest.is_empty() {
            break;
        }
        let Some(e) = next.next() else {
            break;
        };
        let f = fm.get(usize::from(e.lane)).copied().unwrap_or(0);
        v = wadd(v, wadd(e.dv[0], wmul(e.dv[1], f)));
        s = wadd(s, wadd(e.ds[0], wmul(e.ds[1], f)));
        left = e.run;
    }
    let entry = events.len() - next.len();
    (w.entry, w.left, w.v, w.s) = (entry, left, v, s);
    [w.q.q, w.q.dq, w.q.ddq] = q;
}

/// `k` samples of a run into chunk `c` from slot `at` (`k` at most its room): the merged value
/// `v` stepped by `s` with the quadric `q` (`NOQ` zero, `AFFINE` a constant step) and, with
/// `GRADS`, the derivatives: `gx = q_x + (S >> fv)` the merged slope, `gy = q_y + (G >> fv)`
/// the merged derivative across the rows (`g` stepped by `gs`), as the axial kernel's passes
/// write them; without, the chunk's gradient slots are left as they are. The pixel loops of
/// [`row_chunks`] and [`chunk_fill`].
#[cfg(not(texcore_lean))]
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn run_samples<const GRADS: bool, const NOQ: bool, const AFFINE: bool>(
    c: &mut SampleChunk,
    at: usize,
    k: usize,
    fvs: u32,
    v: &mut i64,
    s: i64,
    g: &mut i64,
    gs: i64,
    q: &mut QuadStep,
) {
    let Some(fo) = c.f.get_mut(at..at + k) else {
        return;
    };
    let mut qq = *q;
    let mut x = *v;
    for o in fo.iter_mut() {
        *o = TexValue::from_bits(if NOQ {
            (x >> (fvs + 32)) as i32
        } else {
            (qq.q.wrapping_add(x >> fvs) >> 32) as i32
        });
        x = x.wrapping_add(s);
        if !NOQ {
            qq.q = qq.q.wrapping_add(qq.dq);
            if !AFFINE {
                qq.dq = qq.dq.wrapping_add(qq.ddq);
            }
        }
    }
    *v = x;
    if GRADS {
        if let (Some(ox), Some(oy)) = (c.gx.get_mut(at..at + k), c.gy.get_mut(at..at + k)) {
            let sx = s >> fvs;
            let mut qx = q.gx;
            for o in ox.iter_mut() {
                *o = if NOQ { sx } else { qx.wrapping_add(sx) };
                if !AFFINE {
                    qx = qx.wrapping_add(q.dgx);
                }
            }
            let mut qy = q.gy;
            let mut gg = *g;
            for o in oy.iter_mut() {
                *o = if NOQ {
                    gg >> fvs
                } else {
                    qy.wrapping_add(gg >> fvs)
                };
                gg = gg.wrapping_add(gs);
                if !AFFINE {
                    qy = qy.wrapping_add(q.dgy);
                }
            }
            *g = gg;
            q.gx = qx;
            q.gy = qy;
        }
    }
    q.q = qq.q;
    q.dq = qq.dq;
}

/// The samples of a whole row from its schedule's `events` into `sink` ([`run_samples`] run
/// by run, a chunk's room at a time; `GRADS`: with the derivatives). Inlined into the rows'
/// loop, which hands each chunk to its one consumer (the spans of a plane take
/// [`chunk_fill`]).
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn row_chunks<const GRADS: bool, const NOQ: bool, const AFFINE: bool, const T: usize>(
    events: &[RowEvent],
    fm: &[i64; T],
    fvs: u32,
    sink: &mut ChunkSink<'_, '_>,
    q: &mut QuadStep,
) {
    let (mut v, mut s, mut g, mut gs) = (0i64, 0i64, 0i64, 0i64);
    for e in events {
        let f = fm.get(usize::from(e.lane)).copied().unwrap_or(0);
        v = wadd(v, wadd(e.dv[0], wmul(e.dv[1], f)));
        s = wadd(s, wadd(e.ds[0], wmul(e.ds[1], f)));
        if GRADS {
            g = wadd(g, e.dg[0]);
            gs = wadd(gs, e.dg[1]);
        }
        let mut left = usize::from(e.run);
        while left > 0 {
            let n = left.min(sink.room());
            let at = sink.chunk.len;
            run_samples::<GRADS, NOQ, AFFINE>(sink.chunk, at, n, fvs, &mut v, s, &mut g, gs, q);
            sink.advance(n);
            left -= n;
        }
    }
}

/// The next `n` samples of a row from its walk `w` into `chunk` from its length on (`n` at
/// most its room; the caller hands it over), with the derivatives ([`run_samples`]), leaving
/// the entries at the pixel after them to the next part. Out of line, a chunk at a time, for
/// the spans of a plane.
#[cfg(not(texcore_lean))]
#[inline(never)]
pub(super) fn chunk_fill<const NOQ: bool, const AFFINE: bool, const T: usize>(
    w: &mut RowWalk<T>,
    events: &[RowEvent],
    fvs: u32,
    chunk: &mut SampleChunk,
    n: usize,
) {
    let RowWalk {
        entry,
        left,
        v,
        s,
        g,
        gs,
        q,
        fm,
    } = w;
    let mut rest = n;
    let mut at = chunk.len;
    let mut next = events.get(*entry..).unwrap_or_default().iter();
    loop {
        // The pixels of the run in progress (at most `rest`).
        let k = usize::from(*left).min(rest);
        *left -= k as u16;
        rest -= k;
        run_samples::<true, NOQ, AFFINE>(chunk, at, k, fvs, v, *s, g, *gs, q);
        at += k;
        if rest == 0 {
            break;
        }
        let Some(e) = next.next() else {
            break;
        };
        let f = fm.get(usize::from(e.lane)).copied().unwrap_or(0);
        *v = wadd(*v, wadd(e.dv[0], wmul(e.dv[1], f)));
        *s = wadd(*s, wadd(e.ds[0], wmul(e.ds[1], f)));
        *g = wadd(*g, e.dg[0]);
        *gs = wadd(*gs, e.dg[1]);
        *left = e.run;
    }
    *entry = events.len() - next.len();
}

/// The next `n` samples of a row from its walk `w` into `sink`, with their derivatives when
/// `grads` ([`chunk_fill`]) or without (the chunk's gradient slots left as they are: zero;
/// [`walk_part`] into each chunk's values), a chunk at a time, each handed over here.
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn walk_chunks<const T: usize>(
    w: &mut RowWalk<T>,
    events: &[RowEvent],
    fvs: u32,
    n: usize,
    grads: bool,
    sink: &mut ChunkSink<'_, '_>,
) {
    let noq = w.quadric_is_zero();
    let noq_value = (w.q.q | w.q.dq | w.q.ddq) == 0;
    let mut k = n;
    while k > 0 {
        let m = k.min(sink.room());
        let c = &mut *sink.chunk;
        // A quadric is stepped as curved (an affine one adds zeros: one code shape fewer).
        if grads {
            if noq {
                chunk_fill::<true, true, T>(w, events, fvs, c, m);
            } else {
                chunk_fill::<false, false, T>(w, events, fvs, c, m);
            }
        } else if let Some(fo) = c.f.get_mut(c.len..c.len + m) {
            if noq_value {
                walk_part::<true, true, T>(w, events, fvs, fo);
            } else {
                walk_part::<false, false, T>(w, events, fvs, fo);
            }
        }
        sink.advance(m);
        k -= m;
    }
}

/// Whether `b` is value noise with the smooth fade (the row schedule's non-linear cells).
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn is_smooth_value(b: &crate::noise::NoiseBasis) -> bool {
    #[cfg(feature = "smooth-fade")]
    return b.kind == crate::noise::BasisKind::Value && b.fade == crate::noise::Fade::Smooth;
    #[cfg(not(feature = "smooth-fade"))]
    {
        let _ = b;
        false
    }
}

/// The most gradient-noise terms a row schedule serves (a row of more is evaluated span by
/// span).
#[cfg(not(texcore_lean))]
pub(super) const GRADIENT_TERMS: usize = 8;

/// Whether `b` is gradient noise (the row schedule's per-pixel gradient cells, `gradient`).
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn is_gradient_basis(b: &crate::noise::NoiseBasis) -> bool {
    #[cfg(feature = "gradient-noise")]
    return b.kind == crate::noise::BasisKind::Gradient;
    #[cfg(not(feature = "gradient-noise"))]
    {
        let _ = b;
        false
    }
}

/// Keeps each term's fades along its `k` for a row of `n` pixels in `weights` (term `l` at
/// `l n`; each `w << shift`, `shift <= 15`) when they hold them all, unless they already do
/// (`made`, the weights in use): the weights in use after it (0: the fades do not fit). The rows
/// of one smooth-fade term and of gradient noise read them.
#[cfg(not(texcore_lean))]
#[inline(never)]
pub(super) fn row_fades(
    lanes: &[RowLane],
    made: usize,
    weights: &mut [u32],
    n: usize,
    shift: u32,
) -> usize {
    let all = n * lanes.len();
    let Some(w) = weights.get_mut(..all) else {
        return 0;
    };
    if made != all {
        for (lane, w) in lanes.iter().zip(w.chunks_exact_mut(n.max(1))) {
            let d = lane.du[lane.k.min(2)];
            let mut u = lane.u0k;
            for x in w.iter_mut() {
                *x = (lane.fade.apply(u as u32) as u32) << (shift & 15);
                u = u.wrapping_add(d);
            }
        }
    }
    all
}

/// The interpolation weight of fraction `f` (raw 0.16): `f`, or its smooth fade.
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn weight(smooth: bool, f: u32) -> u32 {
    #[cfg(feature = "smooth-fade")]
    if smooth {
        return crate::noise::Fade::Smooth.apply(f) as u32;
    }
    let _ = smooth;
    f
}

/// The smooth fade of fraction `a` (raw 0.16) in 32-bit words: `Fade::apply`'s
/// `(3 a^2 2^16 - 2 a^3 + 2^31) >> 32` as `(a^2 (3 2^16 - 2 a) + 2^31) >> 32`, one 32 x 32-bit
/// product (`a^2 < 2^32`, `3 2^16 - 2 a < 2^18`).
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn smooth_fade(a: u32) -> i64 {
    let a = a & 0xFFFF;
    let p = u64::from(a * a) * u64::from(0x30000 - 2 * a);
    ((p + (1 << 31)) >> 32) as i64
}

/// The samples of a row with smooth-fade terms (as [`walk_part`]): the linear terms' merged
/// value and slope, plus each smooth term's `D w(j)`, `w(j)` the fade of its fraction along `k`
/// ([`smooth_fade`]), the lattice coordinate stepped a pixel at a time; a row of one smooth term
/// without quadric reads its fades from `table` when it holds them.
#[cfg(not(texcore_lean))]
#[allow(clippy::too_many_arguments)]
#[inline(never)]
pub(super) fn smooth_walk<const T: usize>(
    events: &[RowEvent],
    lanes: &heapless::Vec<RowLane, T>,
    wm: &[i64; T],
    fvs: u32,
    out: &mut [TexValue],
    q: &mut [i64; 3],
    table: Option<&[u32]>,
) {
    let (mut v, mut s) = (0i64, 0i64);
    let mut table = table.unwrap_or_default();
    // Each smooth term's `D` and lattice coordinate along `k` (its step: `du[k]`).
    let mut dd = [0i64; T];
    let mut uk = [0i32; T];
    for (u, lane) in uk.iter_mut().zip(lanes.iter()) {
        *u = lane.u0k;
    }
    let one = lanes.len() == 1;
    let mut rest = out;
    for e in events {
        let li = usize::from(e.lane);
        let (Some(lane), Some(&f)) = (lanes.get(li), wm.get(li)) else {
            continue;
        };
        v = wadd(v, wadd(e.dv[0], wmul(e.dv[1], f)));
        if lane.smooth {
            if let Some(d) = dd.get_mut(li) {
                *d = wadd(*d, wadd(e.ds[0], wmul(e.ds[1], f)));
            }
        } else {
            s = wadd(s, wadd(e.ds[0], wmul(e.ds[1], f)));
        }
        let n = usize::from(e.run).min(rest.len());
        let (run, tail) = core::mem::take(&mut rest).split_at_mut(n);
        rest = tail;
        let [mut qq, mut dq, ddq] = *q;
        if let (Some(&d), Some(u), Some(lane), true) =
            (dd.first(), uk.first_mut(), lanes.first(), one)
        {
            // One smooth term: its value alone.
            let step = lane.du[lane.k.min(2)];
            let mut x = *u;
            let (ws, tail) = table.split_at(n.min(table.len()));
            table = tail;
            if ws.len() == n && (qq | dq | ddq) == 0 {
                // The fades from the table.
                for (o, w) in run.iter_mut().zip(ws) {
                    let n = wadd(v, wmul(d, i64::from(*w)));
                    *o = TexValue::from_bits(((n >> 32) as i32) >> fvs);
                }
                x = x.wrapping_add(step.wrapping_mul(n as i32));
            } else if (qq | dq | ddq) == 0 {
                for o in run.iter_mut() {
                    let n = wadd(v, wmul(d, smooth_fade(x as u32)));
                    *o = TexValue::from_bits(((n >> 32) as i32) >> fvs);
                    x = x.wrapping_add(step);
                }
            } else {
                for o in run.iter_mut() {
                    let n = wadd(v, wmul(d, smooth_fade(x as u32)));
                    *o = TexValue::from_bits((wadd(qq, n >> fvs) >> 32) as i32);
                    x = x.wrapping_add(step);
                    qq = wadd(qq, dq);
                    dq = wadd(dq, ddq);
                }
            }
            *u = x;
        } else {
            for o in run.iter_mut() {
                let mut n = v;
                for ((lane, d), u) in lanes.iter().zip(dd.iter()).zip(uk.iter_mut()) {
                    if lane.smooth {
                        n = wadd(n, wmul(*d, smooth_fade(*u as u32)));
                        *u = u.wrapping_add(lane.du[lane.k.min(2)]);
                    }
                }
                *o = TexValue::from_bits((wadd(qq, n >> fvs) >> 32) as i32);
                v = wadd(v, s);
                qq = wadd(qq, dq);
                dq = wadd(dq, ddq);
            }
        }
        *q = [qq, dq, ddq];
    }
}
