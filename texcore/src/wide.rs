//! Wide-integer helpers shared by the set-up code (triangle set-up, Hermite segments).
//!
//! 32-bit targets have no i128 division instruction or library routine: the compiler expands
//! every i128 division site inline (about 1 KB of code each on the Cortex-M4F). The set-up code
//! divides in i128 in several places, none of them per pixel, so they share the one out-of-line
//! division here.
//!
//! The general 128-bit division is a long software loop on 32-bit targets (well over a thousand
//! instructions on the Cortex-M4F), and even the 64-bit library division costs a couple of
//! hundred, while the operands the set-up code meets almost always allow something narrower (a
//! triangle edge on screen, a plane's gradient: divisors below 2^64, often below 2^32). The
//! division therefore takes the narrowest exact path its operands allow: the 32-bit hardware
//! divide (`sdiv` on the Cortex-M4F, `div` on rv32imc) when both fit 32 bits; for a divisor that
//! fits 64 bits, schoolbook long division in 32-bit digits whose digit estimates are themselves
//! long divisions in 16-bit digits on the 32-bit hardware divide (Knuth, TAOCP vol. 2, 4.3.1,
//! algorithm D; *Hacker's Delight* 9-3, `divlu`); and only for wider divisors, which no set-up
//! meets in practice, a small bit-by-bit long division. Every path gives the exact quotient and
//! remainder (tests compare them with the native operators over edge cases and random operands).

/// `v.leading_zeros()`, for the set-up code's normalisations. rv32imc has no count-leading-zeros
/// instruction (the Zbb extension adds one): the compiler's expansion there is about 30
/// instructions, [`leading_zeros_by_table`] about 8, so rv32imc without Zbb takes the table.
#[inline(always)]
pub(crate) fn leading_zeros_u32(v: u32) -> u32 {
    if cfg!(all(target_arch = "riscv32", not(target_feature = "zbb"))) {
        leading_zeros_by_table(v)
    } else {
        v.leading_zeros()
    }
}

/// The significant bits of each byte value.
const BYTE_BITS: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut i = 1;
    while i < 256 {
        t[i] = t[i / 2] + 1;
        i += 1;
    }
    t
};

/// `v.leading_zeros()` from the byte holding `v`'s top set bit and a 256-entry table.
#[inline(always)]
fn leading_zeros_by_table(v: u32) -> u32 {
    let shift = if v >> 16 != 0 {
        if v >> 24 != 0 {
            24
        } else {
            16
        }
    } else if v >> 8 != 0 {
        8
    } else {
        0
    };
    32 - shift - u32::from(BYTE_BITS[((v >> shift) & 0xFF) as usize])
}

/// `a * b` exactly (the full product of two `i64`, below `2^126` in magnitude).
///
/// 32-bit targets have no 64 x 64 -> 128 multiply instruction: the compiler expands every `i128`
/// product inline (and does not always see that both factors are sign-extended `i64`). The
/// size-lean shape keeps this one copy out of line for the set-up code's many products.
#[cfg_attr(texcore_lean, inline(never))]
#[cfg_attr(not(texcore_lean), inline)]
pub(crate) fn mul_wide(a: i64, b: i64) -> i128 {
    i128::from(a) * i128::from(b)
}

/// `a * b` of two `i128`, wrapping (as the operator in builds without overflow checks; the
/// callers' products stay in range).
///
/// 32-bit targets have no 128-bit multiply routine: the compiler expands every `i128` product
/// inline. The size-lean shape keeps this one copy out of line for the callers that need a
/// factor wider than 64 bits (the noise derivative's chain rule).
#[cfg_attr(texcore_lean, inline(never))]
#[cfg_attr(not(texcore_lean), inline)]
pub(crate) fn mul_i128(a: i128, b: i128) -> i128 {
    a.wrapping_mul(b)
}

/// The size-lean code shape (`cfg(texcore_lean)`, see the crate documentation): the divisions
/// skip their 32-bit shortcuts (operands that fit 32 bits, short division by a 32-bit divisor)
/// and take the general two-word path, which is exact for every operand (unit tests run both
/// shapes in every build).
const LEAN: bool = cfg!(texcore_lean);

/// `(n.div_euclid(d), n.rem_euclid(d))` with a single division; `(0, 0)` where those would panic
/// (`d == 0`, or `i128::MIN / -1`), which no caller reaches.
#[inline(never)]
pub(crate) fn div_rem_euclid_i128(n: i128, d: i128) -> (i128, i128) {
    div_rem_euclid_i128_shaped(n, d, LEAN)
}

/// [`div_rem_euclid_i128`] in the size-lean shape (`lean`) or the fast one.
#[inline(always)]
fn div_rem_euclid_i128_shaped(n: i128, d: i128, lean: bool) -> (i128, i128) {
    if let (false, Ok(n32), Ok(d32)) = (lean, i32::try_from(n), i32::try_from(d)) {
        // `i32::MIN / -1` overflows: left to the wider paths.
        if let Some((q, r)) = div_rem_euclid_i32(n32, d32) {
            return (i128::from(q), i128::from(r));
        }
    }
    if d == 0 || (n == i128::MIN && d == -1) {
        return (0, 0);
    }
    let (nm, dm) = (n.unsigned_abs(), d.unsigned_abs());
    let (qm, rm) = match u64::try_from(dm) {
        Ok(d64) => match div_rem_u128_by_u64(nm, d64, lean) {
            Some((q, r)) => (q, u128::from(r)),
            None => return (0, 0),
        },
        Err(_) => div_rem_u128_binary(nm, dm),
    };
    // Truncated quotient and remainder from the magnitudes (|q| <= |n| <= 2^127; |q| = 2^127
    // only for n = i128::MIN, d = 1, where the wrap gives the right q; |r| < |d|).
    let (qm, rm) = (qm as i128, rm as i128);
    let q = if (n < 0) != (d < 0) {
        qm.wrapping_neg()
    } else {
        qm
    };
    let r = if n < 0 { rm.wrapping_neg() } else { rm };
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

/// `(n.div_euclid(d), n.rem_euclid(d))` on the 32-bit hardware divide; `None` for `d == 0` and
/// for `i32::MIN / -1` (which overflows).
#[inline]
fn div_rem_euclid_i32(n: i32, d: i32) -> Option<(i32, i32)> {
    Some((n.checked_div_euclid(d)?, n.checked_rem_euclid(d)?))
}

/// `(n.div_euclid(d), n.rem_euclid(d))` for `i64` operands: on the 32-bit hardware divide when
/// both fit `i32` (inlined into the caller), otherwise by [`div_rem_euclid_i128`] (`(0, 0)`
/// for `d == 0`; `i64::MIN / -1` wraps). Not used by the size-lean shape, whose callers divide
/// in `i128` directly.
#[cfg(not(texcore_lean))]
#[inline]
pub(crate) fn div_rem_euclid_i64(n: i64, d: i64) -> (i64, i64) {
    if let (Ok(n32), Ok(d32)) = (i32::try_from(n), i32::try_from(d)) {
        if let Some((q, r)) = div_rem_euclid_i32(n32, d32) {
            return (i64::from(q), i64::from(r));
        }
    }
    let (q, r) = div_rem_euclid_i128(i128::from(n), i128::from(d));
    (q as i64, r as i64)
}

/// `(n / d, n % d)` for `d >= 2^64` (never 0): restoring binary long division, one quotient bit
/// per step. Slow (a few thousand instructions on a 32-bit core) but small, and no caller's
/// divisor is that large in practice (the faster paths take everything below 2^64).
fn div_rem_u128_binary(n: u128, d: u128) -> (u128, u128) {
    let (mut q, mut r) = (0u128, 0u128);
    for i in (0..u128::BITS - n.leading_zeros()).rev() {
        // r < d <= 2^127, so the shift does not overflow.
        r = (r << 1) | ((n >> i) & 1);
        if r >= d {
            r -= d;
            q |= 1 << i;
        }
    }
    (q, r)
}

/// A divisor below 2^64 prepared once for many exact divisions by it (the triangle set-up divides
/// fifteen plane numerators by the same doubled area): the normalised divisor and its
/// reciprocal `v = floor((2^128 - 1) / d) - 2^64`, so that each two-word step is a multiplication
/// and at most two corrections (Möller and Granlund, *Improved division by invariant integers*,
/// IEEE Trans. Computers 2011, algorithm 4).
/// (Not used by the size-lean shape, whose set-up divides with [`div_rem_euclid_i128`].)
#[derive(Clone, Copy, Debug)]
#[cfg_attr(texcore_lean, allow(dead_code))]
pub(crate) struct Reciprocal64 {
    /// The divisor shifted left until its top bit is set.
    d: u64,
    /// The reciprocal of `d`.
    v: u64,
    /// The shift.
    s: u32,
}

#[cfg_attr(texcore_lean, allow(dead_code))]
impl Reciprocal64 {
    /// The reciprocal of `d` (`None` for 0).
    pub(crate) fn new(d: u64) -> Option<Reciprocal64> {
        if d == 0 {
            return None;
        }
        let s = d.leading_zeros();
        let d = d << s;
        // floor(((2^64 - 1 - d) 2^64 + 2^64 - 1) / d); !d < 2^63 <= d, as the long division needs.
        let (v, _) = div_rem_below_u64(!d, u64::MAX, d);
        Some(Reciprocal64 { d, v, s })
    }

    /// `(u1:u0 / d, u1:u0 % d)` of the normalised divisor, for `u1 < d`.
    #[inline]
    fn div_2by1(&self, u1: u64, u0: u64) -> (u64, u64) {
        let d = self.d;
        let q = (u128::from(self.v) * u128::from(u1))
            .wrapping_add((u128::from(u1) << 64) | u128::from(u0));
        let (mut q1, q0) = (((q >> 64) as u64).wrapping_add(1), q as u64);
        let mut r = u0.wrapping_sub(q1.wrapping_mul(d));
        if r > q0 {
            q1 = q1.wrapping_sub(1);
            r = r.wrapping_add(d);
        }
        if r >= d {
            q1 = q1.wrapping_add(1);
            r -= d;
        }
        (q1, r)
    }

    /// `(n / d, n % d)` of the original divisor.
    pub(crate) fn div_rem(&self, n: u128) -> (u128, u64) {
        let s = self.s;
        // n << s as three words; the top one is below 2^s <= 2^63 <= d.
        let (n2, n1, n0) = if s == 0 {
            (0, (n >> 64) as u64, n as u64)
        } else {
            let m = n << s;
            ((n >> (128 - s)) as u64, (m >> 64) as u64, m as u64)
        };
        let (q1, r1) = self.div_2by1(n2, n1);
        let (q0, r0) = self.div_2by1(r1, n0);
        ((u128::from(q1) << 64) | u128::from(q0), r0 >> s)
    }
}

/// A divisor below 2^32 prepared once for many exact divisions by it: [`Reciprocal64`] in 32-bit
/// words (the doubled area of every triangle smaller than about 4000 pixels on a side fits), so
/// each quotient digit is one 32 x 32 -> 64-bit multiplication and at most two corrections, and
/// the leading zero words of a numerator cost nothing (a plane numerator of a small triangle has
/// two or three significant words, not four).
/// (Not used by the size-lean shape, whose set-up divides with [`div_rem_euclid_i128`].)
#[derive(Clone, Copy, Debug)]
#[cfg_attr(texcore_lean, allow(dead_code))]
pub(crate) struct Reciprocal32 {
    /// The divisor shifted left until its top bit is set.
    d: u32,
    /// `floor((2^64 - 1) / d) - 2^32`.
    v: u32,
    /// The shift.
    s: u32,
}

#[cfg_attr(texcore_lean, allow(dead_code))]
impl Reciprocal32 {
    /// The reciprocal of `d` (`None` for 0).
    pub(crate) fn new(d: u32) -> Option<Reciprocal32> {
        if d == 0 {
            return None;
        }
        let s = leading_zeros_u32(d);
        let d = d << s;
        // floor(((2^32 - 1 - d) 2^32 + 2^32 - 1) / d); !d < 2^31 <= d, as the long division needs.
        let (v, _) = div_rem_below_u32(!d, u32::MAX, d);
        Some(Reciprocal32 { d, v, s })
    }

    /// `(u1:u0 / d, u1:u0 % d)` of the normalised divisor, for `u1 < d`.
    #[inline(always)]
    fn div_2by1(&self, u1: u32, u0: u32) -> (u32, u32) {
        let d = self.d;
        let q =
            (u64::from(self.v) * u64::from(u1)).wrapping_add((u64::from(u1) << 32) | u64::from(u0));
        let (mut q1, q0) = (((q >> 32) as u32).wrapping_add(1), q as u32);
        let mut r = u0.wrapping_sub(q1.wrapping_mul(d));
        if r > q0 {
            q1 = q1.wrapping_sub(1);
            r = r.wrapping_add(d);
        }
        if r >= d {
            q1 = q1.wrapping_add(1);
            r -= d;
        }
        (q1, r)
    }

    /// `(n / d, n % d)` of the original divisor.
    pub(crate) fn div_rem(&self, n: u128) -> (u128, u32) {
        let (d, s) = (self.d, self.s);
        let w = [
            (n >> 96) as u32,
            (n >> 64) as u32,
            (n >> 32) as u32,
            n as u32,
        ];
        // n << s as five 32-bit words, top first (word shifts only: 128-bit shifts by a variable
        // amount are slow on 32-bit cores); `(y >> 1) >> (31 - s)` is `y >> (32 - s)`, 0 for s = 0.
        let join = |x: u32, y: u32| (x << s) | ((y >> 1) >> (31 - s));
        let sh = [
            join(0, w[0]),
            join(w[0], w[1]),
            join(w[1], w[2]),
            join(w[2], w[3]),
            w[3] << s,
        ];
        // Leading zero words give zero quotient digits, and so does the first non-zero word when
        // it is below d (it becomes the remainder): skipped. (An unrolled loop over registers;
        // the words are not indexed through memory.)
        let zeros = sh.iter().take_while(|&&x| x == 0).count();
        let mut start = zeros;
        let mut r = 0;
        for (i, &x) in sh.iter().enumerate() {
            if i == zeros && x < d {
                r = x;
                start = zeros + 1;
            }
        }
        let mut q = 0u128;
        for (i, &x) in sh.iter().enumerate() {
            if i >= start {
                let (qd, rd) = self.div_2by1(r, x);
                q = (q << 32) | u128::from(qd);
                r = rd;
            }
        }
        (q, r >> s)
    }

    /// `n / d` of the original divisor, for `n < 2^127`, in straight-line code: `n << s` as five
    /// 32-bit words whose top one (below `2^s <= 2^31 <= d`) is the first remainder, then one two-word step per remaining word, high to low, skipping the steps of
    /// leading zero words of `n` (their quotient digits are 0 and their shifted word, below
    /// `2^s`, is the next remainder). At most four steps of one 32 x 32 -> 64-bit product each.
    #[inline(always)]
    pub(crate) fn div_u127(&self, n: u128) -> u128 {
        let s = self.s;
        let (w3, w2, w1, w0) = (
            (n >> 96) as u32,
            (n >> 64) as u32,
            (n >> 32) as u32,
            n as u32,
        );
        // `(x << s) | (y >> (32 - s))`, 0 for the second part when s = 0.
        let join = |x: u32, y: u32| (x << s) | ((y >> 1) >> (31 - s));
        let (q3, r) = if w3 == 0 {
            (0, join(0, w2))
        } else {
            self.div_2by1(join(0, w3), join(w3, w2))
        };
        let (q2, r) = if (w3 | w2) == 0 {
            (0, join(0, w1))
        } else {
            self.div_2by1(r, join(w2, w1))
        };
        let (q1, r) = self.div_2by1(r, join(w1, w0));
        let (q0, _) = self.div_2by1(r, w0 << s);
        let lo = (u64::from(q1) << 32) | u64::from(q0);
        let hi = (u64::from(q3) << 32) | u64::from(q2);
        (u128::from(hi) << 64) | u128::from(lo)
    }
}

/// `(n / d, n % d)` for a 64-bit `n` and a divisor below 2^32 (`None` for `d == 0`): two steps of
/// [`div_rem_below_u32`] on the 32-bit hardware divide instead of the 64-bit library division
/// ([`short_div`] unrolled for two words: the per-projected-vertex and per-perspective-point
/// callers measured ~3% of a scene frame slower through the general loop).
#[inline(never)]
pub(crate) fn div_rem_u64_by_u32(n: u64, d: u32) -> Option<(u64, u32)> {
    if d == 0 {
        return None;
    }
    let (hi, lo) = ((n >> 32) as u32, n as u32);
    let (q_hi, r_hi) = (hi / d, hi % d);
    let (q_lo, r) = div_rem_below_u32(r_hi, lo, d);
    Some(((u64::from(q_hi) << 32) | u64::from(q_lo), r))
}

/// `(n / d, n % d)` for 64-bit operands (`None` for `d == 0`) without the 64-bit library
/// division (two of which, quotient and remainder, cost about 190 instructions on the Cortex-M4F).
/// A divisor below 2^32 takes [`div_rem_u64_by_u32`]. A wider one leaves a quotient below 2^32,
/// estimated by dividing `n >> (k + 1)` by `(d >> (k + 1)) + 1 <= 2^31` (`k` the divisor's bits
/// past 32) on the same path: that divisor exceeds `d / 2^(k+1)`, so the estimate never exceeds
/// the quotient, and falls short of it by at most `q 2^(k+1) / d + 2 <= 6`; the remainder
/// `n - q d` then takes at most six corrections.
#[inline(never)]
pub(crate) fn div_rem_u64(n: u64, d: u64) -> Option<(u64, u64)> {
    if let Ok(d32) = u32::try_from(d) {
        return div_rem_u64_by_u32(n, d32).map(|(q, r)| (q, u64::from(r)));
    }
    let k = 32 - d.leading_zeros(); // 1..=32: d >> k is below 2^32
    let dt = ((d >> (k + 1)) + 1) as u32; // 2^30 < dt <= 2^31
    let (mut q, _) = div_rem_u64_by_u32(n >> (k + 1), dt)?;
    // q <= n / d: the product is at most n.
    let mut r = n.wrapping_sub(q.wrapping_mul(d));
    while r >= d {
        r -= d;
        q += 1;
    }
    Some((q, r))
}

/// Short division by a non-zero 32-bit divisor: one 32-bit quotient digit per word of `n`, high
/// to low, each by [`div_rem_below_u32`] (leading zero words skipped).
fn short_div(n: u128, d: u32) -> (u128, u32) {
    let mut r = 0u32;
    let mut q = 0u128;
    let mut seen = false;
    for k in (0..4).rev() {
        let w = (n >> (32 * k)) as u32;
        seen |= w != 0;
        if seen {
            let (qd, rd) = div_rem_below_u32(r, w, d);
            q |= u128::from(qd) << (32 * k);
            r = rd;
        }
    }
    (q, r)
}

/// `(n / d, n % d)`, `None` for `d == 0`; `lean` (a constant at every call) takes the two-word
/// path for every divisor.
#[inline(always)]
fn div_rem_u128_by_u64(n: u128, d: u64, lean: bool) -> Option<(u128, u64)> {
    if d == 0 {
        return None;
    }
    if let (false, Ok(d32)) = (lean, u32::try_from(d)) {
        let (q, r) = short_div(n, d32);
        return Some((q, u64::from(r)));
    }
    let (hi, lo) = ((n >> 64) as u64, n as u64);
    // d >= 2^32 (outside the size-lean shape): the high word's quotient is below 2^32 (rarely
    // not 0); the two-word step below takes any d > u1.
    let (q_hi, u1) = if hi < d { (0, hi) } else { (hi / d, hi % d) };
    let (q_lo, r) = div_rem_below_u64(u1, lo, d);
    Some(((u128::from(q_hi) << 64) | u128::from(q_lo), r))
}

/// Generates `(u1:u0 / d, u1:u0 % d)` for `u1 < d` (so `d != 0` and the quotient fits one word)
/// over words of `$w` (half-words `$h` bits), by algorithm D with two half-word quotient digits.
/// Each digit is estimated as `$est(top, vn1)` (`top / vn1`, with `vn1` the normalised divisor's
/// top half-word; the estimate may exceed the digit, never fall short) and corrected at most
/// twice. `$lz` counts a word's leading zeros (the divisor's normalisation).
macro_rules! div_rem_below {
    ($name:ident, $w:ty, $h:literal, $est:expr, $lz:path, $doc:literal) => {
        #[doc = $doc]
        #[inline]
        fn $name(u1: $w, u0: $w, d: $w) -> ($w, $w) {
            const B: $w = 1 << $h;
            const LO: $w = B - 1;
            if u1 == 0 {
                // d > u1 = 0: `max(1)` only states it.
                let d = d.max(1);
                return (u0 / d, u0 % d);
            }
            // d > u1 >= 1, so the shift keeps every bit of d.
            let s = $lz(d);
            let v = d << s;
            // v's top bit is set, so vn1 >= B / 2 (`max(1)` only states that it is not 0).
            let (vn1, vn0) = ((v >> $h).max(1), v & LO);
            let un32 = if s == 0 {
                u1
            } else {
                (u1 << s) | (u0 >> (<$w>::BITS - s))
            };
            let un10 = u0 << s;
            let (un1, un0) = (un10 >> $h, un10 & LO);
            let est: fn($w, $w) -> ($w, $w) = $est;
            let digit = |top: $w, next: $w| -> $w {
                let (mut q, mut rhat) = est(top, vn1);
                // q >= B is tested first, so q * vn0 does not overflow; rhat < B, so
                // (rhat << h) + next does not either.
                while q >= B || q * vn0 > (rhat << $h) + next {
                    q = q.wrapping_sub(1);
                    rhat += vn1;
                    if rhat >= B {
                        break;
                    }
                }
                q
            };
            let q1 = digit(un32, un1);
            let un21 = (un32 << $h)
                .wrapping_add(un1)
                .wrapping_sub(q1.wrapping_mul(v));
            let q0 = digit(un21, un0);
            let r = (un21 << $h)
                .wrapping_add(un0)
                .wrapping_sub(q0.wrapping_mul(v))
                >> s;
            ((q1 << $h) | q0, r)
        }
    };
}

div_rem_below!(
    div_rem_below_u32,
    u32,
    16,
    |top, vn1| {
        // The caller's `vn1` is at least 1; restated here for builds that keep this closure
        // out of line (opt-level "z"), where the divide's zero check would otherwise remain.
        let vn1 = vn1.max(1);
        (top / vn1, top % vn1)
    },
    leading_zeros_u32,
    "`(u1:u0 / d, u1:u0 % d)` for 32-bit words, `u1 < d`: the 32-bit hardware divide only."
);

div_rem_below!(
    div_rem_below_u64,
    u64,
    32,
    est_u64_by_u32,
    u64::leading_zeros,
    "`(u1:u0 / d, u1:u0 % d)` for 64-bit words, `u1 < d`: digit estimates by [`est_u64_by_u32`]."
);

/// `(top / vn1, top % vn1)` for `2^31 <= vn1 < 2^32` (a normalised top half-word) by
/// [`div_rem_below_u32`], except where the quotient does not fit 32 bits (the top half of
/// `top` is not below `vn1`), which takes the 64-bit library division.
#[inline]
fn est_u64_by_u32(top: u64, vn1: u64) -> (u64, u64) {
    let (th, tl, v) = ((top >> 32) as u32, top as u32, vn1 as u32);
    if th < v {
        let (q, r) = div_rem_below_u32(th, tl, v);
        (u64::from(q), u64::from(r))
    } else {
        let vn1 = vn1.max(1);
        (top / vn1, top % vn1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The division in both shapes, which must agree (and with [`div_rem_euclid_i128`]).
    fn div(n: i128, d: i128) -> (i128, i128) {
        let fast = div_rem_euclid_i128_shaped(n, d, false);
        assert_eq!(fast, div_rem_euclid_i128_shaped(n, d, true), "{n} / {d}");
        assert_eq!(fast, div_rem_euclid_i128(n, d), "{n} / {d}");
        fast
    }

    /// The table's count against the instruction's: every value below 2^16, every power of two
    /// with its neighbours, and a stride through the rest.
    #[test]
    fn leading_zeros_by_table_is_leading_zeros() {
        let mut check = |v: u32| assert_eq!(leading_zeros_by_table(v), v.leading_zeros(), "{v:#x}");
        (0..=u32::from(u16::MAX)).for_each(&mut check);
        for b in 0..32 {
            let p = 1u32 << b;
            [p - 1, p, p + 1, p | (p >> 1), u32::MAX >> b]
                .into_iter()
                .for_each(&mut check);
        }
        (0..=u32::MAX).step_by(65_537).for_each(&mut check);
        assert_eq!(leading_zeros_u32(0x0001_2345), 15);
    }

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
                    assert_eq!(div(n, d), (0, 0));
                    continue;
                }
                assert_eq!(div(n, d), (n.div_euclid(d), n.rem_euclid(d)), "{n} / {d}");
            }
        }
        assert_eq!(div(i128::MIN, -1), (0, 0));
        assert_eq!(div(i128::MIN, i128::from(i64::MIN)), (1i128 << 64, 0));
        assert_eq!(
            div(i128::MIN, 3),
            (i128::MIN.div_euclid(3), i128::MIN.rem_euclid(3))
        );
    }

    fn check(n: i128, d: i128) {
        if d == 0 {
            return;
        }
        let want = (n.div_euclid(d), n.rem_euclid(d));
        assert_eq!(div(n, d), want, "{n} / {d}");
        // The i64 entry (both of its paths) where the operands and the quotient fit.
        #[cfg(not(texcore_lean))]
        if let (Ok(n64), Ok(d64), Ok(q64)) =
            (i64::try_from(n), i64::try_from(d), i64::try_from(want.0))
        {
            assert_eq!(
                div_rem_euclid_i64(n64, d64),
                (q64, want.1 as i64),
                "{n} / {d}"
            );
        }
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

    proptest::proptest! {
        #[test]
        fn u64_division_matches_the_operators(
            n in proptest::prelude::any::<u64>(),
            d in proptest::prelude::any::<u64>(),
            nshift in 0u32..64,
            dshift in 0u32..64,
        ) {
            for (n, d) in [(n, d), (n >> nshift, d >> dshift), (n, d >> dshift)] {
                let want = (d != 0).then(|| (n / d, n % d));
                proptest::prop_assert_eq!(div_rem_u64(n, d), want, "{} / {}", n, d);
            }
        }
    }

    #[test]
    fn u64_division_edges() {
        let edges = [
            0u64,
            1,
            2,
            u64::from(u32::MAX) - 1,
            u64::from(u32::MAX),
            1 << 32,
            (1 << 32) + 1,
            (1 << 33) - 1,
            (1 << 62) + 12345,
            (1 << 63) - 1,
            1 << 63,
            u64::MAX - 1,
            u64::MAX,
        ];
        for &n in &edges {
            for &d in &edges {
                let want = (d != 0).then(|| (n / d, n % d));
                assert_eq!(div_rem_u64(n, d), want, "{n} / {d}");
            }
        }
    }

    #[test]
    fn reciprocal_edges() {
        for d in [
            1u64,
            2,
            3,
            7,
            u64::from(u32::MAX),
            1 << 32,
            (1 << 63) - 1,
            1 << 63,
            u64::MAX,
        ] {
            let r = Reciprocal64::new(d).expect("non-zero");
            for n in [
                0u128,
                1,
                u128::from(d) - 1,
                u128::from(d),
                u128::MAX,
                u128::MAX - 1,
                1 << 127,
            ] {
                assert_eq!(
                    r.div_rem(n),
                    (n / u128::from(d), (n % u128::from(d)) as u64),
                    "{n} / {d}"
                );
            }
        }
        assert!(Reciprocal64::new(0).is_none());
    }

    #[test]
    fn reciprocal32_edges() {
        for d in [
            1u32,
            2,
            3,
            7,
            1 << 16,
            (1 << 31) - 1,
            1 << 31,
            u32::MAX - 1,
            u32::MAX,
        ] {
            let r = Reciprocal32::new(d).expect("non-zero");
            for n in [
                0u128,
                1,
                u128::from(d) - 1,
                u128::from(d),
                u128::from(d) << 32,
                (u128::from(d) << 96) - 1,
                u128::from(u64::MAX),
                u128::MAX,
                u128::MAX - 1,
                1 << 127,
            ] {
                assert_eq!(
                    r.div_rem(n),
                    (n / u128::from(d), (n % u128::from(d)) as u32),
                    "{n} / {d}"
                );
                for n in [n >> 1, n >> 33, n >> 65, n >> 97] {
                    assert_eq!(r.div_u127(n), n / u128::from(d), "{n} / {d}");
                }
            }
        }
        assert!(Reciprocal32::new(0).is_none());
    }

    proptest::proptest! {
        #[test]
        fn reciprocal_matches_native(n in proptest::prelude::any::<u128>(), d in 1u64.., shift in 0u32..64, nshift in 0u32..128) {
            for d in [d, (d >> shift).max(1)] {
                let r = Reciprocal64::new(d).expect("non-zero");
                for n in [n, n >> nshift] {
                    proptest::prop_assert_eq!(r.div_rem(n), (n / u128::from(d), (n % u128::from(d)) as u64));
                }
            }
        }

        #[test]
        fn reciprocal32_matches_native(n in proptest::prelude::any::<u128>(), d in 1u32.., shift in 0u32..32, nshift in 0u32..128) {
            for d in [d, (d >> shift).max(1)] {
                let r = Reciprocal32::new(d).expect("non-zero");
                for n in [n, n >> nshift] {
                    proptest::prop_assert_eq!(r.div_rem(n), (n / u128::from(d), (n % u128::from(d)) as u32));
                    let n = n >> 1;
                    proptest::prop_assert_eq!(r.div_u127(n), n / u128::from(d));
                }
            }
        }

        #[test]
        fn u64_by_u32_matches_native(n in proptest::prelude::any::<u64>(), d in proptest::prelude::any::<u32>(), shift in 0u32..32) {
            for d in [d, d >> shift, 1, u32::MAX] {
                let want = (d != 0).then(|| (n / u64::from(d), (n % u64::from(d)) as u32));
                proptest::prop_assert_eq!(div_rem_u64_by_u32(n, d), want);
            }
        }

        #[test]
        fn long_divisions_match_native(
            n in proptest::prelude::any::<u128>(),
            d in 1u64..,
            shift in 0u32..64,
            nshift in 0u32..128,
        ) {
            for d in [d, (d >> shift).max(1)] {
                let n = n >> nshift;
                for lean in [false, true] {
                    let q = div_rem_u128_by_u64(n, d, lean);
                    proptest::prop_assert_eq!(q, Some((n / u128::from(d), (n % u128::from(d)) as u64)));
                }
                let u1 = ((n >> 64) as u64) % d;
                let wide = (u128::from(u1) << 64) | u128::from(n as u64);
                let (q, r) = div_rem_below_u64(u1, n as u64, d);
                proptest::prop_assert_eq!(
                    (u128::from(q), u128::from(r)),
                    (wide / u128::from(d), wide % u128::from(d))
                );
                let d32 = (d as u32).max(1);
                let u1 = ((n >> 32) as u32) % d32;
                let wide = (u64::from(u1) << 32) | u64::from(n as u32);
                let (q, r) = div_rem_below_u32(u1, n as u32, d32);
                proptest::prop_assert_eq!(
                    (u64::from(q), u64::from(r)),
                    (wide / u64::from(d32), wide % u64::from(d32))
                );
            }
            proptest::prop_assert_eq!(div_rem_u128_by_u64(n, 0, false), None);
            proptest::prop_assert_eq!(div_rem_u128_by_u64(n, 0, true), None);
        }
    }
}
