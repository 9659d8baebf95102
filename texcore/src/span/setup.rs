//! The per-span set-up shared by every mode: each term's lattice start and steps, **the per-span
//! band-limiting decision** (per term, from its lattice steps and
//! [`crate::bandlimit::term_band`]), and the quadric along the span.
//!
//! Guarantees: the set-up is a function of the model, the options and the span (`s0`, `ds`,
//! `dsdy`) alone. `U0` and `DU` are rounded to the model's coordinate precision so that
//! `u(i) = U0 + i DU` stays linear in `i`; band-limiting uses the unrounded step. The quadric's
//! coefficients are exact modulo 2^128 (wrapping), as `Quadric::along` and
//! `Quadric::derivative_along`; nothing here panics.

use super::*;

/// A term's span set-up (read by the multipass evaluator too).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct TermSetup {
    /// Lattice point of pixel 0 (rounded to the model's coordinate precision).
    pub(crate) u0: [i32; 3],
    /// Lattice step along the span (rounded as `u0`).
    pub(crate) du: [i32; 3],
    /// Lattice step to the next row (unrounded).
    pub(crate) dy: [i32; 3],
    /// Evaluate the value.
    pub(crate) active: bool,
    /// Evaluate the gradient (false past one cell a pixel: the term's spread goes to
    /// `extra_width48`, [`crate::bandlimit`]).
    pub(crate) gradient: bool,
    /// The amplitude of this span (raw 16.16): the term's own, or faded
    /// ([`crate::bandlimit::term_band`]).
    pub(crate) amp: i32,
}

#[cfg_attr(not(texcore_lean), inline(always))]
pub(super) fn exact(p: TexPoint) -> [i64; 3] {
    let b = p.to_bits();
    [i64::from(b[0]), i64::from(b[1]), i64::from(b[2])]
}

/// The per-span part of the model evaluation shared by every mode (multipass included).
pub(crate) struct Setup<const T: usize> {
    /// One per model term, in order (inactive where culled).
    pub(crate) terms: heapless::Vec<TermSetup, T>,
    /// The quadric along the span, `None` when it is zero (fast shape: an empty set-up writes a
    /// tag, not the 120 bytes of a zero quadric).
    #[cfg(not(texcore_lean))]
    pub(super) quadric: Option<QuadSetup>,
    /// The quadric along the span (size-lean shape: zero in an empty set-up).
    #[cfg(texcore_lean)]
    pub(super) quadric: QuadSetup,
    /// The span's extra filter width ([`SpanInfo::extra_width48`]).
    pub(super) extra_width48: i64,
}

/// The quadric along a span and its gradients.
#[derive(Clone, Copy, Debug)]
pub(crate) struct QuadSetup {
    /// The quadric along the span (48 fraction bits).
    pub(crate) quad: QuadraticSpan,
    /// The quadric's x-gradient along the span: `gqx[0] + i gqx[1]` (zero without gradients).
    pub(crate) gqx: [i128; 2],
    /// The quadric's y-gradient along the span, as `gqx`.
    pub(crate) gqy: [i128; 2],
}

/// The zero quadric.
pub(super) const ZERO_QUAD: QuadSetup = QuadSetup {
    quad: QuadraticSpan { c: [0; 3] },
    gqx: [0; 2],
    gqy: [0; 2],
};

impl<const T: usize> Setup<T> {
    /// No terms, a zero quadric (built in place: the term slots stay unwritten).
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub(super) fn empty() -> Self {
        Setup {
            terms: heapless::Vec::new(),
            #[cfg(not(texcore_lean))]
            quadric: None,
            #[cfg(texcore_lean)]
            quadric: ZERO_QUAD,
            extra_width48: 0,
        }
    }

    /// The quadric along the span and its gradients (zero for a zero quadric).
    #[inline(always)]
    pub(crate) fn quadric(&self) -> &QuadSetup {
        #[cfg(not(texcore_lean))]
        return match &self.quadric {
            Some(q) => q,
            None => &ZERO_QUAD,
        };
        #[cfg(texcore_lean)]
        &self.quadric
    }
}

/// The per-term band-limiting of `span` ([`crate::bandlimit::term_band`]), the one loop behind
/// the span set-up, [`SpanEvaluator::extra_width48`] and the multipass evaluator (which takes the
/// span set-up), band-limited by `rule` (`None`: the unfaded contract): calls
/// `each(term, du, dy, band)` for every term of `model` in order, with the
/// term's unrounded lattice steps along and across the span and `band` its amplitude for the
/// span and whether its gradient widens the filter ([`crate::bandlimit::TermBand`]; `None`:
/// culled), and returns the span's extra filter width ([`SpanInfo::extra_width48`]) from the
/// summed variances (the callback does not see them: builds without filter widths drop them).
///
/// In the size-lean shape with filter widths (feature `gradients`, where both callers are
/// linked) the callers hand `each` over as an [`EachTerm`] trait object: one out-of-line copy.
/// Elsewhere it is inlined with `each` (the fast shape; the lean builds without filter widths,
/// whose only caller is the span set-up and which drop the variances).
#[cfg_attr(not(all(texcore_lean, feature = "gradients")), inline(always))]
pub(super) fn band_terms<const T: usize, F>(
    model: &TextureModel<T>,
    span: &Span,
    rule: Option<&BandLimit>,
    each: &mut F,
) -> i64
where
    F: FnMut(&NoiseTerm, &[i32; 3], &[i32; 3], Option<(i32, bool)>) + ?Sized,
{
    let mut variance: u64 = 0;
    for term in model.terms().iter().take(T) {
        let (du, dy) = lattice_steps(term, span);
        let band = term_band(term, du, dy, rule);
        // Summed only where filter widths exist (`build_spread_width48`).
        if cfg!(feature = "gradients") {
            variance = variance.saturating_add(band.variance);
        }
        each(
            term,
            &du,
            &dy,
            band.active.then_some((band.amplitude, band.gradient)),
        );
    }
    build_spread_width48(variance)
}

/// The callback of [`band_terms`] as a trait object (the size-lean shape with filter widths).
#[cfg(all(texcore_lean, feature = "gradients"))]
pub(super) type EachTerm<'a> =
    dyn FnMut(&NoiseTerm, &[i32; 3], &[i32; 3], Option<(i32, bool)>) + 'a;

/// A callback as [`band_terms`] takes it: a trait object in the size-lean shape with filter
/// widths (one copy of the loop for every caller), itself elsewhere (inlined with the loop).
#[cfg(all(texcore_lean, feature = "gradients"))]
pub(super) fn each_term<'a>(each: &'a mut EachTerm<'a>) -> &'a mut EachTerm<'a> {
    each
}

/// See the size-lean version.
#[cfg(not(all(texcore_lean, feature = "gradients")))]
#[inline(always)]
pub(super) fn each_term<F>(each: &mut F) -> &mut F {
    each
}

/// A term's lattice steps along the span and across it (raw 16.16 cells a pixel).
#[inline]
pub(super) fn lattice_steps(term: &NoiseTerm, span: &Span) -> ([i32; 3], [i32; 3]) {
    let du = term.transform.apply_vector(span.ds);
    let dy = term.transform.apply_vector(span.dsdy);
    (du, dy)
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// Fills `out` (empty, as [`Setup::empty`]) for `span`; in place, as the set-up is large.
    /// Out of line in the fast shape: one copy for the span's and the plane's callers (a plane
    /// set-up made for another evaluator falls back to it). The terms before the quadric (the
    /// two parts are independent): the other order measured 7 instructions a pixel dearer on
    /// rv32imc's `stage:noise-octave` (16-pixel spans).
    #[cfg_attr(not(texcore_lean), inline(never))]
    pub(super) fn setup(&mut self, span: &Span, out: &mut Setup<T>) {
        self.term_setup(span, out);
        self.quadric_setup(span, out);
    }

    /// The quadric part of [`Self::setup`] (`out.quadric`; nothing for a zero quadric). Out of
    /// line in the fast shape on the Cortex-M, where it measured about 1% cheaper on the
    /// scenes' set-ups (`scene:wood`); inlined on rv32imc.
    #[cfg_attr(all(not(texcore_lean), not(target_arch = "riscv32")), inline(never))]
    #[cfg_attr(any(texcore_lean, target_arch = "riscv32"), inline(always))]
    fn quadric_setup(&mut self, span: &Span, out: &mut Setup<T>) {
        let m = self.model;
        let s0 = exact(span.s0);
        let ds = exact(span.ds);
        let dy = exact(span.dsdy);
        // The quadric along the span from two matrix-vector products, `Q x` and `Q d` (entries
        // 32 x 32 -> 64-bit, zero entries skipped), and five dot products: the same values mod
        // 2^128 as `Quadric::along` / `derivative_along` (`x^T Q d = d^T Q x`).
        let grads = GRADIENTS && self.opts.gradients;
        if self.qmask != 0 {
            let qm = quadric_matrix(m.quadric());
            let xh = [s0[0], s0[1], s0[2], 1 << 16];
            let dh = [ds[0], ds[1], ds[2], 0];
            let qx = mat_vec(&qm, self.qmask, &xh);
            let qd = mat_vec(&qm, self.qmask, &dh);
            let c1 = dot(&dh, &qx).wrapping_mul(2);
            let c2 = dot(&dh, &qd);
            // Written in place: the size-lean shape keeps its set-up's zeros where gradients
            // are off; the fast shape writes the whole quadric.
            #[cfg(not(texcore_lean))]
            let q = out.quadric.insert(ZERO_QUAD);
            #[cfg(texcore_lean)]
            let q = &mut out.quadric;
            q.quad = QuadraticSpan {
                c: [dot(&xh, &qx), c1, c2],
            };
            if grads {
                let yh = [dy[0], dy[1], dy[2], 0];
                q.gqx = [c1, c2.wrapping_mul(2)];
                q.gqy = [dot(&yh, &qx).wrapping_mul(2), dot(&yh, &qd).wrapping_mul(2)];
            }
        }
    }

    /// The terms' part of [`Self::setup`] (`out.terms`, `out.extra_width48` and the counters).
    #[inline(always)]
    fn term_setup(&mut self, span: &Span, out: &mut Setup<T>) {
        let m = self.model;
        let grads = GRADIENTS && self.opts.gradients;
        // A vector, not an array: nothing is written for the slots past the model's terms.
        let terms = &mut out.terms;
        let stats = &mut self.stats;
        // Coordinate precision (`docs/model.md` 3.2): `U0` and `DU` rounded to `F` fraction bits,
        // so `u(i) = U0 + i DU` stays linear in `i`; band-limiting uses the unrounded step.
        let cb = m.precision().coord_bits();
        let mut each =
            |term: &NoiseTerm, du: &[i32; 3], dyl: &[i32; 3], band: Option<(i32, bool)>| {
                let Some((amp, gradient)) = band else {
                    stats.culled_octaves += 1;
                    // At most T terms: never full.
                    let _ = terms.push(TermSetup::default());
                    return;
                };
                if amp != term.amplitude.to_bits() {
                    stats.faded_octaves += 1;
                }
                let mut u0 = term.transform.apply_point(span.s0);
                let mut du = *du;
                if cb < 16 {
                    u0 = u0.map(|c| quantize_coord(c, cb));
                    du = du.map(|c| quantize_coord(c, cb));
                }
                let _ = terms.push(TermSetup {
                    u0,
                    du,
                    dy: *dyl,
                    active: true,
                    gradient: grads && gradient,
                    amp,
                });
            };
        out.extra_width48 = band_terms(m, span, self.opts.band(), each_term(&mut each));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bandlimit::spread_width48;
    use crate::model::Precision;

    /// The set-up is its definition, term by term: `U0 = round(M s0 + t)` and `DU = round(M ds)`
    /// at the model's coordinate precision, `dy = round(M dsdy)`, the band decision and spread
    /// of [`crate::bandlimit`] from the unrounded steps, and the quadric of
    /// `Quadric::along` / `Quadric::derivative_along`, for spans of every size of step (plain,
    /// faded and culled octaves), with and without gradients and band-limiting.
    #[test]
    fn setup_is_its_definition() {
        let coarse = Precision::new(9, 16).unwrap();
        let mut rng = crate::test_rng::XorShift64::new(0x9E37_79B9_7F4A_7C15);
        let mut next = move |bits: u32| ((rng.next_u64() >> 16) as i32) >> (32 - bits);
        for model in [
            super::super::tests::marble(),
            super::super::tests::marble().with_precision(coarse),
        ] {
            let cb = model.precision().coord_bits();
            for (gradients, cull) in [(true, true), (false, true), (true, false)] {
                let opts = EvalOptions {
                    mode: EvalMode::Fd,
                    gradients,
                    cull,
                    ..Default::default()
                };
                let mut core = EvalCore::new(&model, opts);
                for case in 0..300 {
                    let step_bits = 8 + (case % 12) as u32;
                    let span = Span {
                        s0: TexPoint::from_bits(next(31), next(31), next(24)),
                        ds: TexPoint::from_bits(next(step_bits), next(step_bits), next(step_bits)),
                        dsdy: TexPoint::from_bits(next(step_bits), next(step_bits), 0),
                        len: 16,
                    };
                    let mut setup = Setup::empty();
                    core.setup(&span, &mut setup);
                    let mut variance = 0u64;
                    for (term, ts) in model.terms().iter().zip(&setup.terms) {
                        let du = term.transform.apply_vector(span.ds);
                        let dy = term.transform.apply_vector(span.dsdy);
                        let band = term_band(term, du, dy, opts.band());
                        variance = variance.saturating_add(band.variance);
                        assert_eq!(ts.active, band.active, "case {case}");
                        if !band.active {
                            continue;
                        }
                        let q = |u: [i32; 3]| {
                            u.map(|c| if cb < 16 { quantize_coord(c, cb) } else { c })
                        };
                        assert_eq!(ts.u0, q(term.transform.apply_point(span.s0)), "case {case}");
                        assert_eq!(ts.du, q(du), "case {case}");
                        assert_eq!(ts.dy, dy, "case {case}");
                        assert_eq!(ts.amp, band.amplitude, "case {case}");
                        assert_eq!(ts.gradient, GRADIENTS && gradients && band.gradient);
                    }
                    assert_eq!(setup.terms.len(), model.terms().len());
                    let want = if GRADIENTS {
                        spread_width48(variance)
                    } else {
                        0
                    };
                    assert_eq!(setup.extra_width48, want, "case {case}");
                    let (s0, ds, dsdy) = (exact(span.s0), exact(span.ds), exact(span.dsdy));
                    let quadric = model.quadric();
                    assert_eq!(
                        setup.quadric().quad.c,
                        quadric.along(s0, ds).c,
                        "case {case}"
                    );
                    if GRADIENTS && gradients {
                        assert_eq!(setup.quadric().gqx, quadric.derivative_along(s0, ds, ds));
                        assert_eq!(setup.quadric().gqy, quadric.derivative_along(s0, ds, dsdy));
                    }
                }
            }
        }
    }
}
