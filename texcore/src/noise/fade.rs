//! Fade (interpolant) functions of the noise bases, on `U0F16` fractions.
//!
//! A fade maps the position `a` inside a cell (raw `0..65536`, i.e. `[0, 1)`) to an interpolation
//! weight in `0..=65536`. The exact integer formulas are `docs/model.md` section 4.1; every one is
//! monotone, maps 0 to 0, and is total (defined and panic-free for every `u32` input, which the
//! forward-difference set-up relies on when it evaluates polynomials just outside a cell).

/// The interpolant between lattice points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Fade {
    /// Linear: plain trilinear interpolation (the papers' hardware noise; exactly a cubic along a
    /// span, so it forward-differences exactly).
    #[default]
    Linear,
    /// `3a^2 - 2a^3` (Perlin 1985, Rayshade).
    #[cfg(feature = "smooth-fade")]
    Smooth,
    /// `6a^5 - 15a^4 + 10a^3` (Perlin 2002).
    #[cfg(feature = "smooth-fade")]
    Quintic,
}

/// One in U0F16.
pub const ONE: i64 = 1 << 16;

/// The quintic fade of `a < 2^16`: `(6 a^5 - 15 a^4 2^16 + 10 a^3 2^32 + 2^63) >> 64`, computed
/// as `(a^3 P + 2^63) >> 64` with `P = 6 a^2 - 15 a 2^16 + 10 2^32` (in `(2^32, 10 2^32]`) from
/// 32 x 32 -> 64-bit products of 32-bit limbs (no 128-bit multiplication: a few instructions
/// on a 32-bit core; exhaustively tested against the 128-bit formula, which the size-lean
/// code shape and 64-bit targets keep).
#[cfg(feature = "smooth-fade")]
#[inline(never)]
fn quintic(a: u32) -> i64 {
    const M: u64 = 0xFFFF_FFFF;
    let a = a & 0xFFFF;
    let a2 = a * a;
    let a3 = u64::from(a2) * u64::from(a);
    let p = 6 * u64::from(a2) + (10 << 32) - ((15 * u64::from(a)) << 16);
    let (ah, al) = (a3 >> 32, a3 & M);
    let (ph, pl) = (p >> 32, p & M);
    let lo = al * pl;
    let (m1, m2) = (al * ph, ah * pl);
    let carry = ((lo >> 32) + (m1 & M) + (m2 & M) + (1 << 31)) >> 32;
    (ah * ph + (m1 >> 32) + (m2 >> 32) + carry) as i64
}

impl Fade {
    /// The fade of fraction `a` (raw U0F16 in `0..65536`), in `0..=65536`.
    #[inline]
    pub fn apply(self, a: u32) -> i64 {
        let a = i64::from(a & 0xFFFF);
        match self {
            Fade::Linear => a,
            #[cfg(feature = "smooth-fade")]
            Fade::Smooth => (3 * a * a * ONE - 2 * a * a * a + (1 << 31)) >> 32,
            #[cfg(feature = "smooth-fade")]
            Fade::Quintic => {
                if cfg!(any(texcore_lean, target_pointer_width = "64")) {
                    // The size-lean shape keeps the shorter 128-bit form, and 64-bit targets
                    // multiply it natively (the same values).
                    let a = i128::from(a);
                    let a3 = a * a * a;
                    ((6 * a3 * a * a - 15 * a3 * a * (1 << 16) + 10 * a3 * (1 << 32) + (1 << 63))
                        >> 64) as i64
                } else {
                    quintic(a as u32)
                }
            }
        }
    }

    /// The derivative `dF/da` at fraction `a`, in U?F16 (`65536` = slope 1).
    #[inline]
    #[cfg_attr(not(feature = "smooth-fade"), allow(unused_variables))]
    pub fn derivative(self, a: u32) -> i64 {
        #[cfg(feature = "smooth-fade")]
        let a = i64::from(a & 0xFFFF);
        match self {
            Fade::Linear => ONE,
            // 6a(1 - a)
            #[cfg(feature = "smooth-fade")]
            Fade::Smooth => (6 * a * (ONE - a) + (1 << 15)) >> 16,
            // 30 a^2 (1 - a)^2
            #[cfg(feature = "smooth-fade")]
            Fade::Quintic => {
                let b = i128::from(a * (ONE - a));
                ((30 * b * b + (1 << 47)) >> 48) as i64
            }
        }
    }

    /// Whether noise with this fade is a polynomial of degree 3 along a span (trilinear).
    #[inline]
    pub const fn is_linear(self) -> bool {
        matches!(self, Fade::Linear)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> &'static [Fade] {
        &[
            Fade::Linear,
            #[cfg(feature = "smooth-fade")]
            Fade::Smooth,
            #[cfg(feature = "smooth-fade")]
            Fade::Quintic,
        ]
    }

    #[test]
    fn endpoints_and_monotone() {
        for &f in all() {
            assert_eq!(f.apply(0), 0, "{f:?}");
            assert!(f.apply(65535) >= 65530, "{f:?} {}", f.apply(65535));
            let mut prev = 0;
            for a in 0..65536u32 {
                let v = f.apply(a);
                assert!(v >= prev && v <= ONE, "{f:?} at {a}: {v} < {prev}");
                prev = v;
            }
        }
    }

    #[test]
    fn matches_real_polynomials() {
        for &f in all() {
            for a in (0..65536u32).step_by(97) {
                let x = a as f64 / 65536.0;
                let (want, dwant) = match f {
                    Fade::Linear => (x, 1.0),
                    #[cfg(feature = "smooth-fade")]
                    Fade::Smooth => (3.0 * x * x - 2.0 * x * x * x, 6.0 * x * (1.0 - x)),
                    #[cfg(feature = "smooth-fade")]
                    Fade::Quintic => (
                        x * x * x * (x * (6.0 * x - 15.0) + 10.0),
                        30.0 * x * x * (1.0 - x) * (1.0 - x),
                    ),
                };
                let got = f.apply(a) as f64 / 65536.0;
                assert!(
                    (got - want).abs() < 4.0 / 65536.0,
                    "{f:?} {x}: {got} vs {want}"
                );
                let dgot = f.derivative(a) as f64 / 65536.0;
                assert!(
                    (dgot - dwant).abs() < 4.0 / 65536.0,
                    "{f:?}' {x}: {dgot} vs {dwant}"
                );
            }
        }
    }

    #[test]
    #[cfg(feature = "smooth-fade")]
    fn quintic_is_the_128_bit_formula() {
        for a in 0..65536u32 {
            let x = i128::from(a);
            let x3 = x * x * x;
            let want = ((6 * x3 * x * x - 15 * x3 * x * (1 << 16)
                + 10 * x3 * (1 << 32)
                + (1 << 63))
                >> 64) as i64;
            assert_eq!(quintic(a), want, "{a}");
            assert_eq!(Fade::Quintic.apply(a | 0xABC_0000), want, "{a}");
        }
    }

    #[test]
    fn total_for_any_input() {
        for &f in all() {
            for a in [u32::MAX, 65536, 65537, 1 << 31] {
                let _ = f.apply(a);
                let _ = f.derivative(a);
            }
        }
    }
}
