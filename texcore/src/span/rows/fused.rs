//! Gradient-noise rows of [`EvalMode::Fused`]: each term's trilinear interpolation in one
//! rounding, its corner sums stepped by two 64-bit additions a pixel.
//!
//! In a cell entered at pixel `j0` of a row along axis `k`, the weights `u`, `v` along the two
//! other axes are fixed, and each corner's dot product `d_c(j)` is linear in the pixel
//! (`gradient`). So the exact trilinear value (units `2^-16`) is
//! `R(j) = (A_0(j) + w_k(j) (A_1(j) - A_0(j)) / 2^16) / 2^32`, with `A_b(j)` the bilinear blend
//! of the four corners whose bit `k` is `b`, scaled by `2^32` (`2^32 d_00 + 2^16 u (d_10 - d_00)
//! + 2^16 v (d_01 - d_00) + u v (d_11 - d_10 - d_01 + d_00)`, exact in 64 bits): two values
//! linear in the pixel, made once per cell and row and stepped by additions. A pixel keeps
//! `a = A_0` and `d = A_1 - A_0` (`|a| <= 2^49`, `|d| <= 2^50`: `|d_c| <= 2^17`) and makes
//! `n = floor(a / 2^32) + floor(w_k floor(d / 2^32) / 2^16)`.
//!
//! Guarantees: `n` is in `(R - 3, R]` (each of its three floors loses less than one unit), and
//! so is `NoiseBasis::sample`'s value from the seven staged lerps (each of its three stages
//! floors once, and the lerps are convex combinations): the two differ by at most 2 units of
//! `2^-16`. Tested against the exact `R` (128-bit) and against `Direct` in the module `rows`.
//! The steps wrap (`a` and `d` are exact modulo `2^64`, and their true values are in range at
//! every pixel of the cell). Nothing here panics.

use super::gradient::{Fades, GradCell, GradLane};
use super::*;

/// What a fused row keeps of a gradient-noise term between pixels (module documentation).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct FusedLane {
    /// The weights `u`, `v` along the axes after `k` (`(k + 1) % 3`, `(k + 2) % 3`), and
    /// `u v`.
    u: i64,
    v: i64,
    uv: i64,
    /// `A_0` and `A_1 - A_0` at the current pixel (wrapping).
    a: i64,
    d: i64,
    /// Their steps a pixel (wrapping).
    sa: i64,
    sd: i64,
}

impl FusedLane {
    /// The lane of gradient term `g` in the current row: its weights along the other axes.
    pub(super) fn new(g: &GradLane) -> FusedLane {
        let k = g.k.min(2);
        let axes = [(k + 1) % 3, (k + 2) % 3];
        let w = |axis: usize| i64::from(g.w.get(axis).copied().unwrap_or_default());
        let (u, v) = (w(axes[0]), w(axes[1]));
        FusedLane {
            u,
            v,
            uv: u * v,
            ..FusedLane::default()
        }
    }

    /// The bilinear blend of `x00`, `x10`, `x01`, `x11` (`x_ij`: bit `i` along the first other
    /// axis, bit `j` along the second; each within `2^19`) with the weights `u`, `v` (at most
    /// `2^16`), scaled by `2^32`: exact (32 x 32-bit products; `u v <= 2^32`).
    #[inline(always)]
    fn blend2(&self, x: [i32; 4]) -> i64 {
        let [x00, x10, x01, x11] = x;
        let mul = |w: i64, d: i32| i64::from(w as i32) * i64::from(d);
        let cross = x11.wrapping_sub(x10).wrapping_sub(x01).wrapping_add(x00);
        (i64::from(x00) << 32)
            .wrapping_add(mul(self.u, x10.wrapping_sub(x00)) << 16)
            .wrapping_add(mul(self.v, x01.wrapping_sub(x00)) << 16)
            .wrapping_add((self.uv as u64 as i64).wrapping_mul(i64::from(cross)))
    }

    /// Enters the cell of entry `e` of term `g` (`g.fm`: the row's fraction along `m`), a row
    /// along axis `K`.
    #[inline(always)]
    fn enter<const K: usize>(&mut self, g: &GradLane, e: &RowEvent) {
        let cell = GradCell::load(e);
        // The corners' dot products at the entry pixel (their true values are within `2^17`, so
        // the wrapping sums are exact) and their gradients along `K`.
        let mut dot = [0i32; 8];
        let mut grad = [0i32; 8];
        for c in 0..8 {
            dot[c] = cell.base[c].wrapping_add(i32::from(cell.gm[c]) * g.fm);
            grad[c] = i32::from(cell.gk[c]);
        }
        // The four corners whose bit `K` is `b`, in `blend2`'s order.
        let corners = |b: usize| {
            let (p, q) = ((K + 1) % 3, (K + 2) % 3);
            [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(i, j)| ((b << K) | (i << p) | (j << q)) & 7)
        };
        let (c0, c1) = (corners(0), corners(1));
        let a0 = self.blend2(c0.map(|c| dot[c]));
        let a1 = self.blend2(c1.map(|c| dot[c]));
        let g0 = self.blend2(c0.map(|c| grad[c]));
        let g1 = self.blend2(c1.map(|c| grad[c]));
        let step = i64::from(g.step);
        self.a = a0;
        self.d = a1.wrapping_sub(a0);
        self.sa = g0.wrapping_mul(step);
        self.sd = g1.wrapping_sub(g0).wrapping_mul(step);
    }

    /// [`Self::enter`] for a row along `g.k`.
    #[inline(always)]
    fn enter_any(&mut self, g: &GradLane, e: &RowEvent) {
        match g.k {
            0 => self.enter::<0>(g, e),
            1 => self.enter::<1>(g, e),
            _ => self.enter::<2>(g, e),
        }
    }

    /// The term's value `n` (units `2^-16`) at the current pixel with fade `wk` along the row,
    /// then one pixel on.
    #[inline(always)]
    fn pixel(&mut self, wk: i32) -> i32 {
        let n = blend(self.a, self.d, wk);
        self.a = self.a.wrapping_add(self.sa);
        self.d = self.d.wrapping_add(self.sd);
        n
    }
}

/// `floor(a / 2^32) + floor(w floor(d / 2^32) / 2^16)`: the fused value of the module
/// documentation (`0 <= w <= 2^16`, `|d| <= 2^50`: the product is within `2^34`).
#[inline(always)]
fn blend(a: i64, d: i64, w: i32) -> i32 {
    let (ah, dh) = ((a >> 32) as i32, (d >> 32) as i32);
    ah.wrapping_add(((i64::from(dh) * i64::from(w)) >> 16) as i32)
}

/// The pixels `run` of one term (`g`, `f`) without quadric, its fades along the row from `ws`:
/// the sample `(amp n) >> 16`, as the staged rows make it from their `n`; for an amplitude
/// `2^p`, `0 <= p <= 16` (an octave's `2^-i`), the same floor as `n >> (16 - p)`.
#[inline(never)]
fn one_run(g: &mut GradLane, f: &mut FusedLane, ws: &[u32], run: &mut [TexValue]) {
    let amp = g.amp;
    if amp > 0 && amp <= 1 << 16 && amp & (amp - 1) == 0 {
        let sh = 16 - amp.trailing_zeros();
        scaled_run(f, ws, run, |n| n >> sh);
    } else {
        let amp = i64::from(amp);
        scaled_run(f, ws, run, |n| ((amp * i64::from(n)) >> 16) as i32);
    }
    g.uk = g.uk.wrapping_add(g.step.wrapping_mul(run.len() as i32));
}

/// [`one_run`]'s loop, each value `n` scaled by `scale`.
#[inline(always)]
fn scaled_run(f: &mut FusedLane, ws: &[u32], run: &mut [TexValue], scale: impl Fn(i32) -> i32) {
    let (mut a, mut d, sa, sd) = (f.a, f.d, f.sa, f.sd);
    for (o, wk) in run.iter_mut().zip(ws) {
        *o = TexValue::from_bits(scale(blend(a, d, *wk as i32)));
        a = a.wrapping_add(sa);
        d = d.wrapping_add(sd);
    }
    (f.a, f.d) = (a, d);
}

/// The pixels `run` of the terms `gl` / `fl` with the quadric `qq` stepped by `dq` and `ddq`:
/// `V = sum_i amp_i n_i` combined as the staged rows combine it, `(q + (V << 16)) >> 32`.
#[inline(always)]
fn multi_run(
    gl: &mut [GradLane],
    fl: &mut [FusedLane],
    run: &mut [TexValue],
    q: &mut [i64; 3],
    fades: Fades<'_>,
) {
    let [mut qq, mut dq, ddq] = *q;
    for (j, o) in run.iter_mut().enumerate() {
        let mut v = 0i64;
        for (l, (g, f)) in gl.iter_mut().zip(fl.iter_mut()).enumerate() {
            let wk = fades.at(l, j, g);
            v = wadd(v, i64::from(g.amp) * i64::from(f.pixel(wk)));
            g.uk = g.uk.wrapping_add(g.step);
        }
        *o = TexValue::from_bits((wadd(qq, v << 16) >> 32) as i32);
        qq = wadd(qq, dq);
        dq = wadd(dq, ddq);
    }
    *q = [qq, dq, ddq];
}

/// The samples of a row whose terms `gl` are all gradient noise (set up for this row by
/// `gradient_walk`), fused: at each entry the entering term's corner sums, then per pixel each
/// term's blend; the fades along the row from `table` (term `l` at `l len`) when it holds
/// them all.
#[inline(never)]
pub(super) fn fused_walk(
    events: &[RowEvent],
    gl: &mut [GradLane],
    out: &mut [TexValue],
    q: &mut [i64; 3],
    table: &[u32],
) {
    let mut fl: heapless::Vec<FusedLane, GRADIENT_TERMS> = heapless::Vec::new();
    for g in gl.iter() {
        let _ = fl.push(FusedLane::new(g));
    }
    let (len, lanes) = (out.len(), gl.len());
    let mut x = 0usize;
    let mut rest = out;
    for e in events {
        let l = usize::from(e.lane);
        if let (Some(g), Some(f)) = (gl.get(l), fl.get_mut(l)) {
            if lanes == 1 && g.k == 0 {
                f.enter::<0>(g, e);
            } else {
                f.enter_any(g, e);
            }
        }
        let n = usize::from(e.run).min(rest.len());
        let (run, tail) = core::mem::take(&mut rest).split_at_mut(n);
        rest = tail;
        let ws = table.get(x..x + n).unwrap_or_default();
        match (gl.first_mut(), fl.first_mut(), lanes) {
            (Some(g), Some(f), 1) if ws.len() == n && (q[0] | q[1] | q[2]) == 0 => {
                one_run(g, f, ws, run)
            }
            _ => multi_run(gl, &mut fl, run, q, Fades { table, len, x }),
        }
        x += n;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::gradient::perlin_gradient;
    use crate::noise::Fade;

    /// Xorshift64 from `x`: the tests' pseudo-random numbers.
    fn xorshift(x: &mut u64) -> u64 {
        *x ^= *x << 13;
        *x ^= *x >> 7;
        *x ^= *x << 17;
        *x
    }

    /// The exact trilinear value of dot products `d` with weights `w` (units `2^-64`).
    fn exact(d: &[i32; 8], w: [i64; 3]) -> i128 {
        (0..8)
            .map(|c| {
                let wc: i128 = (0..3)
                    .map(|a| i128::from(if (c >> a) & 1 == 1 { w[a] } else { 65_536 - w[a] }))
                    .product();
                wc * i128::from(d[c])
            })
            .sum()
    }

    /// A lane of one cell: `n` stepped along `k` is in `(R - 3, R]` of the exact value `R` and
    /// within two of the staged value at every pixel of the cell, for random corner gradients,
    /// fractions, steps and every row axis.
    #[test]
    fn a_fused_cell_is_within_one_of_the_exact_value() {
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
            let mut w = [0i32; 3];
            for a in 0..3 {
                if a != k {
                    w[a] = fade.apply(frac[a]) as i32;
                }
            }
            // The entry: each corner's dot product less its part along `m` (here: all of it,
            // `fm` = 0) and its gradient along `k`.
            let dot = |c: usize, f: [u32; 3]| -> i32 {
                (0..3)
                    .map(|a| {
                        let o = f[a] as i32 - (((c >> a) & 1) as i32) * 65_536;
                        i32::from(grads[c][a]) * o
                    })
                    .sum()
            };
            let mut e = RowEvent::default();
            let cell = GradCell {
                base: core::array::from_fn(|c| dot(c, frac)),
                gk: core::array::from_fn(|c| grads[c][k]),
                gm: [0; 8],
            };
            cell.store(&mut e);
            let g = GradLane {
                fade,
                w,
                fm: 0,
                amp: 65_536,
                k,
                step,
                uk: frac[k] as i32,
                d: [0; 8],
                s: [0; 8],
            };
            let mut f = FusedLane::new(&g);
            f.enter_any(&g, &e);
            let mut fk = frac[k];
            while fk < 65_536 {
                let mut fr = frac;
                fr[k] = fk;
                let d: [i32; 8] = core::array::from_fn(|c| dot(c, fr));
                let wk = fade.apply(fk) as i32;
                let mut wv = w.map(i64::from);
                wv[k] = i64::from(wk);
                let r = exact(&d, wv);
                let n = f.pixel(wk);
                // `n` in `(R - 3, R]`, `R = r / 2^48`.
                let lo = (i128::from(n) << 48) - r;
                assert!(lo <= 0 && lo > -(3i128 << 48), "{n} {r}");
                let staged = crate::noise::gradient::value(&grads, fr, fade);
                assert!((i64::from(n) - staged).abs() <= 2, "{n} {staged}");
                fk += step as u32;
            }
        }
    }

    /// `blend` at the ends of its ranges does not wrap.
    #[test]
    fn blend_at_its_bounds() {
        let top = 1i64 << 49;
        assert_eq!(blend(top, 0, 0), 1 << 17);
        assert_eq!(blend(-top, 0, 65_536), -(1 << 17));
        let dmax = 1i64 << 50;
        assert_eq!(blend(0, dmax, 65_536), 1 << 18);
        assert_eq!(blend(0, -dmax, 65_536), -(1 << 18));
        assert_eq!(blend(-1, -1, 65_535), -2);
    }

    /// The bilinear blend is the four corners weighted, scaled by `2^32`.
    #[test]
    fn blend2_is_the_weighted_sum() {
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || xorshift(&mut x);
        for _ in 0..20_000 {
            let (u, v) = ((next() % 65_537) as i64, (next() % 65_537) as i64);
            let f = FusedLane { u, v, uv: u * v, ..FusedLane::default() };
            let c: [i32; 4] = core::array::from_fn(|_| (next() % (1 << 19)) as i32 - (1 << 18));
            let want = (65_536 - u) * (65_536 - v) * i64::from(c[0])
                + u * (65_536 - v) * i64::from(c[1])
                + (65_536 - u) * v * i64::from(c[2])
                + u * v * i64::from(c[3]);
            assert_eq!(f.blend2(c), want);
        }
    }
}
