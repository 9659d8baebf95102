//! The plan: which strategy evaluates each term along a span, decided once per span from the
//! evaluation mode as compiled in, the term's set-up and the span's length.
//!
//! Guarantees: a mode or strategy whose code is not compiled in is never chosen (`compiled_mode`
//! maps it to an exact one), culled terms are `Strategy::Off`, and every strategy gives the
//! same samples as `Strategy::Direct` except the approximate ones of the approximate modes
//! ([`EvalMode::Fd32`], [`EvalMode::Reanchored`]).

use super::*;

/// Break-even of [`EvalMode::Auto`] in pixels a cell set-up: forward differencing a trilinear
/// term costs a cell set-up (corner hashing, the cubic and its forward differences, the exit
/// pixel, and at the exit the subtraction of its state) per cell it visits, and little per
/// pixel; per-pixel evaluation costs a cheaper cell set-up (corner hashing, the monomial form)
/// per cell and the polynomial per pixel. Forward differencing pays when a span gives each of
/// its cell set-ups more than this many pixels (measured on the devices, `docs/performance.md`).
pub const AUTO_FD_PIXELS: u32 = 2;

/// Whether forward differencing a trilinear term with lattice step `du` pays over a span of
/// `len` pixels: the span visits about `1 + len sum|du| / 2^16` cells, and forward differencing
/// pays when that leaves more than [`AUTO_FD_PIXELS`] pixels to each.
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn fd_pays(len: u16, du: [i32; 3]) -> bool {
    let sum: u64 = du.iter().map(|d| u64::from(d.unsigned_abs())).sum();
    let len = u64::from(len);
    // len / (1 + len sum / 2^16) > P  <=>  2^16 len > P (2^16 + len sum)
    (len << 16) > u64::from(AUTO_FD_PIXELS) * ((1 << 16) + len * sum)
}

/// How one term is evaluated along the current span.
///
/// Which strategies the general loop ([`SpanEvaluator::run`]) carries depends on the features:
/// `Direct` always; `Fd` (for terms the merged fast path does not take) with `turbulence-fd`;
/// `Cached` with a basis that is not a cubic (`smooth-fade`, `gradient-noise`, `mnoise`); `Fd32`
/// with `fd32`; `Hermite` with `reanchor` and a basis that is not a cubic. A strategy that is
/// not compiled in is never chosen (see [`SpanEvaluator::eval_inner`] and
/// [`SpanEvaluator::run`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Strategy {
    Off,
    /// Per-pixel hashing and interpolation.
    Direct,
    /// Cached cell, per-pixel interpolation (exact).
    #[cfg_attr(
        not(any(
            feature = "smooth-fade",
            feature = "gradient-noise",
            feature = "mnoise"
        )),
        allow(dead_code)
    )]
    Cached,
    /// Exact 64-bit forward differencing of the cubic.
    Fd,
    /// 32-bit forward differencing, re-anchored every [`FD32_ANCHOR`] pixels.
    #[cfg_attr(not(feature = "fd32"), allow(dead_code))]
    Fd32,
    /// Cubic Hermite segments of at most [`HERMITE_SEGMENT`] pixels (approximate).
    #[cfg_attr(not(texcore_hermite), allow(dead_code))]
    Hermite,
}

/// Whether the general loop forward-differences cubic terms itself (`Strategy::Fd`); without it
/// they are evaluated per pixel there (identical samples) and turbulent cubic terms go through
/// the merged loop's per-pixel path.
pub(super) const GENERAL_FD: bool = cfg!(feature = "turbulence-fd");

/// Whether forward differencing is compiled in (crate feature `fd`); without it every mode
/// evaluates per pixel (see [`compiled_mode`]).
pub(super) const FD: bool = cfg!(feature = "fd");

/// Whether the filter-width gradients are compiled in (crate feature `gradients`, enabled by the
/// colour-table filters); without it [`EvalOptions::gradients`] has no effect and every gradient
/// is zero.
pub(crate) const GRADIENTS: bool = cfg!(feature = "gradients");

/// The size-lean code shape (built at `opt-level = "s"` or `"z"`, `cfg(texcore_lean)`): the
/// merged loop runs one pixel loop that tests the span's shape (gradients, affine quadric) per
/// pixel, instead of its eight specialisations and the component passes over long cells; with
/// [`GENERAL_FD`] the merged loop is not used at all (the general loop forward-differences every
/// term). The samples are identical (unit tests compare both shapes in every build).
pub(super) const LEAN: bool = cfg!(texcore_lean);

/// Whether any strategy of the general loop keeps per-term state across pixels (cell caches,
/// forward differences, segments); without one it only evaluates per pixel.
pub(super) const GENERAL_ANCHORS: bool = cfg!(any(
    feature = "turbulence-fd",
    feature = "fd32",
    feature = "smooth-fade",
    feature = "gradient-noise",
    feature = "mnoise"
));

/// The evaluation mode actually run for `mode`: a mode whose code is not compiled in is
/// [`EvalMode::Fd`] (see the variants' documentation), and without the crate feature `fd` every
/// mode is [`EvalMode::Direct`].
#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) const fn compiled_mode(mode: EvalMode) -> EvalMode {
    if !FD {
        return EvalMode::Direct;
    }
    match mode {
        #[cfg(not(feature = "fd32"))]
        EvalMode::Fd32 => EvalMode::Fd,
        #[cfg(not(texcore_hermite))]
        EvalMode::Reanchored => EvalMode::Fd,
        #[cfg(not(feature = "fused"))]
        EvalMode::Fused => EvalMode::Fd,
        m => m,
    }
}

/// The plan: each term's strategy for a span, decided once per span by `choose(term set-up,
/// is_cubic)` (`Off` for the terms the set-up culled), as the general loop makes it.
#[cfg(not(texcore_lean))]
#[inline(always)]
pub(super) fn plan<const T: usize>(
    setup: &Setup<T>,
    terms: &[NoiseTerm],
    choose: impl Fn(&TermSetup, bool) -> Strategy,
) -> [Strategy; T] {
    let mut strategies = [Strategy::Off; T];
    for ((st, ts), term) in strategies.iter_mut().zip(setup.terms.iter()).zip(terms) {
        if ts.active {
            *st = choose(ts, term.basis.is_cubic());
            // Without the general loop's forward differencing, turbulent cubic terms are
            // evaluated per pixel, which the merged loop does (identical samples).
            if !GENERAL_FD && *st == Strategy::Fd && term.turbulence {
                *st = Strategy::Direct;
            }
        }
    }
    strategies
}

/// The strategy of an active term (`cubic`: a trilinear basis) with set-up `ts` in a span of
/// `len` pixels under `mode` (as compiled, [`compiled_mode`]).
#[inline(always)]
pub(super) fn strategy(mode: EvalMode, ts: &TermSetup, cubic: bool, len: u16) -> Strategy {
    match mode {
        EvalMode::Direct => Strategy::Direct,
        EvalMode::Fd | EvalMode::Fused => {
            if cubic {
                Strategy::Fd
            } else {
                Strategy::Cached
            }
        }
        EvalMode::Auto => {
            if ts.du.iter().any(|d| d.unsigned_abs() > NYQUIST_STEP as u32) {
                Strategy::Direct
            } else if cubic {
                if fd_pays(len, ts.du) {
                    Strategy::Fd
                } else {
                    Strategy::Direct
                }
            } else {
                Strategy::Cached
            }
        }
        EvalMode::Fd32 => {
            if cubic {
                Strategy::Fd32
            } else {
                Strategy::Cached
            }
        }
        EvalMode::Reanchored => {
            if cubic {
                Strategy::Fd
            } else {
                Strategy::Hermite
            }
        }
        #[cfg(feature = "multipass")]
        EvalMode::Multipass(_) => Strategy::Direct,
    }
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// The span's set-up into `setup` (empty), its counters and facts ([`Self::begin`]), and its
    /// plan ([`Self::plan_span`]; `None` for an empty span, which sets nothing up).
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    pub(super) fn begin_planned(
        &mut self,
        span: &Span,
        from: SetupFrom<'_, '_, T>,
        setup: &mut Setup<T>,
    ) -> (SpanInfo, Option<[Strategy; T]>) {
        let info = self.begin(span, from, setup);
        if span.len == 0 {
            return (info, None);
        }
        (info, Some(self.plan_span(span.len, setup)))
    }

    /// The plan of a span of `len` pixels with set-up `setup` under the evaluator's mode.
    #[cfg(not(texcore_lean))]
    #[inline(always)]
    pub(super) fn plan_span(&self, len: u16, setup: &Setup<T>) -> [Strategy; T] {
        let mode = compiled_mode(self.opts.mode);
        let choose = |ts: &TermSetup, cubic| strategy(mode, ts, cubic, len);
        plan(setup, self.model.terms(), choose)
    }
}
