//! Gradient-noise rows by stepped sums: each term's corner sums stepped by two 64-bit
//! additions a pixel and blended in one product. The exact path of rows along the lattice's x
//! axis in every mode; with [`EvalMode::Fused`], of rows along any axis (approximate there).
//!
//! In a cell entered at pixel `j0` of a row along axis `k`, the weights `u` (along the row axis
//! `m`) and `v` (along the fixed axis `o`) are fixed, and each corner's dot product `d_c(j)` is
//! linear in the pixel (`gradient`). `A_b(j)`, the bilinear blend (scaled by `2^32`, exact) of
//! the four corners whose bit `k` is `b`, is then linear in the pixel too: made once per cell
//! and row and stepped by additions.
//!
//! The blend along `o` is the same in every row of the cell's slab: an entry ([`FusedCell`])
//! holds, for each pair of corners along `o`, `E_0 = (2^16 - v) base_0 + v base_1` (the dot
//! products at the row axis' fraction 0) and the corners' gradient components along `m` and `k`;
//! a row adds `f_m ((2^16 - v) gm_0 + v gm_1)` and blends along `m` with `u`. Every step is exact
//! integer arithmetic (`|d_c| <= 2^17`: `|E| < 2^35`, `|A| <= 2^49`).
//!
//! A pixel keeps `a = A_0` and `d4 = 4 (A_1 - A_0)` and makes
//! `n = floor(a / 2^32) + floor(floor(d4 / 2^32) w14 / 2^32)`, `w14 = w_k 2^14` (the fades along
//! the row are kept so): one signed high-word product (`noise::gradient::last_step`).
//!
//! A row of one term without quadric runs in one call (`one_term_row`); with a quadric or
//! several terms, pixel after pixel (`gradient::walk_lanes`, the terms' sum floored once, as `Direct`
//! floors it); in `EvalMode::Fused` several terms without quadric run term after term, each
//! over its own cells, adding its floored `(amp n) >> 16` into the row (`lane_rows`: one floor a
//! term instead of one of the sum).
//!
//! Guarantees: for `k = 0` (x), `A_b` are the sums of `noise::gradient::blend` and `n` is its
//! value, so every sample is `Direct`'s (tested in the module `rows`). For `k = 1` or `2`
//! (`EvalMode::Fused` only) the last product is taken along `k` instead of x: both values are
//! in `(R - 3, R]` of the exact trilinear value `R` (the floors lose less than one unit, a
//! quarter and one), so they differ by at most 2 units of `2^-16`; tested against `Direct`. The
//! steps wrap (`a` and `d` are exact modulo `2^64`, and their true values are in range at every
//! pixel of the cell). Nothing here panics.

use super::gradient::{grad_cell, walk_lanes, GradCell, WalkedLane};
use super::*;
use crate::noise::gradient::last_step;
use crate::noise::Fade;

/// One gradient-noise cell of a fused row schedule, packed into a [`RowEvent`]'s words: for
/// each pair `p = 2 b + i` of corners along `o` (`b` the bit along `k`, `i` along `m`), `e0[p]`
/// (in `dv`, `ds`), and the pair's gradient components along `m` (`dg[0]`) and `k` (`dg[1]`),
/// a byte a corner, the corner at `o = 0` first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct FusedCell {
    e0: [i64; 4],
    gm: [[i8; 2]; 4],
    gk: [[i8; 2]; 4],
}

impl FusedCell {
    fn store(&self, e: &mut RowEvent) {
        e.dv = [self.e0[0], self.e0[1]];
        e.ds = [self.e0[2], self.e0[3]];
        let bytes =
            |g: &[[i8; 2]; 4]| i64::from_le_bytes(core::array::from_fn(|i| g[i / 2][i % 2] as u8));
        e.dg = [bytes(&self.gm), bytes(&self.gk)];
    }

    #[inline(always)]
    fn load(e: &RowEvent) -> FusedCell {
        let pairs = |w: i64| {
            let b = w.to_le_bytes().map(|x| x as i8);
            [[b[0], b[1]], [b[2], b[3]], [b[4], b[5]], [b[6], b[7]]]
        };
        FusedCell {
            e0: [e.dv[0], e.dv[1], e.ds[0], e.ds[1]],
            gm: pairs(e.dg[0]),
            gk: pairs(e.dg[1]),
        }
    }
}

/// The entries of gradient-noise term `li` (`lane`) of a schedule: each cell's corner
/// gradients (as `gradient::grad_cell` hashes them) blended along `o` ([`FusedCell`]). Out of
/// line: the schedule's set-up keeps its code shape.
#[inline(never)]
pub(super) fn fused_entries(li: usize, lane: &RowLane, hash: HashKind, events: &mut [RowEvent]) {
    let axes = [lane.k.min(2), lane.m.min(2), lane.o.min(2)];
    // The fade along `o` (`row_schedule` makes it before the entries).
    let v = lane.wo as i32;
    for e in events.iter_mut().filter(|e| usize::from(e.lane) == li) {
        fused_cell(&grad_cell(lane, hash, e.at), axes, v).store(e);
    }
}

/// The [`FusedCell`] of cell `g` of a row along `k` with row axis `m` and fixed axis `o`
/// (`[k, m, o]`), the weight along `o` `v`.
fn fused_cell(g: &GradCell, [k, m, o]: [usize; 3], v: i32) -> FusedCell {
    let v = i64::from(v);
    let mut f = FusedCell {
        e0: [0; 4],
        gm: [[0; 2]; 4],
        gk: [[0; 2]; 4],
    };
    for p in 0..4 {
        let c0 = ((((p >> 1) & 1) << k) | ((p & 1) << m)) & 7;
        let c1 = (c0 | (1 << o)) & 7;
        let (b0, b1) = (i64::from(g.base[c0]), i64::from(g.base[c1]));
        f.e0[p] = ((65_536 - v) * b0) + v * b1;
        f.gm[p] = [g.gm[c0], g.gm[c1]];
        f.gk[p] = [g.gk[c0], g.gk[c1]];
    }
    f
}

/// What a fused row keeps of a gradient-noise term between pixels (module documentation).
#[derive(Clone, Copy, Debug)]
pub(super) struct FusedLane {
    /// The term's fade and amplitude.
    fade: Fade,
    amp: i32,
    /// The weights `u` along `m` and `v` along `o`, the row's fraction `f_m`, the step along
    /// `k` and the coordinate along `k` at the current pixel.
    u: i32,
    v: i32,
    fm: i32,
    step: i32,
    uk: i32,
    /// `16 - p` for an amplitude `2^p`, `0 <= p <= 16` ([`scaled`]: `(amp n) >> 16` is then
    /// `n >> (16 - p)`, `n` itself for an amplitude of one); 32 for any other.
    shift: u32,
    /// `A_0` and `4 (A_1 - A_0)` at the current pixel (wrapping).
    a: i64,
    d: i64,
    /// Their steps a pixel (wrapping).
    sa: i64,
    sd: i64,
}

impl FusedLane {
    /// The lane of term `lane` (set up as `ts`) in the current row.
    #[inline(always)]
    fn new(lane: &RowLane, ts: &TermSetup) -> FusedLane {
        let (m, k) = (lane.m.min(2), lane.k.min(2));
        let fm = split(ts.u0).1[m];
        let amp = lane.amp;
        FusedLane {
            fade: lane.fade,
            amp,
            u: lane.fade.apply(fm) as i32,
            v: lane.wo as i32,
            fm: fm as i32,
            step: lane.du[k],
            uk: lane.u0k,
            shift: if amp > 0 && amp <= 1 << 16 && amp & (amp - 1) == 0 {
                16 - amp.trailing_zeros()
            } else {
                32
            },
            a: 0,
            d: 0,
            sa: 0,
            sd: 0,
        }
    }

    /// Enters the cell of entry `e`.
    #[inline(always)]
    fn enter(&mut self, e: &RowEvent) {
        [self.a, self.d, self.sa, self.sd] = self.entered_apart(e);
    }

    /// [`FusedLane::entered`] out of line: the pixel-by-pixel rows (`walk_lanes`) keep their
    /// lanes' state in registers across the call (inlined there, `peers:perlin-4oct` costs 7.7
    /// more a sample on the Cortex-M4F); the one-term and term-by-term rows inline it.
    #[inline(never)]
    fn entered_apart(&self, e: &RowEvent) -> [i64; 4] {
        self.entered(e)
    }

    /// The state `[a, d, sa, sd]` at the entry pixel of the cell of entry `e`.
    #[inline(always)]
    fn entered(&self, e: &RowEvent) -> [i64; 4] {
        let cell = FusedCell::load(e);
        let (u, v, fm) = (self.u, self.v, self.fm);
        // `(2^16 - v) g_0 + v g_1` of a pair's components (within `2^16`).
        let along_o = |g: [i8; 2]| {
            let (g0, g1) = (i32::from(g[0]), i32::from(g[1]));
            (g0 << 16) + v * (g1 - g0)
        };
        // The pair's blend along `o` in this row (`E_0 + f_m E_1`, within `2^35`).
        let x: [i64; 4] = core::array::from_fn(|p| {
            let e1 = along_o(cell.gm.get(p).copied().unwrap_or_default());
            let e0 = cell.e0.get(p).copied().unwrap_or_default();
            e0.wrapping_add(i64::from(fm) * i64::from(e1))
        });
        let h: [i32; 4] =
            core::array::from_fn(|p| along_o(cell.gk.get(p).copied().unwrap_or_default()));
        // Along `m`: `2^16 x_0 + u (x_1 - x_0)`, exact.
        let blend = |x0: i64, x1: i64| {
            (x0 << 16).wrapping_add(x1.wrapping_sub(x0).wrapping_mul(i64::from(u)))
        };
        let hblend = |h0: i32, h1: i32| (i64::from(h0) << 16) + i64::from(u) * i64::from(h1 - h0);
        let (a0, a1) = (blend(x[0], x[1]), blend(x[2], x[3]));
        let (g0, g1) = (hblend(h[0], h[1]), hblend(h[2], h[3]));
        let step = i64::from(self.step);
        [
            a0,
            a1.wrapping_sub(a0).wrapping_mul(4),
            g0.wrapping_mul(step),
            g1.wrapping_sub(g0).wrapping_mul(step).wrapping_mul(4),
        ]
    }

    /// The term's value `n` (units `2^-16`) at the current pixel with fade `w14 = wk << 14` along
    /// the row, then one pixel on.
    #[inline(always)]
    fn pixel(&mut self, w14: i32) -> i32 {
        let n = last_step(self.a, self.d, w14);
        self.a = self.a.wrapping_add(self.sa);
        self.d = self.d.wrapping_add(self.sd);
        n
    }
}

/// A cell's pixels `run` of one term `f` from the state `[a, d, sa, sd]`, their fades along the
/// row (`w << 14`) in `ws`: the sample `(amp n) >> 16`, as `Direct` makes it from `n` (`n`
/// itself for an amplitude of one). With `ADD` each sample is added to the pixel's value
/// instead of stored. Returns `[a, d]` after the run.
#[cfg(feature = "fused")]
#[inline(always)]
fn scaled<const ADD: bool>(
    f: &FusedLane,
    state: [i64; 4],
    ws: &[u32],
    run: &mut [TexValue],
) -> [i64; 2] {
    let sh = f.shift;
    if sh == 0 {
        return scaled_run::<ADD>(state, ws, run, |n| n);
    }
    // An octave's amplitude `2^-i` as a shift.
    if sh <= 16 {
        return scaled_run::<ADD>(state, ws, run, |n| n >> sh);
    }
    let amp = i64::from(f.amp);
    scaled_run::<ADD>(state, ws, run, |n| ((amp * i64::from(n)) >> 16) as i32)
}

/// On Arm, keeps the compiler from unrolling the loop it is in: an opaque call on a branch that
/// a fade weight (at most `2^30` here) never takes. Unrolled four times, a run's loop holds four
/// copies of its 64-bit state and spills it among Thumb's 13 registers, and each copy of the
/// loop costs its code again.
#[inline(always)]
fn keep_rolled(w: u32) {
    #[cfg(target_arch = "arm")]
    if w > 1 << 30 {
        core::hint::black_box(());
    }
    let _ = w;
}

/// [`scaled`]'s loop, each value `n` scaled by `scale` (with `ADD`, added to the pixel's value,
/// wrapping: the terms' sum is within range, `gradient::small_amps`).
#[inline(always)]
fn scaled_run<const ADD: bool>(
    [mut a, mut d, sa, sd]: [i64; 4],
    ws: &[u32],
    run: &mut [TexValue],
    scale: impl Fn(i32) -> i32,
) -> [i64; 2] {
    for (o, wk) in run.iter_mut().zip(ws) {
        if !ADD {
            keep_rolled(*wk);
        }
        let v = scale(last_step(a, d, *wk as i32));
        *o = TexValue::from_bits(if ADD { o.to_bits().wrapping_add(v) } else { v });
        a = a.wrapping_add(sa);
        d = d.wrapping_add(sd);
    }
    [a, d]
}

/// The samples of a row of one term `f` of amplitude one without quadric (each sample the
/// term's `n`), its fades along the row (`w << 14`) in `table`: each cell entered, then its
/// pixels.
#[inline(never)]
fn one_term_row(f: &FusedLane, events: &[RowEvent], table: &[u32], out: &mut [TexValue]) {
    let mut rest = out;
    let mut fades = table;
    for e in events {
        let n = usize::from(e.run).min(rest.len());
        let (run, tail) = core::mem::take(&mut rest).split_at_mut(n);
        rest = tail;
        let Some((ws, later)) = fades.split_at_checked(n) else {
            return;
        };
        fades = later;
        scaled_run::<false>(f.entered(e), ws, run, |n| n);
    }
}

/// The samples of a row of several terms `fl` without quadric, their fades along the row
/// (`w << 14`) in `table` (term `l` at `l len`): term after term, each over its own cells, its
/// scaled values added into `out` (so each term's `(amp n) >> 16` is floored on its own: at most
/// one unit more a term than `walk_lanes`'s one floor of the sum: `EvalMode::Fused` only).
#[cfg(feature = "fused")]
#[inline(never)]
fn lane_rows(fl: &[FusedLane], events: &[RowEvent], table: &[u32], out: &mut [TexValue]) {
    let len = out.len();
    out.fill(TexValue::ZERO);
    for (l, f) in fl.iter().enumerate() {
        let Some(fades) = table.get(l * len..(l + 1) * len) else {
            return;
        };
        // The term's cells: from each of its entries to its next (or the row's end).
        let mut cell: Option<([i64; 4], usize)> = None;
        let mut x = 0usize;
        let mut add = |cell: Option<([i64; 4], usize)>, end: usize| {
            if let Some((state, start)) = cell {
                if let (Some(ws), Some(run)) = (fades.get(start..end), out.get_mut(start..end)) {
                    scaled::<true>(f, state, ws, run);
                }
            }
        };
        for e in events {
            if usize::from(e.lane) == l {
                add(cell, x);
                cell = Some((f.entered(e), x));
            }
            x = (x + usize::from(e.run)).min(len);
        }
        add(cell, x);
    }
}

impl WalkedLane for FusedLane {
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

    #[inline(always)]
    fn enter(&mut self, e: &RowEvent) {
        FusedLane::enter(self, e);
    }

    /// [`FusedLane::pixel`] with the fade as `w << 14`, the coordinate along `k` stepped too.
    #[inline(always)]
    fn pixel_on(&mut self, w14: i32) -> i32 {
        let n = self.pixel(w14);
        self.uk = self.uk.wrapping_add(self.step);
        n
    }
}

/// The samples of a row whose terms (`lanes`, set up as `terms`) are all gradient noise, fused:
/// at each entry the entering term's corner sums, then per pixel each term's blend; the fades
/// along the row (`w << 14`) from `table` (term `l` at `l len`), or computed when it is empty.
/// With `approx` (`EvalMode::Fused`), rows of several terms without quadric add their floored
/// products term after term ([`lane_rows`]); otherwise the terms' sum is floored once, as
/// `Direct` floors it.
#[inline(never)]
pub(super) fn fused_walk(
    events: &[RowEvent],
    lanes: &[RowLane],
    terms: &[TermSetup],
    out: &mut [TexValue],
    q: &mut [i64; 3],
    table: &[u32],
    approx: bool,
) {
    // At most `GRADIENT_TERMS` lanes, as `rows_take` checks: never full.
    let mut fl: heapless::Vec<FusedLane, GRADIENT_TERMS> = heapless::Vec::new();
    for lane in lanes {
        if let Some(ts) = terms.get(lane.term) {
            let _ = fl.push(FusedLane::new(lane, ts));
        }
    }
    let len = out.len();
    // Terms without quadric, their fades in the table: the whole row in one call.
    if table.len() >= fl.len() * len && (q[0] | q[1] | q[2]) == 0 {
        if let [f] = fl.as_slice() {
            if f.shift == 0 {
                return one_term_row(f, events, table, out);
            }
        }
        #[cfg(feature = "fused")]
        if approx {
            return lane_rows(&fl, events, table, out);
        }
    }
    let _ = approx;
    walk_lanes(events, &mut fl, out, q, table, 14);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::gradient::perlin_gradient;
    use crate::noise::Fade;

    use crate::test_rng::xorshift64 as xorshift;

    /// The exact trilinear value of dot products `d` with weights `w` (units `2^-64`).
    fn exact(d: &[i32; 8], w: [i64; 3]) -> i128 {
        (0..8)
            .map(|c| {
                let wc: i128 = (0..3)
                    .map(|a| {
                        i128::from(if (c >> a) & 1 == 1 {
                            w[a]
                        } else {
                            65_536 - w[a]
                        })
                    })
                    .product();
                wc * i128::from(d[c])
            })
            .sum()
    }

    /// A lane of one cell: `n` stepped along `k` is in `(R - 3, R]` of the exact value `R` at
    /// every pixel of the cell, the basis's value along x and within two of it along y and z,
    /// for random corner gradients, fractions, steps and every row axis.
    #[test]
    fn a_fused_cell_is_within_its_bound() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || xorshift(&mut x);
        for _ in 0..4000 {
            let k = (next() % 3) as usize;
            let grads: [[i8; 3]; 8] = core::array::from_fn(|_| perlin_gradient(next() as u8));
            let frac: [u32; 3] = core::array::from_fn(|_| (next() & 0xFFFF) as u32);
            let step = 1 + (next() % 4096) as i32;
            let fades = [
                Fade::Linear,
                #[cfg(feature = "smooth-fade")]
                Fade::Quintic,
            ];
            let fade = fades[(next() % fades.len() as u64) as usize];
            let (m, o) = if next() & 1 == 0 {
                ((k + 1) % 3, (k + 2) % 3)
            } else {
                ((k + 2) % 3, (k + 1) % 3)
            };
            let mut w = [0i32; 3];
            for a in 0..3 {
                if a != k {
                    w[a] = fade.apply(frac[a]) as i32;
                }
            }
            // The entry: each corner's dot product at the row axis' fraction `fm` less its part
            // along `m` (`fm` times its component) and its gradients along `k` and `m`.
            let dot = |c: usize, f: [u32; 3]| -> i32 {
                (0..3)
                    .map(|a| {
                        let o = f[a] as i32 - (((c >> a) & 1) as i32) * 65_536;
                        i32::from(grads[c][a]) * o
                    })
                    .sum()
            };
            let fm = frac[m] as i32;
            let cell = GradCell {
                base: core::array::from_fn(|c| dot(c, frac) - i32::from(grads[c][m]) * fm),
                gk: core::array::from_fn(|c| grads[c][k]),
                gm: core::array::from_fn(|c| grads[c][m]),
            };
            let mut e = RowEvent::default();
            fused_cell(&cell, [k, m, o], w[o]).store(&mut e);
            assert_eq!(FusedCell::load(&e), fused_cell(&cell, [k, m, o], w[o]));
            let mut f = FusedLane {
                fade,
                amp: 65_536,
                u: w[m],
                v: w[o],
                fm,
                step,
                uk: 0,
                shift: 0,
                a: 0,
                d: 0,
                sa: 0,
                sd: 0,
            };
            f.enter(&e);
            let mut fk = frac[k];
            while fk < 65_536 {
                let mut fr = frac;
                fr[k] = fk;
                let d: [i32; 8] = core::array::from_fn(|c| dot(c, fr));
                let wk = fade.apply(fk) as i32;
                let mut wv = w.map(i64::from);
                wv[k] = i64::from(wk);
                let r = exact(&d, wv);
                let n = f.pixel(wk << 14);
                // `n` in `(R - 3, R]`, `R = r / 2^48`.
                let lo = (i128::from(n) << 48) - r;
                assert!(lo <= 0 && lo > -(3i128 << 48), "{n} {r}");
                // Along x the basis's value; along y or z (`EvalMode::Fused`) within two.
                let want = crate::noise::gradient::value(&grads, fr, fade);
                if k == 0 {
                    assert_eq!(i64::from(n), want);
                } else {
                    assert!((i64::from(n) - want).abs() <= 2, "{n} {want}");
                }
                fk += step as u32;
            }
        }
    }

    /// `last_step` at the ends of its ranges (`|d4| <= 2^52`, `0 <= w14 <= 2^30`) does not
    /// wrap.
    #[test]
    fn last_step_at_its_bounds() {
        let top = 1i64 << 49;
        let one = 1 << 30;
        assert_eq!(last_step(top, 0, 0), 1 << 17);
        assert_eq!(last_step(-top, 0, one), -(1 << 17));
        let dmax = 1i64 << 52;
        assert_eq!(last_step(0, dmax, one), 1 << 18);
        assert_eq!(last_step(0, -dmax, one), -(1 << 18));
        assert_eq!(last_step(-1, -1, one - (1 << 14)), -2);
    }
}
