//! What the row schedule's gradient-noise terms (Perlin's improved noise) share: each cell's
//! corner gradients hashed once per cell along the row's two other axes ([`grad_cell`]), the
//! fades along the row ([`Fades`]), the amplitudes' bound ([`small_amps`]) and the row's entry
//! point ([`gradient_row`]); the rows themselves are `fused`'s stepped sums.
//!
//! A gradient-noise cell is not a polynomial of low degree along the row (the fade and the
//! blend's floors), so it is not forward differenced. What the row schedule saves is everything
//! else: in a cell entered at pixel `j0`, corner `c`'s dot product is `d_c(j) = g_c . o_c(j)`,
//! whose offsets along the two other axes are constant along the row and whose offset along `k`
//! grows by the lattice step `du_k` a pixel, so `d_c(j) = base_c + gm_c f_m + gk_c (j - j0)
//! du_k` (`base_c` fixed while the rows stay in the same cells along `m` and `o`, `f_m` the
//! row's fraction along its row axis `m`). The fades along `k` are the same at a pixel in every
//! row the schedule serves: the rows read them from the cache's weights when they hold every
//! term's. The terms' values are summed unscaled ([`small_amps`]).
//!
//! The schedule takes gradient-noise rows along the lattice's x axis in every mode (exact:
//! `fused`), and along the other axes only in `EvalMode::Fused`. Nothing here panics.

use super::*;
use crate::noise::fade::ONE;
use crate::noise::gradient::perlin_gradient;
use crate::noise::Fade;

/// One gradient-noise cell of a row schedule (see the module documentation): the corners' dot
/// products `base` at the cell's entry pixel (along `m` at fraction 0) and their gradients'
/// components along `k` and `m` (corner `c`'s bit 0 along x, 1 along y, 2 along z), which
/// `fused` blends into its entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct GradCell {
    pub(super) base: [i32; 8],
    pub(super) gk: [i8; 8],
    pub(super) gm: [i8; 8],
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

/// The samples of a row whose terms are all gradient noise: `fused::fused_walk`'s stepped sums
/// (with `approx`, in `EvalMode::Fused`, its approximations too), each term's fades along its
/// `k` (the same in every row the schedule serves) kept in `weights` as `w << 14` when they hold
/// them all, term after term.
#[inline(always)]
pub(super) fn gradient_row<const T: usize>(
    events: &[RowEvent],
    state: &mut RowsState<T>,
    weights: &mut [u32],
    setup: &Setup<T>,
    out: &mut [TexValue],
    q: &mut [i64; 3],
    approx: bool,
) {
    let made = state.weights;
    // The rows read the fades as `w << 14` (`noise::gradient::last_step`).
    state.weights = row_fades(&state.lanes, made, weights, out.len(), 14);
    // Each term's fades along the row (term `l` at `l len`), when the weights hold them all.
    let table = weights
        .get(..state.weights)
        .filter(|t| t.len() >= state.lanes.len() * out.len())
        .unwrap_or_default();
    super::fused::fused_walk(events, &state.lanes, &setup.terms, out, q, table, approx)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Xorshift64 from `x`: the tests' pseudo-random numbers.
    fn xorshift(x: &mut u64) -> u64 {
        *x ^= *x << 13;
        *x ^= *x >> 7;
        *x ^= *x << 17;
        *x
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
