//! Fixed-point formats of the texture unit, named by layout and aliased by meaning.
//!
//! Every stage of the pixel path works on one of these formats. The full contract, with the
//! overflow policy of each stage, is `docs/model.md`; in short:
//!
//! | alias | layout | overflow policy |
//! |---|---|---|
//! | [`TexCoord`] | `I16F16` | exact along a span (widened to i64) |
//! | [`LatticeCoord`] | `I16F16` | wrapping (lattice noise is periodic in 2^16) |
//! | [`Amplitude`], [`MatrixEntry`], [`QuadricCoeff`] | `I16F16` | checked once at construction |
//! | [`TexValue`] | `I16F16` | wrapping for `mod` tables, saturating for `clamp` tables |
//! | [`TableCoord`], [`FilterWidth`] | `U16F16` | saturating at the table size |
//!
//! No floating point is used by any of these types' arithmetic in the pixel path; the `from_num`
//! conversions from `f32`/`f64` are for building models on the host and in tests.

pub use fixed::types::{I16F16, U16F16};

/// A solid texture coordinate component (`s`, `t` or `r`): 16 integer and 16 fraction bits.
pub type TexCoord = I16F16;
/// A point in a noise term's lattice space. Integer part: the cell (taken mod 2^16); fraction: the
/// position inside the cell. Arithmetic on lattice coordinates wraps.
pub type LatticeCoord = I16F16;
/// Amplitude `a_k` of a noise term.
pub type Amplitude = I16F16;
/// Entry of a noise term's 3x4 affine transform `T_k`.
pub type MatrixEntry = I16F16;
/// One of the ten quadric coefficients `A..J`.
pub type QuadricCoeff = I16F16;
/// The texture function value `f`, the colour-table argument.
pub type TexValue = I16F16;
/// A position in a colour table, in entries.
pub type TableCoord = U16F16;
/// A box filter width, in colour-table entries.
pub type FilterWidth = U16F16;
/// A lattice value-noise corner value: `v / 32768` in `[-1, 1)`.
pub type LatticeValue = i16;

/// A point or vector of solid texture coordinates `(s, t, r)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TexPoint {
    /// First coordinate.
    pub s: TexCoord,
    /// Second coordinate.
    pub t: TexCoord,
    /// Third coordinate.
    pub r: TexCoord,
}

impl TexPoint {
    /// The origin / zero vector.
    pub const ZERO: TexPoint = TexPoint {
        s: TexCoord::ZERO,
        t: TexCoord::ZERO,
        r: TexCoord::ZERO,
    };

    /// Builds a point from three coordinates.
    pub const fn new(s: TexCoord, t: TexCoord, r: TexCoord) -> Self {
        TexPoint { s, t, r }
    }

    /// Builds a point from raw 16.16 bit patterns.
    pub const fn from_bits(s: i32, t: i32, r: i32) -> Self {
        TexPoint {
            s: TexCoord::from_bits(s),
            t: TexCoord::from_bits(t),
            r: TexCoord::from_bits(r),
        }
    }

    /// The raw 16.16 bit patterns as an array.
    pub const fn to_bits(self) -> [i32; 3] {
        [self.s.to_bits(), self.t.to_bits(), self.r.to_bits()]
    }

    /// Host convenience: builds a point from floating-point values (rounded to nearest, saturating).
    /// Not used in the pixel path.
    pub fn from_f64(s: f64, t: f64, r: f64) -> Self {
        TexPoint {
            s: TexCoord::saturating_from_num(s),
            t: TexCoord::saturating_from_num(t),
            r: TexCoord::saturating_from_num(r),
        }
    }
}

/// Rounds a value with 32 fraction bits to 16 fraction bits, half up (`(x + 2^15) >> 16`).
#[cfg_attr(not(texcore_lean), inline(always))]
pub(crate) const fn round_32_to_16(x: i64) -> i64 {
    (x + (1 << 15)) >> 16
}

#[cfg(feature = "defmt")]
impl defmt::Format for TexPoint {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "TexPoint(raw 16.16 {=i32}, {=i32}, {=i32})",
            self.s.to_bits(),
            self.t.to_bits(),
            self.r.to_bits()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texpoint_bits_round_trip() {
        let p = TexPoint::from_bits(-65536, 1, i32::MAX);
        assert_eq!(p.to_bits(), [-65536, 1, i32::MAX]);
        assert_eq!(p.s, TexCoord::from_num(-1));
    }

    #[test]
    fn round_half_up() {
        assert_eq!(round_32_to_16(0x8000), 1);
        assert_eq!(round_32_to_16(0x7FFF), 0);
        assert_eq!(round_32_to_16(-0x8000), 0);
        assert_eq!(round_32_to_16(-0x8001), -1);
    }
}
