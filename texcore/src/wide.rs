//! Wide-integer helpers shared by the set-up code (triangle set-up, Hermite segments).
//!
//! 32-bit targets have no i128 division instruction or library routine: the compiler expands
//! every i128 division site inline (about 1 KB of code each on the Cortex-M4F). The set-up code
//! divides in i128 in several places, none of them per pixel, so they share the one out-of-line
//! division here.
//!
//! The full-width division is a long software loop on 32-bit targets (thousands of instructions
//! on the Cortex-M4F), while the operands the set-up code meets almost always fit narrower
//! types (a triangle's edge on screen, a plane gradient). The division therefore takes the
//! narrowest exact path its operands allow: the 32-bit hardware divide (`sdiv` on the Cortex-M4F,
//! `div` on rv32imc), the 64-bit library division, a 128-by-64-bit long division in two 32-bit
//! digits (Knuth's algorithm D as in *Hacker's Delight* `divlu`, whenever the divisor fits 64 bits
//! and the quotient does too, as in the triangle set-up's plane equations), and only then the
//! general 128-bit one. Every path gives the same quotient and remainder.

/// `(n.div_euclid(d), n.rem_euclid(d))` with a single division; `(0, 0)` where those would panic
/// (`d == 0`, or `i128::MIN / -1`), which no caller reaches.
#[inline(never)]
pub(crate) fn div_rem_euclid_i128(n: i128, d: i128) -> (i128, i128) {
    if let (Ok(n32), Ok(d32)) = (i32::try_from(n), i32::try_from(d)) {
        // `i32::MIN / -1` overflows: left to the wider paths.
        if d32 != 0 && !(n32 == i32::MIN && d32 == -1) {
            return (
                i128::from(n32.div_euclid(d32)),
                i128::from(n32.rem_euclid(d32)),
            );
        }
    }
    if let (Ok(n64), Ok(d64)) = (i64::try_from(n), i64::try_from(d)) {
        if d64 != 0 && !(n64 == i64::MIN && d64 == -1) {
            return (
                i128::from(n64.div_euclid(d64)),
                i128::from(n64.rem_euclid(d64)),
            );
        }
    }
    if let Ok(dm) = u64::try_from(d.unsigned_abs()) {
        if n == i128::MIN && d == -1 {
            return (0, 0);
        }
        if let Some((qm, rm)) = div_rem_u128_by_u64(n.unsigned_abs(), dm) {
            // Truncated quotient and remainder from the magnitudes (|q| <= |n| <= 2^127;
            // |q| = 2^127 only for n = i128::MIN, d = 1, where the wrap gives the right q).
            let (qm, rm) = (qm as i128, i128::from(rm));
            let q = if (n < 0) != (d < 0) {
                qm.wrapping_neg()
            } else {
                qm
            };
            let r = if n < 0 { -rm } else { rm };
            return euclid(q, r, d);
        }
    }
    wide_div_rem_euclid(n, d)
}

/// The Euclidean quotient and remainder from the truncated ones (`n = q d + r`, `r` with the
/// sign of `n`).
#[inline]
fn euclid(q: i128, r: i128, d: i128) -> (i128, i128) {
    if r < 0 {
        if d > 0 {
            (q.wrapping_sub(1), r.wrapping_add(d))
        } else {
            (q.wrapping_add(1), r.wrapping_sub(d))
        }
    } else {
        (q, r)
    }
}

/// `(n / d, n % d)` for `d != 0` (`None` for `d == 0`): the high 64 bits of `n` by a 64-bit
/// division, then a long division of the remainder and the low 64 bits, normalised, by the
/// divisor's top 32-bit digit: two quotient digits, each estimated by one 64-by-32-bit division
/// and corrected at most twice (Knuth, TAOCP vol. 2, 4.3.1, algorithm D; *Hacker's Delight* 9-3,
/// `divlu`).
fn div_rem_u128_by_u64(n: u128, d: u64) -> Option<(u128, u64)> {
    let (hi, u0) = ((n >> 64) as u64, n as u64);
    let q_hi = hi.checked_div(d)?;
    let u1 = hi - q_hi * d;
    let (q_lo, r) = div_rem_below(u1, u0, d);
    Some(((u128::from(q_hi) << 64) | u128::from(q_lo), r))
}

/// `(u1:u0 / d, u1:u0 % d)` for `u1 < d` (so `d != 0` and the quotient fits 64 bits).
fn div_rem_below(u1: u64, u0: u64, d: u64) -> (u64, u64) {
    const B: u64 = 1 << 32;
    const LO: u64 = B - 1;
    if u1 == 0 {
        // `max(1)`: d > u1 = 0 already.
        let d = d.max(1);
        return (u0 / d, u0 % d);
    }
    let s = d.leading_zeros();
    let v = d << s;
    // v's top bit is set, so vn1 >= 2^31 (`max(1)` only states that it is not 0).
    let (vn1, vn0) = ((v >> 32).max(1), v & LO);
    let un32 = if s == 0 {
        u1
    } else {
        (u1 << s) | (u0 >> (64 - s))
    };
    let un10 = u0 << s;
    let (un1, un0) = (un10 >> 32, un10 & LO);
    let digit = |top: u64, next: u64| -> u64 {
        let mut q = top / vn1;
        let mut rhat = top - q * vn1;
        // q >= B is tested first, so q * vn0 < 2^64; rhat < B, so B * rhat + next < 2^64.
        while q >= B || q * vn0 > (rhat << 32) + next {
            q = q.wrapping_sub(1);
            rhat += vn1;
            if rhat >= B {
                break;
            }
        }
        q
    };
    let q1 = digit(un32, un1);
    let un21 = (un32 << 32)
        .wrapping_add(un1)
        .wrapping_sub(q1.wrapping_mul(v));
    let q0 = digit(un21, un0);
    let r = (un21 << 32)
        .wrapping_add(un0)
        .wrapping_sub(q0.wrapping_mul(v))
        >> s;
    ((q1 << 32) | q0, r)
}

/// The 128-bit path of [`div_rem_euclid_i128`].
#[inline(never)]
fn wide_div_rem_euclid(n: i128, d: i128) -> (i128, i128) {
    let Some(q) = n.checked_div(d) else {
        return (0, 0);
    };
    let r = n.wrapping_sub(q.wrapping_mul(d));
    euclid(q, r, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_div_euclid_and_rem_euclid() {
        let vals: [i128; 22] = [
            0,
            1,
            -1,
            2,
            -2,
            7,
            -7,
            15,
            -16,
            3375,
            i128::from(i32::MAX),
            i128::from(i32::MIN),
            i128::from(i32::MIN) + 1,
            i128::from(i32::MAX) + 1,
            i128::from(i64::MAX),
            i128::from(i64::MIN),
            i128::from(i64::MIN) + 1,
            -123_456_789_012,
            i128::from(i64::MAX) * 5 + 3,
            -(i128::from(i64::MAX) * 7) - 11,
            i128::MAX,
            i128::MIN + 1,
        ];
        for &n in &vals {
            for &d in &vals {
                if d == 0 {
                    assert_eq!(div_rem_euclid_i128(n, d), (0, 0));
                    continue;
                }
                assert_eq!(
                    div_rem_euclid_i128(n, d),
                    (n.div_euclid(d), n.rem_euclid(d)),
                    "{n} / {d}"
                );
            }
        }
        assert_eq!(div_rem_euclid_i128(i128::MIN, -1), (0, 0));
        assert_eq!(
            div_rem_euclid_i128(i128::MIN, i128::from(i64::MIN)),
            (1i128 << 64, 0)
        );
        assert_eq!(
            div_rem_euclid_i128(i128::MIN, 3),
            (i128::MIN.div_euclid(3), i128::MIN.rem_euclid(3))
        );
    }

    fn check(n: i128, d: i128) {
        if d == 0 {
            return;
        }
        assert_eq!(
            div_rem_euclid_i128(n, d),
            (n.div_euclid(d), n.rem_euclid(d)),
            "{n} / {d}"
        );
    }

    #[test]
    fn long_division_edges() {
        // Divisors around the normalisation shifts and digit boundaries, dividends whose
        // quotient just fits 64 bits, and the correction steps of both digits.
        let ds: [u64; 10] = [
            1,
            3,
            (1 << 32) - 1,
            1 << 32,
            (1 << 32) + 1,
            (1 << 63) - 1,
            1 << 63,
            u64::MAX,
            0x8000_0000_0000_0001,
            0xffff_ffff_0000_0001,
        ];
        for &d in &ds {
            let d = i128::from(d);
            for n in [
                d * i128::from(i64::MAX),
                d * i128::from(i64::MAX) + d - 1,
                d * 0x7654_3210_fedc_ba98 + d / 3,
                d.saturating_mul(i128::from(u64::MAX)),
                d.saturating_mul(i128::from(u64::MAX)) - 1,
                d * (1 << 40) + 12345,
                (d << 32) - 1,
                (1i128 << 64) + d / 2,
                ((1i128 << 96) - 1).min(d * i128::from(i64::MAX)),
            ] {
                for (sn, sd) in [(1, 1), (-1, 1), (1, -1), (-1, -1)] {
                    check(sn * n, sd * d);
                }
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn every_path_matches_div_euclid(
            n in proptest::prelude::any::<i128>(),
            d in proptest::prelude::any::<i64>(),
            shift in 0u32..127,
            nshift in 0u32..127,
        ) {
            check(n, i128::from(d));
            check(n >> nshift, i128::from(d));
            check(n >> nshift, (i128::from(d) << 64) >> shift);
            check(n >> nshift, i128::from(d >> (shift % 64)));
        }
    }
}
