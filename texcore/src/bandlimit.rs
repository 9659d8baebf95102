//! Band-limiting of noise octaves near and past the Nyquist limit (`docs/model.md` section 8).
//!
//! A pixel's true colour is the colour table averaged over the *distribution* of `f` across the
//! pixel's footprint. An octave whose cells are smaller than a pixel contributes two things to
//! that distribution: its footprint average (the part a pixel can still show) and its spread
//! inside the footprint (the part only the filter can show). Per noise term and per span, with
//! `L` the term's **reach**, the largest lattice step a pixel makes along either screen direction
//! (cells a pixel, [`reach`]):
//!
//! - `L <= 1/2` ([`GRADIENT_REACH`], the Nyquist limit): the term is resolved. It enters `f` at
//!   full amplitude and its analytic gradient widens the filter.
//! - `1/2 < L <= 1` ([`FADE_START`]): the term enters `f` at full amplitude; half its variance
//!   ([`NEAR_PART`]) widens the filter instead of its gradient (the span evaluator's exactness
//!   bounds on the summed gradients hold for steps up to half a cell).
//! - `L > 1`: the term is **faded**: it enters `f` with its amplitude times the weight
//!   `w = max(1 / sqrt(lx' ly'), 1/4)` ([`fade_weight`]; [`BandLimit`] sets the rule, the floor
//!   and the share below: an accuracy knob), with `lx' = max(lx, 1)` and
//!   `ly' = max(ly, 1)` its reaches along the span and across it ([`reach_along`]): the standard
//!   deviation of the octave's average over the `lx' ly'` cells of the pixel's footprint. A
//!   receding plane's footprint reaches far in depth but little across, so its average falls only
//!   as `1 / sqrt(ly)`, not as `1 / L`; the floor `1/4` keeps distant octaves from freezing (the
//!   supersampled truth keeps its few samples' spread). Of the term's variance `a^2 sigma^2`
//!   (`sigma` the basis's standard deviation, [`basis_sigma`]), `w^2` is carried by the faded
//!   amplitude and the rest, `1 - w^2`, is spread inside the footprint: [`FADED_PART`] of it
//!   widens the filter instead of the term's gradient ([`faded_part`]).
//! - A faded term whose faded amplitude is below [`CULL_AMPLITUDE`] (1/256 of the table's unit
//!   range: it cannot move the colour by an entry) is **culled**: not evaluated at all, its whole
//!   variance `a^2 sigma^2` goes to the filter.
//!
//! Without band-limiting (`EvalOptions::cull` off, the `--no-cull` contract) every term enters
//! `f` at full amplitude; a term past `L = 1/2` widens the filter by its whole variance instead
//! of its gradient.
//!
//! The variances of a span's terms add up, and the filter width they stand for is the width of
//! the box with the same variance, `sqrt(12 var)` in `f` units ([`spread_width48`]); it combines
//! with the gradient's width in quadrature (`crate::filter::WidthStream::width_with`).
//!
//! Guarantees: integer only, `const fn`s, identical on every target; no input panics or
//! overflows (every intermediate saturates); a faded amplitude never exceeds the term's own in
//! magnitude, so every exactness bound of the span evaluator that holds for the amplitude holds
//! for the faded one.

use crate::model::NoiseTerm;
use crate::noise::BasisKind;

/// Reach (raw 16.16 cells a pixel) up to which a term's gradient widens the filter: half a cell
/// a pixel, the Nyquist limit (the span evaluator's exactness bounds on the summed gradients
/// assume it).
pub const GRADIENT_REACH: u32 = 1 << 15;
/// Reach (raw 16.16 cells a pixel) up to which a term enters `f` unfaded: one cell a pixel.
pub const FADE_START: u32 = 1 << 16;
/// The part of an unfaded term's variance past [`GRADIENT_REACH`] that widens the filter (raw
/// 0.16): 1/2 (a faded one adds [`faded_part`]).
pub const NEAR_PART: u32 = 1 << 15;
/// The smallest fade weight (raw 0.16): 1/4 (measured against the supersampled truth: 1/8 left
/// six rows flat below the seascape's horizon; 1/4 leaves one flat row; no floor four).
pub const FADE_FLOOR: u32 = 1 << 14;
/// The share (raw 0.16) of a faded term's within-footprint variance `1 - w^2` that widens the
/// filter: 3/4. Measured against the supersampled truth (seascape and flight, 320 x 240, 4 x 4
/// truth): with the whole `1 - w^2` the flight's horizon flickers 0.66 times as much as the
/// truth's (PSNR 31.51 dB), with 1/2 of it 0.71 (31.54 dB), 5/8 0.69 and 3/4 0.68 (31.58 dB,
/// the closest), 7/8 0.67 (31.56 dB). The accuracy report's `band_limit` knob (`docs/accuracy.md`:
/// the seascape's still frame at 160 x 120 against an 8 x 8 truth) puts 1/2 0.42 dB closer on
/// that frame (33.23 against 32.81 dB) with the same horizon flicker (0.35 against 0.34, the
/// truth's 0.34): the share is a trade between the two scenes, not a clear optimum.
pub const FADED_PART: u32 = 3 << 14;
/// A faded term whose faded amplitude (raw 16.16) is below this is culled: 1/256.
pub const CULL_AMPLITUDE: u32 = 1 << 8;

/// What a term contributes to one span.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TermBand {
    /// The amplitude the term is evaluated with (raw 16.16; the term's own when not faded).
    pub amplitude: i32,
    /// The term is evaluated (false: culled).
    pub active: bool,
    /// Its gradient widens the filter (only for resolved terms).
    pub gradient: bool,
    /// The variance it adds to the filter instead (raw 16.16 `f`-units squared, saturating).
    pub variance: u64,
}

/// The term's reach: the largest magnitude of the lattice steps `du` (along the span) and `dy`
/// (to the next row), raw 16.16 cells a pixel.
pub const fn reach(du: [i32; 3], dy: [i32; 3]) -> u32 {
    let (a, b) = (reach_along(du), reach_along(dy));
    if a > b {
        a
    } else {
        b
    }
}

/// Which reaches a faded term's weight counts (a [`BandLimit`] setting).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FadeWeight {
    /// One over the square root of the cells the footprint covers, `1 / sqrt(lx' ly')`: a
    /// receding plane's long and narrow footprint keeps `1 / sqrt(ly)` of the octave (the
    /// default, measured best).
    Footprint,
    /// One over the largest reach, `1 / max(lx', ly')`: the footprint taken as a square as long
    /// as its longest side (fades a receding plane's octaves further; the earlier rule).
    Reach,
}

/// How band-limiting fades a term past one cell a pixel and how much of its lost variance
/// widens the filter: an accuracy knob (`texsim report accuracy`, knob `band_limit`) whose
/// default, [`BandLimit::DEFAULT`], is the setting measured closest to the supersampled truth.
///
/// Invariants (checked by [`BandLimit::new`]): the floor is in `[1/16, 1]` and the faded part in
/// `[0, 1]` (raw 0.16 each), so every weight is in `[floor, 1]` and no arithmetic overflows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BandLimit {
    weight: FadeWeight,
    floor: u32,
    /// The product of the reaches (24 fraction bits) whose weight is the floor:
    /// `(2^28 / floor)^2`, saturating.
    p_max: u32,
    faded_part: u32,
}

impl BandLimit {
    /// The default: [`FadeWeight::Footprint`], floor [`FADE_FLOOR`], faded part [`FADED_PART`].
    pub const DEFAULT: BandLimit = BandLimit {
        weight: FadeWeight::Footprint,
        floor: FADE_FLOOR,
        p_max: 1 << 28,
        faded_part: FADED_PART,
    };

    /// A setting: the weight rule, the smallest weight `floor` (raw 0.16, `1 << 12` (1/16) to
    /// `1 << 16` (1: nothing fades)) and the share `faded_part` (raw 0.16, at most `1 << 16`)
    /// of a faded term's within-footprint variance `1 - w^2` that widens the filter. `None` when
    /// either is out of range.
    pub const fn new(weight: FadeWeight, floor: u32, faded_part: u32) -> Option<BandLimit> {
        if floor < 1 << 12 || floor > 1 << 16 || faded_part > 1 << 16 {
            return None;
        }
        // (2^28 / floor)^2 in [2^24, 2^32]: saturate the top one.
        let q = (1u64 << 28) / floor as u64;
        let p = q * q;
        let p_max = if p > u32::MAX as u64 {
            u32::MAX
        } else {
            p as u32
        };
        Some(BandLimit {
            weight,
            floor,
            p_max,
            faded_part,
        })
    }

    /// The weight rule.
    pub const fn weight(&self) -> FadeWeight {
        self.weight
    }

    /// The smallest fade weight (raw 0.16).
    pub const fn floor(&self) -> u32 {
        self.floor
    }

    /// The share of a faded term's within-footprint variance that widens the filter (raw 0.16).
    pub const fn faded_part(&self) -> u32 {
        self.faded_part
    }

    /// The fade weight (raw 0.16, `1 << 16` is 1) of a term whose reaches along the span and
    /// across it are `lx` and `ly` (raw 16.16 cells a pixel, [`reach_along`]), each taken as at
    /// least one cell (`lx' = max(lx, 1)`, `ly' = max(ly, 1)`): `1 / sqrt(lx' ly')`
    /// ([`FadeWeight::Footprint`]: the standard deviation of an octave's average over that many
    /// independent cells) or `1 / max(lx', ly')` ([`FadeWeight::Reach`]), at least the floor.
    /// In 32-bit integers: `p = (lx' >> 4) (ly' >> 4)` (cells, 24 fraction bits, saturating;
    /// both reaches the largest one for `Reach`), at most `(2^28 / floor)^2`, and
    /// `floor(2^28 / isqrt(p))` (1 at `p = 2^24`, one cell each way).
    pub const fn weight_of(&self, lx: u32, ly: u32) -> u32 {
        // Each reach at least one cell. No upper clamp is needed: the product saturates and is
        // clamped to `p_max` below.
        let lx = if lx < FADE_START { FADE_START } else { lx };
        let ly = if ly < FADE_START { FADE_START } else { ly };
        let (lx, ly) = match self.weight {
            FadeWeight::Footprint => (lx, ly),
            FadeWeight::Reach => {
                let l = if lx > ly { lx } else { ly };
                (l, l)
            }
        };
        let p = (lx >> 4).saturating_mul(ly >> 4);
        let p = if p > self.p_max { self.p_max } else { p };
        // r = floor(sqrt(p)) (12 fraction bits, in [2^12, 2^16)) digit by digit (smaller than a
        // general square root where nothing else needs one): w = 2^28 / r in (2^12, 2^16].
        let (mut rem, mut r, mut bit) = (p, 0u32, 1u32 << 30);
        while bit != 0 {
            if rem >= r + bit {
                rem -= r + bit;
                r = (r >> 1) + bit;
            } else {
                r >>= 1;
            }
            bit >>= 2;
        }
        // r >= 2^12 here (p >= 2^24); the checked division keeps the pixel path free of a panic
        // branch (the optimiser cannot see the bound through the loop).
        match (1u32 << 28).checked_div(r) {
            Some(w) => w,
            None => FADE_FLOOR,
        }
    }

    /// The part (raw 0.16) of a faded term's variance that widens the filter for a fade weight
    /// `w` (raw 0.16, at most `1 << 16`): `faded_part (1 - w^2)`, floor at each step.
    pub const fn part_of(&self, w: u32) -> u32 {
        let rest = (1u32 << 16) - ((w as u64 * w as u64) >> 16) as u32;
        ((rest as u64 * self.faded_part as u64) >> 16) as u32
    }
}

impl Default for BandLimit {
    fn default() -> Self {
        BandLimit::DEFAULT
    }
}

impl core::fmt::Display for FadeWeight {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            FadeWeight::Footprint => "footprint",
            FadeWeight::Reach => "reach",
        })
    }
}

/// `rule, floor F, share P` with `F` and `P` to four decimals (rounded down), for example
/// `footprint, floor 0.2500, share 0.7500`.
impl core::fmt::Display for BandLimit {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let dec = |raw: u32| {
            let d = (u64::from(raw) * 10_000) >> 16;
            (d / 10_000, d % 10_000)
        };
        let ((fi, ff), (pi, pf)) = (dec(self.floor), dec(self.faded_part));
        write!(f, "{}, floor {fi}.{ff:04}, share {pi}.{pf:04}", self.weight)
    }
}

/// The default fade weight ([`BandLimit::DEFAULT`]'s [`BandLimit::weight_of`]): with
/// [`FadeWeight::Footprint`] and the floor [`FADE_FLOOR`] reached at 16 cells.
pub const fn fade_weight(lx: u32, ly: u32) -> u32 {
    BandLimit::DEFAULT.weight_of(lx, ly)
}

/// The default part of a faded term's variance that widens the filter
/// ([`BandLimit::DEFAULT`]'s [`BandLimit::part_of`]): `FADED_PART (1 - w^2)`.
pub const fn faded_part(w: u32) -> u32 {
    BandLimit::DEFAULT.part_of(w)
}

/// The largest magnitude of the components of a lattice step (raw 16.16 cells a pixel): a term's
/// reach along one screen direction.
pub const fn reach_along(d: [i32; 3]) -> u32 {
    let mut m = 0u32;
    let mut k = 0;
    while k < 3 {
        let a = d[k].unsigned_abs();
        if a > m {
            m = a;
        }
        k += 1;
    }
    m
}

/// The standard deviation of a basis's values (raw 0.16), measured over its lattice (plain, and
/// with turbulence `|n|`): value noise 0.35 / 0.21, gradient noise 0.26 / 0.15, mNoise 0.21 /
/// 0.12 (the fades move these by less than 15%).
pub const fn basis_sigma(kind: BasisKind, turbulence: bool) -> u32 {
    let (plain, turb) = match kind {
        BasisKind::Value => (22938, 13763),
        #[cfg(feature = "gradient-noise")]
        BasisKind::Gradient => (17039, 9830),
        #[cfg(feature = "mnoise")]
        BasisKind::Modified => (13763, 7864),
    };
    if turbulence {
        turb
    } else {
        plain
    }
}

/// `(a sigma)^2 * part` (raw 16.16 `f`-units squared) for an amplitude `a` (raw 16.16), a sigma
/// and a part (raw 0.16 each), floor at every step, saturating.
const fn variance(a: i32, sigma: u32, part: u32) -> u64 {
    let s = ((a.unsigned_abs() as u64) * sigma as u64) >> 16; // (a sigma), 16.16, < 2^47
    let s2 = s.saturating_mul(s) >> 16; // 16.16
    s2.saturating_mul(part as u64) >> 16
}

/// What `term` contributes to a span whose lattice steps are `du` and `dy`, band-limited by the
/// setting `band` (`None`: the unfaded contract).
#[inline(always)]
pub const fn term_band(
    term: &NoiseTerm,
    du: [i32; 3],
    dy: [i32; 3],
    band: Option<&BandLimit>,
) -> TermBand {
    let a = term.amplitude.to_bits();
    let (lx, ly) = (reach_along(du), reach_along(dy));
    let l = if lx > ly { lx } else { ly };
    if l <= GRADIENT_REACH {
        return TermBand {
            amplitude: a,
            active: true,
            gradient: true,
            variance: 0,
        };
    }
    let sigma = basis_sigma(term.basis.kind, term.turbulence);
    // (amplitude, active, the part of the term's variance it adds to the spread): one
    // `variance` below for every case (code size).
    let (amplitude, active, part) = if let Some(band) = band {
        if l <= FADE_START {
            (a, true, (1 << 16) - NEAR_PART)
        } else {
            band_faded(band, a, lx, ly)
        }
    } else {
        (a, true, 1 << 16)
    };
    TermBand {
        amplitude,
        active,
        gradient: false,
        variance: variance(a, sigma, part),
    }
}

/// A faded term's (amplitude, active, part of its variance that widens the filter), for a term of
/// amplitude `a` (raw 16.16) whose reaches are `lx` and `ly`, past one cell.
#[inline(always)]
const fn band_faded(band: &BandLimit, a: i32, lx: u32, ly: u32) -> (i32, bool, u32) {
    let w = band.weight_of(lx, ly);
    // |a w| < 2^31 * 2^16: the product fits i64; the shift floors (towards minus infinity) and
    // the result has at most the magnitude of `a` (w <= 1), so it fits i32.
    let faded = ((a as i64 * w as i64) >> 16) as i32;
    if faded.unsigned_abs() < CULL_AMPLITUDE {
        // Culled: its whole variance.
        (0, false, 1 << 16)
    } else {
        // The spread it adds: `faded_part (1 - w^2)` of its variance (`w^2` of it is carried by
        // the faded amplitude; the whole variance only when culled).
        (faded, true, band.part_of(w))
    }
}

/// The filter width (in `f` units, 48 fraction bits, saturating) of a summed variance (raw
/// 16.16): the width of the box with that variance, `sqrt(12 var)`.
pub const fn spread_width48(variance: u64) -> i64 {
    spread_width48_always(variance)
}

/// [`spread_width48`] where the build has filter widths (feature `gradients`, which every
/// colour-table filter needs); 0 where it has none, so that a build without filters carries
/// neither the square root nor the variance behind it. What the span evaluators report as
/// [`crate::span::SpanInfo::extra_width48`].
pub(crate) const fn build_spread_width48(variance: u64) -> i64 {
    if cfg!(feature = "gradients") {
        spread_width48_always(variance)
    } else {
        0
    }
}

const fn spread_width48_always(variance: u64) -> i64 {
    if variance == 0 {
        return 0;
    }
    // sqrt(12 var) in 16.16 is isqrt(12 var_raw 2^16). The fast shape takes the 32-bit root
    // (Newton's iteration on the 32-bit divide) when the argument fits, as every spread of a
    // device-sized scene does; the digit-by-digit root otherwise. Both are exact.
    let v = variance.saturating_mul(12).saturating_mul(1 << 16);
    let w16 = if !cfg!(texcore_lean) && v <= u32::MAX as u64 {
        crate::filter::width::isqrt32(v as u32) as u64
    } else {
        crate::filter::isqrt(v)
    };
    if w16 >= 1 << 31 {
        i64::MAX
    } else {
        (w16 as i64) << 32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::Amplitude;
    use crate::noise::NoiseBasis;
    use crate::transform::Affine3;

    /// The default band-limiting, or none.
    fn on(band_limit: bool) -> Option<&'static BandLimit> {
        band_limit.then_some(&BandLimit::DEFAULT)
    }

    fn term(a: f64, turbulence: bool) -> NoiseTerm {
        NoiseTerm {
            amplitude: Amplitude::from_num(a),
            transform: Affine3::IDENTITY,
            basis: NoiseBasis::default(),
            turbulence,
        }
    }

    #[test]
    fn weights() {
        assert_eq!(fade_weight(0, 0), 1 << 16);
        assert_eq!(fade_weight(FADE_START, FADE_START), 1 << 16);
        assert_eq!(fade_weight(FADE_START, 1), 1 << 16);
        // Square footprints: 1 / l.
        assert_eq!(fade_weight(2 << 16, 2 << 16), 1 << 15);
        assert_eq!(fade_weight(4 << 16, 4 << 16), 1 << 14);
        // Long and narrow ones: 1 / sqrt(l).
        assert_eq!(fade_weight(1 << 15, 4 << 16), 1 << 15);
        assert_eq!(fade_weight(16 << 16, 1 << 10), 1 << 14);
        assert_eq!(fade_weight(2 << 16, 8 << 16), 1 << 14);
        assert_eq!(fade_weight(0, 9 << 16), 21845);
        assert_eq!(fade_weight(8 << 16, 8 << 16), FADE_FLOOR);
        assert_eq!(fade_weight(u32::MAX, u32::MAX), FADE_FLOOR);
        assert_eq!(fade_weight(u32::MAX, 0), FADE_FLOOR);
        // Monotone non-increasing in either reach.
        for other in [0, 1 << 16, 3 << 16] {
            let mut last = u32::MAX;
            for l in (0..40u32).map(|k| k * 13_000) {
                let w = fade_weight(l, other);
                assert!(w <= last);
                assert_eq!(w, fade_weight(other, l));
                last = w;
            }
        }
    }

    #[test]
    fn fade_weight_equals_its_clamped_form() {
        // The form with both reaches clamped to [1, 16] cells and an early return at one cell.
        fn clamped(lx: u32, ly: u32) -> u32 {
            let c = |l: u32| l.clamp(FADE_START, 16 << 16);
            let p = u64::from(c(lx) >> 4) * u64::from(c(ly) >> 4);
            if p <= 1 << 24 {
                1 << 16
            } else if p >= 1 << 28 {
                FADE_FLOOR
            } else {
                (1 << 28) / (p as f64).sqrt().floor() as u32
            }
        }
        let mut rng = crate::test_rng::XorShift32::new(0x2545_f491);
        let mut next = || rng.next_u32();
        for i in 0..200_000u32 {
            // Every scale: below a cell, around 1 and 16 cells, and huge.
            let (a, b) = (next() >> (next() % 32), next() >> (next() % 32));
            let (a, b) = if i < 4096 {
                ((i & 63) << 14, (i >> 6) << 14)
            } else {
                (a, b)
            };
            assert_eq!(fade_weight(a, b), clamped(a, b), "{a:#x} {b:#x}");
        }
        assert_eq!(fade_weight(u32::MAX, u32::MAX), FADE_FLOOR);
        assert_eq!(fade_weight(0, 0), 1 << 16);
    }

    #[test]
    fn band_limit_settings_are_checked() {
        let d = BandLimit::new(FadeWeight::Footprint, FADE_FLOOR, FADED_PART);
        assert_eq!(d, Some(BandLimit::DEFAULT));
        assert_eq!(BandLimit::default(), BandLimit::DEFAULT);
        assert!(BandLimit::new(FadeWeight::Footprint, (1 << 12) - 1, 0).is_none());
        assert!(BandLimit::new(FadeWeight::Reach, (1 << 16) + 1, 0).is_none());
        assert!(BandLimit::new(FadeWeight::Reach, 1 << 14, (1 << 16) + 1).is_none());
        let b = BandLimit::new(FadeWeight::Reach, 1 << 13, 1 << 15);
        assert_eq!(
            b.map(|b| (b.weight(), b.floor(), b.faded_part())),
            Some((FadeWeight::Reach, 1 << 13, 1 << 15))
        );
    }

    #[test]
    fn band_limits_print_their_settings() {
        use core::fmt::Write;
        let mut s = heapless::String::<64>::new();
        let _ = write!(s, "{}", BandLimit::DEFAULT);
        assert_eq!(s.as_str(), "footprint, floor 0.2500, share 0.7500");
        let mut s = heapless::String::<64>::new();
        let b = BandLimit::new(FadeWeight::Reach, 1 << 16, 1 << 16).unwrap_or_default();
        let _ = write!(s, "{b}");
        assert_eq!(s.as_str(), "reach, floor 1.0000, share 1.0000");
    }

    #[test]
    fn every_rule_stays_between_its_floor_and_one() {
        let mut rng = crate::test_rng::XorShift32::new(0x9e37_79b9);
        let mut next = || rng.next_u32();
        for weight in [FadeWeight::Footprint, FadeWeight::Reach] {
            for floor in [1 << 12, 1 << 13, FADE_FLOOR, 1 << 15, 1 << 16] {
                let Some(b) = BandLimit::new(weight, floor, FADED_PART) else {
                    panic!("floor {floor:#x}");
                };
                for _ in 0..20_000 {
                    let (lx, ly) = (next() >> (next() % 32), next() >> (next() % 32));
                    let w = b.weight_of(lx, ly);
                    assert!(
                        w >= floor && w <= 1 << 16,
                        "{weight:?} {floor:#x} {lx:#x} {ly:#x}: {w}"
                    );
                }
                assert_eq!(b.weight_of(0, 0), 1 << 16);
                // The floor is reached at 1/floor cells each way (1/floor^2 cells).
                let cells = ((1u64 << 16) / u64::from(floor)) as u32;
                assert_eq!(b.weight_of(cells << 16, cells << 16), floor);
                assert_eq!(b.weight_of(u32::MAX, u32::MAX), floor);
            }
        }
        // `Reach`: one over the largest reach, whatever the other one is.
        let Some(reach) = BandLimit::new(FadeWeight::Reach, FADE_FLOOR, FADED_PART) else {
            panic!("reach rule");
        };
        assert_eq!(reach.weight_of(2 << 16, 0), 1 << 15);
        assert_eq!(reach.weight_of(1 << 10, 4 << 16), 1 << 14);
        assert_eq!(reach.weight_of(3 << 16, 3 << 16), 21845);
        // `Footprint` against `Reach` on a long, narrow footprint: 1 / sqrt(4) against 1 / 4.
        assert_eq!(fade_weight(1 << 10, 4 << 16), 1 << 15);
    }

    #[test]
    fn the_share_scales_the_faded_part() {
        for part in [0, 1 << 15, FADED_PART, 1 << 16] {
            let Some(b) = BandLimit::new(FadeWeight::Footprint, FADE_FLOOR, part) else {
                panic!("part {part:#x}");
            };
            assert_eq!(b.part_of(0), part);
            assert_eq!(b.part_of(1 << 16), 0);
            // w = 1/2: part (3/4).
            assert_eq!(b.part_of(1 << 15), (u64::from(part) * 3 / 4) as u32);
        }
        // The faded term carries the rule through `term_band`: half the amplitude with either
        // rule on a square footprint, a quarter with `Reach` on a long one.
        let t = term(0.5, false);
        let Some(reach) = BandLimit::new(FadeWeight::Reach, FADE_FLOOR, FADED_PART) else {
            panic!("reach rule");
        };
        let long = term_band(&t, [1 << 14, 0, 0], [0, 4 << 16, 0], Some(&reach));
        assert_eq!(long.amplitude, 1 << 13);
        let square = term_band(&t, [2 << 16, 0, 0], [0, 2 << 16, 0], Some(&reach));
        assert_eq!(
            square,
            term_band(&t, [2 << 16, 0, 0], [0, 2 << 16, 0], on(true))
        );
    }

    #[test]
    fn faded_parts() {
        assert_eq!(faded_part(1 << 16), 0);
        assert_eq!(faded_part(0), FADED_PART);
        // w = 1/2: 3/4 of 3/4.
        assert_eq!(faded_part(1 << 15), 9 << 12);
        // w = 1/4: 3/4 of 15/16.
        assert_eq!(faded_part(FADE_FLOOR), (45 << 16) / 64);
    }

    #[test]
    fn reach_is_the_largest_step() {
        assert_eq!(reach([1, -5, 2], [0, 3, -4]), 5);
        assert_eq!(reach([i32::MIN, 0, 0], [0; 3]), 1 << 31);
    }

    #[test]
    fn resolved_faded_and_culled_terms() {
        let t = term(0.5, false);
        let r = term_band(&t, [1 << 15, 0, 0], [0; 3], on(true));
        assert_eq!(
            r,
            TermBand {
                amplitude: 1 << 15,
                active: true,
                gradient: true,
                variance: 0
            }
        );
        // Three quarters of a cell a pixel: unfaded, half its variance instead of its gradient.
        let near = term_band(&t, [3 << 14, 0, 0], [0; 3], on(true));
        assert_eq!(near.amplitude, 1 << 15);
        assert!(near.active && !near.gradient);
        let near_full = term_band(&t, [3 << 14, 0, 0], [0; 3], on(false));
        assert!(near.variance * 2 >= near_full.variance - 2);
        assert!(near.variance * 2 <= near_full.variance + 2);
        // Two cells a pixel along and across: half the amplitude.
        let f = term_band(&t, [2 << 16, 0, 0], [0, 2 << 16, 0], on(true));
        assert_eq!(f.amplitude, 1 << 14);
        assert!(f.active && !f.gradient);
        let full = term_band(&t, [2 << 16, 0, 0], [0; 3], on(false));
        assert_eq!(full.amplitude, 1 << 15);
        assert!(full.active && !full.gradient);
        // 3/4 (1 - w^2) = 9/16 of the variance.
        assert!(
            f.variance * 16 >= full.variance * 9 - 16 && f.variance * 16 <= full.variance * 9 + 16
        );
        // Long and narrow: four cells a pixel across, a quarter along: w = 1/2.
        let long = term_band(&t, [1 << 14, 0, 0], [0, 4 << 16, 0], on(true));
        assert_eq!(long.amplitude, 1 << 14);
        // Negative amplitudes fade symmetrically (up to the floor's rounding).
        let n = term_band(
            &term(-0.5, false),
            [2 << 16, 0, 0],
            [0, 0, 2 << 16],
            on(true),
        );
        assert_eq!(n.amplitude, -(1 << 14));
        // Tiny amplitudes are culled far away, never nearby.
        let tiny = term(1.0 / 128.0, false);
        let c = term_band(&tiny, [0, 100 << 16, 0], [0; 3], on(true));
        assert!(!c.active);
        assert_eq!(c.variance, full_variance(&tiny));
        assert!(term_band(&tiny, [1 << 16, 0, 0], [0; 3], on(true)).active);
    }

    fn full_variance(t: &NoiseTerm) -> u64 {
        term_band(t, [2 << 16, 0, 0], [0; 3], on(false)).variance
    }

    #[test]
    fn spread_width_is_the_digit_root() {
        // Every variance whose argument `12 var 2^16` lies below 2^32 takes the 32-bit root in
        // the fast shape: the same as the digit-by-digit root, at the boundary and around it.
        let edge = u64::from(u32::MAX) / (12 << 16);
        let mut rng = crate::test_rng::XorShift64::new(0x2545_F491_4F6C_DD1D);
        let random = core::iter::from_fn(move || Some(rng.spread()));
        for v in (0..5000)
            .chain(edge - 3..edge + 4)
            .chain(random.take(20_000))
        {
            let want = crate::filter::isqrt(v.saturating_mul(12).saturating_mul(1 << 16));
            let want = if want >= 1 << 31 {
                i64::MAX
            } else {
                (want as i64) << 32
            };
            assert_eq!(spread_width48(v), want, "{v}");
        }
    }

    #[test]
    fn spread_width_of_a_variance() {
        assert_eq!(spread_width48(0), 0);
        // var = 1/12: width 1.
        let v = (1u64 << 16) / 12;
        let w = spread_width48(v) >> 32;
        assert!((w - 65536).abs() < 8, "{w}");
        assert_eq!(spread_width48(u64::MAX), i64::MAX);
        // A unit-amplitude value-noise term, culled: sqrt(12) * 0.35.
        let full = full_variance(&term(1.0, false));
        let w = (spread_width48(full) >> 32) as f64 / 65536.0;
        assert!((w - 12f64.sqrt() * 0.35).abs() < 1e-3, "{w}");
    }

    #[test]
    fn extreme_amplitudes_do_not_overflow() {
        for a in [i32::MIN, i32::MAX, -1, 1] {
            let t = NoiseTerm {
                amplitude: Amplitude::from_bits(a),
                ..term(0.0, true)
            };
            for l in [0, 1 << 16, (1 << 16) + 1, 3 << 16, u32::MAX >> 1] {
                for bl in [true, false] {
                    let b = term_band(&t, [l as i32, 0, 0], [0; 3], on(bl));
                    assert!(b.amplitude.unsigned_abs() <= a.unsigned_abs());
                    let _ = spread_width48(b.variance);
                }
            }
        }
    }
}
