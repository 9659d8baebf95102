//! How a span is evaluated: the evaluation modes ([`EvalMode`]) and an evaluator's options
//! ([`EvalOptions`]).

use super::*;

/// How a span is evaluated; the exact modes (`Direct`, `Fd`, `Auto`, exact `Multipass`) give
/// identical samples, the approximate ones (`Fd32`, `Reanchored`, `Fused`) state their error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EvalMode {
    /// Per-pixel evaluation.
    Direct,
    /// Exact forward differencing (crate feature `fd`; without it, per pixel as `Direct`).
    Fd,
    /// Forward differencing where cells and spans are long, direct where they are short
    /// ([`AUTO_FD_PIXELS`]; without the crate feature `fd`, per pixel as `Direct`).
    #[default]
    Auto,
    /// Cheaper forward differencing of the cubic terms with 32-bit accumulators, re-anchored to
    /// the exact polynomial every [`FD32_ANCHOR`] pixels: **not** bit-identical; the error of `f` is
    /// at most `5489 * 2^-(16 + fv)` (one anchor interval's truncation drift, `1 + 32 + C(32,2) +
    /// C(32,3)` units) plus one unit of the final floor, per cubic term. Other terms as `Fd`.
    /// Since the exact merged accumulators of `Fd` (one set for all cubic terms) cost less than
    /// per-term 32-bit ones, non-turbulent cubic terms take the exact merged path here too (error
    /// zero, within the bound); the 32-bit accumulators remain for turbulent cubic terms.
    ///
    /// The 32-bit accumulators are compiled in with the crate feature `fd32`; without it this mode
    /// is [`EvalMode::Fd`] (exact, so within the bound above).
    Fd32,
    /// Terms that are not cubics along a span (smooth and quintic fades, gradient noise, mNoise:
    /// degree 9 or more) forward-differenced as cubic Hermite segments through exact values and
    /// exact derivatives at both ends of each segment (piecewise re-anchoring): approximate between
    /// anchors, exact at them. A segment covers at most [`HERMITE_SEGMENT`] pixels and at most a
    /// quarter of a cell along the span (the Hermite error grows with the fourth power of the
    /// segment's length in cells), so it pays only where cells span many pixels. Cubic terms as
    /// `Fd`.
    ///
    /// The Hermite segments are compiled in with the crate feature `reanchor` together with a
    /// basis that is not a cubic (`smooth-fade`, `gradient-noise` or `mnoise`); otherwise this mode
    /// is [`EvalMode::Fd`] (exact).
    Reanchored,
    /// Rows of Perlin gradient noise (`BasisKind::Gradient`) served by the row schedule
    /// ([`SpanEvaluator::rows`]) along any lattice axis, not only along x: per cell and row, the
    /// corners' dot products weighted along the row's two other axes are summed exactly into
    /// two 64-bit values, which a pixel steps by additions and blends with its fade along the
    /// row in one product. Along x that is `docs/model.md` 4.3's blend, which every mode steps
    /// so; along y or z the last product is along the row's axis instead of x, and rows of
    /// several terms without quadric floor each term's product on its own, term after term.
    /// **Not** bit-identical there: a term's value `n` and `Direct`'s are both within three
    /// units of `2^-16` below the exact trilinear value, so they differ by at most
    /// `2 * 2^-16`, and a sample by at most `2 sum |a_i| 2^-16` plus one unit a term.
    /// Everything else (other bases, spans outside the row schedule) as `Fd`.
    ///
    /// Compiled in with the crate feature `fused`; without it this mode is [`EvalMode::Fd`]
    /// (exact, so within the bound above).
    Fused,
    /// Multipass corner-by-corner noise (Hart 2001, [`crate::multipass`], crate feature
    /// `multipass`): value-noise terms evaluated a band of pixels at a time, one pass per corner.
    /// With [`crate::multipass::MultipassConfig::EXACT`] bit-identical to `Direct`; the reduced
    /// precisions are approximate (their error is in `texsim report accuracy`).
    #[cfg(feature = "multipass")]
    Multipass(crate::multipass::MultipassConfig),
}

/// Options of the span evaluator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EvalOptions {
    /// Evaluation strategy.
    pub mode: EvalMode,
    /// Compute the filter-width gradients `gx`, `gy` (off: they are zero and cost nothing).
    /// Needs the crate feature `gradients` (enabled by `csat` and `mip`); without it this has no
    /// effect and the gradients are always zero.
    pub gradients: bool,
    /// Band-limit octaves past the Nyquist limit: fade them, cull the negligible ones and widen
    /// the filter by what they lose ([`crate::bandlimit`]).
    pub cull: bool,
    /// How band-limiting fades and spreads (when `cull` is on): an accuracy knob, the measured
    /// best by default.
    pub band_limit: BandLimit,
}

impl EvalOptions {
    /// The band-limiting setting in force: `None` when `cull` is off.
    #[inline(always)]
    pub fn band(&self) -> Option<&BandLimit> {
        self.cull.then_some(&self.band_limit)
    }
}

impl Default for EvalOptions {
    fn default() -> Self {
        EvalOptions {
            mode: EvalMode::Auto,
            gradients: true,
            cull: true,
            band_limit: BandLimit::DEFAULT,
        }
    }
}
