//! Filter width from the gradient of `f` (`docs/model.md` section 8).
//!
//! `gx = df/dx` and `gy = df/dy` arrive as `i64` with 48 fraction bits. Each magnitude is first
//! saturated to `U16F16` (`min(|g| >> 32, u32::MAX)`, floor), then combined by the chosen
//! [`GradientNorm`] in `u64` (`L1 = a + b`, `Max = max(a, b)`, `L2 = isqrt(a^2 + b^2)`, all exact on
//! the saturated values; if `a^2 + b^2` does not fit `u64` the norm exceeds 46340 entries and the
//! width saturates), and the width `w = N * norm` (raw `norm << log2 N`) saturates at `N`.
//!
//! Guarantees: integer only, `const fn`, never panics or overflows for any input (including
//! `i64::MIN`); the result is always in `[0, N]` (with `log2 N` taken as at most 15, so `N << 16`
//! fits; larger values give `U16F16::MAX`). [`isqrt`] is the exact floor square root of any `u64`
//! in a fixed 32 iterations (no division, no floating point).

use crate::format::FilterWidth;

/// How the two screen-space derivatives of `f` combine into one filter width.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum GradientNorm {
    /// `|gx| + |gy|`: cheapest, over-blurs diagonals by up to sqrt(2).
    L1,
    /// `sqrt(gx^2 + gy^2)`: the gradient magnitude (one integer square root).
    #[default]
    L2,
    /// `max(|gx|, |gy|)`: under-blurs diagonals by up to sqrt(2).
    Max,
}

/// Where the filter widths come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WidthSource {
    /// The analytic gradient of `f` (exact: the model's gradients, `docs/model.md` section 8).
    #[default]
    Gradients,
    /// The differences of neighbouring values, as a GPU's `ddx`/`ddy` (approximate, about half
    /// the noise's cost: no gradients; [`crate::texture::DifferenceRows`]).
    Differences,
}

/// Exact integer square root, `floor(sqrt(v))`, for every `u64` (digit by digit, 32 fixed
/// iterations).
pub const fn isqrt(v: u64) -> u64 {
    let mut rem = v;
    let mut root = 0u64;
    let mut bit = 1u64 << 62;
    while bit != 0 {
        let trial = root + bit; // root < 2^(32 + i) and bit = 4^i here: no overflow
        if rem >= trial {
            rem -= trial;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// Exact integer square root of a `u32`, `floor(sqrt(v))`, by Newton's iteration from a power of
/// two above the root (monotone decreasing, so it stops at the floor; about four divisions).
/// Equal to [`isqrt`] on every `u32`; the filter width uses it in the pixel path.
pub const fn isqrt32(v: u32) -> u32 {
    if v == 0 {
        return 0;
    }
    // 2^ceil(bits / 2) > sqrt(v).
    let mut x = 1u32 << (32 - v.leading_zeros()).div_ceil(2);
    loop {
        // x >= 1 always (x > floor(sqrt(v)) >= 1 until the last step); x + v / x <= 2^17.
        let d = if x == 0 { 1 } else { x };
        let y = (x + v / d) >> 1;
        if y >= x {
            return x;
        }
        x = y;
    }
}

/// `floor((x + floor(v / x)) / 2)` without overflow: one integer Newton step (`None` for `x = 0`,
/// which the callers never pass).
#[cfg_attr(not(texcore_lean), inline(always))]
const fn newton_step(v: u32, x: u32) -> Option<u32> {
    match v.checked_div(x) {
        Some(q) => Some((x >> 1) + (q >> 1) + (x & q & 1)),
        None => None,
    }
}

/// Exact integer square root of a `u32`, `floor(sqrt(v))`, by Newton's iteration started from
/// `guess` (any value; a guess near the root makes it cheap). Equal to [`isqrt`] on every `u32`
/// for every guess.
///
/// Why it is exact for any guess: for any integer `x >= 1`, one step
/// `floor((x + floor(v / x)) / 2) = floor((x + v / x) / 2) >= floor(sqrt(v))` (arithmetic and
/// geometric means), so after the first, unconditional step the iterate is at or above the root;
/// from there every step strictly decreases the iterate while it is above `floor(sqrt(v))`
/// (`v / x < x`), and a step from `floor(sqrt(v))` does not decrease, which stops the loop there.
/// With the previous pixel's root as the guess (the filter width changes slowly along a span) this
/// costs two or three divisions.
pub const fn isqrt32_from(v: u32, guess: u32) -> u32 {
    if v == 0 {
        return 0;
    }
    // Any start in 1..=65535 (the root of a u32 is at most 65535).
    let x = if guess == 0 {
        1
    } else if guess > 0xFFFF {
        0xFFFF
    } else {
        guess
    };
    // After one step the iterate is >= floor(sqrt(v)) >= 1, so no later step divides by zero.
    let Some(mut x) = newton_step(v, x) else {
        return 0;
    };
    loop {
        let Some(y) = newton_step(v, x) else {
            return x;
        };
        if y >= x {
            return x;
        }
        x = y;
    }
}

/// The filter width of [`filter_width`] for a stream of pixels: the norm and table size are fixed
/// once, and the L2 square root starts from the previous pixel's root ([`isqrt32_from`]), which is
/// exact for any start. Every result equals [`filter_width`] of the same inputs.
#[derive(Clone, Copy, Debug)]
pub struct WidthStream {
    norm: GradientNorm,
    n_log2: u32,
    root: u32,
}

impl WidthStream {
    /// A stream for `norm` and a table of `2^n_log2` entries.
    pub const fn new(norm: GradientNorm, n_log2: u32) -> Self {
        WidthStream {
            norm,
            n_log2: if n_log2 > 15 { 16 } else { n_log2 },
            root: 1 << 8,
        }
    }

    /// [`filter_width`]`(gx, gy, norm, n_log2)`.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub fn width(&mut self, gx: i64, gy: i64) -> FilterWidth {
        let n_log2 = self.n_log2;
        if let (GradientNorm::L2, true) = (self.norm, n_log2 <= 15) {
            let a = saturate_to_u16f16(gx);
            let b = saturate_to_u16f16(gy);
            // A norm of at least 1.0 (2^16 raw) gives the cap `N` (L2 >= max(a, b)); below it,
            // `g << n_log2 < 2^31` is under the cap as it stands.
            let cap = FilterWidth::from_bits(1 << (16 + n_log2));
            if a >= 1 << 16 || b >= 1 << 16 {
                return cap;
            }
            // a, b < 2^16: the sum of squares is below 2^33.
            let (s, carry) = (a * a).overflowing_add(b * b);
            let g = if carry {
                isqrt(u64::from(s) + (1 << 32)) as u32
            } else {
                let r = isqrt32_from(s, self.root);
                self.root = r;
                r
            };
            return if g >= 1 << 16 {
                cap
            } else {
                FilterWidth::from_bits(g << n_log2)
            };
        }
        scale_width(gradient_norm(gx, gy, self.norm), n_log2)
    }

    /// [`filter_width_spread`]`(gx, gy, spread48, norm, n_log2)`: the width with a span's spread
    /// ([`crate::bandlimit`]) in quadrature; [`WidthStream::width`] when the spread is zero.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub fn width_with(&mut self, gx: i64, gy: i64, spread48: i64) -> FilterWidth {
        let e = saturate_to_u16f16(spread48);
        if e == 0 {
            return self.width(gx, gy);
        }
        let n_log2 = self.n_log2;
        if let (GradientNorm::L2, true) = (self.norm, n_log2 <= 15) {
            let a = saturate_to_u16f16(gx);
            let b = saturate_to_u16f16(gy);
            let cap = FilterWidth::from_bits(1 << (16 + n_log2));
            if a >= 1 << 16 || b >= 1 << 16 || e >= 1 << 16 {
                return cap;
            }
            // a, b, e < 2^16: the sum of squares is below 3 * 2^32.
            let s = u64::from(a * a) + u64::from(b * b) + u64::from(e * e);
            let g = if s <= u64::from(u32::MAX) {
                let r = isqrt32_from(s as u32, self.root);
                self.root = r;
                r
            } else {
                isqrt(s) as u32
            };
            return if g >= 1 << 16 {
                cap
            } else {
                FilterWidth::from_bits(g << n_log2)
            };
        }
        filter_width_spread(gx, gy, spread48, self.norm, n_log2)
    }
}

/// `w = g << n_log2` saturating at `N` (and at `u32::MAX`), `n_log2 <= 16`.
#[cfg_attr(not(texcore_lean), inline(always))]
const fn scale_width(g: u64, n_log2: u32) -> FilterWidth {
    let cap = 1u64 << (16 + n_log2);
    // g >> (48 - n_log2) != 0 means g << n_log2 would overflow u64; it is then far above the cap.
    let w = if g >> (48 - n_log2) != 0 {
        cap
    } else {
        let w = g << n_log2;
        if w > cap {
            cap
        } else {
            w
        }
    };
    FilterWidth::from_bits(if w > u32::MAX as u64 {
        u32::MAX
    } else {
        w as u32
    })
}

/// `|g|` (48 fraction bits) as `U16F16` raw, saturated to `u32::MAX` (floor).
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn saturate_to_u16f16(g: i64) -> u32 {
    let a = g.unsigned_abs() >> 32;
    if a > u32::MAX as u64 {
        u32::MAX
    } else {
        a as u32
    }
}

/// The norm of `(gx, gy)` (48 fraction bits each) in `U16F16` raw units (may exceed `u32` for
/// `L1`; `u64::MAX` stands for "too large to matter" when `L2` overflows).
pub const fn gradient_norm(gx: i64, gy: i64, norm: GradientNorm) -> u64 {
    let a = saturate_to_u16f16(gx) as u64;
    let b = saturate_to_u16f16(gy) as u64;
    match norm {
        GradientNorm::L1 => a + b,
        GradientNorm::Max => {
            if a > b {
                a
            } else {
                b
            }
        }
        GradientNorm::L2 => match (a * a).checked_add(b * b) {
            Some(s) => isqrt(s),
            None => u64::MAX,
        },
    }
}

/// The box filter width in table entries, `w = N * norm(gx, gy)` saturating at `N = 2^n_log2`
/// (model section 8). `gx`, `gy` have 48 fraction bits.
pub const fn filter_width(gx: i64, gy: i64, norm: GradientNorm, n_log2: u32) -> FilterWidth {
    let n_log2 = if n_log2 > 15 { 16 } else { n_log2 };
    let g = match norm {
        // Fast path, same result: a norm of at least 1.0 (2^16 raw) always gives the cap, and L2 is
        // at least max(a, b); below that a^2 + b^2 < 2^33, almost always a u32 (isqrt32).
        GradientNorm::L2 => {
            let a = saturate_to_u16f16(gx) as u64;
            let b = saturate_to_u16f16(gy) as u64;
            if a >= 1 << 16 || b >= 1 << 16 {
                1 << 16
            } else {
                let s = a * a + b * b;
                if s <= u32::MAX as u64 {
                    isqrt32(s as u32) as u64
                } else {
                    isqrt(s)
                }
            }
        }
        _ => gradient_norm(gx, gy, norm),
    };
    scale_width(g, n_log2)
}

/// The box filter width with a spread: `w = N * sqrt(norm(gx, gy)^2 + e^2)` saturating at `N`,
/// where `e` is the spread width of faded and culled octaves (`spread48`, `f` units with 48
/// fraction bits, [`crate::bandlimit::spread_width48`]): a standard deviation, so it adds in
/// quadrature. Each of `norm` and `e` is first saturated to `U16F16` (floor); either at 1.0 or
/// more gives the cap. Equal to [`filter_width`] when `spread48` is zero or negative.
pub const fn filter_width_spread(
    gx: i64,
    gy: i64,
    spread48: i64,
    norm: GradientNorm,
    n_log2: u32,
) -> FilterWidth {
    let e = saturate_to_u16f16(spread48) as u64;
    if spread48 <= 0 || e == 0 {
        return filter_width(gx, gy, norm, n_log2);
    }
    let n_log2 = if n_log2 > 15 { 16 } else { n_log2 };
    // The square of the gradient's norm (U16F16 squared), `None` at 1.0 or more (the cap).
    let sq = match norm {
        GradientNorm::L2 => {
            let a = saturate_to_u16f16(gx) as u64;
            let b = saturate_to_u16f16(gy) as u64;
            if a >= 1 << 16 || b >= 1 << 16 {
                None
            } else {
                Some(a * a + b * b)
            }
        }
        _ => {
            let n = gradient_norm(gx, gy, norm);
            if n >= 1 << 16 {
                None
            } else {
                Some(n * n)
            }
        }
    };
    let g = match sq {
        Some(sq) if e < 1 << 16 => isqrt(sq + e * e),
        _ => 1 << 16,
    };
    scale_width(g, n_log2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn check_isqrt(v: u64) {
        let r = isqrt(v) as u128;
        assert!(
            r * r <= v as u128 && (r + 1) * (r + 1) > v as u128,
            "isqrt({v}) = {r}"
        );
    }

    #[test]
    fn isqrt_exact() {
        for v in 0..200_000u64 {
            check_isqrt(v);
        }
        for k in [1u64, 2, 3, 255, 256, 65535, 65536, 1 << 31, (1 << 32) - 1] {
            for d in [-1i64, 0, 1] {
                check_isqrt((k * k).wrapping_add_signed(d));
            }
        }
        check_isqrt(u64::MAX);
        assert_eq!(isqrt(u64::MAX), u32::MAX as u64);
        assert_eq!(isqrt(1 << 62), 1 << 31);
        const C: u64 = isqrt(1_000_000);
        assert_eq!(C, 1000);
    }

    /// The pre-fast-path definition of the width, for comparison.
    fn filter_width_reference(gx: i64, gy: i64, norm: GradientNorm, n_log2: u32) -> u32 {
        let n_log2 = n_log2.min(16);
        let cap = 1u64 << (16 + n_log2);
        let g = gradient_norm(gx, gy, norm);
        let w = if g >> (48 - n_log2) != 0 {
            cap
        } else {
            (g << n_log2).min(cap)
        };
        w.min(u64::from(u32::MAX)) as u32
    }

    #[test]
    fn isqrt32_from_at_square_boundaries() {
        // Every root's first and last value (r^2 and r^2 + 2r), from guesses at, next to and far
        // from the root: the loop stops exactly at the boundaries.
        for r in (1u32..=0xFFFF).step_by(7).chain([1, 2, 3, 0xFFFE, 0xFFFF]) {
            let lo = r * r;
            let hi = lo + (2 * r).min(u32::MAX - lo);
            for v in [lo, hi, lo - 1] {
                let want = isqrt(u64::from(v)) as u32;
                for g in [r - 1, r, r + 1, r + 2, r / 2, 1, 0xFFFF] {
                    assert_eq!(isqrt32_from(v, g), want, "{v} from {g}");
                }
            }
        }
    }

    #[test]
    fn isqrt32_from_guesses() {
        for v in (0..=u32::MAX)
            .step_by(65_521)
            .chain([u32::MAX, 1, 2, 3, 4, 65535 * 65535])
        {
            let r = isqrt(u64::from(v)) as u32;
            for g in [
                0,
                1,
                2,
                r.saturating_sub(1),
                r,
                r + 1,
                r * 2,
                65535,
                65536,
                u32::MAX,
            ] {
                assert_eq!(isqrt32_from(v, g), r, "{v} from {g}");
            }
        }
    }

    #[test]
    fn isqrt32_exact() {
        for v in (0..=u32::MAX)
            .step_by(9973)
            .chain(0..100_000)
            .chain([u32::MAX, u32::MAX - 1])
        {
            assert_eq!(u64::from(isqrt32(v)), isqrt(u64::from(v)), "{v}");
        }
        for r in 0..=65535u32 {
            for v in [r * r, (r * r).saturating_sub(1), r * r + 2 * r] {
                assert_eq!(u64::from(isqrt32(v)), isqrt(u64::from(v)), "{v}");
            }
        }
    }

    proptest! {
        #[test]
        fn width_fast_path_is_the_reference(
            gx in any::<i64>(),
            gy in any::<i64>(),
            shift in 0u32..40,
            n_log2 in 0u32..18,
        ) {
            let (gx, gy) = (gx >> shift, gy >> (shift / 2));
            for norm in [GradientNorm::L1, GradientNorm::L2, GradientNorm::Max] {
                prop_assert_eq!(
                    filter_width(gx, gy, norm, n_log2).to_bits(),
                    filter_width_reference(gx, gy, norm, n_log2)
                );
            }
        }

        #[test]
        fn width_stream_is_filter_width(
            g in proptest::collection::vec((any::<i64>(), any::<i64>(), 0u32..40), 1..40),
            n_log2 in 0u32..18,
        ) {
            for norm in [GradientNorm::L1, GradientNorm::L2, GradientNorm::Max] {
                let mut st = WidthStream::new(norm, n_log2);
                for &(gx, gy, shift) in &g {
                    let (gx, gy) = (gx >> shift, gy >> shift);
                    prop_assert_eq!(st.width(gx, gy), filter_width(gx, gy, norm, n_log2));
                }
            }
        }

        #[test]
        fn isqrt32_from_any_guess(v in any::<u32>(), guess in any::<u32>()) {
            prop_assert_eq!(u64::from(isqrt32_from(v, guess)), isqrt(u64::from(v)));
        }

        #[test]
        fn isqrt_random(v in any::<u64>()) {
            check_isqrt(v);
            prop_assert_eq!(isqrt(v), v.isqrt());
        }
    }

    /// f64 reference of section 8 (floor of each step, saturations as specified).
    fn width_f64(gx: i64, gy: i64, norm: GradientNorm, n_log2: u32) -> f64 {
        let sat = |g: i64| ((g as f64).abs() / 2f64.powi(48)).min(u32::MAX as f64 / 65536.0);
        let sat = |g: i64| (sat(g) * 65536.0).floor() / 65536.0;
        let (a, b) = (sat(gx), sat(gy));
        let n = 2f64.powi(n_log2 as i32);
        let nrm = match norm {
            GradientNorm::L1 => a + b,
            GradientNorm::Max => a.max(b),
            GradientNorm::L2 => (a * a + b * b).sqrt(),
        };
        (nrm * n).min(n)
    }

    fn check_width(gx: i64, gy: i64) {
        for norm in [GradientNorm::L1, GradientNorm::L2, GradientNorm::Max] {
            for n_log2 in [1u32, 4, 8, 10] {
                let w = filter_width(gx, gy, norm, n_log2).to_num::<f64>();
                let r = width_f64(gx, gy, norm, n_log2);
                // Exact for L1 / Max; L2 floors the root in 1/65536 units before scaling by N.
                let tol = match norm {
                    GradientNorm::L2 => (1u32 << n_log2) as f64 / 65536.0 + 1e-9,
                    _ => 1e-12,
                };
                assert!(
                    w <= r + 1e-9 && w >= r - tol,
                    "{gx} {gy} {norm:?} {n_log2}: {w} vs {r}"
                );
                assert!(w <= (1u32 << n_log2) as f64);
            }
        }
    }

    #[test]
    fn width_examples() {
        let one = 1i64 << 48;
        // |grad| = 1/256 entry-widths of f per pixel, N = 256 -> w = 1 entry.
        assert_eq!(
            filter_width(one / 256, 0, GradientNorm::L2, 8),
            FilterWidth::from_num(1)
        );
        // 3-4-5.
        assert_eq!(
            filter_width(3 * one / 1024, -4 * one / 1024, GradientNorm::L2, 10),
            FilterWidth::from_num(5)
        );
        assert_eq!(
            filter_width(3 * one / 1024, -4 * one / 1024, GradientNorm::L1, 10),
            FilterWidth::from_num(7)
        );
        assert_eq!(
            filter_width(3 * one / 1024, -4 * one / 1024, GradientNorm::Max, 10),
            FilterWidth::from_num(4)
        );
        // Saturation at N.
        for norm in [GradientNorm::L1, GradientNorm::L2, GradientNorm::Max] {
            assert_eq!(filter_width(one, one, norm, 8), FilterWidth::from_num(256));
            assert_eq!(
                filter_width(i64::MIN, i64::MIN, norm, 8),
                FilterWidth::from_num(256)
            );
            assert_eq!(
                filter_width(i64::MAX, i64::MIN, norm, 10),
                FilterWidth::from_num(1024)
            );
            assert_eq!(filter_width(0, 0, norm, 8), FilterWidth::ZERO);
            assert_eq!(filter_width(i64::MAX, 0, norm, 40), FilterWidth::MAX);
            assert_eq!(
                filter_width(i64::MAX, 0, norm, 15),
                FilterWidth::from_num(32768)
            );
        }
        // Below U16F16 resolution: floors to zero.
        assert_eq!(
            filter_width((1 << 32) - 1, 0, GradientNorm::L1, 1),
            FilterWidth::ZERO
        );
    }

    #[test]
    fn width_grid() {
        let vals = [
            0i64,
            1,
            -1,
            1 << 32,
            (1 << 32) + 1,
            1 << 40,
            -(1 << 40),
            1 << 47,
            1 << 48,
            3 << 47,
            1 << 62,
            i64::MAX,
            i64::MIN,
            123_456_789_012,
        ];
        for &a in &vals {
            for &b in &vals {
                check_width(a, b);
            }
        }
    }

    proptest! {
        #[test]
        fn width_random(gx in -(1i64 << 50)..(1i64 << 50), gy in -(1i64 << 50)..(1i64 << 50)) {
            check_width(gx, gy);
        }

        #[test]
        fn width_random_any(gx in any::<i64>(), gy in any::<i64>()) {
            check_width(gx, gy);
        }
    }
}
