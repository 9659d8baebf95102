//! Multipass corner-by-corner noise (Hart 2001, "Perlin noise pixel shaders"): lattice value noise
//! evaluated a buffer at a time, one data-parallel pass per step, in the order of fixed-function
//! pipelines, FPGA pipelines and SIMD units (crate feature `multipass`).
//!
//! A [`Band`] holds up to `N` lattice points (capacity in the type). Evaluating one noise term
//! over it runs the passes of the paper's Fig. 3, each a loop over the whole buffer:
//!
//! 1. **decompose** (one pass per axis): the lattice coordinate `U0 + i DU` of every pixel split
//!    into its integer part `solid_int` and its fraction, which is also the linear weight;
//! 2. **smooth curve** (one pass per axis, smooth fades only): the weight through the fade;
//! 3. **random fields** (summed and XOR hashes only, two passes per axis): the per-axis random
//!    values of `solid_int` and `solid_int + 1`, shared by the eight corners;
//! 4. for each of the eight corners `k`: a **corner** pass (the corner's lattice point from
//!    `solid_int` or `solid_int + 1` per axis as `k` selects, hashed to a random value) and a
//!    **weight** pass (the value times the three weights or their complements, added into the
//!    running sum); with gradients a **partials** pass (the corner's share of the three partial
//!    derivatives of the interpolant);
//! 5. **finish** (one pass): the sum scaled into the model's noise units (reduced precisions),
//!    the gradients from the partials.
//!
//! [`Band::passes`] counts the passes actually run, so the pass table of `docs/multipass.md` is
//! measured, not asserted.
//!
//! ## Settings
//!
//! [`PassPrecision`] chooses the arithmetic of the weight passes:
//! - [`PassPrecision::Native`]: texcore's 16.16 lattice coordinates, 16-bit corner values and
//!   exact 64-bit products. With [`PassHash::Texcore`] the result is **bit-identical** to the
//!   direct evaluation of the term ([`crate::noise::NoiseBasis::sample`] and
//!   [`crate::noise::NoiseBasis::derivative`], and so to [`crate::span::EvalMode::Direct`]), for
//!   every fade (tested, also by proptest).
//! - [`PassPrecision::Fixed16_8`]: the 16.8 format the paper proposes for register combiners:
//!   16 integer and 8 fraction bits of lattice coordinate (truncated), 8-bit weights (`1.0` =
//!   256), 8-bit corner values, each product truncated to 8 fraction bits, a 16.8 sum.
//! - [`PassPrecision::Bits8`]: the paper's 8-bit framebuffer passes: an 8-bit coordinate channel
//!   with 4 integer and 4 fraction bits (its `bf = 4`; the lattice wraps every 16 cells), the
//!   weight `fraction << 4` (`1.0` = 255, the complement `255 - w`), modulate blends rounding to
//!   8 bits and a saturating 8-bit sum.
//!
//! At the reduced precisions the value is approximate (its error against the f64 reference is in
//! `texsim report accuracy`); the gradients are the exact derivatives of the trilinear
//! interpolant of the same quantised corner values and weights.
//!
//! [`PassHash`] chooses the random value of a lattice point: texcore's own lattice hash (the
//! term's [`crate::hash::HashKind`]), the paper's SGI hash (three per-axis random values in
//! `[0, 1/3]` summed, with the Gaussian bias of a sum) or the XOR of three per-axis random bytes
//! (uniform; the blend mode the paper asks for).
//!
//! Guarantees: no allocation, no floating point, nothing panics for any input (any lattice
//! coordinates, any step, any amplitude the model accepts); the same bits on every target.

mod band;
mod eval;

pub use band::{Band, PassTerm};
pub(crate) use eval::eval_span;
pub use eval::MULTIPASS_BAND;

/// Arithmetic of the multipass weight passes (module documentation, "Settings").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PassPrecision {
    /// 8-bit channels, coordinates 4.4 (lattice period 16), modulate blends, saturating sum.
    Bits8,
    /// The 16.8 fixed-point format: coordinates 16.8, 8-bit weights and values, a 16.8 sum.
    Fixed16_8,
    /// texcore's native precision: bit-identical to direct evaluation with texcore's hash.
    #[default]
    Native,
}

impl PassPrecision {
    /// Every setting, coarsest first.
    pub const ALL: [PassPrecision; 3] = [
        PassPrecision::Bits8,
        PassPrecision::Fixed16_8,
        PassPrecision::Native,
    ];

    /// The name used by `texsim` and the reports: `8`, `16.8` or `native`.
    pub const fn name(self) -> &'static str {
        match self {
            PassPrecision::Bits8 => "8",
            PassPrecision::Fixed16_8 => "16.8",
            PassPrecision::Native => "native",
        }
    }
}

/// The random value of a lattice point in the corner passes (module documentation, "Settings").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PassHash {
    /// The term's own lattice hash ([`crate::hash::lattice_value`]).
    #[default]
    Texcore,
    /// Three per-axis random values in `0..=85` summed (`0..=255`): the paper's SGI hash, with
    /// the Gaussian bias of a sum of three uniform values.
    SummedRandom,
    /// Three per-axis random bytes combined by exclusive or (uniform).
    Xor,
}

impl PassHash {
    /// Every setting.
    pub const ALL: [PassHash; 3] = [PassHash::Texcore, PassHash::SummedRandom, PassHash::Xor];

    /// The name used by `texsim` and the reports: `texcore`, `summed` or `xor`.
    pub const fn name(self) -> &'static str {
        match self {
            PassHash::Texcore => "texcore",
            PassHash::SummedRandom => "summed",
            PassHash::Xor => "xor",
        }
    }
}

/// A multipass setting: precision and hash. Every combination is valid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MultipassConfig {
    /// Arithmetic of the weight passes.
    pub precision: PassPrecision,
    /// Random value of a lattice point.
    pub hash: PassHash,
}

impl MultipassConfig {
    /// Native precision with texcore's hash: bit-identical to direct evaluation.
    pub const EXACT: MultipassConfig = MultipassConfig {
        precision: PassPrecision::Native,
        hash: PassHash::Texcore,
    };

    /// `precision` with texcore's hash.
    pub const fn with_precision(precision: PassPrecision) -> Self {
        MultipassConfig {
            precision,
            hash: PassHash::Texcore,
        }
    }
}

/// The per-axis random byte of lattice coordinate `x` on `axis` (0, 1, 2) for the summed and XOR
/// hashes: a table-free mixer of the coordinate's 16 bits (the paper's `sran`, `tran`, `rran`
/// tables; period 2^16).
#[inline]
pub const fn axis_random(x: u16, axis: u32) -> u8 {
    let mut h = (x as u32 ^ (axis.wrapping_mul(0x68E3_1DA4))).wrapping_mul(0x9E37_79B1);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^= h >> 13;
    (h >> 24) as u8
}

/// The summed hash's per-axis value: [`axis_random`] scaled to `0..=85` (a third of 255).
#[inline]
pub const fn axis_third(x: u16, axis: u32) -> u8 {
    ((axis_random(x, axis) as u32 * 86) >> 8) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_randoms_cover_their_ranges() {
        let mut seen = [false; 256];
        let mut max_third = 0;
        for x in 0..4096u16 {
            for axis in 0..3 {
                seen[usize::from(axis_random(x, axis))] = true;
                max_third = max_third.max(axis_third(x, axis));
            }
        }
        assert!(seen.iter().all(|&s| s));
        assert_eq!(max_third, 85);
        // The axes differ.
        assert!((0..64u16).any(|x| axis_random(x, 0) != axis_random(x, 1)));
    }

    #[test]
    fn names() {
        let p: Vec<_> = PassPrecision::ALL.iter().map(|p| p.name()).collect();
        assert_eq!(p, ["8", "16.8", "native"]);
        let h: Vec<_> = PassHash::ALL.iter().map(|h| h.name()).collect();
        assert_eq!(h, ["texcore", "summed", "xor"]);
        assert_eq!(MultipassConfig::default(), MultipassConfig::EXACT);
    }
}
