//! The configured texture model `f(s) = q(s) + sum_k a_k n_k(T_k s)`.
//!
//! A [`TextureModel`] holds a [`Quadric`], up to `T` [`NoiseTerm`]s (a const generic capacity, at
//! most 8 in practice) and the colour-table wrap flag, which decides the overflow policy of `f`:
//! wrapping for `mod` tables (only `f mod 1` matters, so wrapped quadrics stay exact) and
//! saturating for `clamp` tables.
//!
//! Invariants, checked once when terms are added or amplitudes change, never per pixel:
//! - at most `T` terms;
//! - `sum_k |a_k| <= 512`, from which the noise accumulator's fraction bits `fv` are derived
//!   (`docs/model.md` 4.4) so that no noise sum or exact interpolation can overflow.
//!
//! Evaluation lives in [`crate::span`]; this module only configures.

use heapless::Vec;

use crate::format::{Amplitude, MatrixEntry};
use crate::noise::NoiseBasis;
use crate::quadric::Quadric;
use crate::table::TableWrap;
use crate::transform::{Affine3, OCTAVE_ROTATION};

/// One noise term `a n(T s)`, optionally turbulent (`a |n(T s)|`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct NoiseTerm {
    /// Amplitude `a`.
    pub amplitude: Amplitude,
    /// Affine transform `T` (frequency, rotation, phase).
    pub transform: Affine3,
    /// Noise basis.
    pub basis: NoiseBasis,
    /// Absolute value of the noise (turbulence).
    pub turbulence: bool,
}

impl NoiseTerm {
    /// A term with amplitude `a`, transform `t` and basis `b`, not turbulent.
    pub const fn new(amplitude: Amplitude, transform: Affine3, basis: NoiseBasis) -> Self {
        NoiseTerm {
            amplitude,
            transform,
            basis,
            turbulence: false,
        }
    }
}

/// Why a model could not be built or changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ModelError {
    /// More noise terms than the model's capacity `T`.
    TooManyTerms {
        /// The capacity.
        capacity: usize,
    },
    /// `sum |a_k|` exceeds 512.
    AmplitudeSumTooLarge,
    /// A parameter outside its documented range.
    OutOfRange {
        /// Which parameter.
        what: &'static str,
    },
    /// A term index that does not exist.
    NoSuchTerm {
        /// The index asked for.
        index: usize,
    },
}

impl core::fmt::Display for ModelError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ModelError::TooManyTerms { capacity } => {
                write!(
                    f,
                    "too many noise terms: the model holds at most {capacity}"
                )
            }
            ModelError::AmplitudeSumTooLarge => {
                write!(
                    f,
                    "the sum of |amplitude| over all noise terms must be at most 512"
                )
            }
            ModelError::NoSuchTerm { index } => write!(f, "there is no noise term {index}"),
            ModelError::OutOfRange { what } => write!(f, "{what} is out of range"),
        }
    }
}

impl core::error::Error for ModelError {}

/// A sum of octaves `sum_i a g^i n(R^i 2^i B s)` (fBm; turbulence with `turbulence`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Octaves {
    /// Number of octaves (1..).
    pub count: u8,
    /// Base transform `B` applied to `s` before the octave scaling.
    pub base: Affine3,
    /// Amplitude of the first octave.
    pub amplitude: Amplitude,
    /// Rotate each octave by [`OCTAVE_ROTATION`] relative to the previous one to hide the lattice
    /// alignment (Miné & Neyret).
    pub rotate: bool,
    /// Basis of every octave.
    pub basis: NoiseBasis,
    /// `|n|` per octave.
    pub turbulence: bool,
}

/// The arithmetic precision of a model's noise terms: the precision study of Hart et al. (1999,
/// section 4.3 and Fig. 10) and Kameya & Hart's bit-width tests (`docs/model.md` 3.2).
///
/// - `coord_bits` (`F`): fraction bits of the lattice coordinates. A span's lattice origin `U0`
///   and step `DU` are rounded half up to multiples of `2^-F` cell at span set-up, so the lattice
///   point `U0 + i DU` stays linear in the pixel index (forward differencing stays exact).
/// - `value_bits` (`V`): bits of the value-noise corner values (`v / 32768`, rounded half up to
///   multiples of `2^(16-V)` and saturated). Gradient noise and mNoise have small integer corner
///   gradients (2 bits), which this does not change.
///
/// Both are `1..=16`; 16 is the native format ([`Precision::NATIVE`], the default), where the
/// model is exactly the unquantised one. More than 16 coordinate bits (e.g. 24) is not offered:
/// `LatticeCoord` is I16F16 in a 32-bit word and the exact forward differences are sized for it
/// (16 bits of cell index for the 2^16 lattice period, 16 fraction bits; the trilinear cubic's
/// coefficients reach 48 + `fv` + 16 bits in i64); 24 fraction bits would need a 40-bit lattice
/// coordinate and 72-bit difference accumulators, i.e. a wider format on both devices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Precision {
    coord_bits: u8,
    value_bits: u8,
}

impl Default for Precision {
    fn default() -> Self {
        Self::NATIVE
    }
}

impl Precision {
    /// The native format: 16 coordinate fraction bits, 16-bit corner values (no quantisation).
    pub const NATIVE: Precision = Precision {
        coord_bits: 16,
        value_bits: 16,
    };
    /// The most bits of either kind (the native format).
    pub const MAX_BITS: u32 = 16;

    /// A precision with `coord_bits` lattice-coordinate fraction bits and `value_bits`-bit corner
    /// values, each in `1..=16`.
    pub const fn new(coord_bits: u32, value_bits: u32) -> Result<Self, ModelError> {
        if coord_bits == 0 || coord_bits > Self::MAX_BITS {
            return Err(ModelError::OutOfRange {
                what: "coordinate fraction bits (1..=16)",
            });
        }
        if value_bits == 0 || value_bits > Self::MAX_BITS {
            return Err(ModelError::OutOfRange {
                what: "lattice value bits (1..=16)",
            });
        }
        Ok(Precision {
            coord_bits: coord_bits as u8,
            value_bits: value_bits as u8,
        })
    }

    /// Lattice-coordinate fraction bits `F`.
    pub const fn coord_bits(&self) -> u32 {
        self.coord_bits as u32
    }

    /// Corner-value bits `V`.
    pub const fn value_bits(&self) -> u32 {
        self.value_bits as u32
    }

    /// The same precision with `F = bits` (`1..=16`).
    pub const fn with_coord_bits(self, bits: u32) -> Result<Self, ModelError> {
        Self::new(bits, self.value_bits as u32)
    }

    /// The same precision with `V = bits` (`1..=16`).
    pub const fn with_value_bits(self, bits: u32) -> Result<Self, ModelError> {
        Self::new(self.coord_bits as u32, bits)
    }

    /// Whether this is the native format (nothing is quantised).
    pub const fn is_native(&self) -> bool {
        self.coord_bits == 16 && self.value_bits == 16
    }

    /// A lattice coordinate (raw 16.16, wrapping) rounded half up to `F` fraction bits.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub const fn quantize_coord(&self, u: i32) -> i32 {
        quantize_coord(u, self.coord_bits as u32)
    }
}

/// `u` (raw 16.16, wrapping) rounded half up to a multiple of `2^(16 - bits)` raw units
/// (`bits` fraction bits), wrapping; the identity for `bits >= 16`.
#[cfg_attr(not(texcore_lean), inline(always))]
pub const fn quantize_coord(u: i32, bits: u32) -> i32 {
    if bits >= 16 {
        return u;
    }
    let sh = 16 - bits;
    u.wrapping_add(1 << (sh - 1)) & !((1i32 << sh) - 1)
}

/// The parameterized texture model with capacity for `T` noise terms.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureModel<const T: usize> {
    quadric: Quadric,
    terms: Vec<NoiseTerm, T>,
    wrap: TableWrap,
    fv: u8,
    precision: Precision,
}

/// The largest `fv <= 16` with `sum_raw * 2^fv <= 2^29` (`sum |a| * 2^fv <= 2^13`).
fn frac_bits_for(sum_raw: u64) -> Option<u8> {
    let mut fv = 16u8;
    while (sum_raw << fv) > (1u64 << 29) {
        if fv == 4 {
            return None;
        }
        fv -= 1;
    }
    Some(fv)
}

impl<const T: usize> TextureModel<T> {
    /// A model with only a quadric.
    pub const fn new(quadric: Quadric, wrap: TableWrap) -> Self {
        TextureModel {
            quadric,
            terms: Vec::new(),
            wrap,
            fv: 16,
            precision: Precision::NATIVE,
        }
    }

    /// The same model at another arithmetic precision (builder style).
    pub const fn with_precision(mut self, precision: Precision) -> Self {
        self.precision = precision;
        self
    }

    /// Sets the arithmetic precision of the noise terms.
    pub fn set_precision(&mut self, precision: Precision) {
        self.precision = precision;
    }

    /// Sets the lattice-coordinate fraction bits (`1..=16`); unchanged on error.
    pub fn set_coord_bits(&mut self, bits: u32) -> Result<(), ModelError> {
        self.precision = self.precision.with_coord_bits(bits)?;
        Ok(())
    }

    /// Sets the corner-value bits (`1..=16`); unchanged on error.
    pub fn set_value_bits(&mut self, bits: u32) -> Result<(), ModelError> {
        self.precision = self.precision.with_value_bits(bits)?;
        Ok(())
    }

    /// The arithmetic precision of the noise terms.
    pub const fn precision(&self) -> Precision {
        self.precision
    }

    /// Adds a term (builder style).
    pub fn with(mut self, term: NoiseTerm) -> Result<Self, ModelError> {
        self.push(term)?;
        Ok(self)
    }

    /// Adds octaves (builder style).
    pub fn with_octaves(mut self, octaves: &Octaves) -> Result<Self, ModelError> {
        self.push_octaves(octaves)?;
        Ok(self)
    }

    /// Adds a term.
    pub fn push(&mut self, term: NoiseTerm) -> Result<(), ModelError> {
        let fv = self.frac_bits_with(Some(term), None)?;
        self.terms
            .push(term)
            .map_err(|_| ModelError::TooManyTerms { capacity: T })?;
        self.fv = fv;
        Ok(())
    }

    /// Adds `octaves.count` terms: octave `i` has amplitude `a / 2^i` and transform
    /// `R^i 2^i B` (R only with `rotate`).
    pub fn push_octaves(&mut self, octaves: &Octaves) -> Result<(), ModelError> {
        if self.terms.len() + usize::from(octaves.count) > T {
            return Err(ModelError::TooManyTerms { capacity: T });
        }
        let mut transform = octaves.base;
        for i in 0..octaves.count {
            let amp = Amplitude::from_bits(octaves.amplitude.to_bits() >> i);
            self.push(NoiseTerm {
                amplitude: amp,
                transform,
                basis: octaves.basis,
                turbulence: octaves.turbulence,
            })?;
            let mut next = transform.then(&Affine3::scale(MatrixEntry::from_num(2)));
            if octaves.rotate {
                next = next.then(&OCTAVE_ROTATION);
            }
            transform = next;
        }
        Ok(())
    }

    fn frac_bits_with(
        &self,
        extra: Option<NoiseTerm>,
        replace: Option<(usize, Amplitude)>,
    ) -> Result<u8, ModelError> {
        let mut sum: u64 = 0;
        for (k, t) in self.terms.iter().enumerate() {
            let a = match replace {
                Some((r, a)) if r == k => a,
                _ => t.amplitude,
            };
            sum += u64::from(a.to_bits().unsigned_abs());
        }
        if let Some(t) = extra {
            sum += u64::from(t.amplitude.to_bits().unsigned_abs());
        }
        frac_bits_for(sum).ok_or(ModelError::AmplitudeSumTooLarge)
    }

    /// Changes the amplitude of term `k` (animation of marble forming); re-derives `fv`.
    pub fn set_amplitude(&mut self, k: usize, a: Amplitude) -> Result<(), ModelError> {
        if k >= self.terms.len() {
            return Err(ModelError::NoSuchTerm { index: k });
        }
        self.fv = self.frac_bits_with(None, Some((k, a)))?;
        self.terms[k].amplitude = a;
        Ok(())
    }

    /// Changes the translation (phase) of term `k` (animation of fire and clouds).
    pub fn set_translation(&mut self, k: usize, t: [MatrixEntry; 3]) -> Result<(), ModelError> {
        let term = self
            .terms
            .get_mut(k)
            .ok_or(ModelError::NoSuchTerm { index: k })?;
        term.transform = term.transform.with_translation(t);
        Ok(())
    }

    /// Replaces the quadric.
    pub fn set_quadric(&mut self, q: Quadric) {
        self.quadric = q;
    }

    /// The quadric.
    pub const fn quadric(&self) -> &Quadric {
        &self.quadric
    }

    /// The noise terms.
    pub fn terms(&self) -> &[NoiseTerm] {
        &self.terms
    }

    /// The colour-table wrap flag (and so the overflow policy of `f`).
    pub const fn wrap(&self) -> TableWrap {
        self.wrap
    }

    /// The noise accumulator's fraction bits beyond 48 (`fv`, `docs/model.md` 4.4).
    pub const fn noise_frac_bits(&self) -> u32 {
        self.fv as u32
    }

    /// Whether any term needs per-pixel evaluation (not a cubic along spans).
    pub fn all_terms_cubic(&self) -> bool {
        self.terms.iter().all(|t| t.basis.is_cubic())
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for NoiseTerm {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "NoiseTerm(a raw {=i32}, {}, {}, turbulence {=bool})",
            self.amplitude.to_bits(),
            self.transform,
            self.basis,
            self.turbulence
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::QuadricCoeff;
    use crate::hash::HashKind;

    fn term(a: f64) -> NoiseTerm {
        NoiseTerm::new(
            Amplitude::from_num(a),
            Affine3::IDENTITY,
            NoiseBasis::trilinear(HashKind::Integer),
        )
    }

    #[test]
    fn frac_bits_follow_amplitudes() {
        let mut m: TextureModel<8> = TextureModel::new(Quadric::ZERO, TableWrap::Mod);
        assert_eq!(m.noise_frac_bits(), 16);
        m.push(term(1.0)).unwrap();
        assert_eq!(m.noise_frac_bits(), 13);
        m.push(term(-0.875)).unwrap();
        assert_eq!(m.noise_frac_bits(), 12);
        m.set_amplitude(1, Amplitude::from_num(300)).unwrap();
        assert_eq!(m.noise_frac_bits(), 4);
        assert_eq!(
            m.set_amplitude(1, Amplitude::from_num(600)),
            Err(ModelError::AmplitudeSumTooLarge)
        );
        // unchanged after the failed update
        assert_eq!(m.terms()[1].amplitude, Amplitude::from_num(300));
        assert_eq!(
            m.set_amplitude(5, Amplitude::ONE),
            Err(ModelError::NoSuchTerm { index: 5 })
        );
    }

    #[test]
    fn capacity_is_checked() {
        let mut m: TextureModel<2> = TextureModel::new(Quadric::ZERO, TableWrap::Clamp);
        m.push(term(0.5)).unwrap();
        m.push(term(0.5)).unwrap();
        assert_eq!(
            m.push(term(0.5)),
            Err(ModelError::TooManyTerms { capacity: 2 })
        );
        let oct = Octaves {
            count: 3,
            base: Affine3::IDENTITY,
            amplitude: Amplitude::ONE,
            rotate: false,
            basis: NoiseBasis::default(),
            turbulence: false,
        };
        let m2: TextureModel<2> = TextureModel::new(Quadric::ZERO, TableWrap::Clamp);
        assert_eq!(
            m2.with_octaves(&oct),
            Err(ModelError::TooManyTerms { capacity: 2 })
        );
    }

    #[test]
    fn octaves_double_frequency_and_halve_amplitude() {
        let oct = Octaves {
            count: 4,
            base: Affine3::scale(MatrixEntry::from_num(3)),
            amplitude: Amplitude::ONE,
            rotate: false,
            basis: NoiseBasis::default(),
            turbulence: true,
        };
        let m: TextureModel<8> = TextureModel::new(
            Quadric::linear(
                QuadricCoeff::ZERO,
                QuadricCoeff::ZERO,
                QuadricCoeff::ONE,
                QuadricCoeff::ZERO,
            ),
            TableWrap::Mod,
        )
        .with_octaves(&oct)
        .unwrap();
        assert_eq!(m.terms().len(), 4);
        for (i, t) in m.terms().iter().enumerate() {
            assert_eq!(t.amplitude.to_bits(), 65536 >> i);
            assert_eq!(t.transform.matrix()[0][0], MatrixEntry::from_num(3 << i));
            assert!(t.turbulence);
        }
        let r: TextureModel<8> = TextureModel::new(Quadric::ZERO, TableWrap::Mod)
            .with_octaves(&Octaves {
                rotate: true,
                ..oct
            })
            .unwrap();
        assert_ne!(
            r.terms()[1].transform.matrix(),
            m.terms()[1].transform.matrix()
        );
    }
}
