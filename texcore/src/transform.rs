//! Affine maps `p -> M p + t` with `Q16.16` entries: the one affine type of texcore, both the
//! noise terms' transforms `T_k` (frequency, rotation, phase: `u = M s + t`) and a scene object's
//! placement (object to world) and solid-texture mapping.
//!
//! # Guarantees
//!
//! - Entries are `I16F16` [`MatrixEntry`] (raw `Q16.16`); every value is a valid map, so the
//!   fields are private and the constructors are total (no invariant can be broken).
//! - Nothing here uses floating point (apart from the host convenience [`Affine3::from_f64`]) and
//!   nothing panics for any input: host and devices compute identical bits.
//! - Applying a map forms each component exactly in `i64` (products with 32 fraction bits, the
//!   translation shifted up) and rounds half up once. The overflow policy is in the name:
//!   [`Affine3::apply_point`] / [`Affine3::apply_vector`] (texture space, the span set-up of
//!   `docs/model.md` section 3) wrap to `i32` lattice coordinates;
//!   [`Affine3::saturating_apply`] / [`Affine3::saturating_apply_vector`] (scene geometry)
//!   saturate; [`Affine3::apply_wide`] keeps `i64`.
//! - Composition ([`Affine3::then`]) rounds each entry half up once and saturates.

use crate::format::{round_32_to_16, MatrixEntry, TexPoint};
use crate::scene::math::{
    q30_to_q16, round_shift, round_shift_128, sat_i32, sat_i64, sin_cos, Angle, Vec3, ONE,
};

/// An affine map `p -> M p + t` (rows of `M`, then `t`), `Q16.16` entries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Affine3 {
    m: [[MatrixEntry; 3]; 3],
    t: [MatrixEntry; 3],
}

impl Default for Affine3 {
    fn default() -> Self {
        Self::IDENTITY
    }
}

const Z: MatrixEntry = MatrixEntry::ZERO;
const O: MatrixEntry = MatrixEntry::ONE;

/// A raw `Q16.16` value as a [`MatrixEntry`].
const fn e(bits: i32) -> MatrixEntry {
    MatrixEntry::from_bits(bits)
}

/// Entries below this magnitude (raw) take the `i64` path of [`Affine3::apply_wide`]: each product is below `2^61` and a sum of three plus a shifted
/// translation fits `i64`.
const SMALL: i32 = 1 << 30;

impl Affine3 {
    /// The identity.
    pub const IDENTITY: Affine3 = Affine3 {
        m: [[O, Z, Z], [Z, O, Z], [Z, Z, O]],
        t: [Z, Z, Z],
    };

    /// From a matrix (rows) and a translation.
    pub const fn new(m: [[MatrixEntry; 3]; 3], t: [MatrixEntry; 3]) -> Self {
        Affine3 { m, t }
    }

    /// From raw `Q16.16` rows and translation (`65536` = 1.0).
    pub const fn from_bits(m: [[i32; 3]; 3], t: [i32; 3]) -> Self {
        Affine3 {
            m: [
                [e(m[0][0]), e(m[0][1]), e(m[0][2])],
                [e(m[1][0]), e(m[1][1]), e(m[1][2])],
                [e(m[2][0]), e(m[2][1]), e(m[2][2])],
            ],
            t: [e(t[0]), e(t[1]), e(t[2])],
        }
    }

    /// Uniform scale by `k` (frequency).
    pub const fn scale(k: MatrixEntry) -> Self {
        Affine3 {
            m: [[k, Z, Z], [Z, k, Z], [Z, Z, k]],
            t: [Z, Z, Z],
        }
    }

    /// Per-axis scale.
    pub const fn scale3(ks: MatrixEntry, kt: MatrixEntry, kr: MatrixEntry) -> Self {
        Affine3 {
            m: [[ks, Z, Z], [Z, kt, Z], [Z, Z, kr]],
            t: [Z, Z, Z],
        }
    }

    /// A translation by a `Q16.16` vector.
    pub const fn translate(v: Vec3) -> Self {
        Affine3::IDENTITY.with_translation([e(v.x), e(v.y), e(v.z)])
    }

    /// A rotation about the x axis (y towards z), right-handed; sine and cosine from
    /// [`Angle::sin_cos`] rounded half up to `Q16.16`.
    pub const fn rotate_x(a: Angle) -> Self {
        let (s, c) = sin_cos(a);
        let (s, c) = (q30_to_q16(s), q30_to_q16(c));
        Affine3::from_bits([[ONE, 0, 0], [0, c, -s], [0, s, c]], [0; 3])
    }

    /// A rotation about the y axis (z towards x), right-handed.
    pub const fn rotate_y(a: Angle) -> Self {
        let (s, c) = sin_cos(a);
        let (s, c) = (q30_to_q16(s), q30_to_q16(c));
        Affine3::from_bits([[c, 0, s], [0, ONE, 0], [-s, 0, c]], [0; 3])
    }

    /// A rotation about the z axis (x towards y), right-handed.
    pub const fn rotate_z(a: Angle) -> Self {
        let (s, c) = sin_cos(a);
        let (s, c) = (q30_to_q16(s), q30_to_q16(c));
        Affine3::from_bits([[c, -s, 0], [s, c, 0], [0, 0, ONE]], [0; 3])
    }

    /// Host convenience: from real rows and translation (rounded, saturating).
    pub fn from_f64(m: [[f64; 3]; 3], t: [f64; 3]) -> Self {
        let e = MatrixEntry::saturating_from_num::<f64>;
        Affine3 {
            m: m.map(|row| row.map(e)),
            t: t.map(e),
        }
    }

    /// The matrix rows.
    pub const fn matrix(&self) -> [[MatrixEntry; 3]; 3] {
        self.m
    }

    /// The translation (phase).
    pub const fn translation(&self) -> [MatrixEntry; 3] {
        self.t
    }

    /// The translation as a raw `Q16.16` vector.
    pub const fn translation_vec3(&self) -> Vec3 {
        Vec3::new(
            self.t[0].to_bits(),
            self.t[1].to_bits(),
            self.t[2].to_bits(),
        )
    }

    /// The same transform with another translation.
    pub const fn with_translation(mut self, t: [MatrixEntry; 3]) -> Self {
        self.t = t;
        self
    }

    /// Raw entry `(i, j)` of `M` (`i, j < 3`).
    #[inline]
    const fn mb(&self, i: usize, j: usize) -> i32 {
        self.m[i][j].to_bits()
    }

    /// Whether every entry of `M` is below [`SMALL`] in magnitude: [`Affine3::apply_wide`]'s
    /// products then fit `i64`. A property of the transform alone, so a caller that applies it
    /// to many points finds it once ([`Affine3::saturating_apply_with`]).
    pub(crate) const fn small(&self) -> bool {
        let mut i = 0;
        while i < 3 {
            let mut j = 0;
            while j < 3 {
                let v = self.mb(i, j);
                if v <= -SMALL || v >= SMALL {
                    return false;
                }
                j += 1;
            }
            i += 1;
        }
        true
    }

    /// `self` followed by `other` (`other * self`), each entry rounded half up and saturated.
    ///
    /// The same bits as the exact product for every input: each product of two entries is exact
    /// in `i64` (at most `2^62`); the sums saturate, which can only happen when the exact sum
    /// is beyond `2^62` in magnitude, and then the entry saturates either way (the remaining
    /// terms, each at most `2^62`, cannot bring it below `2^47`).
    pub fn then(&self, other: &Affine3) -> Affine3 {
        let mut m = [[Z; 3]; 3];
        let mut t = [Z; 3];
        // Iterators rather than indices: no bounds check survives at any opt-level.
        let bits = |e: &MatrixEntry| i64::from(e.to_bits());
        // One loop for the four columns of each row (the translation is the fourth: its own
        // entry times 2^16, plus the row times this transform's translation).
        for (((row, ti), orow), ot) in m.iter_mut().zip(&mut t).zip(&other.m).zip(&other.t) {
            for (j, e) in row.iter_mut().chain(core::iter::once(ti)).enumerate() {
                let mut acc: i64 = if j == 3 { bits(ot) << 16 } else { 0 };
                for ((o, srow), st) in orow.iter().zip(&self.m).zip(&self.t) {
                    let s = if j == 3 {
                        bits(st)
                    } else {
                        srow.get(j).map_or(0, bits)
                    };
                    acc = acc.saturating_add(bits(o) * s);
                }
                *e = round_sat_entry(acc);
            }
        }
        Affine3 { m, t }
    }

    /// `round(M s + t)` for a point (raw 16.16), wrapped to lattice coordinates.
    #[inline]
    pub fn apply_point(&self, s: TexPoint) -> [i32; 3] {
        // The sums of `point_sums`, rounded in the same loop (the sums stay in registers;
        // rounding `point_sums`' array measured dearer on rv32imc).
        let b = s.to_bits();
        let mut out = [0i32; 3];
        for ((o, row), t) in out.iter_mut().zip(&self.m).zip(&self.t) {
            let mut acc: i64 = i64::from(t.to_bits()) << 16;
            for (m, bk) in row.iter().zip(&b) {
                acc = acc.wrapping_add(i64::from(m.to_bits()) * i64::from(*bk));
            }
            *o = round_32_to_16(acc) as i32;
        }
        out
    }

    /// `M s + t` for a point (raw 16.16) before [`Affine3::apply_point`]'s rounding: 32 fraction
    /// bits, wrapping modulo 2^64 ([`Affine3::vector_sums`] plus `t`: the same sums in another
    /// order).
    pub(crate) fn point_sums(&self, s: TexPoint) -> [i64; 3] {
        let mut v = self.vector_sums(s);
        for (o, t) in v.iter_mut().zip(&self.t) {
            *o = o.wrapping_add(i64::from(t.to_bits()) << 16);
        }
        v
    }

    /// `M d` for a vector (raw 16.16) before [`Affine3::apply_vector`]'s rounding: 32 fraction
    /// bits, wrapping modulo 2^64. Out of line: the plane set-up calls it three times a term.
    #[inline(never)]
    pub(crate) fn vector_sums(&self, d: TexPoint) -> [i64; 3] {
        let b = d.to_bits();
        let mut out = [0i64; 3];
        for (o, row) in out.iter_mut().zip(&self.m) {
            for (m, bk) in row.iter().zip(&b) {
                *o = o.wrapping_add(i64::from(m.to_bits()) * i64::from(*bk));
            }
        }
        out
    }

    /// `round(M d)` for a vector (raw 16.16), wrapped.
    #[inline]
    pub fn apply_vector(&self, d: TexPoint) -> [i32; 3] {
        let b = d.to_bits();
        #[cfg(texcore_lean)]
        {
            let mut out = [0i32; 3];
            for (o, row) in out.iter_mut().zip(&self.m) {
                let mut acc: i64 = 0;
                for (m, bk) in row.iter().zip(&b) {
                    acc = acc.wrapping_add(i64::from(m.to_bits()) * i64::from(*bk));
                }
                *o = round_32_to_16(acc) as i32;
            }
            out
        }
        #[cfg(not(texcore_lean))]
        {
            // Fast shape: column by column, skipping the zero components of `d` (a span along
            // a lattice axis has two): the same sum modulo 2^64.
            let mut acc = [0i64; 3];
            for (c, &bc) in b.iter().enumerate() {
                if bc == 0 {
                    continue;
                }
                for (o, row) in acc.iter_mut().zip(&self.m) {
                    let m = row.get(c).map_or(0, |m| m.to_bits());
                    *o = o.wrapping_add(i64::from(m) * i64::from(bc));
                }
            }
            [
                round_32_to_16(acc[0]) as i32,
                round_32_to_16(acc[1]) as i32,
                round_32_to_16(acc[2]) as i32,
            ]
        }
    }

    /// `M p + t` of a `Q16.16` point in `i64` `Q16.16` (exact products, one half-up rounding;
    /// saturates only past `i64`, for absurd inputs).
    #[inline]
    pub const fn apply_wide(&self, p: Vec3) -> [i64; 3] {
        self.apply_wide_with(p, self.small())
    }

    /// [`Affine3::apply_wide`] with `small` = [`Affine3::small`] found by the caller.
    #[inline]
    const fn apply_wide_with(&self, p: Vec3, small: bool) -> [i64; 3] {
        let p = [p.x as i64, p.y as i64, p.z as i64];
        let mut out = [0i64; 3];
        if small {
            let mut i = 0;
            while i < 3 {
                let acc = self.mb(i, 0) as i64 * p[0]
                    + self.mb(i, 1) as i64 * p[1]
                    + self.mb(i, 2) as i64 * p[2]
                    + ((self.t[i].to_bits() as i64) << 16);
                out[i] = round_shift(acc, 16);
                i += 1;
            }
            return out;
        }
        let mut i = 0;
        while i < 3 {
            // |each product| < 2^62; three of them plus the shifted translation fit i128,
            // and their sum can exceed i64 only for absurd inputs: accumulate in i128.
            let acc = self.mb(i, 0) as i128 * p[0] as i128
                + self.mb(i, 1) as i128 * p[1] as i128
                + self.mb(i, 2) as i128 * p[2] as i128
                + ((self.t[i].to_bits() as i128) << 16);
            out[i] = sat_i64(round_shift_128(acc, 16));
            i += 1;
        }
        out
    }

    /// `M p + t` of a `Q16.16` point, saturated to `Q16.16` `i32`.
    #[inline]
    pub const fn saturating_apply(&self, p: Vec3) -> Vec3 {
        self.saturating_apply_with(p, self.small())
    }

    /// [`Affine3::saturating_apply`] with `small` = [`Affine3::small`], found once by the
    /// caller for all the points it transforms (the same values; the entries are not checked
    /// again at every point).
    #[inline]
    pub(crate) const fn saturating_apply_with(&self, p: Vec3, small: bool) -> Vec3 {
        let w = self.apply_wide_with(p, small);
        Vec3::new(sat_i32(w[0]), sat_i32(w[1]), sat_i32(w[2]))
    }

    /// `M v` (no translation) of a `Q16.16` vector, saturated.
    pub const fn saturating_apply_vector(&self, v: Vec3) -> Vec3 {
        self.with_translation([Z; 3]).saturating_apply(v)
    }

    /// The largest absolute row sum of `M` (raw 16.16): bounds how many cells a unit step crosses.
    pub fn max_row_sum(&self) -> u64 {
        let mut best = 0u64;
        for row in &self.m {
            let s: u64 = row
                .iter()
                .map(|e| u64::from(e.to_bits().unsigned_abs()))
                .sum();
            best = best.max(s);
        }
        best
    }
}

/// `x` (32 fraction bits) rounded half up to 16 fraction bits, saturated to an entry.
fn round_sat_entry(x: i64) -> MatrixEntry {
    let r = x.saturating_add(1 << 15) >> 16;
    MatrixEntry::from_bits(r.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32)
}

/// Rotation by a fixed irrational-looking angle used between octaves (Miné & Neyret): a rotation
/// of about 36.87 degrees about the axis (1, 1, 1)/sqrt(3), stored exactly as rounded 16.16 entries.
/// Returned as a constant so that no trigonometry runs on the device.
pub const OCTAVE_ROTATION: Affine3 = Affine3 {
    // Rotation by acos(0.8) about (1,1,1)/sqrt(3): R = cI + (1-c) aa^T + s [a]x, c=0.8, s=0.6.
    m: [
        [
            MatrixEntry::from_bits(56798),  // c + (1-c)/3
            MatrixEntry::from_bits(-18333), // (1-c)/3 - s/sqrt3
            MatrixEntry::from_bits(27071),  // (1-c)/3 + s/sqrt3
        ],
        [
            MatrixEntry::from_bits(27071),
            MatrixEntry::from_bits(56798),
            MatrixEntry::from_bits(-18333),
        ],
        [
            MatrixEntry::from_bits(-18333),
            MatrixEntry::from_bits(27071),
            MatrixEntry::from_bits(56798),
        ],
    ],
    t: [Z, Z, Z],
};

#[cfg(feature = "defmt")]
impl defmt::Format for Affine3 {
    fn format(&self, f: defmt::Formatter) {
        let r = |i: usize| {
            [
                self.m[i][0].to_bits(),
                self.m[i][1].to_bits(),
                self.m[i][2].to_bits(),
                self.t[i].to_bits(),
            ]
        };
        defmt::write!(
            f,
            "Affine3(raw 16.16 rows {=[?]} {=[?]} {=[?]})",
            r(0),
            r(1),
            r(2)
        );
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    #[test]
    fn octave_rotation_is_a_rotation() {
        let m = OCTAVE_ROTATION.matrix();
        let f = |e: MatrixEntry| e.to_num::<f64>();
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| f(m[i][k]) * f(m[j][k])).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((dot - want).abs() < 1e-4, "{i}{j}: {dot}");
            }
        }
        // Determinant +1.
        let det = f(m[0][0]) * (f(m[1][1]) * f(m[2][2]) - f(m[1][2]) * f(m[2][1]))
            - f(m[0][1]) * (f(m[1][0]) * f(m[2][2]) - f(m[1][2]) * f(m[2][0]))
            + f(m[0][2]) * (f(m[1][0]) * f(m[2][1]) - f(m[1][1]) * f(m[2][0]));
        assert!((det - 1.0).abs() < 1e-4);
        // The axis is fixed.
        let v = OCTAVE_ROTATION.apply_vector(TexPoint::from_bits(65536, 65536, 65536));
        for c in v {
            assert!((c - 65536).abs() <= 2);
        }
    }

    #[test]
    fn apply_rounds_half_up_and_wraps() {
        let t = Affine3::scale(MatrixEntry::from_num(4));
        assert_eq!(t.apply_point(TexPoint::from_bits(1, -1, 3)), [4, -4, 12]);
        let h = Affine3::scale(MatrixEntry::from_bits(32768)); // 0.5
        assert_eq!(h.apply_vector(TexPoint::from_bits(1, -1, 3)), [1, 0, 2]);
        let big = Affine3::scale(MatrixEntry::from_num(256));
        let p = big.apply_point(TexPoint::from_bits(i32::MAX, i32::MIN, 0));
        assert_eq!(
            p,
            [
                (i64::from(i32::MAX) * 256) as i32,
                (i64::from(i32::MIN) * 256) as i32,
                0
            ]
        );
    }

    #[test]
    fn composition() {
        let a = Affine3::scale(MatrixEntry::from_num(2)).with_translation([O, Z, Z]);
        let b = Affine3::scale(MatrixEntry::from_num(3));
        let c = a.then(&b);
        // b(a(s)) = 3 (2 s + (1,0,0)) = 6 s + (3, 0, 0)
        assert_eq!(
            c.apply_point(TexPoint::from_bits(65536, 0, 0)),
            [9 * 65536, 0, 0]
        );
    }

    /// A small xorshift from `seed`: each call a value in `(-limit, limit)`.
    fn xorshift(seed: u64) -> impl FnMut(i64) -> i32 {
        let mut rng = crate::test_rng::XorShift64::new(seed);
        move |limit: i64| ((rng.next_u64() as i64) % limit) as i32
    }

    /// `other * self` with every product in i128 (the reference for both paths of `then`).
    fn then_reference(a: &Affine3, b: &Affine3) -> Affine3 {
        let (am, at, bm, bt) = (a.matrix(), a.translation(), b.matrix(), b.translation());
        let r = |acc: i128| sat_i32(sat_i64(round_shift_128(acc, 16)));
        let mut m = [[0i32; 3]; 3];
        let mut t = [0i32; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = r((0..3)
                    .map(|k| i128::from(bm[i][k].to_bits()) * i128::from(am[k][j].to_bits()))
                    .sum());
            }
            t[i] = r((i128::from(bt[i].to_bits()) << 16)
                + (0..3)
                    .map(|k| i128::from(bm[i][k].to_bits()) * i128::from(at[k].to_bits()))
                    .sum::<i128>());
        }
        Affine3::from_bits(m, t)
    }

    #[test]
    fn composition_paths_agree_with_the_exact_product() {
        // Entries around the fast-path limit, below and above it.
        let mut next = xorshift(0x2545_F491_4F6C_DD1D);
        for round in 0..4000 {
            let lim = [1i64 << 18, 1 << 29, 1 << 31, 1 << 32][round % 4];
            let mut mk = || {
                let m = [(); 3].map(|_| [(); 3].map(|_| next(lim)));
                Affine3::from_bits(m, [(); 3].map(|_| next(1 << 32)))
            };
            let (a, b) = (mk(), mk());
            assert_eq!(a.then(&b), then_reference(&a, &b), "{a:?} then {b:?}");
        }
        let full = Affine3::from_bits(
            [[i32::MIN; 3], [i32::MAX; 3], [i32::MIN, i32::MAX, i32::MIN]],
            [i32::MIN, i32::MAX, i32::MIN],
        );
        let f2 = full.then(&full);
        assert_eq!(f2.matrix()[0][0].to_bits(), i32::MAX);
        assert_eq!(f2, then_reference(&full, &full));
    }

    /// The point transform with the entries' size found once is the checked one, for transforms
    /// below and above the `i64` path's limit and points up to `i32`'s ends.
    #[test]
    fn saturating_apply_with_is_saturating_apply() {
        let mut next = xorshift(0x9E37_79B9_7F4A_7C15);
        let mut paths = [0usize; 2];
        for round in 0..8000 {
            let lim = [1i64 << 18, 1 << 29, 1 << 31, 1 << 32][round % 4];
            let m = [(); 3].map(|_| [(); 3].map(|_| next(lim)));
            let a = Affine3::from_bits(m, [(); 3].map(|_| next(1 << 32)));
            let p = if round % 7 == 0 {
                Vec3::new(i32::MIN, i32::MAX, next(1 << 32))
            } else {
                Vec3::new(next(1 << 32), next(1 << 20), next(1 << 24))
            };
            let small = a.small();
            paths[usize::from(small)] += 1;
            assert_eq!(
                a.saturating_apply_with(p, small),
                a.saturating_apply(p),
                "{a:?} {p:?}"
            );
        }
        assert!(paths[0] > 100 && paths[1] > 100, "{paths:?}");
        // Sums past i64 (only the wide path holds them): saturated either way.
        let big = Affine3::from_bits([[i32::MIN; 3]; 3], [i32::MIN; 3]);
        let p = Vec3::new(i32::MIN, i32::MIN, i32::MIN);
        assert!(!big.small());
        assert_eq!(
            big.saturating_apply_with(p, big.small()),
            big.saturating_apply(p)
        );
        assert_eq!(
            big.saturating_apply(p),
            Vec3::new(i32::MAX, i32::MAX, i32::MAX)
        );
    }

    #[test]
    fn scene_placements() {
        use crate::scene::math::units;
        let r = Affine3::rotate_z(Angle::QUARTER);
        assert_eq!(r.saturating_apply(Vec3::X), Vec3::Y);
        let r = Affine3::rotate_x(Angle::QUARTER);
        assert_eq!(r.saturating_apply(Vec3::Y), Vec3::Z);
        let r = Affine3::rotate_y(Angle::QUARTER);
        assert_eq!(r.saturating_apply(Vec3::Z), Vec3::X);
        let t = Affine3::scale(e(units(2))).then(&Affine3::translate(Vec3::units(1, 2, 3)));
        assert_eq!(
            t.saturating_apply(Vec3::units(1, 1, 1)),
            Vec3::units(3, 4, 5)
        );
        assert_eq!(t.translation_vec3(), Vec3::units(1, 2, 3));
        assert_eq!(
            t.saturating_apply_vector(Vec3::units(1, 1, 1)),
            Vec3::units(2, 2, 2)
        );
        let a = Affine3::rotate_y(Angle::from_degrees(30));
        let p = Vec3::milli(1234, -567, 890);
        let q = a.saturating_apply(p);
        let ang = 30f64.to_radians();
        let (x, z) = (1.234f64, 0.890f64);
        let ex = [
            x * ang.cos() + z * ang.sin(),
            -0.567,
            -x * ang.sin() + z * ang.cos(),
        ];
        for k in 0..3 {
            assert!((q.to_array()[k] as f64 / 65536.0 - ex[k]).abs() < 1e-4);
        }
        // The saturating and wrapping applications agree wherever nothing overflows.
        let s = a.then(&Affine3::translate(Vec3::milli(-250, 4000, 17)));
        assert_eq!(
            s.saturating_apply(p).to_array(),
            s.apply_point(TexPoint::from_bits(p.x, p.y, p.z))
        );
        assert_eq!(
            s.saturating_apply_vector(p).to_array(),
            s.apply_vector(TexPoint::from_bits(p.x, p.y, p.z))
        );
        // Never panics on extreme values.
        let big = Affine3::scale(e(i32::MAX)).then(&Affine3::scale(e(i32::MIN)));
        let _ = big.saturating_apply(Vec3::new(i32::MIN, i32::MAX, i32::MIN));
        let full = Affine3::from_bits(
            [[i32::MIN; 3], [i32::MAX; 3], [i32::MIN, i32::MAX, i32::MIN]],
            [i32::MIN, i32::MAX, i32::MIN],
        );
        let _ = full.apply_wide(Vec3::new(i32::MIN, i32::MIN, i32::MIN));
        let _ = full.saturating_apply_vector(Vec3::new(i32::MAX, i32::MAX, i32::MAX));
        let _ = full.apply_point(TexPoint::from_bits(i32::MIN, i32::MIN, i32::MIN));
    }
}
