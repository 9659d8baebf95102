//! Fixed-point 3D math for scene geometry: angles and their sine/cosine, integer square roots,
//! vectors. Affine maps of points are [`crate::transform::Affine3`] (one type for scene
//! placement and texture mapping).
//!
//! # Formats
//!
//! | quantity | type | layout | range |
//! |---|---|---|---|
//! | position, vector, matrix entry | `i32` raw | `Q16.16` ([`ONE`] = 1.0) | `±32768`, step `2^-16` |
//! | wide (camera-space) position | `i64` raw | `Q16.16` | no practical limit |
//! | angle | [`Angle`] (`u32`) | turns, `2^32` = one turn | wraps |
//! | sine, cosine | `i32` raw | `Q2.30` ([`ONE_Q30`] = 1.0) | `[-1, 1]` exactly |
//!
//! # Rounding
//!
//! Every product is formed exactly in `i64` (or `i128` where noted) and rounded **half up**
//! (`(x + 2^(k-1)) >> k`, i.e. to nearest with ties towards `+inf`) once, back to `Q16.16`.
//! Results that do not fit `i32` saturate. Divisions round half up as well ([`div_round`]).
//! Nothing here uses floating point, so the host and the devices compute identical bits; nothing
//! panics for any input.

/// `1.0` in `Q16.16`.
pub const ONE: i32 = 1 << 16;
/// `1.0` in `Q2.30` (sine and cosine).
pub const ONE_Q30: i32 = 1 << 30;

/// `x` thousandths as a `Q16.16` raw value, rounded to nearest (ties up). For writing scenes
/// with exact integer literals: `milli(1500)` is 1.5.
pub const fn milli(x: i32) -> i32 {
    sat_i32(div_round(x as i64 * ONE as i64, 1000))
}

/// Whole units as `Q16.16` (saturating).
pub const fn units(x: i32) -> i32 {
    sat_i32((x as i64) << 16)
}

/// Saturates an `i64` to `i32`: its low word when that is the value (one comparison of the
/// high word with the low word's sign on a 32-bit core), else the bound on its side.
#[inline]
pub const fn sat_i32(v: i64) -> i32 {
    let lo = v as i32;
    if lo as i64 == v {
        lo
    } else if v < 0 {
        i32::MIN
    } else {
        i32::MAX
    }
}

/// Saturates an `i128` to `i64`.
#[inline]
pub const fn sat_i64(v: i128) -> i64 {
    if v > i64::MAX as i128 {
        i64::MAX
    } else if v < i64::MIN as i128 {
        i64::MIN
    } else {
        v as i64
    }
}

/// Operands below this magnitude take the `i64` path of [`div_round`] / [`div_round_128`].
const FAST_DIV: i64 = 1 << 61;

/// `round(n / d)`, ties towards `+inf`, for any `d != 0` (the quotient of the exact rationals).
/// Returns 0 for `d == 0` (never panics; saturates the one overflowing case). Uses `i64`
/// division when `|n|, |d| < 2^61` (the common case; a library call on 32-bit cores) and `i128`
/// division otherwise, with identical results.
#[inline]
pub const fn div_round(n: i64, d: i64) -> i64 {
    if n > -FAST_DIV && n < FAST_DIV && d > -FAST_DIV && d < FAST_DIV {
        div_round_small(n, d)
    } else {
        sat_i64(div_round_wide(n as i128, d as i128))
    }
}

/// [`div_round`] at run time, the same value for every input: for operands below `2^61`
/// the raster's half-up division (`raster::div_round_i64`, on the 32-bit hardware divide through
/// `wide::div_rem_u64`) instead of the 64-bit library division, which `div_round` (a `const fn`,
/// as the scene constants need) cannot avoid. For the per-quad mesh points.
pub(crate) fn div_round_rt(n: i64, d: i64) -> i64 {
    if d == 0 || !(n > -FAST_DIV && n < FAST_DIV && d > -FAST_DIV && d < FAST_DIV) {
        return div_round(n, d);
    }
    // round(n / d) half up is round(-n / -d) half up: the divisor made positive, as the raster's
    // division needs.
    let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
    crate::raster::div_round_i64(n, d)
}

/// `round(n / d)` in `i128`, ties towards `+inf`; 0 for `d == 0`. Same as [`div_round`] (fast
/// `i64` path for small operands).
#[inline]
pub const fn div_round_128(n: i128, d: i128) -> i128 {
    let lim = FAST_DIV as i128;
    if n > -lim && n < lim && d > -lim && d < lim {
        div_round_small(n as i64, d as i64) as i128
    } else {
        div_round_wide(n, d)
    }
}

/// [`div_round_128`] at run time, the same value: small operands through [`div_round_rt`].
#[cfg(any(feature = "lighting", test))]
pub(crate) fn div_round_128_rt(n: i128, d: i128) -> i128 {
    let lim = FAST_DIV as i128;
    if n > -lim && n < lim && d > -lim && d < lim {
        div_round_rt(n as i64, d as i64) as i128
    } else {
        div_round_wide(n, d)
    }
}

/// [`div_round`] for `|n|, |d| < 2^61`: `floor((2n + d) / 2d)` after making `d` positive.
#[inline]
const fn div_round_small(n: i64, d: i64) -> i64 {
    if d == 0 {
        return 0;
    }
    let (n, d) = if d < 0 { (-n, -d) } else { (n, d) };
    match (2 * n + d).checked_div_euclid(2 * d) {
        Some(q) => q,
        None => 0,
    }
}

/// [`div_round_128`] by `i128` division.
const fn div_round_wide(n: i128, d: i128) -> i128 {
    if d == 0 {
        return 0;
    }
    let (n, d) = if d < 0 {
        (n.saturating_neg(), d.saturating_neg())
    } else {
        (n, d)
    };
    // floor((2n + d) / 2d) == floor(n/d + 1/2). 2n and 2d may overflow only for |n| or d
    // above 2^126, which no caller produces; saturate rather than wrap.
    let num = n.saturating_mul(2).saturating_add(d);
    let den = d.saturating_mul(2);
    // den >= 2 here; checked so that no panic path exists.
    match num.checked_div_euclid(den) {
        Some(q) => q,
        None => 0,
    }
}

/// Rounds a value with `k` extra fraction bits (`1 <= k <= 62`) half up.
#[inline]
pub const fn round_shift(v: i64, k: u32) -> i64 {
    if k == 0 {
        return v;
    }
    let half = 1i64 << (k - 1);
    (v >> k) + (((v & ((half << 1) - 1)) >= half) as i64)
}

/// Rounds an `i128` with `k` extra fraction bits (`1 <= k <= 126`) half up.
#[inline]
pub const fn round_shift_128(v: i128, k: u32) -> i128 {
    if k == 0 {
        return v;
    }
    let half = 1i128 << (k - 1);
    (v >> k) + (((v & ((half << 1) - 1)) >= half) as i128)
}

/// `floor(sqrt(v))`, exact: values below `2^64` by [`isqrt_u64`], larger ones by the bit-by-bit
/// (digit) method in `u128`.
pub const fn isqrt_u128(v: u128) -> u128 {
    if v >> 64 == 0 {
        return isqrt_u64(v as u64) as u128;
    }
    isqrt_u128_digits(v)
}

/// `floor(sqrt(v))` by the bit-by-bit (digit) method in `u128` (64 steps at most).
const fn isqrt_u128_digits(v: u128) -> u128 {
    let mut rem = v;
    let mut root: u128 = 0;
    // Highest power of four <= v.
    let mut bit: u128 = 1 << 126;
    while bit > v {
        bit >>= 2;
    }
    while bit != 0 {
        if rem >= root + bit {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// `floor(sqrt(v))` for `u64`, exact: the root of the top 32 bits by Newton's iteration on the
/// 32-bit divide, the remaining digits by the digit method in `u64`.
pub const fn isqrt_u64(v: u64) -> u64 {
    isqrt_u64_scaled(v, 0)
}

/// `floor(sqrt(v * 4^k))`, exact, for `k <= 29` (the root is then below `2^61`).
///
/// The root of `v`'s top 32 bits comes from Newton's iteration on the 32-bit divide
/// ([`crate::filter::width::isqrt32`], exact); the digit method then appends `v`'s remaining
/// base-4 digits and `k` zero digits, one root bit each. Its invariant `rem <= 2 root` keeps
/// every step in `u64` (`4 rem + 3 < 2^64` while the root is below `2^61`). At most 16 + `k`
/// steps of `u64` arithmetic, against 64 steps of `u128` for the digit method alone. `k` above
/// 29 is taken as 29 (crate-private: its one caller passes 16).
pub(crate) const fn isqrt_u64_scaled(v: u64, k: u32) -> u64 {
    let k = if k > 29 { 29 } else { k };
    let bits = 64 - v.leading_zeros();
    // An even number of low bits, so that `v >> low` is below 2^32.
    let low = if bits > 32 { (bits - 31) & !1 } else { 0 };
    let top = (v >> low) as u32;
    let mut root = crate::filter::width::isqrt32(top) as u64;
    let mut rem = top as u64 - root * root;
    let mut i = low / 2 + k;
    while i > 0 {
        i -= 1;
        // Digit i of v * 4^k: zero below 4^k.
        let d = if i < k { 0 } else { (v >> (2 * (i - k))) & 3 };
        rem = (rem << 2) | d;
        let trial = (root << 2) | 1;
        root <<= 1;
        if rem >= trial {
            rem -= trial;
            root |= 1;
        }
    }
    root
}

// ---------------------------------------------------------------------------------------------
// Angles.

/// An angle in turns: `2^32` is one full turn (so angles wrap like `u32`). Resolution
/// `2^-32` turn (1.5e-9 rad).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Angle(pub u32);

impl Angle {
    /// Zero.
    pub const ZERO: Angle = Angle(0);
    /// A quarter turn (90 degrees).
    pub const QUARTER: Angle = Angle(1 << 30);
    /// A half turn (180 degrees).
    pub const HALF: Angle = Angle(1 << 31);

    /// `num / den` of a turn, rounded to nearest (`den == 0` gives zero). Exact for any `den`
    /// that divides `2^32`.
    pub const fn from_turns(num: i64, den: u32) -> Angle {
        if den == 0 {
            return Angle(0);
        }
        // 0 <= r < den: the angle mod one turn (checked so that no panic path exists).
        let r = match num.checked_rem_euclid(den as i64) {
            Some(r) => r as u64,
            None => 0,
        };
        // round(r 2^32 / den), ties up: floor((r 2^32 + floor(den / 2)) / den) (for odd den no
        // tie exists); r 2^32 + den / 2 < 2^64.
        let q = match ((r << 32) + den as u64 / 2).checked_div(den as u64) {
            Some(q) => q,
            None => 0,
        };
        Angle(q as u32) // q == 2^32 wraps to 0
    }

    /// [`Angle::from_turns`] of a non-negative `num` at run time, the same angle: the remainder
    /// and the rounded quotient on the 32-bit hardware divide (`wide::div_rem_u64_by_u32`)
    /// instead of the 64-bit library division. For the per-quad angles of the sphere and torus
    /// meshes.
    pub(crate) fn from_turns_rt(num: u32, den: u32) -> Angle {
        let (Some(r), Some(h)) = (num.checked_rem(den), den.checked_div(2)) else {
            return Angle(0);
        };
        // r < den: r 2^32 + den / 2 < 2^64, and the quotient is at most 2^32 (wrapping to 0).
        match crate::wide::div_rem_u64_by_u32((u64::from(r) << 32) + u64::from(h), den) {
            Some((q, _)) => Angle(q as u32),
            None => Angle(0),
        }
    }

    /// Whole degrees.
    pub const fn from_degrees(deg: i32) -> Angle {
        Angle::from_turns(deg as i64, 360)
    }

    /// Thousandths of a degree.
    pub const fn from_millidegrees(mdeg: i32) -> Angle {
        Angle::from_turns(mdeg as i64, 360_000)
    }

    /// The sum (wrapping, like angles).
    pub const fn add(self, other: Angle) -> Angle {
        Angle(self.0.wrapping_add(other.0))
    }

    /// `k` times the angle (wrapping).
    pub const fn mul(self, k: u32) -> Angle {
        Angle(self.0.wrapping_mul(k))
    }

    /// The negated angle.
    pub const fn neg(self) -> Angle {
        Angle(self.0.wrapping_neg())
    }

    /// Half the angle, taken in `[0, 1)` turn.
    pub const fn half(self) -> Angle {
        Angle(self.0 >> 1)
    }

    /// `(sin, cos)` in `Q2.30`; see [`sin_cos`].
    pub const fn sin_cos(self) -> (i32, i32) {
        sin_cos(self)
    }
}

/// `2 pi` in `Q30` (rounded).
const TWO_PI_Q30: i64 = 6_746_518_852;

/// Taylor coefficients of `sin x / x` after the constant term, in `x^2`: `-1/3!`, `1/5!`,
/// `-1/7!`, `1/9!`, `Q30` rounded to nearest.
const SIN_C: [i64; 4] = [-178_956_971, 8_947_849, -213_044, 2_959];
/// Taylor coefficients of `cos x` after the constant term, in `x^2`: `-1/2!`, `1/4!`, `-1/6!`,
/// `1/8!`, `-1/10!`, `Q30` rounded to nearest.
const COS_C: [i64; 5] = [-536_870_912, 44_739_243, -1_491_308, 26_631, -296];

/// `(sin a, cos a)` in `Q2.30`, by octant reduction and odd/even Taylor polynomials on
/// `[0, pi/4]` (degree 9 for sine, 10 for cosine; truncation error below `2e-9`), evaluated in
/// `i64` Horner form with the Taylor coefficients rounded to `Q30` and round-half-up after each
/// product (multiplications and shifts only). Maximum error about `1e-8`, measured over the
/// full circle by the tests. Exact at multiples of a quarter turn (`0`, `±1`).
pub const fn sin_cos(a: Angle) -> (i32, i32) {
    let quadrant = a.0 >> 30;
    let f = a.0 & ((1 << 30) - 1);
    // Reduce to x in [0, pi/4]: for f past the octant use sin(pi/2 - x) = cos x.
    let (x, swap) = if f <= 1 << 29 {
        (f, false)
    } else {
        ((1u32 << 30) - f, true)
    };
    // Radians, Q30: x * 2pi / 2^32, x <= 2^29 so the product fits i64.
    let xr = round_shift(x as i64 * TWO_PI_Q30, 32);
    let x2 = round_shift(xr * xr, 30);
    // sin x = x + x (x^2 (c1 + x^2 (c3 + x^2 (c5 + x^2 c7)))), |x^2 p| < 2^59.
    let mut p = SIN_C[3];
    let mut i = 3;
    while i > 0 {
        i -= 1;
        p = SIN_C[i] + round_shift(x2 * p, 30);
    }
    let s = xr + round_shift(xr * round_shift(x2 * p, 30), 30);
    // cos x = 1 + x^2 (c0 + x^2 (c2 + ... + x^2 c8)).
    let mut p = COS_C[4];
    let mut i = 4;
    while i > 0 {
        i -= 1;
        p = COS_C[i] + round_shift(x2 * p, 30);
    }
    let c = ONE_Q30 as i64 + round_shift(x2 * p, 30);
    let (s, c) = if swap { (c, s) } else { (s, c) };
    let (s, c) = match quadrant {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    };
    (clamp_unit(s), clamp_unit(c))
}

const fn clamp_unit(v: i64) -> i32 {
    if v > ONE_Q30 as i64 {
        ONE_Q30
    } else if v < -(ONE_Q30 as i64) {
        -ONE_Q30
    } else {
        v as i32
    }
}

/// A `Q2.30` value rounded to `Q16.16`.
#[inline]
pub const fn q30_to_q16(v: i32) -> i32 {
    round_shift(v as i64, 14) as i32
}

// ---------------------------------------------------------------------------------------------
// Vectors.

/// A point or vector, `Q16.16` raw components.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Vec3 {
    /// x (right).
    pub x: i32,
    /// y (up).
    pub y: i32,
    /// z (towards the viewer of a default camera).
    pub z: i32,
}

impl Vec3 {
    /// The origin.
    pub const ZERO: Vec3 = Vec3::new(0, 0, 0);
    /// Unit x.
    pub const X: Vec3 = Vec3::new(ONE, 0, 0);
    /// Unit y.
    pub const Y: Vec3 = Vec3::new(0, ONE, 0);
    /// Unit z.
    pub const Z: Vec3 = Vec3::new(0, 0, ONE);

    /// From raw `Q16.16` components.
    pub const fn new(x: i32, y: i32, z: i32) -> Vec3 {
        Vec3 { x, y, z }
    }

    /// From thousandths of a unit (see [`milli`]).
    pub const fn milli(x: i32, y: i32, z: i32) -> Vec3 {
        Vec3::new(milli(x), milli(y), milli(z))
    }

    /// From whole units.
    pub const fn units(x: i32, y: i32, z: i32) -> Vec3 {
        Vec3::new(units(x), units(y), units(z))
    }

    /// The components as an array.
    pub const fn to_array(self) -> [i32; 3] {
        [self.x, self.y, self.z]
    }

    /// From an array.
    pub const fn from_array(a: [i32; 3]) -> Vec3 {
        Vec3::new(a[0], a[1], a[2])
    }

    /// Component-wise sum (saturating).
    pub const fn add(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.x.saturating_add(o.x),
            self.y.saturating_add(o.y),
            self.z.saturating_add(o.z),
        )
    }

    /// Component-wise difference (saturating).
    pub const fn sub(self, o: Vec3) -> Vec3 {
        Vec3::new(
            self.x.saturating_sub(o.x),
            self.y.saturating_sub(o.y),
            self.z.saturating_sub(o.z),
        )
    }

    /// The vector scaled by a `Q16.16` factor (rounded, saturating).
    pub const fn scale(self, k: i32) -> Vec3 {
        Vec3::new(mul_q16(self.x, k), mul_q16(self.y, k), mul_q16(self.z, k))
    }

    /// The dot product, exact, `Q32.32` in `i128` form.
    pub const fn dot_wide(self, o: Vec3) -> i128 {
        self.x as i128 * o.x as i128 + self.y as i128 * o.y as i128 + self.z as i128 * o.z as i128
    }

    /// The dot product rounded to `Q16.16` (saturating).
    pub const fn dot(self, o: Vec3) -> i32 {
        sat_i32(sat_i64(round_shift_128(self.dot_wide(o), 16)))
    }

    /// The cross product rounded to `Q16.16` (saturating).
    pub const fn cross(self, o: Vec3) -> Vec3 {
        Vec3::new(
            det2(self.y, o.z, self.z, o.y),
            det2(self.z, o.x, self.x, o.z),
            det2(self.x, o.y, self.y, o.x),
        )
    }

    /// The length, `Q16.16` (rounded down; saturating).
    pub const fn length(self) -> i32 {
        let s = self.x as i128 * self.x as i128
            + self.y as i128 * self.y as i128
            + self.z as i128 * self.z as i128;
        let r = isqrt_u128(s as u128);
        if r > i32::MAX as u128 {
            i32::MAX
        } else {
            r as i32
        }
    }

    /// The unit vector along `self`, `Q16.16` (each component within about `2^-16` of the
    /// exact one), or `None` for the zero vector.
    ///
    /// The vector is first shifted left so that its largest component lies in `[2^29, 2^30]`
    /// (exact), then `len = isqrt((x^2 + y^2 + z^2) * 2^32)` (16 extra bits) and each component
    /// is `round(c * 2^32 / len)`.
    pub const fn normalized(self) -> Option<Vec3> {
        let Some((s, len)) = self.unit_parts() else {
            return None;
        };
        Some(Vec3::new(
            unit_component(s[0], len),
            unit_component(s[1], len),
            unit_component(s[2], len),
        ))
    }

    /// [`Vec3::normalized`] at run time, the same vector: the three quotients on the 32-bit
    /// hardware divide (`wide::div_rem_u64`) instead of the 64-bit library division, which the
    /// `const fn` cannot avoid. For the per-vertex normals and half vectors of the lighting.
    #[cfg(any(feature = "lighting", test))]
    pub(crate) fn normalized_rt(self) -> Option<Vec3> {
        let (s, len) = self.unit_parts()?;
        Some(Vec3::new(
            unit_component_rt(s[0], len),
            unit_component_rt(s[1], len),
            unit_component_rt(s[2], len),
        ))
    }

    /// The scaled components and the length of [`Vec3::normalized`] (`None` for the zero vector).
    const fn unit_parts(self) -> Option<([i64; 3], i64)> {
        let c = [self.x as i64, self.y as i64, self.z as i64];
        let m = max3(
            c[0].unsigned_abs(),
            c[1].unsigned_abs(),
            c[2].unsigned_abs(),
        );
        if m == 0 {
            return None;
        }
        // Shift so that m lands in [2^29, 2^30]: m < 2^32 so the shift is at most 29 left
        // or 2 right.
        let bits = 64 - m.leading_zeros(); // bit length, 1..=32
        let (l, r) = if bits <= 30 {
            (30 - bits, 0)
        } else {
            (0, bits - 30)
        };
        let s = [(c[0] << l) >> r, (c[1] << l) >> r, (c[2] << l) >> r];
        let sum = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) as u64; // <= 3 * 2^60
        let len = isqrt_u64_scaled(sum, 16) as i64; // isqrt(sum * 2^32): 2^44 <= len < 2^47
        Some((s, len))
    }
}

/// `round(a b - c d)` of `Q16.16` values, saturating.
const fn det2(a: i32, b: i32, c: i32, d: i32) -> i32 {
    let v = a as i128 * b as i128 - c as i128 * d as i128;
    sat_i32(sat_i64(round_shift_128(v, 16)))
}

/// `round(v 2^32 / len)` (half up, as [`div_round`]) with `|v| <= 2^30` and
/// `2^44 <= len < 2^47`: a component in `[-ONE, ONE]`. In `i64`: for `d > 0`,
/// `floor((2n + d) / 2d) = floor((n + floor(d / 2)) / d)` (for odd `d` the extra half never
/// reaches the next multiple of `d`), and `n + floor(d / 2) <= 2^62 + 2^46` fits.
const fn unit_component(v: i64, len: i64) -> i32 {
    match ((v << 32) + (len >> 1)).checked_div_euclid(len) {
        Some(q) => q as i32,
        None => 0,
    }
}

/// [`unit_component`] on the 32-bit hardware divide: `round(v 2^32 / len)` half up, which is
/// the raster's division (`raster::div_round_i64`; `|v| <= 2^30`, `len > 0`).
#[cfg(any(feature = "lighting", test))]
fn unit_component_rt(v: i64, len: i64) -> i32 {
    crate::raster::div_round_i64(v << 32, len) as i32
}

const fn max3(a: u64, b: u64, c: u64) -> u64 {
    let m = if a > b { a } else { b };
    if m > c {
        m
    } else {
        c
    }
}

/// `a * b` for two `Q16.16` values, rounded half up, saturating.
#[inline]
pub const fn mul_q16(a: i32, b: i32) -> i32 {
    sat_i32(round_shift(a as i64 * b as i64, 16))
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::vec::Vec;

    fn q30(v: i32) -> f64 {
        v as f64 / (1u64 << 30) as f64
    }

    /// `sat_i64` and `sat_i32` are the clamps to their types' ranges: around the ends of `i32`,
    /// `i64` and `i128`, at every power of two of either sign and at random (`sat_i32` on each
    /// value's low 64 bits, which takes in the ends of `i64` too).
    #[test]
    fn saturations_are_the_clamps() {
        let mut vals: Vec<i128> = Vec::new();
        let ends = [
            i32::MIN.into(),
            i32::MAX.into(),
            i64::MIN.into(),
            i64::MAX.into(),
        ];
        for e in ends.into_iter().chain([i128::MIN, i128::MAX, 0]) {
            vals.extend((-3..=3).map(|d| e.saturating_add(d)));
        }
        for k in 0..127 {
            vals.extend([
                1i128 << k,
                -(1i128 << k),
                (1i128 << k) - 1,
                1 - (1i128 << k),
            ]);
        }
        let mut rng = crate::test_rng::XorShift64::new(0x5A7_164);
        vals.extend((0..20_000).map(|_| {
            let v = i128::from(rng.below(u64::MAX)) << 64 | i128::from(rng.below(u64::MAX));
            v >> (rng.below(127) as u32)
        }));
        for v in vals {
            let want = v.clamp(i64::MIN.into(), i64::MAX.into()) as i64;
            assert_eq!(sat_i64(v), want, "{v}");
            let w = v as i64;
            let want = w.clamp(i32::MIN.into(), i32::MAX.into()) as i32;
            assert_eq!(sat_i32(w), want, "{w}");
        }
    }

    #[test]
    fn sin_cos_full_circle_accuracy() {
        let mut worst = 0f64;
        let mut worst_pyth = 0f64;
        // Every 2^14 turn units plus the octant boundaries and their neighbours.
        let mut angles: std::vec::Vec<u32> = (0..(1u32 << 18)).map(|i| i << 14).collect();
        for k in 0..8u32 {
            let b = k << 29;
            angles.extend([b, b.wrapping_add(1), b.wrapping_sub(1)]);
        }
        angles.extend([u32::MAX, 12345, 0x9E37_79B9]);
        for a in angles {
            let (s, c) = sin_cos(Angle(a));
            let r = a as f64 / 4294967296.0 * core::f64::consts::TAU;
            worst = worst
                .max((q30(s) - r.sin()).abs())
                .max((q30(c) - r.cos()).abs());
            worst_pyth = worst_pyth.max((q30(s).powi(2) + q30(c).powi(2) - 1.0).abs());
        }
        assert!(worst < 2e-8, "sin/cos error {worst}");
        assert!(worst_pyth < 5e-8, "sin^2 + cos^2 - 1 = {worst_pyth}");
    }

    #[test]
    fn sin_cos_exact_quarters() {
        assert_eq!(sin_cos(Angle(0)), (0, ONE_Q30));
        assert_eq!(sin_cos(Angle::QUARTER), (ONE_Q30, 0));
        assert_eq!(sin_cos(Angle::HALF), (0, -ONE_Q30));
        assert_eq!(sin_cos(Angle(3 << 30)), (-ONE_Q30, 0));
        assert_eq!(Angle::from_degrees(90), Angle::QUARTER);
        assert_eq!(Angle::from_degrees(-90), Angle(3 << 30));
        assert_eq!(Angle::from_degrees(360), Angle(0));
        assert_eq!(Angle::from_turns(1, 4), Angle::QUARTER);
        assert_eq!(Angle::from_turns(5, 0), Angle(0));
        assert_eq!(Angle::from_millidegrees(45_000), Angle(1 << 29));
    }

    #[test]
    fn isqrt_exact() {
        for v in (0u64..5000).chain([u64::MAX, u64::MAX - 1, 1 << 62, (1 << 62) - 1]) {
            let r = isqrt_u64(v) as u128;
            assert!(r * r <= v as u128 && (r + 1) * (r + 1) > v as u128, "{v}");
        }
        let r = isqrt_u128(u128::MAX);
        assert_eq!(r, u64::MAX as u128);
        assert_eq!(isqrt_u128(0), 0);
    }

    /// `normalized` as first written: the `u128` digit root and the `i128` rounding division.
    fn normalized_reference(v: Vec3) -> Option<Vec3> {
        let c = [v.x as i64, v.y as i64, v.z as i64];
        let m = c.iter().map(|c| c.unsigned_abs()).max().unwrap();
        if m == 0 {
            return None;
        }
        let bits = 64 - m.leading_zeros();
        let (l, r) = if bits <= 30 {
            (30 - bits, 0)
        } else {
            (0, bits - 30)
        };
        let s = c.map(|c| (c << l) >> r);
        let sum = s.iter().map(|&s| (s * s) as u128).sum::<u128>();
        let len = isqrt_u128_digits(sum << 32) as i128;
        let [x, y, z] = s.map(|s| div_round_128((s as i128) << 32, len) as i32);
        Some(Vec3::new(x, y, z))
    }

    #[test]
    fn isqrt_fast_paths_are_the_digit_method() {
        let mut rng = crate::test_rng::XorShift64::new(0x9E37_79B9_7F4A_7C15);
        let mut vals: Vec<u64> = (0..64)
            .flat_map(|b| {
                let p = 1u64 << b;
                [p, p - 1, p + 1, p.wrapping_mul(3) / 2]
            })
            .collect();
        for r in [1u64, 2, 3, 65535, 65536, 65537, (1 << 32) - 1, 1 << 31] {
            // (r + 1)^2 overflows u64 for the last root below 2^32.
            vals.extend([r * r, r * r - 1, r * r + 2 * r]);
            vals.extend((r + 1).checked_mul(r + 1));
        }
        for _ in 0..20_000 {
            vals.push(rng.spread());
        }
        vals.push(u64::MAX);
        for v in vals {
            assert_eq!(
                u128::from(isqrt_u64(v)),
                isqrt_u128_digits(u128::from(v)),
                "{v}"
            );
            // v * 4^k < 2^96 here: inside the documented range.
            for k in [1, 8, 16] {
                assert_eq!(
                    u128::from(isqrt_u64_scaled(v, k)),
                    isqrt_u128_digits(u128::from(v) << (2 * k)),
                    "{v} * 4^{k}"
                );
            }
        }
        assert_eq!(isqrt_u128(u128::MAX), isqrt_u128_digits(u128::MAX));
    }

    proptest! {
        #[test]
        fn normalized_is_the_reference(x in any::<i32>(), y in any::<i32>(), z in any::<i32>(),
                                       shift in 0u32..31) {
            for v in [Vec3::new(x, y, z), Vec3::new(x >> shift, y >> shift, z >> shift)] {
                prop_assert_eq!(v.normalized(), normalized_reference(v));
            }
        }
    }

    #[test]
    fn normalized_extremes_are_the_reference() {
        let e = [
            0,
            1,
            -1,
            2,
            i32::MAX,
            i32::MIN,
            1 << 29,
            -(1 << 29),
            (1 << 30) - 1,
            46341,
        ];
        for &x in &e {
            for &y in &e {
                for &z in &e {
                    let v = Vec3::new(x, y, z);
                    assert_eq!(v.normalized(), normalized_reference(v), "{v:?}");
                }
            }
        }
    }

    #[test]
    fn normalisation() {
        assert_eq!(Vec3::ZERO.normalized(), None);
        assert_eq!(Vec3::new(0, 5, 0).normalized(), Some(Vec3::Y));
        assert_eq!(
            Vec3::new(0, 0, -1).normalized(),
            Some(Vec3::new(0, 0, -ONE))
        );
        assert_eq!(
            Vec3::new(i32::MIN, 0, 0).normalized(),
            Some(Vec3::new(-ONE, 0, 0))
        );
        let cases = [
            [1, 1, 1],
            [3 << 16, -4 << 16, 0],
            [i32::MAX, i32::MIN, i32::MAX],
            [7, -100000, 123456789],
            [-1, 2, -3],
        ];
        for c in cases {
            let n = Vec3::from_array(c).normalized().unwrap();
            let l = (c.iter().map(|&v| (v as f64).powi(2)).sum::<f64>()).sqrt();
            for k in 0..3 {
                let exact = c[k] as f64 / l * 65536.0;
                let got = n.to_array()[k] as f64;
                assert!((exact - got).abs() <= 0.51, "{c:?}: {got} vs {exact}");
            }
        }
    }

    /// A xorshift generator from `seed` (non-zero): every bit pattern, repeatably.
    fn xorshift(seed: u64) -> impl FnMut() -> u64 {
        let mut rng = crate::test_rng::XorShift64::new(seed);
        move || rng.next_u64()
    }

    #[test]
    fn normalized_rt_is_normalized() {
        let mut next = xorshift(0x243F_6A88_85A3_08D3);
        let ends = [
            0,
            1,
            -1,
            7,
            i32::MAX,
            i32::MIN,
            i32::MIN + 1,
            1 << 16,
            -(1 << 29),
        ];
        for &a in &ends {
            for &b in &ends {
                for &c in &ends {
                    let v = Vec3::new(a, b, c);
                    assert_eq!(v.normalized_rt(), v.normalized(), "{v:?}");
                }
            }
        }
        for _ in 0..50_000 {
            let r = next();
            let c = [next(), next(), next()].map(|w| (w as i32) >> (r & 31));
            let v = Vec3::from_array(c);
            assert_eq!(v.normalized_rt(), v.normalized(), "{v:?}");
        }
    }

    #[test]
    fn div_round_128_rt_is_div_round_128() {
        let big = [
            0i128,
            1,
            -1,
            3,
            -3,
            (1 << 61) - 1,
            -(1 << 61) + 1,
            1 << 61,
            -(1 << 61),
            1 << 100,
        ];
        for &n in &big {
            for &d in &big {
                assert_eq!(div_round_128_rt(n, d), div_round_128(n, d), "{n} / {d}");
            }
        }
        for n in -300i128..300 {
            for d in [-7i128, -2, -1, 1, 2, 3, 16, 255, 1 << 40] {
                assert_eq!(div_round_128_rt(n << 20, d), div_round_128(n << 20, d));
            }
        }
    }

    #[test]
    fn from_turns_rt_is_from_turns() {
        for den in (0u32..300).chain([359, 360, 1000, 360_000, u32::MAX - 1, u32::MAX]) {
            for num in (0u32..400).chain([den.wrapping_sub(1), den, den.wrapping_add(1), u32::MAX])
            {
                assert_eq!(
                    Angle::from_turns_rt(num, den),
                    Angle::from_turns(i64::from(num), den),
                    "{num} / {den}"
                );
            }
        }
    }

    #[test]
    fn div_round_rt_is_div_round() {
        let mut next = xorshift(0x9E37_79B9_7F4A_7C15);
        let edges = [
            0i64,
            1,
            -1,
            2,
            -2,
            FAST_DIV - 1,
            -(FAST_DIV - 1),
            FAST_DIV,
            -FAST_DIV,
            i64::MAX,
            i64::MIN,
            (1 << 32) - 1,
            1 << 32,
            -(1 << 32),
        ];
        for &n in &edges {
            for &d in &edges {
                assert_eq!(div_round_rt(n, d), div_round(n, d), "{n} / {d}");
            }
        }
        for _ in 0..200_000 {
            let (a, b) = (next(), next());
            // Every magnitude of numerator and divisor, both signs.
            let n = (a as i64) >> (a & 63);
            let d = (b as i64) >> (b & 63);
            assert_eq!(div_round_rt(n, d), div_round(n, d), "{n} / {d}");
        }
    }

    #[test]
    fn rounding_helpers() {
        assert_eq!(div_round(7, 2), 4);
        assert_eq!(div_round(-7, 2), -3);
        assert_eq!(div_round(7, -2), -3);
        assert_eq!(div_round(5, 0), 0);
        assert_eq!(div_round(i64::MIN, -1), i64::MAX);
        assert_eq!(round_shift(3, 1), 2);
        assert_eq!(round_shift(-3, 1), -1);
        assert_eq!(milli(1500), 98304);
        assert_eq!(milli(-1), -66);
        assert_eq!(units(-2), -131072);
    }

    #[test]
    fn vectors() {
        // Never panics on extreme values.
        let _ = Vec3::new(i32::MIN, i32::MIN, i32::MIN).cross(Vec3::new(i32::MAX, i32::MIN, 1));
        let _ = Vec3::new(i32::MIN, i32::MIN, i32::MIN).length();
        let _ = Vec3::new(i32::MIN, i32::MIN, i32::MIN).normalized();
        let _ =
            Vec3::new(i32::MIN, i32::MIN, i32::MIN).dot(Vec3::new(i32::MIN, i32::MIN, i32::MIN));
        let _ = Vec3::new(i32::MIN, 0, 0).scale(i32::MIN);
        assert_eq!(
            Vec3::X.cross(Vec3::Y),
            Vec3::Z,
            "right-handed cross product"
        );
        assert_eq!(Vec3::units(1, 2, 3).dot(Vec3::units(4, 5, 6)), units(32));
        assert_eq!(Vec3::units(3, 4, 0).length(), units(5));
    }
}
