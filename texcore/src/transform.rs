//! Affine 3x4 transforms `T_k` of the noise terms: `u = M s + t` (frequency, rotation, phase).
//!
//! Entries are `I16F16` [`MatrixEntry`]. Applying a transform is the span set-up of
//! `docs/model.md` section 3: products in i64 (32 fraction bits), rounded half up to 16 fraction
//! bits, wrapped to i32 lattice coordinates. Composition (used by the octave builders) rounds each
//! entry half up and saturates.

use crate::format::{round_32_to_16, MatrixEntry, TexPoint};

/// An affine map of solid texture space into a noise term's lattice space.
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

    /// Host convenience: from real rows and translation (rounded, saturating).
    pub fn from_f64(m: [[f64; 3]; 3], t: [f64; 3]) -> Self {
        let e = MatrixEntry::saturating_from_num::<f64>;
        Affine3 {
            m: [
                [e(m[0][0]), e(m[0][1]), e(m[0][2])],
                [e(m[1][0]), e(m[1][1]), e(m[1][2])],
                [e(m[2][0]), e(m[2][1]), e(m[2][2])],
            ],
            t: [e(t[0]), e(t[1]), e(t[2])],
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

    /// The same transform with another translation.
    pub const fn with_translation(mut self, t: [MatrixEntry; 3]) -> Self {
        self.t = t;
        self
    }

    /// `other` applied after `self` (`other * self`), each entry rounded half up and saturated.
    pub fn then(&self, other: &Affine3) -> Affine3 {
        let mut m = [[Z; 3]; 3];
        let mut t = [Z; 3];
        // Iterators rather than indices: no bounds check survives at any opt-level.
        let bits = |e: &MatrixEntry| i64::from(e.to_bits());
        for (((row, ti), orow), ot) in m.iter_mut().zip(&mut t).zip(&other.m).zip(&other.t) {
            for (j, e) in row.iter_mut().enumerate() {
                let mut acc: i64 = 0;
                for (o, srow) in orow.iter().zip(&self.m) {
                    acc += bits(o) * srow.get(j).map_or(0, bits);
                }
                *e = sat_entry(round_32_to_16(acc));
            }
            let mut acc: i64 = bits(ot) << 16;
            for (o, st) in orow.iter().zip(&self.t) {
                acc += bits(o) * bits(st);
            }
            *ti = sat_entry(round_32_to_16(acc));
        }
        Affine3 { m, t }
    }

    /// `round(M s + t)` for a point (raw 16.16), wrapped to lattice coordinates.
    #[inline]
    pub fn apply_point(&self, s: TexPoint) -> [i32; 3] {
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

fn sat_entry(x: i64) -> MatrixEntry {
    MatrixEntry::from_bits(x.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32)
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
}
