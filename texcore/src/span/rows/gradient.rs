//! Gradient-noise terms (Perlin's improved noise) in a row schedule: each cell's corner
//! gradients hashed once per cell along the row's two other axes ([`grad_cell`]), the fades
//! along the row ([`Fades`]), the amplitudes' bound ([`small_amps`]), the row's entry point
//! ([`gradient_row`]), and the rows along the lattice's y or z axis ([`gradient_walk`]; rows
//! along x take `fused`'s stepped sums).
//!
//! A gradient-noise cell is not a polynomial of low degree along the row (the fade and the
//! blend's floors), so it is not forward differenced. What the row schedule saves is everything
//! else: in a cell entered at pixel `j0`, corner `c`'s dot product is `d_c(j) = g_c . o_c(j)`,
//! whose offsets along the two other axes are constant along the row and whose offset along `k`
//! grows by the lattice step `du_k` a pixel, so `d_c(j) = base_c + gm_c f_m + gk_c (j - j0)
//! du_k` (`base_c` fixed while the rows stay in the same cells along `m` and `o`, `f_m` the
//! row's fraction along its row axis `m`). An entry holds `base_c` and the components `gk_c`,
//! `gm_c` of the eight corners ([`GradCell`]); a row along y or z turns them into the eight
//! `d_c` once per cell, and a pixel is eight additions and the blend of `docs/model.md` 4.3
//! (`noise::gradient::blend`, whose last product is along x: along y or z the fade varies
//! within the exact part, so the sums are not stepped there). The fades along `k` are the same
//! at a pixel in every row the schedule serves: the rows read them from the cache's weights
//! when they hold every term's. The terms' values are summed unscaled ([`small_amps`]).
//!
//! Guarantees: every sample is `NoiseBasis::sample`'s (the same dot products, weights and
//! blend: `|d_c| <= 2^17`, `w <= 2^16`), combined with the quadric as the span path combines
//! it; tested against `Direct` in the module `rows`. Nothing here panics.

use super::*;
use crate::noise::fade::ONE;
use crate::noise::gradient::{blend, perlin_gradient};
use crate::noise::Fade;

/// One gradient-noise cell of a row schedule (see the module documentation): the corners' dot
/// products `base` at the cell's entry pixel (along `m` at fraction 0) and their gradients'
/// components along `k` and `m` (corner `c`'s bit 0 along x, 1 along y, 2 along z). Packed into
/// a [`RowEvent`]'s words for the rows along y or z (`base` in `dv` and `ds`, two corners a
/// word, low half first; the components along `k` in `dg[0]` and along `m` in `dg[1]`, a byte
/// a corner, corner 0 lowest); `fused` blends it into its own entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct GradCell {
    pub(super) base: [i32; 8],
    pub(super) gk: [i8; 8],
    pub(super) gm: [i8; 8],
}

impl GradCell {
    fn store(&self, e: &mut RowEvent) {
        let pair = |a: i32, b: i32| i64::from(a as u32) | (i64::from(b) << 32);
        let b = &self.base;
        e.dv = [pair(b[0], b[1]), pair(b[2], b[3])];
        e.ds = [pair(b[4], b[5]), pair(b[6], b[7])];
        let bytes = |g: &[i8; 8]| i64::from_le_bytes(g.map(|x| x as u8));
        e.dg = [bytes(&self.gk), bytes(&self.gm)];
    }

    #[inline(always)]
    fn load(e: &RowEvent) -> GradCell {
        let words = [e.dv[0], e.dv[1], e.ds[0], e.ds[1]];
        let mut base = [0i32; 8];
        for (pair, w) in base.chunks_exact_mut(2).zip(words) {
            if let [lo, hi] = pair {
                *lo = w as i32;
                *hi = (w >> 32) as i32;
            }
        }
        let bytes = |w: i64| w.to_le_bytes().map(|x| x as i8);
        GradCell {
            base,
            gk: bytes(e.dg[0]),
            gm: bytes(e.dg[1]),
        }
    }
}

/// The entries of gradient-noise term `li` (`lane`) of a schedule: each cell's corner
/// gradients (hashed as `NoiseBasis::cell` hashes them) as a [`GradCell`] for the fraction
/// along `k` at the entry's pixel and the fixed fraction `fo` along `o`.
pub(super) fn gradient_entries(li: usize, lane: &RowLane, hash: HashKind, events: &mut [RowEvent]) {
    for e in events.iter_mut().filter(|e| usize::from(e.lane) == li) {
        grad_cell(lane, hash, e.at).store(e);
    }
}

/// The [`GradCell`] of term `lane` at pixel `at` of the row: each corner's gradient (hashed as
/// `NoiseBasis::cell` hashes it) and dot product for the fraction along `k` at that pixel and
/// the fixed fraction `fo` along `o` (along `m` at fraction 0).
#[inline(always)]
pub(super) fn grad_cell(lane: &RowLane, hash: HashKind, at: u16) -> GradCell {
    let k = lane.k.min(2);
    let (m, o) = (lane.m.min(2), lane.o.min(2));
    let d = lane.du[k];
    let mut cell = [0u16; 3];
    cell[m] = lane.cm;
    cell[o] = lane.co;
    let fo = (lane.fo & 0xFFFF) as i32;
    let uk = lane.u0k.wrapping_add(d.wrapping_mul(i32::from(at)));
    cell[k] = (uk >> 16) as u16;
    let fk = uk & 0xFFFF;
    let mut g = GradCell {
        base: [0; 8],
        gk: [0; 8],
        gm: [0; 8],
    };
    for c in 0..8 {
        let bit = |axis: usize| ((c >> axis) & 1) as u16;
        let bits = crate::hash::gradient_bits(
            hash,
            cell[0].wrapping_add(bit(0)),
            cell[1].wrapping_add(bit(1)),
            cell[2].wrapping_add(bit(2)),
        );
        let gc = perlin_gradient(bits);
        let off = |axis: usize, f: i32| f - i32::from(bit(axis)) * ONE as i32;
        let (gk, gm, go) = (i32::from(gc[k]), i32::from(gc[m]), i32::from(gc[o]));
        g.base[c] = gk * off(k, fk) + go * off(o, fo) + gm * off(m, 0);
        g.gk[c] = gc[k];
        g.gm[c] = gc[m];
    }
    g
}

/// A term's contribution to the noise sum (`48 + fv` fraction bits) from its value `n16`, as
/// `NoiseBasis::sample` scales it (what [`small_amps`] lets the rows skip).
#[cfg(test)]
fn scaled(n16: i32, amp: i32, fv: u32) -> i64 {
    (i64::from(amp) * i64::from(n16)) << ((16 + fv) & 63)
}

/// Whether terms of amplitudes `|amp|` summing to `sum` (raw) in a model of `fv` noise fraction
/// bits contribute `sum_i amp_i n16_i` (units `2^-32`) to a sample, `(q + (V << 16)) >> 32`:
/// true when `sum 2^fv <= 2^29` (what the model keeps, `TextureModel`), so that
/// `|V| < 2^(47 - fv)` (`|n16| <= 2^17 + 3`: the lerps are convex combinations of dot products of
/// at most `2^17`, less a floor each) and the span path's noise sum `V << (16 + fv)` neither
/// wraps nor loses bits in its combination `(q + (n >> fv)) >> 32`.
#[inline(always)]
pub(super) fn small_amps(sum: u64, fv: u32) -> bool {
    fv <= 16 && (sum << fv) <= 1 << 29
}

/// A gradient-noise term walked along a row pixel by pixel ([`walk_lanes`]): the fused lane
/// (`fused::FusedLane`, stepped sums) or the blended one ([`GradLane`], stepped dot products).
pub(super) trait WalkedLane {
    /// The term's fade along the row.
    fn fade(&self) -> Fade;
    /// The term's amplitude.
    fn amp(&self) -> i32;
    /// The term's coordinate along `k` at the current pixel.
    fn uk(&self) -> i32;
    /// Enters the cell of entry `e`.
    fn enter(&mut self, e: &RowEvent);
    /// The term's value `n16` at the current pixel with the fade `wk` along `k` (as the walk's
    /// [`Fades`] give it), then one pixel on.
    fn pixel_on(&mut self, wk: i32) -> i32;
}

/// The samples of a row of gradient-noise terms `lanes` (their fades along the row from
/// `table`, term `l` at `l len`, as `w << shift`, or computed when it does not hold them): at
/// each entry the entering term's cell, then per pixel the sum `V = sum_i amp_i n16_i` with the
/// quadric `q` (value, step, second difference) combined as `(q + (V << 16)) >> 32`
/// ([`small_amps`], which `rows_take` checks).
#[inline(always)]
pub(super) fn walk_lanes<L: WalkedLane>(
    events: &[RowEvent],
    lanes: &mut [L],
    out: &mut [TexValue],
    q: &mut [i64; 3],
    table: &[u32],
    shift: u32,
) {
    let len = out.len();
    let mut x = 0usize;
    let mut rest = out;
    let [mut qq, mut dq, ddq] = *q;
    for e in events {
        if let Some(l) = lanes.get_mut(usize::from(e.lane)) {
            l.enter(e);
        }
        let n = usize::from(e.run).min(rest.len());
        let (run, tail) = core::mem::take(&mut rest).split_at_mut(n);
        rest = tail;
        let fades = Fades {
            table,
            len,
            x,
            shift,
        };
        for (j, o) in run.iter_mut().enumerate() {
            let mut v = 0i64;
            for (i, l) in lanes.iter_mut().enumerate() {
                let wk = fades.at(i, j, l.fade(), l.uk());
                v = wadd(v, i64::from(l.amp()) * i64::from(l.pixel_on(wk)));
            }
            *o = TexValue::from_bits((wadd(qq, v << 16) >> 32) as i32);
            qq = wadd(qq, dq);
            dq = wadd(dq, ddq);
        }
        x += n;
    }
    *q = [qq, dq, ddq];
}

/// The terms' fades along the row: term `l`'s at pixel `x + j` of a run is
/// `table[l len + x + j]` when the table holds it, otherwise computed.
#[derive(Clone, Copy, Debug)]
pub(super) struct Fades<'a> {
    pub(super) table: &'a [u32],
    pub(super) len: usize,
    pub(super) x: usize,
    /// The table's fades are `w << shift`; computed ones are shifted alike.
    pub(super) shift: u32,
}

impl Fades<'_> {
    /// Term `l`'s fade at pixel `j` of the run (`fade` of the term, `uk` its coordinate along
    /// the row at the pixel).
    #[inline(always)]
    pub(super) fn at(&self, l: usize, j: usize, fade: Fade, uk: i32) -> i32 {
        match self.table.get(l * self.len + self.x + j) {
            Some(w) => *w as i32,
            None => (fade.apply(uk as u32) as i32) << (self.shift & 15),
        }
    }
}

/// What a row needs of one gradient-noise term: its fade, the row's weights along its two other
/// axes, its fraction along `m`, amplitude, axis `k`, step along `k`, and the corner dot products
/// and their steps in its current cell.
#[derive(Clone, Copy, Debug)]
struct GradLane {
    fade: Fade,
    w: [i32; 3],
    fm: i32,
    amp: i32,
    k: usize,
    step: i32,
    uk: i32,
    d: [i32; 8],
    s: [i32; 8],
}

impl WalkedLane for GradLane {
    #[inline(always)]
    fn fade(&self) -> Fade {
        self.fade
    }

    #[inline(always)]
    fn amp(&self) -> i32 {
        self.amp
    }

    #[inline(always)]
    fn uk(&self) -> i32 {
        self.uk
    }

    /// Enters the cell of entry `e`.
    #[inline(always)]
    fn enter(&mut self, e: &RowEvent) {
        let g = GradCell::load(e);
        for c in 0..8 {
            self.d[c] = g.base[c].wrapping_add(i32::from(g.gm[c]) * self.fm);
            self.s[c] = i32::from(g.gk[c]).wrapping_mul(self.step);
        }
    }

    /// The term's value `n16` at the current pixel with weight `wk` along `k`, then one pixel on.
    #[inline(always)]
    fn pixel_on(&mut self, wk: i32) -> i32 {
        let mut w = self.w;
        w[self.k.min(2)] = wk;
        let n16 = blend(self.d, w);
        for (d, s) in self.d.iter_mut().zip(self.s) {
            *d = d.wrapping_add(s);
        }
        self.uk = self.uk.wrapping_add(self.step);
        n16
    }
}

/// The samples of a row whose terms are all gradient noise: with `fused` (every term along the
/// lattice's x axis, or `EvalMode::Fused`) `fused::fused_walk`'s stepped sums (with `approx`, in
/// `EvalMode::Fused`, its approximations too), otherwise [`gradient_walk`]'s blends of stepped
/// dot products; each term's fades along its `k` (the same in every row the schedule serves)
/// kept in `weights` when they hold them all, term after term (as `w << 14` for `fused`).
#[inline(always)]
pub(super) fn gradient_row<const T: usize>(
    events: &[RowEvent],
    state: &mut RowsState<T>,
    weights: &mut [u32],
    setup: &Setup<T>,
    out: &mut [TexValue],
    q: &mut [i64; 3],
    (fused, approx): (bool, bool),
) {
    let made = state.weights;
    // The fused rows read the fades as `w << 14` (`noise::gradient::last_step`).
    let shift = if fused { 14 } else { 0 };
    state.weights = row_fades(&state.lanes, made, weights, out.len(), shift);
    // Each term's fades along the row (term `l` at `l len`), when the weights hold them all.
    let table = weights
        .get(..state.weights)
        .filter(|t| t.len() >= state.lanes.len() * out.len())
        .unwrap_or_default();
    if fused {
        return super::fused::fused_walk(events, &state.lanes, &setup.terms, out, q, table, approx);
    }
    gradient_walk(events, &state.lanes, &setup.terms, out, q, table);
}

/// The samples of a row whose terms are all gradient noise, some along y or z (as
/// `walk_part`): at each entry the entering term's corner dot products for this row, then per
/// pixel every term's blend (`noise::gradient::blend`) and the quadric `q`, the fades along
/// the row from `table` when it holds every term's (`Fades`).
#[inline(never)]
fn gradient_walk(
    events: &[RowEvent],
    lanes: &[RowLane],
    terms: &[TermSetup],
    out: &mut [TexValue],
    q: &mut [i64; 3],
    table: &[u32],
) {
    // The terms' row state (pushed, not a zeroed array: at most `GRADIENT_TERMS` lanes, as
    // `rows_take` checks; never full).
    let mut gl: heapless::Vec<GradLane, GRADIENT_TERMS> = heapless::Vec::new();
    for lane in lanes.iter() {
        let Some(ts) = terms.get(lane.term) else {
            continue;
        };
        let (m, o, k) = (lane.m.min(2), lane.o.min(2), lane.k.min(2));
        let fm = split(ts.u0).1[m];
        let mut w = [0i32; 3];
        w[m] = lane.fade.apply(fm) as i32;
        w[o] = lane.wo as i32;
        let _ = gl.push(GradLane {
            fade: lane.fade,
            w,
            fm: fm as i32,
            amp: lane.amp,
            k,
            step: lane.du[k],
            uk: lane.u0k,
            d: [0; 8],
            s: [0; 8],
        });
    }
    walk_lanes(events, &mut gl, out, q, table, 0);
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::test_rng::xorshift64 as xorshift;

    #[test]
    fn a_cell_packs_into_an_entry() {
        let g = GradCell {
            base: [i32::MIN, -1, 0, 1, 131_072, -131_072, i32::MAX, 7],
            gk: [-1, 0, 1, 1, 0, -1, 0, 1],
            gm: [1, 1, -1, 0, 0, -1, 1, 0],
        };
        let mut e = RowEvent::default();
        g.store(&mut e);
        assert_eq!(GradCell::load(&e), g);
    }

    #[test]
    fn small_sums_combine_as_the_span_path() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || xorshift(&mut x);
        for _ in 0..50_000 {
            let fv = (next() % 17) as u32;
            // Amplitudes at the model's bound: `sum |amp| 2^fv <= 2^29`.
            let n = 1 + (next() % 4) as usize;
            let mut amps = [0i32; 4];
            let mut sum = 0u64;
            for a in amps.iter_mut().take(n) {
                let room = (1u64 << (29 - fv)) - sum;
                *a = (next() % (room / n as u64 + 1)) as i32 * if next() & 1 == 0 { 1 } else { -1 };
                sum += u64::from(a.unsigned_abs());
            }
            assert!(small_amps(sum, fv));
            let q = (next() as i64) >> (next() % 40);
            let (mut small, mut span) = (0i64, 0i64);
            for a in amps.iter().take(n) {
                let n16 = (next() % (2 * 131_075)) as i32 - 131_075;
                small = wadd(small, i64::from(*a) * i64::from(n16));
                span = wadd(span, scaled(n16, *a, fv));
            }
            // `multi_run`'s combination, and the span path's (`combine` of `mod` tables).
            let rows = (wadd(q, small << 16) >> 32) as i32;
            assert_eq!(rows, (wadd(q, span >> fv) >> 32) as i32);
        }
        assert!(!small_amps(1 << 16, 14));
        assert!(small_amps(1 << 16, 13));
        assert!(!small_amps(1, 17));
    }
}
