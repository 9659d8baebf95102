//! The row schedule: which term enters a new cell at which pixel of every row, and each
//! entry's `A` and `B` (the entering cell's start less the leaving cell's end, as functions of
//! the row's weight `w_m`), from the face blends.
//!
//! Guarantees: a schedule that does not fit the caller's [`RowCache`] is refused (`None`), never
//! truncated; the entries are exact in the ring of 64-bit integers (tested against the blends);
//! nothing here panics.

use super::*;

/// The pixels (and terms) of a row's schedule for `lanes` over `len` pixels, in order of pixel,
/// into `events` (their values left to `lane_entries`): the number of entries, `None` when
/// they do not fit.
#[cfg(not(texcore_lean))]
pub(super) fn schedule<const T: usize>(
    len: u16,
    lanes: &heapless::Vec<RowLane, T>,
    events: &mut [RowEvent],
) -> Option<usize> {
    // Each term's next cell entry (pixel 0 first).
    let mut next = [0u32; T];
    let len = u32::from(len);
    let mut used = 0usize;
    loop {
        let mut best: Option<(usize, u32)> = None;
        for (li, p) in next.iter().enumerate().take(lanes.len()) {
            if *p < len && best.is_none_or(|(_, b)| *p < b) {
                best = Some((li, *p));
            }
        }
        let Some((li, p)) = best else {
            if let Some(last) = used.checked_sub(1).and_then(|i| events.get_mut(i)) {
                last.run = (len - u32::from(last.at)) as u16;
            }
            return Some(used);
        };
        if let Some(last) = used.checked_sub(1).and_then(|i| events.get_mut(i)) {
            last.run = (p - u32::from(last.at)) as u16;
        }
        let e = events.get_mut(used)?;
        *e = RowEvent {
            at: p as u16,
            lane: li as u16,
            ..RowEvent::default()
        };
        used += 1;
        let (Some(lane), Some(n)) = (lanes.get(li), next.get_mut(li)) else {
            return None;
        };
        let k = lane.k.min(2);
        let d = lane.du[k];
        let uk = lane.u0k.wrapping_add(d.wrapping_mul(p as i32));
        *n = p.saturating_add(pixels_in_cell_axis((uk & 0xFFFF) as u32, d));
    }
}

/// `A` and `B` of a face blend `Phi = A + B f_m` (face `b` of `cell` for a term along `k`, row
/// axis `m`, fixed fraction `fo` along `o`), `Phi` being affine in `f_m` in the ring: with `a <
/// c` the two other axes and `t_j = (w_2j << 16) + (w_2j+1 - w_2j) f_a` (`axis::face`),
/// `Phi = (t_0 << 16) + (t_1 - t_0) f_c`, so for `m = c`: `A = t_0 << 16`, `B = t_1 - t_0`; for
/// `m = a` the face cache's `A` and `B` (`face_cache::blend_ab`). With `grads`, third, the
/// face's derivative across the rows `H` (`axis::face`'s `h` for the lattice step `dy` to the
/// next row, which steps along `m` alone: `H` does not depend on `f_m`); otherwise 0. Tested
/// against the blend.
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn face_ab(
    lane: &RowLane,
    hash: HashKind,
    cell: [u16; 3],
    b: usize,
    fv: u32,
    vb: u32,
    grads: bool,
) -> [i64; 3] {
    let k = lane.k.min(2);
    let w = face_bits(k, hash, cell, b, lane.amp, fv, vb);
    let h = if GRADIENTS && grads {
        let mut frac = [0u32; 3];
        if let Some(f) = frac.get_mut(lane.o) {
            *f = lane.wo;
        }
        face(&w, k, frac, lane.dy, true).h()
    } else {
        0
    };
    if lane.m < lane.o {
        let (a, b) = blend_ab(&w, lane.wo);
        return [a, b, h];
    }
    let fa = i64::from(lane.wo);
    let lerp = |v0: i32, v1: i32| {
        wadd(
            i64::from(v0) << 16,
            wmul(i64::from(v1.wrapping_sub(v0)), fa),
        )
    };
    let (t0, t1) = (lerp(w[0], w[1]), lerp(w[2], w[3]));
    [t0 << 16, wsub(t1, t0), h]
}

/// The cells of one term of a schedule: its index `li` among the schedule's lanes, the lane, the
/// term's hash, the noise fraction bits `fv`, the value precision `vb`, and whether the faces'
/// derivatives across the rows are made (`grads`).
#[cfg(not(texcore_lean))]
#[derive(Clone, Copy)]
pub(super) struct Cells<'a> {
    pub(super) li: usize,
    pub(super) lane: &'a RowLane,
    pub(super) hash: HashKind,
    pub(super) fv: u32,
    pub(super) vb: u32,
    pub(super) grads: bool,
}

/// Calls `each(entry, faces, f_k, c)` for every entry of term `li` (`lane`) of a schedule, in
/// order: the faces of the cell it enters (`A`, `B` and, with `grads`, `H`: [`face_ab`]; the face
/// shared with the previous cell kept), its fraction along `k`, and the cells `c` it lies from
/// the previous entry's along `k` (wrapping in 16 bits; 0 for the first entry).
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn for_each_cell(
    cells: Cells<'_>,
    events: &mut [RowEvent],
    mut each: impl FnMut(&mut RowEvent, [[i64; 3]; 2], i64, i64),
) {
    let Cells {
        li,
        lane,
        hash,
        fv,
        vb,
        grads,
    } = cells;
    let k = lane.k.min(2);
    let d = lane.du[k];
    let mut cell = [0u16; 3];
    if let Some(c) = cell.get_mut(lane.m) {
        *c = lane.cm;
    }
    if let Some(c) = cell.get_mut(lane.o) {
        *c = lane.co;
    }
    // The previous cell's coordinate along k and its faces.
    let mut prev: Option<(u16, [[i64; 3]; 2])> = None;
    for e in events.iter_mut().filter(|e| usize::from(e.lane) == li) {
        let uk = lane.u0k.wrapping_add(d.wrapping_mul(i32::from(e.at)));
        let ck = (uk >> 16) as u16;
        if let Some(c) = cell.get_mut(k) {
            *c = ck;
        }
        let blend = |b: usize| face_ab(lane, hash, cell, b, fv, vb, grads);
        let c = prev.map_or(0, |(pk, _)| ck.wrapping_sub(pk) as i16);
        let faces = match (c, prev) {
            (1, Some((_, f))) => [f[1], blend(1)],
            (-1, Some((_, f))) => [blend(0), f[0]],
            _ => [blend(0), blend(1)],
        };
        each(e, faces, i64::from(uk & 0xFFFF), i64::from(c));
        prev = Some((ck, faces));
    }
}

/// The entries of term `li` (`lane`) of a schedule: each of its cells' start and slope,
/// `g0 = Phi_0 2^16 + D f_k` and `g1 = D d` (`D = Phi_1 - Phi_0`, `axis::poly`), as `A + B f_m`,
/// less the previous cell's end `g0' + g1' n` and slope; with `grads` the same for the
/// derivative across the rows.
///
/// In terms of the changes: the entry `c` cells from the previous one along `k` carries the
/// previous cell's fraction to `f_k' + d n = f_k + c 2^16`, so with the previous near face
/// `Phi_0'` and difference `D'` (all zero before the first entry, `c = 0`)
/// `g0 - (g0' + g1' n) = (Phi_0 - Phi_0' - c D') 2^16 + (D - D') f_k` and
/// `g1 - g1' = (D - D') d`; for the next cell (`c = 1`, the usual entry) the first part is 0
/// (its near face is the previous far face), and for the cell before (`c = -1`) it is
/// `-(D - D') 2^16`. Exact in the ring (the tests compare every entry with the blends).
#[cfg(not(texcore_lean))]
#[inline(never)]
pub(super) fn lane_entries(cells: Cells<'_>, events: &mut [RowEvent]) {
    let (lane, grads) = (cells.lane, cells.grads);
    let d = i64::from(lane.du[lane.k.min(2)]);
    // The previous cell's near face and difference (`A`, `B` and `H` each).
    let mut prev = ([0i64; 3], [0i64; 3]);
    for_each_cell(cells, events, |e, [f0, f1], fk, c| {
        let (pf0, pd) = prev;
        let part = |i: usize| {
            let dphi = wsub(f1[i], f0[i]);
            let dd = wsub(dphi, pd[i]);
            let base = match c {
                1 => 0,
                -1 => wsub(0, dd),
                _ => far_base(f0[i], pf0[i], pd[i], c),
            };
            (wadd(base << 16, wmul(dd, fk)), wmul(dd, d), dphi)
        };
        let (v0, s0, d0) = part(0);
        let (v1, s1, d1) = part(1);
        (e.dv, e.ds) = ([v0, v1], [s0, s1]);
        let d2 = if grads {
            let (h0, h1, d2) = part(2);
            e.dg = [h0, h1];
            d2
        } else {
            e.dg = [0; 2];
            0
        };
        prev = (f0, [d0, d1, d2]);
    });
}

/// `Phi_0 - Phi_0' - c D'` of [`lane_entries`] for an entry that is not the next cell or the one
/// before (the first entry, `c = 0`, or a step of more than a cell a pixel): out of line, as it
/// is rare.
#[cfg(not(texcore_lean))]
#[inline(never)]
fn far_base(f0: i64, pf0: i64, pd: i64, c: i64) -> i64 {
    wsub(wsub(f0, pf0), wmul(c, pd))
}

/// The entries of a smooth-fade term `li` (`lane`): a cell's value at pixel `j` is
/// `G + D w(j)`, `G = Phi_0 2^16` and `D = Phi_1 - Phi_0` constants of the cell (as `A + B w_m`),
/// `w(j)` the fade of the fraction along `k`; each entry holds the change of `G` (`dv`) and of
/// `D` (`ds`) from the term's previous cell.
#[cfg(not(texcore_lean))]
pub(super) fn smooth_entries(cells: Cells<'_>, events: &mut [RowEvent]) {
    // The previous cell's `G` and `D` (the faces' derivatives across the rows are not made).
    let mut prev: Option<[[i64; 2]; 2]> = None;
    let cells = Cells {
        grads: false,
        ..cells
    };
    for_each_cell(cells, events, |e, [f0, f1], _, _| {
        let g = [f0[0] << 16, f0[1] << 16];
        let dd = [wsub(f1[0], f0[0]), wsub(f1[1], f0[1])];
        (e.dv, e.ds) = match prev {
            None => (g, dd),
            Some([pg, pd]) => (
                [wsub(g[0], pg[0]), wsub(g[1], pg[1])],
                [wsub(dd[0], pd[0]), wsub(dd[1], pd[1])],
            ),
        };
        e.dg = [0; 2];
        prev = Some([g, dd]);
    });
}
