//! Gradient lattice noise (Perlin's improved noise and Olano's corner-gradient mNoise): the
//! corner dot products interpolated in one exact blend, with the analytic gradient.
//!
//! Values are in units of 2^-16 (`n16`), the blend of `docs/model.md` 4.3 ([`blend`]): the dot
//! products blended exactly along y and z into two sums `A_0`, `A_1` (the corners at x = 0 and
//! x = 1, scaled by `2^32`), then `floor(A_0 / 2^32) + floor(floor(4 (A_1 - A_0) / 2^32) (w_x
//! 2^14) / 2^32)`: one product along x. Along a row of the lattice's x axis `A_0` and `A_1` are
//! linear in the pixel, so the row schedule steps them by additions and a pixel is one
//! high-word product (`span::rows`); the value is within three units below the exact trilinear
//! value `R` (`(R - 3, R]`: the floors lose less than one unit, a quarter and one).
//!
//! The gradient is computed by the product rule through staged lerps (x first, then y, then
//! z), the analytic gradient of the interpolant up to the rounding of each stage: it only sets
//! the filter width. Both are total functions of their inputs: no overflow is possible (every
//! intermediate is bounded by a few times 2^18 before scaling, `2^53` after).

use super::fade::{Fade, ONE};

/// A corner gradient vector with components in `{-1, 0, 1}`.
pub type Grad = [i8; 3];

/// Perlin's improved-noise gradient for hash bits `g` (low 4 bits used): one of the 12 edge
/// centres of the cube (four repeated), as his `grad()` function selects it.
#[cfg(feature = "gradient-noise")]
#[inline]
pub const fn perlin_gradient(g: u8) -> Grad {
    let g = g & 15;
    // axis index: 0 = x, 1 = y, 2 = z
    let u = if g < 8 { 0 } else { 1 };
    let v = if g < 4 {
        1
    } else if g == 12 || g == 14 {
        0
    } else {
        2
    };
    let su: i8 = if g & 1 == 0 { 1 } else { -1 };
    let sv: i8 = if g & 2 == 0 { 1 } else { -1 };
    let mut out = [0i8; 3];
    out[u] = su;
    out[v] = sv;
    out
}

/// Olano's corner gradient `(±1, ±1, ±1)` from bits 0, 1, 2 of the mNoise hash.
#[cfg(feature = "mnoise")]
#[inline]
pub const fn corner_gradient(m: u32) -> Grad {
    [
        if m & 1 == 0 { 1 } else { -1 },
        if m & 2 == 0 { 1 } else { -1 },
        if m & 4 == 0 { 1 } else { -1 },
    ]
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn lerp16(p: i64, q: i64, w: i64) -> i64 {
    p + (((q - p) * w) >> 16)
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn dot(g: Grad, o: [i64; 3]) -> i64 {
    i64::from(g[0]) * o[0] + i64::from(g[1]) * o[1] + i64::from(g[2]) * o[2]
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn offsets(frac: [u32; 3], c: usize) -> [i64; 3] {
    let f = |axis: usize| i64::from(frac[axis] & 0xFFFF) - (((c >> axis) & 1) as i64) * ONE;
    [f(0), f(1), f(2)]
}

/// The blend of `docs/model.md` 4.3 of the corner dot products `d` (corner `c` at bit 0 = x,
/// bit 1 = y, bit 2 = z; `|d_c| < 2^18`) with the fades `w` (`0..=2^16`) along x, y and z, in
/// units of 2^-16: `A_b = sum (2^16 - w_y or w_y) (2^16 - w_z or w_z) d_c` over the four corners
/// whose x bit is `b` (exact: `|A_b| < 2^50`), then
/// `floor(A_0 / 2^32) + floor(floor(4 (A_1 - A_0) / 2^32) (w_x 2^14) / 2^32)`
/// (`|4 (A_1 - A_0)| < 2^53`; the product of its high word and `w_x 2^14 <= 2^30` is within
/// `2^51`). The row schedule makes the same two sums by additions and the same last step
/// (`span::rows`). Out of line: one copy for every path that blends a pixel's own dot products
/// (`Direct`, the rows along y or z).
#[inline(never)]
pub fn blend(d: [i32; 8], w: [i32; 3]) -> i32 {
    // `2^16 p + w (q - p)`: the exact blend of two values along one axis, of two dot products
    // (`|q - p| < 2^19`: one 32 x 32-bit product) and of two such blends (`|.| < 2^35`).
    let along_y = |p: i32, q: i32| (i64::from(p) << 16) + i64::from(w[1]) * i64::from(q - p);
    let along_z = |p: i64, q: i64| (p << 16).wrapping_add(i64::from(w[2]).wrapping_mul(q - p));
    // `A_b` of the corners `b`, `b + 2`, `b + 4`, `b + 6` (a loop: one copy of the blends).
    let mut a = [0i64; 2];
    for (b, ab) in a.iter_mut().enumerate() {
        let c = |i: usize| d.get(b + i).copied().unwrap_or_default();
        *ab = along_z(along_y(c(0), c(2)), along_y(c(4), c(6)));
    }
    let [a0, a1] = a;
    last_step(a0, a1.wrapping_sub(a0).wrapping_mul(4), w[0] << 14)
}

/// The last step of [`blend`] from `A_0`, `d4 = 4 (A_1 - A_0)` and `w14 = w_x 2^14`:
/// `floor(A_0 / 2^32) + floor(floor(d4 / 2^32) w14 / 2^32)`, one signed high-word product
/// (`smmul`, `mulh`).
#[inline(always)]
pub(crate) fn last_step(a0: i64, d4: i64, w14: i32) -> i32 {
    let (ah, dh) = ((a0 >> 32) as i32, (d4 >> 32) as i32);
    ah.wrapping_add(((i64::from(dh) * i64::from(w14)) >> 32) as i32)
}

/// The interpolated value in units of 2^-16 (not yet normalised): the corners' dot products
/// and the fades, then [`blend`].
///
/// The size-lean shape (`cfg(texcore_lean)`) takes it from the one out-of-line
/// [`value_and_gradient`] that the derivative uses too (the same dot products, fades and blend);
/// the fast one has its own out-of-line copy, one for every evaluation path that takes a
/// pixel's value on its own (the rows of the lattice's x axis step [`blend`]'s sums instead).
#[inline]
pub fn value(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> i64 {
    if cfg!(texcore_lean) {
        value_and_gradient(grads, frac, fade).0
    } else {
        value_alone(grads, frac, fade)
    }
}

/// [`value`] in the fast shape.
#[inline(never)]
fn value_alone(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> i64 {
    // The fades (one call each: the compiler would otherwise copy the fade's three forms for
    // each axis) and the dot products.
    let mut w = [0i32; 3];
    for (wa, &fa) in w.iter_mut().zip(&frac) {
        *wa = fade_apart(fade, fa) as i32;
    }
    let mut d = [0i32; 8];
    for (c, dc) in d.iter_mut().enumerate() {
        *dc = dot(grads[c & 7], offsets(frac, c)) as i32;
    }
    i64::from(blend(d, w))
}

/// `fade.apply(a)` out of line.
#[inline(never)]
fn fade_apart(fade: Fade, a: u32) -> i64 {
    fade.apply(a)
}

/// The analytic gradient (`dn/du`, units 2^-16 per cell) of the interpolant, through staged
/// lerps (x first, then y, then z) by the product rule (the size-lean shape: from
/// [`value_and_gradient`]).
#[inline]
pub fn gradient(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> [i64; 3] {
    if cfg!(texcore_lean) {
        value_and_gradient(grads, frac, fade).1
    } else {
        gradient_unrolled(grads, frac, fade)
    }
}

/// [`value`] and [`gradient`] together: the stages as loops (the eight corners, then per axis
/// the pairs of the previous stage, adjacent along that axis, into half as many), the value by
/// [`blend`] from the corners' dot products and the fades. Out of line in the size-lean shape:
/// its one copy of the interpolation.
#[cfg_attr(texcore_lean, inline(never))]
pub fn value_and_gradient(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> (i64, [i64; 3]) {
    let mut s = [[0i64; 4]; 8];
    for (c, sc) in s.iter_mut().enumerate() {
        *sc = corner(grads, frac, c);
    }
    // |d_c| < 2^18.
    let d = s.map(|sc| sc[0] as i32);
    let mut ws = [0i32; 3];
    for ((axis, &a), wa) in frac.iter().enumerate().zip(ws.iter_mut()) {
        let (w, dw) = (fade.apply(a), fade.derivative(a));
        *wa = w as i32;
        let prev = s;
        for (out, pq) in s.iter_mut().zip(prev.chunks_exact(2).take(4 >> axis)) {
            if let [p, q] = *pq {
                *out = stage(p, q, axis, w, dw);
            }
        }
    }
    let [_, gx, gy, gz] = s[0];
    (i64::from(blend(d, ws)), [gx, gy, gz])
}

/// The corner `c`'s stage input: (value, d/dx, d/dy, d/dz).
#[cfg_attr(not(texcore_lean), inline(always))]
fn corner(grads: &[Grad; 8], frac: [u32; 3], c: usize) -> [i64; 4] {
    let g = grads[c & 7];
    [
        dot(g, offsets(frac, c)),
        i64::from(g[0]) * ONE,
        i64::from(g[1]) * ONE,
        i64::from(g[2]) * ONE,
    ]
}

/// One interpolation stage along `axis` (weight `w`, its derivative `dw`) of (value, gradient)
/// pairs, by the product rule.
#[cfg_attr(not(texcore_lean), inline(always))]
fn stage(p: [i64; 4], q: [i64; 4], axis: usize, w: i64, dw: i64) -> [i64; 4] {
    let mut out = [0i64; 4];
    for k in 0..4 {
        out[k] = lerp16(p[k], q[k], w);
    }
    out[(axis + 1) & 3] += ((q[0] - p[0]) * dw) >> 16;
    out
}

/// [`gradient`]'s seven stages written out.
#[cfg_attr(not(texcore_lean), inline(always))]
fn gradient_unrolled(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> [i64; 3] {
    let w = [
        fade.apply(frac[0]),
        fade.apply(frac[1]),
        fade.apply(frac[2]),
    ];
    let dw = [
        fade.derivative(frac[0]),
        fade.derivative(frac[1]),
        fade.derivative(frac[2]),
    ];
    let corner = |c: usize| corner(grads, frac, c);
    let stage = |p: [i64; 4], q: [i64; 4], axis: usize| stage(p, q, axis, w[axis], dw[axis]);
    let e0 = stage(corner(0), corner(1), 0);
    let e1 = stage(corner(2), corner(3), 0);
    let e2 = stage(corner(4), corner(5), 0);
    let e3 = stage(corner(6), corner(7), 0);
    let f0 = stage(e0, e1, 1);
    let f1 = stage(e2, e3, 1);
    let g = stage(f0, f1, 2);
    [g[1], g[2], g[3]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(feature = "gradient-noise")]
    #[test]
    fn perlin_gradients_are_edge_centres() {
        for g in 0..16u8 {
            let v = perlin_gradient(g);
            assert_eq!(v.iter().filter(|c| **c != 0).count(), 2, "{g}: {v:?}");
            // Perlin's grad(): dot with (x, y, z) = (1, 2, 4) identifies the combination.
            let x = 1i64;
            let y = 2;
            let z = 4;
            let h = g & 15;
            let u = if h < 8 { x } else { y };
            let vv = if h < 4 {
                y
            } else if h == 12 || h == 14 {
                x
            } else {
                z
            };
            let want = (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { vv } else { -vv });
            assert_eq!(dot(v, [x, y, z]), want, "g = {g}");
        }
    }

    #[cfg(feature = "mnoise")]
    #[test]
    fn corner_gradients() {
        assert_eq!(corner_gradient(0), [1, 1, 1]);
        assert_eq!(corner_gradient(7), [-1, -1, -1]);
        assert_eq!(corner_gradient(5), [-1, 1, -1]);
    }

    fn fades() -> heapless::Vec<Fade, 3> {
        let mut v = heapless::Vec::new();
        let _ = v.push(Fade::Linear);
        #[cfg(feature = "smooth-fade")]
        {
            let _ = v.push(Fade::Smooth);
            let _ = v.push(Fade::Quintic);
        }
        v
    }

    /// The exact trilinear value of the dot products with the fades, times `2^48`.
    fn exact48(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> i128 {
        let w = [0, 1, 2].map(|a| i128::from(fade.apply(frac[a])));
        (0..8)
            .map(|c| {
                let wc: i128 = (0..3)
                    .map(|a| {
                        if (c >> a) & 1 == 1 {
                            w[a]
                        } else {
                            65_536 - w[a]
                        }
                    })
                    .product();
                wc * i128::from(dot(grads[c], offsets(frac, c)))
            })
            .sum()
    }

    /// Eight corner gradients from 24 components.
    fn corners(g: &[i8]) -> [Grad; 8] {
        let mut grads = [[0i8; 3]; 8];
        for (gc, v) in grads.iter_mut().zip(g.chunks_exact(3)) {
            gc.copy_from_slice(v);
        }
        grads
    }

    proptest::proptest! {
        #[test]
        fn both_shapes_agree(
            g in proptest::collection::vec(-1i8..=1, 24),
            frac in proptest::prelude::any::<[u32; 3]>(),
        ) {
            let grads = corners(&g);
            for fade in fades() {
                let want = gradient_unrolled(&grads, frac, fade);
                let both = value_and_gradient(&grads, frac, fade);
                proptest::prop_assert_eq!(both.1, want);
                proptest::prop_assert_eq!(gradient(&grads, frac, fade), want);
                proptest::prop_assert_eq!(both.0, value_alone(&grads, frac, fade));
                proptest::prop_assert_eq!(value(&grads, frac, fade), both.0);
            }
        }

        /// The blend is within three units below the exact trilinear value `R`, `(R - 3, R]`,
        /// for any gradients (components -1, 0, 1: Perlin's and Olano's) and fraction.
        #[test]
        fn the_blend_is_within_three_units_below_the_exact_value(
            g in proptest::collection::vec(-1i8..=1, 24),
            frac in proptest::prelude::any::<[u32; 3]>(),
        ) {
            let grads = corners(&g);
            for fade in fades() {
                let r = exact48(&grads, frac, fade);
                let n = i128::from(value(&grads, frac, fade)) << 48;
                proptest::prop_assert!(n <= r && r - n < 3 << 48, "{} {}", n >> 48, r >> 48);
            }
        }
    }

    /// The blend's extremes: every dot product at its largest magnitude with every weight at
    /// 0, 1 or at its ends, against the exact value.
    #[test]
    fn the_blend_at_its_extremes() {
        for signs in 0u32..256 {
            let d: [i32; 8] = core::array::from_fn(|c| {
                if (signs >> c) & 1 == 1 {
                    -(3 << 16)
                } else {
                    3 << 16
                }
            });
            for w in [
                [0, 0, 0],
                [65_536; 3],
                [1, 65_535, 32_768],
                [65_535, 1, 65_536],
            ] {
                let mut r: i128 = 0;
                for (c, &dc) in d.iter().enumerate() {
                    let wc: i128 = (0..3)
                        .map(|a| {
                            let wa = i128::from(w[a]);
                            if (c >> a) & 1 == 1 {
                                wa
                            } else {
                                65_536 - wa
                            }
                        })
                        .product();
                    r += wc * i128::from(dc);
                }
                let n = i128::from(blend(d, w)) << 48;
                assert!(n <= r && r - n < 3 << 48, "{d:?} {w:?}");
            }
        }
    }

    #[test]
    fn zero_at_lattice_points_and_gradient_matches_the_exact_differences() {
        let grads: [Grad; 8] = [
            [1, 1, 0],
            [-1, 0, 1],
            [0, -1, 1],
            [1, 0, -1],
            [-1, -1, 0],
            [0, 1, -1],
            [1, 1, 1],
            [-1, 1, -1],
        ];
        for fade in [
            Fade::Linear,
            #[cfg(feature = "smooth-fade")]
            Fade::Smooth,
            #[cfg(feature = "smooth-fade")]
            Fade::Quintic,
        ] {
            assert_eq!(value(&grads, [0, 0, 0], fade), 0);
            for &p in &[
                [1000u32, 2000, 3000],
                [40000, 30000, 20000],
                [65000, 100, 33333],
            ] {
                let g = gradient(&grads, p, fade);
                for axis in 0..3 {
                    let h = 64u32;
                    let mut lo = p;
                    let mut hi = p;
                    lo[axis] -= h;
                    hi[axis] += h;
                    // The exact interpolant's central difference (the value's floors would
                    // add up to 3 units either side).
                    let fd = (exact48(&grads, hi, fade) - exact48(&grads, lo, fade)) as f64
                        / (1u64 << 48) as f64
                        / (2.0 * h as f64)
                        * 65536.0;
                    let err = (fd - g[axis] as f64).abs();
                    assert!(
                        err < 0.01 * 65536.0,
                        "{fade:?} {p:?} axis {axis}: {fd} vs {}",
                        g[axis]
                    );
                }
            }
        }
    }
}
