//! Gradient lattice noise (Perlin's improved noise and Olano's corner-gradient mNoise):
//! staged interpolation of corner dot products, with the analytic gradient.
//!
//! Values are in units of 2^-16 (`n16`), computed by the seven staged lerps of `docs/model.md` 4.3,
//! each `p + ((q - p) * w) >> 16` (arithmetic shift). The gradient is computed alongside by the
//! product rule through the same stages, so it is the analytic gradient of the fixed-point
//! interpolant up to the rounding of each stage. Both are total functions of their inputs: no
//! overflow is possible (every intermediate is bounded by a few times 2^18 before scaling).

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

/// The interpolated value in units of 2^-16 (not yet normalised).
///
/// The size-lean shape (`cfg(texcore_lean)`) takes it from the one out-of-line
/// [`value_and_gradient`] (the same value stages, bit for bit; tested) instead of compiling a
/// second staged interpolation.
#[inline]
pub fn value(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> i64 {
    if cfg!(texcore_lean) {
        value_and_gradient(grads, frac, fade).0
    } else {
        value_unrolled(grads, frac, fade)
    }
}

/// [`value`] with the seven lerps written out.
#[cfg_attr(not(texcore_lean), inline(always))]
fn value_unrolled(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> i64 {
    let w = [
        fade.apply(frac[0]),
        fade.apply(frac[1]),
        fade.apply(frac[2]),
    ];
    let d = |c: usize| dot(grads[c], offsets(frac, c));
    let e = |c: usize| lerp16(d(c), d(c + 1), w[0]);
    let f0 = lerp16(e(0), e(2), w[1]);
    let f1 = lerp16(e(4), e(6), w[1]);
    lerp16(f0, f1, w[2])
}

/// Value and analytic gradient (`dn/du`, units 2^-16 per cell) of the interpolant.
///
/// The size-lean shape (`cfg(texcore_lean)`) keeps one out-of-line copy that runs the stages as a
/// loop over the axes (`value_and_gradient_looped`); the fast one writes them out. Both give the
/// same result (tested).
#[cfg_attr(texcore_lean, inline(never))]
#[cfg_attr(not(texcore_lean), inline)]
pub fn value_and_gradient(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> (i64, [i64; 3]) {
    if cfg!(texcore_lean) {
        value_and_gradient_looped(grads, frac, fade)
    } else {
        value_and_gradient_unrolled(grads, frac, fade)
    }
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

/// [`value_and_gradient`] with the stages as loops: the eight corners, then per axis the pairs
/// of the previous stage (adjacent along that axis) into half as many.
fn value_and_gradient_looped(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> (i64, [i64; 3]) {
    let mut s = [[0i64; 4]; 8];
    for (c, sc) in s.iter_mut().enumerate() {
        *sc = corner(grads, frac, c);
    }
    for (axis, &a) in frac.iter().enumerate() {
        let (w, dw) = (fade.apply(a), fade.derivative(a));
        let prev = s;
        for (out, pq) in s.iter_mut().zip(prev.chunks_exact(2).take(4 >> axis)) {
            if let [p, q] = *pq {
                *out = stage(p, q, axis, w, dw);
            }
        }
    }
    let [v, gx, gy, gz] = s[0];
    (v, [gx, gy, gz])
}

/// [`value_and_gradient`] with the seven stages written out.
#[cfg_attr(not(texcore_lean), inline(always))]
fn value_and_gradient_unrolled(grads: &[Grad; 8], frac: [u32; 3], fade: Fade) -> (i64, [i64; 3]) {
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
    (g[0], [g[1], g[2], g[3]])
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

    proptest::proptest! {
        #[test]
        fn both_shapes_agree(
            g in proptest::collection::vec(-1i8..=1, 24),
            frac in proptest::prelude::any::<[u32; 3]>(),
        ) {
            let mut grads = [[0i8; 3]; 8];
            for (gc, v) in grads.iter_mut().zip(g.chunks_exact(3)) {
                gc.copy_from_slice(v);
            }
            for fade in fades() {
                let want = value_and_gradient_unrolled(&grads, frac, fade);
                proptest::prop_assert_eq!(value_and_gradient_looped(&grads, frac, fade), want);
                proptest::prop_assert_eq!(value_and_gradient(&grads, frac, fade), want);
                proptest::prop_assert_eq!(value_unrolled(&grads, frac, fade), want.0);
                proptest::prop_assert_eq!(value(&grads, frac, fade), want.0);
            }
        }
    }

    #[test]
    fn zero_at_lattice_points_and_gradient_matches_differences() {
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
                let (v, g) = value_and_gradient(&grads, p, fade);
                assert_eq!(v, value(&grads, p, fade));
                for axis in 0..3 {
                    let h = 64u32;
                    let mut lo = p;
                    let mut hi = p;
                    lo[axis] -= h;
                    hi[axis] += h;
                    let fd = (value(&grads, hi, fade) - value(&grads, lo, fade)) as f64
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
