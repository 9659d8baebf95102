//! Spans of one plane in texture space, their terms set up once: [`SpanPlane`] and
//! [`PlaneSetup`].
//!
//! A rasteriser or a tiled fill hands a plane over in short spans (16 pixels, a tile's width):
//! span `(x, y)` starts at `s(x, y) = origin + x ds + y dsdy` and steps `ds`, every span of the
//! plane with the same `ds` and `dsdy`. [`SpanEvaluator::eval_values`] would transform each span
//! from scratch: for every term the point `M s0 + t` (nine 32 x 32-bit products), both lattice
//! steps `M ds`, `M dsdy` and the band-limiting decision. All of it but the start is the same in
//! every span of the plane, and the start is affine in `(x, y)`:
//!
//! `M s(x, y) + t = (M origin + t) + x (M ds) + y (M dsdy)`,
//!
//! an identity of integers, so it holds modulo 2^64 for the wrapping sums the set-up rounds. A
//! [`PlaneSetup`] keeps, per term, the three sums `M origin + t`, `M ds`, `M dsdy` (32 fraction
//! bits), the rounded steps and the band decision; a span's set-up is then, per term and axis,
//! two products and a rounding.
//!
//! # Guarantees
//!
//! - **Exact**: a span evaluated through a [`PlaneSetup`] has the samples, facts and counters
//!   of [`SpanPlane::span`] evaluated directly, bit for bit, in every mode (the quadric is set
//!   up per span as before). [`SpanPlane::new`] checks that every span start of the plane is a
//!   [`TexPoint`] without wrapping, which is what makes the identity above the set-up's own sum.
//! - A [`PlaneSetup`] made by another evaluator's model or band-limiting setting is not used:
//!   such a span is set up from scratch (the same samples, the saving lost).
//! - Capacity in the type: a [`PlaneSetup<'_, T>`] holds `T` terms (about 100 bytes each), on
//!   the caller's stack; no allocation, never panics.

// The size-lean shape sets every span up from scratch: the plane's set-up is built but unused.
#![cfg_attr(texcore_lean, allow(dead_code))]

use super::*;
use crate::format::round_32_to_16;

/// A rectangle of spans on a plane in texture space: span `(x, y)` of length `len` starts at
/// `origin + x ds + y dsdy` and steps `ds` a pixel (`dsdy` is its second screen direction), for
/// `x + len <= width` and `y < height`.
///
/// Checked at construction ([`SpanPlane::new`]): every such start is representable (raw 16.16
/// without wrapping), so [`SpanPlane::span`] never fails for spans inside the rectangle.
///
/// A 64 x 32 field of four octaves of value noise in 16-pixel spans, the terms set up once:
///
/// ```
/// use texcore::format::{Amplitude, MatrixEntry, TexPoint, TexValue};
/// use texcore::hash::HashKind;
/// use texcore::model::{Octaves, TextureModel};
/// use texcore::noise::NoiseBasis;
/// use texcore::quadric::Quadric;
/// use texcore::span::{EvalOptions, FaceCache, SpanEvaluator, SpanPlane};
/// use texcore::table::TableWrap;
/// use texcore::transform::Affine3;
///
/// let mut model: TextureModel<4> = TextureModel::new(Quadric::ZERO, TableWrap::Mod);
/// model.push_octaves(&Octaves {
///     count: 4,
///     base: Affine3::scale(MatrixEntry::ONE),
///     amplitude: Amplitude::ONE,
///     rotate: false,
///     basis: NoiseBasis::trilinear(HashKind::Integer),
///     turbulence: false,
/// })?;
/// let opts = EvalOptions { gradients: false, ..Default::default() };
/// let mut ev = SpanEvaluator::new(&model, opts);
/// let plane = SpanPlane::new(
///     TexPoint::from_f64(0.0, 0.0, 0.5),
///     TexPoint::from_f64(1.0 / 8.0, 0.0, 0.0),
///     TexPoint::from_f64(0.0, 1.0 / 8.0, 0.0),
///     64,
///     32,
/// )?;
/// let setup = ev.plane_setup(&plane);
/// let mut faces = FaceCache::<64>::new();
/// let mut field = [[TexValue::ZERO; 64]; 32];
/// for (y, row) in (0u16..).zip(field.iter_mut()) {
///     for (x, tile) in (0u16..).step_by(16).zip(row.chunks_mut(16)) {
///         ev.eval_plane_values(&setup, x, y, tile, &mut faces);
///     }
/// }
/// // The same values as each span set up on its own.
/// let mut tile = [TexValue::ZERO; 16];
/// let span = plane.span(16, 5, 16).unwrap();
/// SpanEvaluator::new(&model, opts).eval_values(&span, &mut tile);
/// assert_eq!(tile, field[5][16..32]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SpanPlane {
    origin: TexPoint,
    ds: TexPoint,
    dsdy: TexPoint,
    width: u16,
    height: u16,
}

/// Why [`SpanPlane::new`] refused a plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SpanPlaneError {
    /// The start of some span inside the rectangle leaves the range of [`TexPoint`] along this
    /// axis (0: `s`, 1: `t`, 2: `r`).
    OutOfRange {
        /// The axis.
        axis: u8,
    },
}

impl core::fmt::Display for SpanPlaneError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SpanPlaneError::OutOfRange { axis } => write!(
                f,
                "span plane: a span start leaves the texture-coordinate range along axis {}",
                ["s", "t", "r"][usize::from(*axis).min(2)]
            ),
        }
    }
}

impl core::error::Error for SpanPlaneError {}

impl SpanPlane {
    /// The plane through `origin` with steps `ds` (along a span) and `dsdy` (to the next row),
    /// spans inside `width x height` pixels; an error when a span start inside the rectangle
    /// (`x <= width`, `y < height`) would leave the raw 16.16 range.
    pub fn new(
        origin: TexPoint,
        ds: TexPoint,
        dsdy: TexPoint,
        width: u16,
        height: u16,
    ) -> Result<SpanPlane, SpanPlaneError> {
        let (o, d, e) = (origin.to_bits(), ds.to_bits(), dsdy.to_bits());
        let (w, h) = (i64::from(width), i64::from(height.saturating_sub(1)));
        for (axis, ((&o, &d), &e)) in o.iter().zip(&d).zip(&e).enumerate() {
            let (o, d, e) = (i64::from(o), i64::from(d), i64::from(e));
            // Affine in (x, y): the extremes are at the rectangle's corners.
            let lo = o + (w * d).min(0) + (h * e).min(0);
            let hi = o + (w * d).max(0) + (h * e).max(0);
            if lo < i64::from(i32::MIN) || hi > i64::from(i32::MAX) {
                return Err(SpanPlaneError::OutOfRange { axis: axis as u8 });
            }
        }
        Ok(SpanPlane {
            origin,
            ds,
            dsdy,
            width,
            height,
        })
    }

    /// Whether the span of `len` pixels at `(x, y)` lies inside the rectangle: `x + len <= width`
    /// and `y < height`.
    pub fn contains(&self, x: u16, y: u16, len: u16) -> bool {
        u32::from(x) + u32::from(len) <= u32::from(self.width) && y < self.height
    }

    /// The span of `len` pixels at `(x, y)`; `None` unless [`SpanPlane::contains`] it.
    pub fn span(&self, x: u16, y: u16, len: u16) -> Option<Span> {
        if !self.contains(x, y, len) {
            return None;
        }
        let (o, d, e) = (
            self.origin.to_bits(),
            self.ds.to_bits(),
            self.dsdy.to_bits(),
        );
        let (x, y) = (i64::from(x), i64::from(y));
        let mut s0 = [0i32; 3];
        for (((s, &o), &d), &e) in s0.iter_mut().zip(&o).zip(&d).zip(&e) {
            // In range: checked by `new` for every such (x, y).
            *s = (i64::from(o) + x * i64::from(d) + y * i64::from(e)) as i32;
        }
        let [s, t, r] = s0;
        Some(Span {
            s0: TexPoint::from_bits(s, t, r),
            ds: self.ds,
            dsdy: self.dsdy,
            len,
        })
    }

    /// Width of the rectangle, in pixels.
    pub fn width(&self) -> u16 {
        self.width
    }

    /// Height of the rectangle, in rows.
    pub fn height(&self) -> u16 {
        self.height
    }
}

/// One term of a [`PlaneSetup`].
#[derive(Clone, Copy, Debug, Default)]
struct PlaneTerm {
    /// `M origin + t`, `M ds`, `M dsdy` per axis (32 fraction bits, wrapping).
    at0: [i64; 3],
    along: [i64; 3],
    down: [i64; 3],
    /// The span set-up of the term but its start `u0` (zero): the steps (`du` rounded to the
    /// coordinate precision, `dy` unrounded) and the band decision (`gradient` before the
    /// evaluator's option; the default, inactive set-up for a culled term).
    setup: TermSetup,
}

/// The terms of a model set up once for every span of a [`SpanPlane`] (see the module
/// documentation), for the evaluator that made it ([`SpanEvaluator::plane_setup`]).
#[derive(Clone, Debug)]
pub struct PlaneSetup<'m, const T: usize> {
    plane: SpanPlane,
    model: &'m TextureModel<T>,
    band: Option<BandLimit>,
    terms: heapless::Vec<PlaneTerm, T>,
    extra_width48: i64,
    /// Terms culled and faded in every span of the plane (the span counters).
    culled: u8,
    faded: u8,
    /// The quadric along span `(x, y)` as polynomials in `x` and `y` (`None`: a zero quadric).
    quad: Option<PlaneQuad>,
}

/// The quadric's set-up along the spans of a plane: with `h(x, y) = o + x d + y e` a span's
/// homogeneous start (`o` the origin with weight `2^16`, `d = ds` and `e = dsdy` with weight 0),
/// the set-up's dot products `h.Qh`, `d.Qh`, `e.Qh` are polynomials in `x` and `y` whose
/// coefficients are dot products of `o`, `d`, `e` (exact identities of integers, so the
/// wrapping values modulo 2^128 are the set-up's own).
#[derive(Clone, Copy, Debug)]
struct PlaneQuad {
    /// `h.Qh`: the coefficients of `1, x, y, x^2, xy, y^2`.
    hqh: [i128; 6],
    /// `d.Qh` and `e.Qh`: the coefficients of `1, x, y` (`d.Qh`'s of `x` is `d.Qd`).
    dqh: [i128; 3],
    eqh: [i128; 3],
}

impl PlaneQuad {
    /// The quadric of `plane` under the quadric matrix `qm` with nonzero entries `mask` (out of
    /// line, once a plane).
    #[inline(never)]
    fn new(qm: &[[i32; 4]; 4], mask: u16, plane: &SpanPlane) -> PlaneQuad {
        let (o, d, e) = (exact(plane.origin), exact(plane.ds), exact(plane.dsdy));
        let oh = [o[0], o[1], o[2], 1 << 16];
        let dh = [d[0], d[1], d[2], 0];
        let eh = [e[0], e[1], e[2], 0];
        let (qo, qd, qe) = (
            mat_vec(qm, mask, &oh),
            mat_vec(qm, mask, &dh),
            mat_vec(qm, mask, &eh),
        );
        PlaneQuad {
            hqh: [
                dot(&oh, &qo),
                dot(&dh, &qo).wrapping_add(dot(&oh, &qd)),
                dot(&eh, &qo).wrapping_add(dot(&oh, &qe)),
                dot(&dh, &qd),
                dot(&dh, &qe).wrapping_add(dot(&eh, &qd)),
                dot(&eh, &qe),
            ],
            dqh: [dot(&dh, &qo), dot(&dh, &qd), dot(&dh, &qe)],
            eqh: [dot(&eh, &qo), dot(&eh, &qd), dot(&eh, &qe)],
        }
    }
}

/// `c k`, wrapping.
#[inline(always)]
fn mul_u32(c: i128, k: u32) -> i128 {
    c.wrapping_mul(i128::from(k))
}

/// `c[0] + c[1] x + c[2] y`, wrapping.
#[inline(always)]
fn linear(c: &[i128; 3], x: u32, y: u32) -> i128 {
    c[0].wrapping_add(mul_u32(c[1], x))
        .wrapping_add(mul_u32(c[2], y))
}

impl<const T: usize> PlaneSetup<'_, T> {
    /// The plane.
    pub fn plane(&self) -> &SpanPlane {
        &self.plane
    }

    /// Whether `core` takes its spans' set-up from this plane (its model and band-limiting
    /// setting: `plane_setup_of`'s test).
    pub(super) fn serves(&self, core: &EvalCore<'_, T>) -> bool {
        core::ptr::eq(self.model, core.model) && self.band.as_ref() == core.opts.band()
    }

    /// Whether every active term's step along a span is a whole number of the lattice's raw
    /// 16.16 units (`M ds` has no bits below the rounding): then the set-up of span `(x, y)`
    /// is that of span `(0, y)` moved on by `x` pixels (`u0 + x du`, wrapping), for every `x`.
    pub(super) fn whole_steps(&self) -> bool {
        self.terms
            .iter()
            .all(|t| !t.setup.active || t.along.iter().all(|a| a & 0xFFFF == 0))
    }

    /// The band-limiting counters of every span of the plane (terms culled, faded) and its
    /// extra filter width.
    pub(super) fn span_facts(&self) -> (u8, u8, i64) {
        (self.culled, self.faded, self.extra_width48)
    }
}

impl<'m, const T: usize> SpanEvaluator<'m, T> {
    /// The terms of this evaluator's model set up for every span of `plane` (see
    /// [`PlaneSetup`]).
    pub fn plane_setup(&self, plane: &SpanPlane) -> PlaneSetup<'m, T> {
        let m = self.core.model;
        // The span set-up of the plane's origin gives every term's steps and band decision
        // (the same for every span of the plane), its gradient flag taken before the
        // evaluator's option (a core of its own, with gradients on, counts the culled and
        // faded terms).
        let opts = EvalOptions {
            gradients: true,
            ..self.core.opts
        };
        let mut core = EvalCore::new(m, opts);
        let span = Span {
            s0: plane.origin,
            ds: plane.ds,
            dsdy: plane.dsdy,
            len: 0,
        };
        let mut setup = Setup::empty();
        core.setup(&span, &mut setup);
        let mut terms = heapless::Vec::new();
        for (term, ts) in m.terms().iter().zip(setup.terms.iter()) {
            let tr = &term.transform;
            // At most T terms: never full.
            let _ = terms.push(PlaneTerm {
                at0: tr.point_sums(plane.origin),
                along: tr.vector_sums(plane.ds),
                down: tr.vector_sums(plane.dsdy),
                setup: TermSetup { u0: [0; 3], ..*ts },
            });
        }
        let quad = (core.qmask != 0)
            .then(|| PlaneQuad::new(&quadric_matrix(m.quadric()), core.qmask, plane));
        // At most T <= 255 terms in a model.
        let count = |n: u64| n.min(255) as u8;
        PlaneSetup {
            plane: *plane,
            model: m,
            band: opts.band().copied(),
            terms,
            extra_width48: setup.extra_width48,
            culled: count(core.stats.culled_octaves),
            faded: count(core.stats.faded_octaves),
            quad,
        }
    }

    /// [`SpanEvaluator::eval_values_cached`] of the span of `out.len()` pixels at `(x, y)` of
    /// `plane`'s [`SpanPlane`], its terms' set-up taken from `plane`: the same values, facts and
    /// counters (through the same cache), bit for bit. Nothing is evaluated (and the default
    /// facts are returned) when the span is not inside the plane's rectangle or is longer than
    /// `u16::MAX`.
    pub fn eval_plane_values<const N: usize, const L: usize>(
        &mut self,
        plane: &PlaneSetup<'_, T>,
        x: u16,
        y: u16,
        out: &mut [TexValue],
        faces: &mut FaceCache<N, L>,
    ) -> SpanInfo {
        let Ok(len) = u16::try_from(out.len()) else {
            return SpanInfo::default();
        };
        let Some(span) = plane.plane.span(x, y, len) else {
            return SpanInfo::default();
        };
        let grads = self.core.opts.gradients;
        self.core.opts.gradients = false;
        let from = SetupFrom::Plane(plane, x, y);
        let info = self
            .core
            .eval_values_from(&span, from, out, &mut faces.parts());
        self.core.opts.gradients = grads;
        info
    }

    /// [`SpanEvaluator::eval_chunks`] of the span of `len` pixels at `(x, y)` of `plane`'s
    /// [`SpanPlane`], its terms' set-up taken from `plane`: the same samples, facts and
    /// counters, bit for bit. Nothing is evaluated (and the default facts are returned) when the
    /// span is not inside the plane's rectangle.
    pub fn eval_plane_chunks(
        &mut self,
        plane: &PlaneSetup<'_, T>,
        x: u16,
        y: u16,
        len: u16,
        out: &mut dyn FnMut(&SampleChunk),
    ) -> SpanInfo {
        let Some(span) = plane.plane.span(x, y, len) else {
            return SpanInfo::default();
        };
        self.eval_chunks_from(&span, SetupFrom::Plane(plane, x, y), out)
    }
}

/// Where a span's set-up comes from: the span itself, or a [`PlaneSetup`] and the span's
/// pixel `(x, y)` on its plane.
#[derive(Clone, Copy)]
pub(crate) enum SetupFrom<'p, 'q, const T: usize> {
    Span,
    Plane(&'p PlaneSetup<'q, T>, u16, u16),
}

impl<'m, const T: usize> EvalCore<'m, T> {
    /// The set-up of `span` (empty `out`, as [`Setup::empty`]) from `from`: the plane's terms
    /// when `from` is a plane set up for this evaluator, otherwise [`Self::setup`]. The
    /// size-lean shape sets every span up from scratch (the same set-up; no plane code linked).
    #[inline(always)]
    pub(super) fn setup_from(
        &mut self,
        span: &Span,
        from: SetupFrom<'_, '_, T>,
        out: &mut Setup<T>,
    ) {
        #[cfg(not(texcore_lean))]
        if let SetupFrom::Plane(p, x, y) = from {
            return self.plane_setup_of(span, p, x, y, out);
        }
        #[cfg(texcore_lean)]
        let _ = from;
        self.setup(span, out)
    }

    /// [`Self::setup_from`] a plane (out of line: one copy for every caller).
    #[inline(never)]
    fn plane_setup_of(
        &mut self,
        span: &Span,
        p: &PlaneSetup<'_, T>,
        x: u16,
        y: u16,
        out: &mut Setup<T>,
    ) {
        if p.serves(self) {
            if let Some(pq) = &p.quad {
                self.plane_quadric(pq, x, y, out);
            }
            self.plane_terms(p, x, y, out);
        } else {
            self.setup(span, out);
        }
    }

    /// The quadric's set-up of span `(x, y)` of a plane (as `quadric_setup` of that span).
    #[inline(always)]
    fn plane_quadric(&mut self, pq: &PlaneQuad, x: u16, y: u16, out: &mut Setup<T>) {
        let grads = GRADIENTS && self.opts.gradients;
        let (x, y) = (u32::from(x), u32::from(y));
        let k = &pq.hqh;
        let c0 = linear(&[k[0], k[1], k[2]], x, y)
            .wrapping_add(mul_u32(k[3], x * x))
            .wrapping_add(mul_u32(k[4], x * y))
            .wrapping_add(mul_u32(k[5], y * y));
        let c1 = linear(&pq.dqh, x, y).wrapping_mul(2);
        let c2 = pq.dqh[1];
        let (gqx, gqy) = if grads {
            (
                [c1, c2.wrapping_mul(2)],
                [
                    linear(&pq.eqh, x, y).wrapping_mul(2),
                    pq.eqh[1].wrapping_mul(2),
                ],
            )
        } else {
            ([0; 2], [0; 2])
        };
        // Written whole (not a zero quadric written and then overwritten: a 120-byte clear a
        // span).
        let q = QuadSetup {
            quad: QuadraticSpan { c: [c0, c1, c2] },
            gqx,
            gqy,
        };
        #[cfg(not(texcore_lean))]
        {
            out.quadric = Some(q);
        }
        #[cfg(texcore_lean)]
        {
            out.quadric = q;
        }
    }

    /// The terms' set-up of span `(x, y)` of `p` (as `term_setup` of that span).
    #[inline(always)]
    fn plane_terms(&mut self, p: &PlaneSetup<'_, T>, x: u16, y: u16, out: &mut Setup<T>) {
        let grads = GRADIENTS && self.opts.gradients;
        let cb = self.model.precision().coord_bits();
        let (x, y) = (i64::from(x), i64::from(y));
        self.stats.culled_octaves += u64::from(p.culled);
        self.stats.faded_octaves += u64::from(p.faded);
        for t in p.terms.iter() {
            let mut ts = t.setup;
            if ts.active {
                for (((u, &a0), &al), &dn) in
                    ts.u0.iter_mut().zip(&t.at0).zip(&t.along).zip(&t.down)
                {
                    let s = a0
                        .wrapping_add(al.wrapping_mul(x))
                        .wrapping_add(dn.wrapping_mul(y));
                    *u = round_32_to_16(s) as i32;
                }
                if cb < 16 {
                    ts.u0 = ts.u0.map(|c| quantize_coord(c, cb));
                }
                ts.gradient &= grads;
            }
            // At most T terms: never full.
            let _ = out.terms.push(ts);
        }
        out.extra_width48 = p.extra_width48;
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::format::{Amplitude, MatrixEntry};
    use crate::model::{Octaves, Precision};
    use crate::noise::NoiseBasis;
    use crate::quadric::Quadric;
    use crate::table::TableWrap;
    use crate::transform::Affine3;

    use crate::test_rng::xorshift64 as xorshift;

    /// Models that take every kind of set-up: rotated octaves with a curved quadric (the
    /// general loop), axis-aligned octaves without a quadric (the lane kernel), coarse
    /// coordinates, and a far-off affine part.
    fn models() -> Vec<TextureModel<8>> {
        let octaves = |rotate, base| Octaves {
            count: 4,
            base,
            amplitude: Amplitude::ONE,
            rotate,
            basis: NoiseBasis::trilinear(HashKind::Integer),
            turbulence: false,
        };
        let curved =
            Quadric::from_f64([0.5, -0.25, 0.0, 0.0, 0.0, 1.5, 0.0, -0.75, 0.125, 1.0]).unwrap();
        let four = Affine3::scale(MatrixEntry::from_num(4));
        let mut out = Vec::new();
        let base = TextureModel::new(curved, TableWrap::Mod);
        out.push(base.clone().with_octaves(&octaves(true, four)).unwrap());
        let flat = TextureModel::new(Quadric::ZERO, TableWrap::Mod);
        out.push(flat.clone().with_octaves(&octaves(false, four)).unwrap());
        out.push(
            flat.clone()
                .with_octaves(&octaves(false, four))
                .unwrap()
                .with_precision(Precision::new(9, 12).unwrap()),
        );
        let far = Affine3::from_f64(
            [[3.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 3.0]],
            [-3000.0, 2500.5, 17.25],
        );
        out.push(base.with_octaves(&octaves(true, far)).unwrap());
        out
    }

    /// Every option set the tests use: each mode, culling on and off, gradients on and off.
    fn options() -> Vec<EvalOptions> {
        let mut v = Vec::new();
        for mode in [EvalMode::Direct, EvalMode::Fd, EvalMode::Auto] {
            for (cull, gradients) in [(true, true), (false, true), (true, false)] {
                v.push(EvalOptions {
                    mode,
                    gradients,
                    cull,
                    ..Default::default()
                });
            }
        }
        v
    }

    /// A random plane of `w x h` pixels: steps from a thousandth to a few cells a pixel, an
    /// origin anywhere in `(-scale, scale)`.
    fn random_plane(x: &mut u64, scale: f64, w: u16, h: u16) -> SpanPlane {
        let mut f = |s: f64| (xorshift(x) % 2_000_001) as f64 / 1_000_000.0 * s - s;
        let step = |f: &mut dyn FnMut(f64) -> f64| {
            let k = [0.002, 0.03, 0.4][(f(1.0).abs() * 2.99) as usize];
            TexPoint::from_f64(f(k), f(k), f(k))
        };
        let origin = TexPoint::from_f64(f(scale), f(scale), f(scale));
        let ds = step(&mut f);
        let dsdy = step(&mut f);
        SpanPlane::new(origin, ds, dsdy, w, h).unwrap()
    }

    #[test]
    fn planes_refuse_starts_out_of_range() {
        let one = TexPoint::from_f64(1.0, 0.0, 0.0);
        let zero = TexPoint::from_f64(0.0, 0.0, 0.0);
        let near = TexPoint::from_f64(32000.0, -1.0, 0.5);
        // 32000 + 767 cells fits, 32000 + 768 does not (the range ends below 32768).
        assert!(SpanPlane::new(near, one, zero, 767, 10).is_ok());
        assert_eq!(
            SpanPlane::new(near, one, zero, 768, 10),
            Err(SpanPlaneError::OutOfRange { axis: 0 })
        );
        // Down the rows: `height - 1` rows below the origin, on the `t` axis.
        let down = TexPoint::from_f64(0.0, -1.0, 0.0);
        let low = TexPoint::from_f64(0.0, -32000.0, 0.0);
        assert!(SpanPlane::new(low, zero, down, 4, 769).is_ok());
        assert_eq!(
            SpanPlane::new(low, zero, down, 4, 770),
            Err(SpanPlaneError::OutOfRange { axis: 1 })
        );
        assert!(SpanPlaneError::OutOfRange { axis: 1 }
            .to_string()
            .contains("axis t"));
        // Empty rectangles are planes without spans.
        let p = SpanPlane::new(near, one, zero, 0, 0).unwrap();
        assert_eq!(p.span(0, 0, 0), None);
        // Spans must lie inside the rectangle; their starts are the plane's points.
        let p = SpanPlane::new(near, one, down, 100, 50).unwrap();
        assert_eq!(p.span(90, 49, 11), None);
        assert_eq!(p.span(90, 50, 1), None);
        let s = p.span(90, 49, 10).unwrap();
        assert_eq!(s.s0, TexPoint::from_f64(32090.0, -50.0, 0.5));
        assert_eq!((s.ds, s.dsdy, s.len), (one, down, 10));
        assert_eq!((p.width(), p.height()), (100, 50));
    }

    /// Every span through the plane's set-up equals the span evaluated as itself: samples,
    /// values, facts and counters, in every mode and option set, on random planes (near the
    /// origin and at huge coordinates) and spans of 1 to 40 pixels.
    #[test]
    fn plane_spans_are_their_spans() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for (mi, m) in models().iter().enumerate() {
            for opts in options() {
                for (pi, scale) in [4.0, 30000.0].into_iter().enumerate() {
                    let plane = random_plane(&mut x, scale, 300, 200);
                    let mut direct = SpanEvaluator::new(m, opts);
                    let mut planar = SpanEvaluator::new(m, opts);
                    let setup = planar.plane_setup(&plane);
                    let mut faces = FaceCache::<64>::new();
                    for _ in 0..12 {
                        let len = 1 + (xorshift(&mut x) % 40) as u16;
                        let px = (xorshift(&mut x) % u64::from(300 - len + 1)) as u16;
                        let py = (xorshift(&mut x) % 200) as u16;
                        let span = plane.span(px, py, len).unwrap();
                        let what = (mi, pi, opts, px, py, len);
                        let mut want = Vec::new();
                        let wi = direct.eval(&span, |s| want.push(s));
                        let mut got = Vec::new();
                        let gi = planar
                            .eval_plane_chunks(&setup, px, py, len, &mut |c| got.extend(c.iter()));
                        assert_eq!(got, want, "{what:?}");
                        assert_eq!(gi, wi, "{what:?}");
                        let mut wv = [TexValue::ZERO; 40];
                        let mut gv = [TexValue::ZERO; 40];
                        let n = usize::from(len);
                        direct.eval_values(&span, &mut wv[..n]);
                        planar.eval_plane_values(&setup, px, py, &mut gv[..n], &mut faces);
                        assert_eq!(gv, wv, "{what:?}");
                        assert_eq!(planar.stats(), direct.stats(), "{what:?}");
                    }
                    // Spans outside the rectangle evaluate nothing.
                    let before = *planar.stats();
                    let mut any = false;
                    planar.eval_plane_chunks(&setup, 290, 0, 11, &mut |_| any = true);
                    planar.eval_plane_values(&setup, 0, 200, &mut [TexValue::ZERO; 4], &mut faces);
                    assert!(!any);
                    assert_eq!(*planar.stats(), before);
                }
            }
        }
    }

    /// A plane set up by another model's evaluator, or under another band-limiting setting,
    /// is not used: the spans are set up from scratch (the same samples).
    #[test]
    fn a_foreign_plane_setup_is_not_used() {
        let ms = models();
        let mut x = 7u64;
        let plane = random_plane(&mut x, 10.0, 64, 64);
        let culled = EvalOptions::default();
        let unculled = EvalOptions {
            cull: false,
            ..culled
        };
        let other = SpanEvaluator::new(&ms[1], culled).plane_setup(&plane);
        let uncull = SpanEvaluator::new(&ms[0], unculled).plane_setup(&plane);
        let mut ev = SpanEvaluator::new(&ms[0], culled);
        let mut direct = SpanEvaluator::new(&ms[0], culled);
        for setup in [&other, &uncull] {
            let span = plane.span(3, 9, 30).unwrap();
            let mut want = Vec::new();
            direct.eval(&span, |s| want.push(s));
            let mut got = Vec::new();
            ev.eval_plane_chunks(setup, 3, 9, 30, &mut |c| got.extend(c.iter()));
            assert_eq!(got, want);
        }
        // A model of the same terms but another address is another model.
        let copy = ms[0].clone();
        let copied = SpanEvaluator::new(&copy, culled).plane_setup(&plane);
        assert!(!core::ptr::eq(copied.model, &ms[0]));
        assert_eq!(copied.plane(), &plane);
    }
}
