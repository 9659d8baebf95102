//! The quadric classification function `q(s) = [s t r 1] Q [s t r 1]^T` and its gradient.
//!
//! `Q` is the symmetric 4x4 matrix of the ten coefficients `A..J`
//! (`q = A s^2 + 2B st + 2C sr + 2D s + E t^2 + 2F tr + 2G t + H r^2 + 2I r + J`), each an
//! `I16F16` [`QuadricCoeff`]. Evaluation is exact: coordinates with 16 fraction bits give `q` with
//! 48 fraction bits, computed in wrapping i128 (`docs/model.md` section 5). Wrapping keeps `q mod 1`
//! exact for any input, which is all a `mod` colour table needs; a `clamp` table saturates the
//! value afterwards, which is exact while `|q| < 2^79` (far beyond any span texcore accepts).
//!
//! Along a span `s(i) = s0 + i ds` the quadric is the quadratic `c0 + c1 i + c2 i^2`
//! ([`Quadric::along`]), which forward-differences exactly with two additions a pixel.

use crate::format::{QuadricCoeff, TexPoint};

/// A quadric with ten fixed-point coefficients.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Quadric {
    c: [QuadricCoeff; 10],
}

/// The quadric along a span: `q(i) = c[0] + c[1] i + c[2] i^2`, 48 fraction bits, wrapping i128.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuadraticSpan {
    /// Coefficients of `1, i, i^2`.
    pub c: [i128; 3],
}

impl QuadraticSpan {
    /// The value at pixel `i` (exact, wrapping i128).
    #[inline]
    pub fn at(&self, i: i64) -> i128 {
        let i = i128::from(i);
        self.c[0]
            .wrapping_add(self.c[1].wrapping_mul(i))
            .wrapping_add(self.c[2].wrapping_mul(i).wrapping_mul(i))
    }

    /// Whether every coefficient is zero (the quadric stage can be skipped).
    #[inline]
    pub fn is_zero(&self) -> bool {
        (self.c[0] | self.c[1] | self.c[2]) == 0
    }
}

#[cfg_attr(not(texcore_lean), inline(always))]
fn homogeneous(p: [i64; 3], w: i64) -> [i128; 4] {
    [
        i128::from(p[0]),
        i128::from(p[1]),
        i128::from(p[2]),
        i128::from(w),
    ]
}

impl Quadric {
    /// The zero quadric.
    pub const ZERO: Quadric = Quadric {
        c: [QuadricCoeff::ZERO; 10],
    };

    /// From the ten coefficients `[A, B, C, D, E, F, G, H, I, J]` of
    /// `A s^2 + 2B st + 2C sr + 2D s + E t^2 + 2F tr + 2G t + H r^2 + 2I r + J`.
    pub const fn from_coefficients(c: [QuadricCoeff; 10]) -> Self {
        Quadric { c }
    }

    /// Host convenience: from real coefficients (rounded, saturating). `None` if any is not finite.
    pub fn from_f64(c: [f64; 10]) -> Option<Self> {
        let mut out = [QuadricCoeff::ZERO; 10];
        for (o, v) in out.iter_mut().zip(c) {
            if !v.is_finite() {
                return None;
            }
            *o = QuadricCoeff::saturating_from_num(v);
        }
        Some(Quadric { c: out })
    }

    /// A linear ramp `q = ks s + kt t + kr r + k0` (stores `D = ks/2` etc., so odd raw slopes lose
    /// their last bit; use [`Quadric::from_coefficients`] for full control).
    pub fn linear(ks: QuadricCoeff, kt: QuadricCoeff, kr: QuadricCoeff, k0: QuadricCoeff) -> Self {
        let z = QuadricCoeff::ZERO;
        let h = |k: QuadricCoeff| QuadricCoeff::from_bits(k.to_bits() >> 1);
        Quadric {
            c: [z, z, z, h(ks), z, z, h(kt), z, h(kr), k0],
        }
    }

    /// The coefficients `[A..J]`.
    pub const fn coefficients(&self) -> [QuadricCoeff; 10] {
        self.c
    }

    /// Whether the quadric is identically zero (a model without it skips the stage).
    pub fn is_zero(&self) -> bool {
        self.c.iter().all(|c| *c == QuadricCoeff::ZERO)
    }

    /// Whether the quadric is affine (no second-order terms): then it is linear along a span.
    pub fn is_affine(&self) -> bool {
        let z = QuadricCoeff::ZERO;
        let [a, b, c, _, e, f, _, h, _, _] = self.c;
        a == z && b == z && c == z && e == z && f == z && h == z
    }

    /// The symmetric matrix as raw i128 entries (16 fraction bits).
    #[inline]
    fn matrix(&self) -> [[i128; 4]; 4] {
        let r = |k: usize| i128::from(self.c[k].to_bits());
        let (a, b, c, d, e, f, g, h, i, j) =
            (r(0), r(1), r(2), r(3), r(4), r(5), r(6), r(7), r(8), r(9));
        [[a, b, c, d], [b, e, f, g], [c, f, h, i], [d, g, i, j]]
    }

    /// `x^T Q y` for homogeneous vectors with 16 fraction bits: 48 fraction bits, wrapping.
    #[inline]
    fn form(&self, x: [i128; 4], y: [i128; 4]) -> i128 {
        let m = self.matrix();
        let mut acc: i128 = 0;
        for (row, xi) in m.iter().zip(x) {
            let mut r: i128 = 0;
            for (q, yj) in row.iter().zip(y) {
                r = r.wrapping_add(q.wrapping_mul(yj));
            }
            acc = acc.wrapping_add(r.wrapping_mul(xi));
        }
        acc
    }

    /// `q` at a point with 16 fraction bits per coordinate (exact i64 coordinates): 48 fraction
    /// bits, wrapping i128.
    #[inline]
    pub fn eval48(&self, s: [i64; 3]) -> i128 {
        let x = homogeneous(s, 1 << 16);
        self.form(x, x)
    }

    /// `q` at a [`TexPoint`] (48 fraction bits).
    pub fn eval_point48(&self, s: TexPoint) -> i128 {
        let b = s.to_bits();
        self.eval48([i64::from(b[0]), i64::from(b[1]), i64::from(b[2])])
    }

    /// The directional derivative `2 [s;1]^T Q [d;0]` at `s` along `d` (both 16 fraction bits):
    /// 48 fraction bits, wrapping i128.
    #[inline]
    pub fn directional48(&self, s: [i64; 3], d: [i64; 3]) -> i128 {
        self.form(homogeneous(s, 1 << 16), homogeneous(d, 0))
            .wrapping_mul(2)
    }

    /// The quadric along the span `s(i) = s0 + i ds`.
    pub fn along(&self, s0: [i64; 3], ds: [i64; 3]) -> QuadraticSpan {
        let x = homogeneous(s0, 1 << 16);
        let d = homogeneous(ds, 0);
        QuadraticSpan {
            c: [
                self.form(x, x),
                self.form(x, d).wrapping_mul(2),
                self.form(d, d),
            ],
        }
    }

    /// The directional derivative along `dir` as a linear function of the pixel index on the span
    /// `s(i) = s0 + i ds`: returns `[g0, g1]` with `g(i) = g0 + g1 i` (48 fraction bits).
    pub fn derivative_along(&self, s0: [i64; 3], ds: [i64; 3], dir: [i64; 3]) -> [i128; 2] {
        let x = homogeneous(s0, 1 << 16);
        let d = homogeneous(ds, 0);
        let v = homogeneous(dir, 0);
        [
            self.form(x, v).wrapping_mul(2),
            self.form(d, v).wrapping_mul(2),
        ]
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for Quadric {
    fn format(&self, f: defmt::Formatter) {
        let c = self.c.map(|c| c.to_bits());
        defmt::write!(f, "Quadric(raw 16.16 A..J {=[?]})", c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(c: [f64; 10]) -> Quadric {
        Quadric::from_f64(c).unwrap()
    }

    fn real(c: [f64; 10], s: [f64; 3]) -> f64 {
        let [a, b, cc, d, e, f, g, h, i, j] = c;
        let [x, y, z] = s;
        a * x * x
            + 2.0 * b * x * y
            + 2.0 * cc * x * z
            + 2.0 * d * x
            + e * y * y
            + 2.0 * f * y * z
            + 2.0 * g * y
            + h * z * z
            + 2.0 * i * z
            + j
    }

    #[test]
    fn eval_matches_formula_exactly() {
        let c = [1.5, -0.25, 0.125, 3.0, 50.0, 0.5, -2.0, 0.75, 0.0625, -7.5];
        let qq = q(c);
        for s in [
            [0.0, 0.0, 0.0],
            [1.0, 2.0, -3.0],
            [0.5, 0.25, 0.125],
            [-100.5, 37.25, 2.0],
        ] {
            let raw = [
                (s[0] * 65536.0) as i64,
                (s[1] * 65536.0) as i64,
                (s[2] * 65536.0) as i64,
            ];
            let got = qq.eval48(raw) as f64 / 2f64.powi(48);
            assert_eq!(got, real(c, s), "{s:?}");
        }
    }

    #[test]
    fn zone_plate() {
        // f = 50 s^2 + 50 t^2
        let qq = q([50.0, 0.0, 0.0, 0.0, 50.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let s = [(65536 + 32768) as i64 / 256, 0, 0]; // (x=0.5 -> s = 0.5/256) scaled: raw 384
        let v = qq.eval48(s);
        let want = 50.0 * (384.0f64 / 65536.0).powi(2);
        assert_eq!(v as f64 / 2f64.powi(48), want);
    }

    #[test]
    fn along_is_exact() {
        let qq = q([1.0, 0.5, -0.25, 0.125, 2.0, 0.0, 1.0, -1.0, 0.5, 0.25]);
        let s0 = [123456, -654321, 99999];
        let ds = [777, -333, 4097];
        let span = qq.along(s0, ds);
        for i in [0i64, 1, 2, 17, 1000, 65535] {
            let s = [s0[0] + i * ds[0], s0[1] + i * ds[1], s0[2] + i * ds[2]];
            assert_eq!(span.at(i), qq.eval48(s), "i = {i}");
            let [g0, g1] = qq.derivative_along(s0, ds, [5, 6, 7]);
            assert_eq!(g0 + g1 * i128::from(i), qq.directional48(s, [5, 6, 7]));
        }
    }

    #[test]
    fn gradient_is_2qs() {
        let c = [1.0, 0.5, -0.25, 0.125, 2.0, 0.0, 1.0, -1.0, 0.5, 0.25];
        let qq = q(c);
        let s = [1.5, -0.5, 2.0];
        let raw = [98304, -32768, 131072];
        for axis in 0..3 {
            let mut d = [0i64; 3];
            d[axis] = 65536;
            let g = qq.directional48(raw, d) as f64 / 2f64.powi(48);
            let h = 1e-6;
            let mut sp = s;
            let mut sm = s;
            sp[axis] += h;
            sm[axis] -= h;
            let fd = (real(c, sp) - real(c, sm)) / (2.0 * h);
            assert!((g - fd).abs() < 1e-6, "axis {axis}: {g} vs {fd}");
        }
    }

    #[test]
    fn huge_coordinates_do_not_panic() {
        let qq = q([
            32767.0, -32768.0, 32767.0, 32767.0, 32767.0, -32768.0, 1.0, 32767.0, 1.0, 1.0,
        ]);
        let big = [i64::MAX / 4, i64::MIN / 4, i64::MAX / 4];
        let _ = qq.eval48(big);
        let _ = qq.along(big, big).at(65535);
        assert!(!qq.is_affine());
        assert!(Quadric::linear(
            QuadricCoeff::ONE,
            QuadricCoeff::ZERO,
            QuadricCoeff::ZERO,
            QuadricCoeff::ZERO
        )
        .is_affine());
    }
}
