//! A configured texture: a shader (texture model or perturbed material) and a colour stage,
//! evaluated span by span into colours.
//!
//! The pipeline of a [`Texture`] is fixed when it is built, never tested per pixel:
//! - with [`Antialias::None`] the span evaluator computes no gradients (the gradient stage does not
//!   run) and colours come from the plain table look-up;
//! - otherwise the filter width `w = N * norm(gx, gy)` (with the spread of faded and culled octaves
//!   in quadrature, [`crate::bandlimit`]) feeds the
//!   colour table's box or MIP filter;
//! - a model with no noise terms runs no noise stage, a zero quadric no quadric stage (see
//!   [`crate::span`]).
//!
//! Every mode of the span evaluator gives the same samples, so [`EvalMode::Direct`] and
//! [`EvalMode::Fd`] give the same colours.

use crate::color::Rgba8888;
use crate::filter::{Antialias, ColorStage, GradientNorm, WidthStream};
use crate::format::{FilterWidth, TexValue};
#[cfg(feature = "perturb")]
use crate::material::{MaterialEvaluator, PerturbedMaterial};
use crate::model::TextureModel;
use crate::span::{
    EvalMode, EvalOptions, PlaneSetup, PlaneWalk, RowCache, SampleChunk, SetupFrom, Span,
    SpanEvaluator, SpanPlane, SpanStats, SAMPLE_CHUNK,
};

mod differences;
mod rgb565;
mod rows;
#[cfg(feature = "differences")]
pub(crate) use differences::MemoryRows;
pub(crate) use differences::SpanColor;
pub use differences::{DifferenceMemory, DifferenceRows, DifferenceSpans, TILE_ROWS};
pub use rows::TextureRows;

/// What computes `f`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Shader<const T: usize> {
    /// The quadric-plus-noise model.
    Model(TextureModel<T>),
    /// A domain-perturbed material.
    #[cfg(feature = "perturb")]
    Perturbed(PerturbedMaterial<T>),
}

/// A shader with its colour stage and evaluation options.
#[derive(Clone, Debug)]
pub struct Texture<const T: usize, const N: usize> {
    shader: Shader<T>,
    stage: ColorStage<N>,
    norm: GradientNorm,
    opts: EvalOptions,
}

/// Colour-stage counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ShadeStats {
    /// Span-evaluator counters.
    pub span: SpanStats,
    /// Filtered colour-table look-ups (box or MIP).
    pub filter_lookups: u64,
    /// Plain colour-table look-ups.
    pub plain_lookups: u64,
}

impl ShadeStats {
    /// Adds another set of counters.
    pub fn add(&mut self, o: &ShadeStats) {
        self.span.add(&o.span);
        self.filter_lookups += o.filter_lookups;
        self.plain_lookups += o.plain_lookups;
    }
}

impl<const T: usize, const N: usize> Texture<T, N> {
    /// A texture. Gradients are computed exactly when the stage filters.
    pub fn new(
        shader: Shader<T>,
        stage: ColorStage<N>,
        norm: GradientNorm,
        mode: EvalMode,
    ) -> Self {
        let gradients = stage.antialias() != Antialias::None;
        Texture {
            shader,
            stage,
            norm,
            opts: EvalOptions {
                mode,
                gradients,
                ..EvalOptions::default()
            },
        }
    }

    /// The same texture with octave culling switched on or off.
    pub fn with_culling(mut self, cull: bool) -> Self {
        self.opts.cull = cull;
        self
    }

    /// The same texture with another band-limiting setting (in force while culling is on).
    pub fn with_band_limit(mut self, band_limit: crate::bandlimit::BandLimit) -> Self {
        self.opts.band_limit = band_limit;
        self
    }

    /// The same texture with another evaluation mode.
    pub fn with_mode(mut self, mode: EvalMode) -> Self {
        self.opts.mode = mode;
        self
    }

    /// Switches the evaluation mode in place (every mode but `Fd32`/`Reanchored` gives the same
    /// colours).
    pub fn set_mode(&mut self, mode: EvalMode) {
        self.opts.mode = mode;
    }

    /// The shader.
    pub fn shader(&self) -> &Shader<T> {
        &self.shader
    }

    /// Mutable access to the shader (animation).
    pub fn shader_mut(&mut self) -> &mut Shader<T> {
        &mut self.shader
    }

    /// The colour stage.
    pub fn stage(&self) -> &ColorStage<N> {
        &self.stage
    }

    /// The gradient norm of the filter width.
    pub fn norm(&self) -> GradientNorm {
        self.norm
    }

    /// The evaluation options.
    pub fn options(&self) -> EvalOptions {
        self.opts
    }

    /// An evaluator for this texture.
    pub fn evaluator(&self) -> TextureEvaluator<'_, T, N> {
        let inner = match &self.shader {
            Shader::Model(m) => Inner::Model(SpanEvaluator::new(m, self.opts)),
            #[cfg(feature = "perturb")]
            Shader::Perturbed(p) => Inner::Perturbed(MaterialEvaluator::new(p, self.opts)),
        };
        TextureEvaluator {
            tex: self,
            inner,
            filter_lookups: 0,
            plain_lookups: 0,
        }
    }
}

#[derive(Debug)]
enum Inner<'t, const T: usize> {
    Model(SpanEvaluator<'t, T>),
    #[cfg(feature = "perturb")]
    Perturbed(MaterialEvaluator<'t, T>),
}

/// Evaluates spans of a [`Texture`] into colours.
#[derive(Debug)]
pub struct TextureEvaluator<'t, const T: usize, const N: usize> {
    tex: &'t Texture<T, N>,
    inner: Inner<'t, T>,
    filter_lookups: u64,
    plain_lookups: u64,
}

/// `log2 N` of a table size that is a power of two.
const fn log2(n: usize) -> u32 {
    usize::BITS - 1 - n.leading_zeros()
}

impl<'t, const T: usize, const N: usize> TextureEvaluator<'t, T, N> {
    /// The colour stage of the texture being evaluated.
    pub fn stage(&self) -> &ColorStage<N> {
        &self.tex.stage
    }

    /// Counters so far.
    pub fn stats(&self) -> ShadeStats {
        let span = match &self.inner {
            Inner::Model(e) => *e.stats(),
            #[cfg(feature = "perturb")]
            Inner::Perturbed(e) => e.stats(),
        };
        ShadeStats {
            span,
            filter_lookups: self.filter_lookups,
            plain_lookups: self.plain_lookups,
        }
    }

    /// Shades `span`, calling `emit` with each pixel's colour in order.
    ///
    /// The size-lean shape (`cfg(texcore_lean)`) compiles one shading pipeline for every `emit`
    /// (called through a trait object); the fast shape specialises it per `emit`.
    #[inline]
    #[cfg_attr(not(texcore_lean), allow(unused_mut))]
    pub fn shade<F: FnMut(Rgba8888)>(&mut self, span: &Span, mut emit: F) {
        #[cfg(texcore_lean)]
        self.shade_with(span, SetupFrom::Span, &mut emit as &mut dyn FnMut(Rgba8888));
        #[cfg(not(texcore_lean))]
        self.shade_with(span, SetupFrom::Span, emit);
    }

    /// [`TextureEvaluator::shade`] with `emit` as given (a trait object in the size-lean shape),
    /// the model's set-up from `from` (the fast shape; the size-lean shape sets every span up
    /// from scratch, with the same colours).
    #[cfg_attr(texcore_lean, allow(unused_variables, unused_mut))]
    fn shade_with<F: FnMut(Rgba8888), S: Source<'t, T>>(
        &mut self,
        span: &Span,
        mut from: S,
        mut emit: F,
    ) {
        let stage = &self.tex.stage;
        let n = u64::from(span.len);
        if stage.antialias() == Antialias::None {
            self.plain_lookups += n;
            #[cfg_attr(texcore_lean, allow(unused_mut))]
            let mut f = |s: crate::span::Sample| emit(stage.shade_unfiltered(s.f));
            match &mut self.inner {
                Inner::Model(e) => {
                    #[cfg(texcore_lean)]
                    e.eval(span, f);
                    #[cfg(not(texcore_lean))]
                    from.chunks(e, span, &mut |c: &SampleChunk| {
                        for s in c.iter() {
                            f(s);
                        }
                    });
                }
                #[cfg(feature = "perturb")]
                Inner::Perturbed(e) => {
                    e.eval(span, f);
                }
            }
            return;
        }
        // The ramp (feature `ramp`): its RGB565 colours from the squared gradients (no root:
        // the same level as the width's, `Ramp565::shade_l2`), widened as `ColorStage::shade`
        // widens them.
        #[cfg(feature = "ramp")]
        if stage.ramp().is_some() {
            self.ramp_with(span, from, |c: crate::color::Rgb565| emit(c.to_rgba8888()));
            return;
        }
        self.filter_lookups += n;
        let norm = self.tex.norm;
        let lg = log2(N);
        // The L2 root of each pixel starts from its neighbour's (exact for any start); the span's
        // spread (faded and culled octaves, `crate::bandlimit`) adds in quadrature.
        let mut widths = WidthStream::new(norm, lg);
        match &mut self.inner {
            Inner::Model(e) => {
                // The model's samples arrive by component, a chunk at a time: widths for the
                // chunk, then its colours with the filter chosen once. Each chunk carries its
                // span's culled width (the span's set-up computed it once).
                let mut w = [FilterWidth::ZERO; SAMPLE_CHUNK];
                let mut each = |c: &SampleChunk| {
                    shade_chunk(stage, &mut widths, &mut w, c, &mut emit);
                };
                #[cfg(texcore_lean)]
                e.eval_chunks(span, &mut each);
                #[cfg(not(texcore_lean))]
                from.chunks(e, span, &mut each);
            }
            #[cfg(feature = "perturb")]
            Inner::Perturbed(e) => {
                let extra = e.extra_width48(span);
                e.eval(span, |s| {
                    emit(stage.shade(s.f, widths.width_with(s.gx, s.gy, extra)));
                });
            }
        }
    }
}

impl<'t, const T: usize, const N: usize> TextureEvaluator<'t, T, N> {
    /// The terms of the texture's model set up once for every span of `plane`
    /// ([`PlaneSetup`]), for [`TextureEvaluator::shade_plane`]; `None` for a perturbed material
    /// (whose spans [`TextureEvaluator::shade`] sets up).
    pub fn plane_setup(&self, plane: &SpanPlane) -> Option<PlaneSetup<'t, T>> {
        match &self.inner {
            Inner::Model(e) => Some(e.plane_setup(plane)),
            #[cfg(feature = "perturb")]
            Inner::Perturbed(_) => None,
        }
    }

    /// The spans of `plane` (made by [`TextureEvaluator::plane_setup`]) shaded from its rows'
    /// cell schedule in `cache` ([`TextureSpans`]; [`PlaneSpans`](crate::span::PlaneSpans) for
    /// the schedule): [`TextureEvaluator::shade_plane`]'s colours, span by span.
    pub fn plane_spans<'e, 'c, const R: usize, const W: usize>(
        &'e mut self,
        plane: &'c PlaneSetup<'t, T>,
        cache: &'c mut RowCache<R, W>,
    ) -> TextureSpans<'e, 't, 'c, T, N> {
        TextureSpans {
            ev: self,
            walk: PlaneWalk::new(plane, cache),
        }
    }

    /// [`TextureEvaluator::shade`] of the span of `len` pixels at `(x, y)` of `plane`'s
    /// [`SpanPlane`], its terms' set-up taken from `plane`: the same colours and counters, bit
    /// for bit (a perturbed material, or a `plane` set up by another texture, shades the span as
    /// `shade` does). Nothing is shaded when the span is not inside the plane's rectangle.
    #[cfg_attr(
        not(feature = "perturb"),
        allow(unused_variables, clippy::infallible_destructuring_match)
    )]
    pub fn shade_plane<F: FnMut(Rgba8888)>(
        &mut self,
        plane: &PlaneSetup<'_, T>,
        x: u16,
        y: u16,
        len: u16,
        emit: F,
    ) {
        let Some(span) = plane.plane().span(x, y, len) else {
            return;
        };
        // The fast shape takes the plane's set-up (a perturbed material's spans, and spans of a
        // plane set up for another texture, are set up from scratch); the size-lean shape sets
        // every span up from scratch. The same colours either way.
        #[cfg(texcore_lean)]
        self.shade(&span, emit);
        #[cfg(not(texcore_lean))]
        self.shade_with(&span, SetupFrom::Plane(plane, x, y), emit);
    }
}

/// Where a shaded span's samples come from: the span evaluator from a set-up ([`SetupFrom`]),
/// or the walk of a plane's rows ([`TextureSpans`]) at pixel `(x, y)`. A type per source, so
/// that the shading of spans from set-ups links no walk.
#[cfg_attr(texcore_lean, allow(dead_code))]
trait Source<'m, const T: usize> {
    /// The samples of `span` by `e` into `out`, in chunks.
    fn chunks(
        &mut self,
        e: &mut SpanEvaluator<'m, T>,
        span: &Span,
        out: &mut dyn FnMut(&SampleChunk),
    );
}

impl<'m, const T: usize> Source<'m, T> for SetupFrom<'_, '_, T> {
    #[inline(always)]
    fn chunks(
        &mut self,
        e: &mut SpanEvaluator<'m, T>,
        span: &Span,
        out: &mut dyn FnMut(&SampleChunk),
    ) {
        #[cfg(texcore_lean)]
        e.eval_chunks(span, out);
        #[cfg(not(texcore_lean))]
        e.eval_chunks_from(span, *self, out);
    }
}

/// A plane's walk at pixel `(x, y)`.
#[cfg_attr(texcore_lean, allow(dead_code))]
struct Walk<'a, 'c, 'm, const T: usize>(&'a mut PlaneWalk<'c, 'm, T>, u16, u16);

impl<'m, const T: usize> Source<'m, T> for Walk<'_, '_, 'm, T> {
    #[inline(always)]
    fn chunks(
        &mut self,
        e: &mut SpanEvaluator<'m, T>,
        span: &Span,
        out: &mut dyn FnMut(&SampleChunk),
    ) {
        self.0.chunks(e, self.1, self.2, span.len, out);
    }
}

/// The spans of one plane shaded from its rows' cell schedule, as [`PlaneSpans`] evaluates
/// them: made by [`TextureEvaluator::plane_spans`]. Each span's colours and counters are those
/// of [`TextureEvaluator::shade_plane`] of the same span, bit for bit (see [`PlaneSpans`] for
/// the counters of the spans walked); a perturbed material shades each span as `shade` does.
///
/// [`PlaneSpans`]: crate::span::PlaneSpans
#[derive(Debug)]
pub struct TextureSpans<'e, 't, 'c, const T: usize, const N: usize> {
    ev: &'e mut TextureEvaluator<'t, T, N>,
    walk: PlaneWalk<'c, 't, T>,
}

impl<const T: usize, const N: usize> TextureSpans<'_, '_, '_, T, N> {
    /// The evaluator's counters so far.
    pub fn stats(&self) -> ShadeStats {
        self.ev.stats()
    }

    /// Shades the span of `len` pixels at `(x, y)` of the plane, calling `emit` with each
    /// pixel's colour in order: [`TextureEvaluator::shade_plane`]'s colours. Nothing is shaded
    /// when the span is not inside the plane's rectangle.
    pub fn shade<F: FnMut(Rgba8888)>(&mut self, x: u16, y: u16, len: u16, emit: F) {
        let Some(span) = self.walk.plane().plane().span(x, y, len) else {
            return;
        };
        #[cfg(texcore_lean)]
        self.ev.shade(&span, emit);
        #[cfg(not(texcore_lean))]
        self.ev.shade_with(&span, Walk(&mut self.walk, x, y), emit);
    }
}

impl<'t, const T: usize, const N: usize> TextureSpans<'_, 't, '_, T, N> {
    /// The plane whose spans are shaded.
    pub(super) fn span_plane(&self) -> SpanPlane {
        *self.walk.plane().plane()
    }

    /// Counts a span's `n` pixels as filtered or plain look-ups (spans shaded elsewhere from
    /// [`TextureSpans::values`]).
    pub(super) fn count(&mut self, filtered: bool, n: u16) {
        self.ev.count_lookups(filtered, u64::from(n));
    }

    /// The values of the span of `out.len()` pixels at `(x, y)` of the plane into `out` (from
    /// the rows' schedule, as [`crate::span::PlaneSpans::values`]): the span's spread.
    pub(super) fn values(&mut self, x: u16, y: u16, out: &mut [TexValue]) -> i64 {
        match &mut self.ev.inner {
            Inner::Model(e) => self.walk.values(e, x, y, out).extra_width48,
            #[cfg(feature = "perturb")]
            Inner::Perturbed(_) => {
                let len = u16::try_from(out.len()).unwrap_or(0);
                match self.span_plane().span(x, y, len) {
                    Some(span) => self.span_values(&span, out),
                    None => 0,
                }
            }
        }
    }

    /// The values of `span` (any span) into `out`, as
    /// [`crate::span::SpanEvaluator::eval_values`] gives them: the span's spread.
    pub(super) fn span_values(&mut self, span: &Span, out: &mut [TexValue]) -> i64 {
        self.ev
            .values_into(span, out, &mut crate::span::Faces::none())
    }
}

impl<const T: usize, const N: usize> TextureEvaluator<'_, T, N> {
    /// Counts `n` pixels shaded from their values as filtered or plain look-ups.
    pub(super) fn count_lookups(&mut self, filtered: bool, n: u64) {
        if filtered {
            self.filter_lookups += n;
        } else {
            self.plain_lookups += n;
        }
    }

    /// The values of `span` into `out`, as [`crate::span::SpanEvaluator::eval_values`] gives
    /// them (through the face cache parts `faces`, the same values): the span's spread.
    pub(super) fn values_into(
        &mut self,
        span: &Span,
        out: &mut [TexValue],
        faces: &mut crate::span::Faces<'_>,
    ) -> i64 {
        match &mut self.inner {
            Inner::Model(e) => e.values_through(span, out, faces).extra_width48,
            #[cfg(feature = "perturb")]
            Inner::Perturbed(e) => e.eval_values(span, out).extra_width48,
        }
    }
}

/// The colours of a chunk of samples with gradients: each pixel's filter width (the chunk's
/// culled width in quadrature) into `w` (scratch kept across a span's chunks, so that it is not
/// cleared for each), then the colours with the filter chosen once.
#[inline(always)]
fn shade_chunk<const N: usize, F: FnMut(Rgba8888)>(
    stage: &ColorStage<N>,
    widths: &mut WidthStream,
    w: &mut [FilterWidth; SAMPLE_CHUNK],
    c: &SampleChunk,
    emit: &mut F,
) {
    let extra = c.extra_width48();
    for ((w, &gx), &gy) in w.iter_mut().zip(c.gx()).zip(c.gy()) {
        *w = widths.width_with(gx, gy, extra);
    }
    stage.shade_each(c.f(), &w[..], emit);
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::format::TexPoint;
    use crate::hash::HashKind;
    use crate::table::TableLookup;

    /// The marble preset's colour table with filter `aa`.
    fn stage(aa: Antialias) -> ColorStage<256> {
        crate::ready::Material::preset_with_hash(
            crate::ready::PresetName::Marble,
            HashKind::Integer,
        )
        .stage(aa, TableLookup::Nearest)
        .unwrap()
    }

    /// Shades `span` through both shapes of the pipeline (`emit` as given and as a trait object,
    /// the size-lean shape's) and through [`TextureEvaluator::shade`]; all must agree.
    fn shade_both_shapes(tex: &Texture<8, 256>, span: &Span) -> Vec<Rgba8888> {
        let mut direct = Vec::new();
        tex.evaluator()
            .shade_with(span, SetupFrom::Span, |c| direct.push(c));
        let mut dynamic = Vec::new();
        let emit: &mut dyn FnMut(Rgba8888) = &mut |c| dynamic.push(c);
        tex.evaluator().shade_with(span, SetupFrom::Span, emit);
        let mut public = Vec::new();
        tex.evaluator().shade(span, |c| public.push(c));
        assert_eq!(direct, dynamic);
        assert_eq!(direct, public);
        direct
    }

    // The shaders grow with the features.
    #[allow(clippy::vec_init_then_push)]
    #[test]
    fn both_shapes_shade_alike() {
        let span = Span {
            s0: TexPoint::from_f64(0.3, -0.2, 0.9),
            ds: TexPoint::from_f64(0.004, 0.001, -0.002),
            dsdy: TexPoint::from_f64(0.0, 0.004, 0.0),
            len: 150,
        };
        let mut shaders = Vec::new();
        shaders.push(Shader::Model(
            crate::presets::marble(HashKind::Integer).model,
        ));
        #[cfg(feature = "perturb")]
        for p in [
            crate::presets::mn_marble(HashKind::Integer),
            crate::presets::mn_wood(HashKind::Integer),
        ] {
            let m = PerturbedMaterial::<8>::new(&p, crate::table::TableWrap::Mod).unwrap();
            shaders.push(Shader::Perturbed(m));
        }
        let filters = [
            Antialias::None,
            Antialias::Mip,
            Antialias::Csat,
            Antialias::Csat3,
        ];
        for shader in &shaders {
            for aa in filters.into_iter().filter(|a| a.is_available()) {
                let tex = Texture::new(shader.clone(), stage(aa), GradientNorm::L2, EvalMode::Auto);
                let c = shade_both_shapes(&tex, &span);
                assert_eq!(c.len(), 150);
            }
        }
    }

    /// With the ramp, `shade` (its colours from the squared gradients, no root) is the stage's
    /// colour at the stream's width of each sample, pixel by pixel, for both wraps and norms,
    /// models and perturbed materials, short and long spans.
    #[cfg(feature = "ramp")]
    #[test]
    fn the_ramp_shades_as_the_stage_at_each_width() {
        let ramps: Vec<_> = zebra_textures(EvalMode::Auto)
            .into_iter()
            .filter(|t| t.stage().antialias() == Antialias::Ramp)
            .collect();
        assert!(ramps.len() >= 4);
        for tex in &ramps {
            for len in [1u16, 5, 150] {
                let span = Span {
                    s0: TexPoint::from_f64(0.3, -0.2, 0.9),
                    ds: TexPoint::from_f64(0.004, 0.001, -0.002),
                    dsdy: TexPoint::from_f64(0.0, 0.004, 0.0),
                    len,
                };
                let mut want = Vec::new();
                let mut widths = WidthStream::new(tex.norm(), log2(256));
                let opts = EvalOptions {
                    gradients: true,
                    ..tex.options()
                };
                match tex.shader() {
                    Shader::Model(m) => {
                        let mut e = SpanEvaluator::new(m, opts);
                        let extra = e.extra_width48(&span);
                        e.eval(&span, |s| {
                            let w = widths.width_with(s.gx, s.gy, extra);
                            want.push(tex.stage().shade(s.f, w));
                        });
                    }
                    #[cfg(feature = "perturb")]
                    Shader::Perturbed(p) => {
                        let mut e = MaterialEvaluator::new(p, opts);
                        let extra = e.extra_width48(&span);
                        e.eval(&span, |s| {
                            let w = widths.width_with(s.gx, s.gy, extra);
                            want.push(tex.stage().shade(s.f, w));
                        });
                    }
                }
                assert_eq!(shade_both_shapes(tex, &span), want, "len {len}");
            }
        }
    }

    /// Textures of the marble model (and, with `perturb`, a perturbed material) in `mode` with
    /// every filter compiled in (the ramp included), both wraps and two norms, on the zebra
    /// table.
    pub(super) fn zebra_textures(mode: EvalMode) -> Vec<Texture<8, 256>> {
        use crate::filter::ColorStage;
        use crate::table::{ColorTable, TableWrap};
        let mut out = Vec::new();
        let table = ColorTable::<256>::zebra().unwrap();
        #[cfg(feature = "ramp")]
        let ramp = [Antialias::Ramp];
        #[cfg(not(feature = "ramp"))]
        let ramp: [Antialias; 0] = [];
        for aa in filters().chain(ramp) {
            for wrap in [TableWrap::Mod, TableWrap::Clamp] {
                for norm in [GradientNorm::L2, GradientNorm::L1] {
                    let stage = ColorStage::new(table, wrap, TableLookup::Nearest, aa).unwrap();
                    let model = crate::texture::workload::marble_model(HashKind::Integer);
                    out.push(Texture::new(
                        Shader::Model(model),
                        stage.clone(),
                        norm,
                        mode,
                    ));
                    // A perturbed material: its samples one by one.
                    #[cfg(feature = "perturb")]
                    {
                        let p = crate::presets::mn_marble(HashKind::Integer);
                        let m = crate::material::PerturbedMaterial::<8>::new(&p, wrap).unwrap();
                        out.push(Texture::new(Shader::Perturbed(m), stage, norm, mode));
                    }
                    #[cfg(not(feature = "perturb"))]
                    let _ = stage;
                }
            }
        }
        out
    }

    /// Every filter compiled in.
    pub(super) fn filters() -> impl Iterator<Item = Antialias> {
        [
            Antialias::None,
            Antialias::Mip,
            Antialias::Csat,
            Antialias::Csat3,
        ]
        .into_iter()
        .filter(|a| a.is_available())
    }

    /// The marble preset's model as a texture of `mode` with each filter compiled in.
    fn marble_textures(
        mode: EvalMode,
    ) -> impl Iterator<Item = (Antialias, Texture<{ crate::presets::PRESET_TERMS }, 256>)> {
        let model = crate::presets::marble(HashKind::Integer).model;
        filters().map(move |aa| {
            let shader = Shader::Model(model.clone());
            (aa, Texture::new(shader, stage(aa), GradientNorm::L2, mode))
        })
    }

    /// [`TextureSpans`] shades a plane's spans as [`TextureEvaluator::shade_plane`] does, with
    /// every filter and whole rows cut into 16-pixel spans, spans out of order and spans outside
    /// the rectangle; walked from the rows' schedule, the 16-pixel rows set up fewer cells.
    #[test]
    fn texture_spans_shade_as_shade_plane() {
        use crate::span::{RowCache, SpanPlane};
        let plane = SpanPlane::new(
            TexPoint::from_bits(0, 32_768, 0),
            TexPoint::from_bits(512, 0, 0),
            TexPoint::from_bits(0, 0, 512),
            96,
            6,
        )
        .unwrap();
        for (aa, tex) in marble_textures(EvalMode::Fd) {
            let (mut ev, mut plain) = (tex.evaluator(), tex.evaluator());
            let setup = ev.plane_setup(&plane).unwrap();
            let mut cache = RowCache::<64>::new();
            let mut spans = ev.plane_spans(&setup, &mut cache);
            let mut pieces: Vec<(u16, u16, u16)> = Vec::new();
            for y in 0..6 {
                pieces.extend((0..96).step_by(16).map(|x| (x, y, 16)));
            }
            pieces.extend([(40, 2, 9), (0, 5, 96), (90, 0, 7), (95, 5, 1), (90, 1, 10)]);
            for &(x, y, len) in &pieces {
                let (mut got, mut want) = (Vec::new(), Vec::new());
                spans.shade(x, y, len, |c| got.push(c));
                plain.shade_plane(&setup, x, y, len, |c| want.push(c));
                assert_eq!(got, want, "{aa:?} {x} {y} {len}");
            }
            let (a, b) = (spans.stats(), plain.stats());
            assert_eq!(
                (a.span.pixels, a.filter_lookups, a.plain_lookups),
                (b.span.pixels, b.filter_lookups, b.plain_lookups)
            );
            if cfg!(feature = "fd") && !cfg!(texcore_lean) {
                assert!(
                    a.span.cell_setups < b.span.cell_setups,
                    "{aa:?}: {a:?} {b:?}"
                );
            }
        }
    }

    /// [`TextureEvaluator::shade_plane`] shades a plane's spans as [`TextureEvaluator::shade`]
    /// shades them, colours and counters, with every filter; a perturbed material has no plane
    /// set-up and shades through a model's plane as `shade` does.
    #[test]
    fn plane_spans_shade_as_their_spans() {
        use crate::span::SpanPlane;
        let plane = SpanPlane::new(
            TexPoint::from_f64(0.3, -0.2, 0.9),
            TexPoint::from_f64(0.004, 0.001, -0.002),
            TexPoint::from_f64(0.0, 0.004, 0.003),
            200,
            100,
        )
        .unwrap();
        for (aa, tex) in marble_textures(EvalMode::Auto) {
            let (mut ev, mut direct) = (tex.evaluator(), tex.evaluator());
            let setup = ev.plane_setup(&plane).unwrap();
            for (x, y, len) in [
                (0, 0, 16),
                (16, 0, 16),
                (37, 99, 1),
                (100, 50, 100),
                (3, 7, 0),
            ] {
                let (mut got, mut want) = (Vec::new(), Vec::new());
                ev.shade_plane(&setup, x, y, len, |c| got.push(c));
                direct.shade(&plane.span(x, y, len).unwrap(), |c| want.push(c));
                assert_eq!(got, want, "{aa:?} {x} {y} {len}");
                assert_eq!(ev.stats(), direct.stats(), "{aa:?}");
            }
            // Outside the rectangle: nothing.
            let mut any = false;
            ev.shade_plane(&setup, 150, 0, 51, |_| any = true);
            assert!(!any);
            assert_eq!(ev.stats(), direct.stats());
        }
        #[cfg(feature = "perturb")]
        {
            let mn = crate::presets::mn_marble(HashKind::Integer);
            let m = PerturbedMaterial::<8>::new(&mn, crate::table::TableWrap::Mod).unwrap();
            let aa = Antialias::None;
            let tex = Texture::new(
                Shader::Perturbed(m),
                stage(aa),
                GradientNorm::L2,
                EvalMode::Auto,
            );
            let (mut ev, mut direct) = (tex.evaluator(), tex.evaluator());
            assert!(ev.plane_setup(&plane).is_none());
            // A model's plane set-up, handed to a perturbed material, is not used.
            let model = crate::presets::marble(HashKind::Integer).model;
            let other = Texture::new(
                Shader::Model(model),
                stage(aa),
                GradientNorm::L2,
                EvalMode::Auto,
            );
            let setup = other.evaluator().plane_setup(&plane).unwrap();
            let (mut got, mut want) = (Vec::new(), Vec::new());
            ev.shade_plane(&setup, 5, 6, 40, |c| got.push(c));
            direct.shade(&plane.span(5, 6, 40).unwrap(), |c| want.push(c));
            assert_eq!(got, want);
        }
    }
}

/// Reference workloads shared by the criterion benchmarks (`texcore/benches`), the device jobs
/// (`workloads/src/bench.rs`) and their host check (`tests/tests/firmware_qemu.rs`), so that all
/// three measure exactly the same thing (`docs/performance.md`).
///
/// - Value-noise planes: `f = r + sum_{i < octaves} 2^-i n(2^i s)` (trilinear value noise,
///   unrotated octaves, `mod` wrap) on a plane of constant `r`, pixel `(x, y)` at
///   `s = ((x + 1/2) step, (y + 1/2) step, 1/2 + 1/1024)`; `step` is the lattice step per pixel of
///   octave 0 ([`workload::CELLS_8`]: 8 cells across 256 pixels; [`workload::ZOOM_IN`]: one cell;
///   [`workload::ZOOM_OUT`]: 128 cells, at the Nyquist limit, so octaves 1.. are culled).
/// - The marble preset with its colour table (`N = 256`, nearest) and the summed-area table
///   filter, L2 gradient norm, on the preset's check plane (feature `csat`).
pub mod workload {
    use crate::format::{Amplitude, MatrixEntry, QuadricCoeff, TexPoint};
    use crate::hash::HashKind;
    use crate::model::{Octaves, TextureModel};
    use crate::noise::NoiseBasis;
    use crate::quadric::Quadric;
    use crate::span::{Sample, Span};
    use crate::table::TableWrap;
    use crate::transform::Affine3;

    /// Octave-0 lattice step of 8 cells across 256 pixels (1/32 cell per pixel), raw 16.16.
    pub const CELLS_8: i32 = 2048;
    /// One cell across 256 pixels.
    pub const ZOOM_IN: i32 = 256;
    /// 128 cells across 256 pixels (half a cell per pixel: the Nyquist limit of octave 0).
    pub const ZOOM_OUT: i32 = 32768;
    /// Noise-term capacity of the workload models.
    pub const TERMS: usize = 8;

    pub mod peers;

    /// FNV-1a 32-bit offset basis (the firmware's checksum).
    pub const FNV_OFFSET: u32 = 0x811C_9DC5;

    /// Folds one word into an FNV-1a checksum.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub fn fold(acc: u32, word: u32) -> u32 {
        (acc ^ word).wrapping_mul(0x0100_0193)
    }

    /// Folds a sample: `f` raw, then `gx` and `gy`, each as low word then high word.
    #[cfg_attr(not(texcore_lean), inline(always))]
    pub fn fold_sample(acc: u32, s: &Sample) -> u32 {
        let mut a = fold(acc, s.f.to_bits() as u32);
        for g in [s.gx, s.gy] {
            a = fold(a, g as u32);
            a = fold(a, (g >> 32) as u32);
        }
        a
    }

    /// `r + sum_{i < octaves} 2^-i n(2^i s)`, trilinear value noise with `hash`, `mod` wrap.
    /// `octaves` is clamped to `1..=TERMS`.
    pub fn value_fbm(octaves: u8, hash: HashKind) -> TextureModel<TERMS> {
        let q = Quadric::linear(
            QuadricCoeff::ZERO,
            QuadricCoeff::ZERO,
            QuadricCoeff::ONE,
            QuadricCoeff::ZERO,
        );
        let mut m = TextureModel::new(q, TableWrap::Mod);
        let oct = Octaves {
            count: octaves.clamp(1, TERMS as u8),
            base: Affine3::scale(MatrixEntry::ONE),
            amplitude: Amplitude::ONE,
            rotate: false,
            basis: NoiseBasis::trilinear(hash),
            turbulence: false,
        };
        // Up to TERMS octaves of amplitude sum < 2 always fit: this cannot fail.
        let _ = m.push_octaves(&oct);
        m
    }

    /// Row `y` of the value-noise plane with octave-0 step `step`, `width` pixels.
    pub fn plane_span(step: i32, y: u16, width: u16) -> Span {
        let h = step / 2;
        Span {
            s0: TexPoint::from_bits(h, i32::from(y).wrapping_mul(step).wrapping_add(h), 0x8040),
            ds: TexPoint::from_bits(step, 0, 0),
            dsdy: TexPoint::from_bits(0, step, 0),
            len: width,
        }
    }

    /// The marble preset's model, `r + sum_{i<4} 2^-i n(2^i s)` (`mod`), built without floating
    /// point (the preset builder converts `f64` constants, which links panicking paths into a
    /// device build); equal to `presets::marble(hash).model` (tested).
    pub fn marble_model(hash: HashKind) -> TextureModel<TERMS> {
        let mut c = [QuadricCoeff::ZERO; 10];
        c[8] = QuadricCoeff::from_bits(1 << 15); // I = 1/2: q = 2 I r = r
        let mut m = TextureModel::new(Quadric::from_coefficients(c), TableWrap::Mod);
        // Four octaves of amplitude sum < 2 always fit: this cannot fail.
        let _ = m.push_octaves(&Octaves {
            count: 4,
            base: Affine3::IDENTITY,
            amplitude: Amplitude::ONE,
            rotate: false,
            basis: NoiseBasis::trilinear(hash),
            turbulence: false,
        });
        m
    }

    /// The marble preset's check plane (equal to `presets::marble(..).plane`, tested).
    pub const MARBLE_PLANE: crate::presets::CheckPlane = crate::presets::CheckPlane {
        origin: [0, 32768, 0],
        step_x: [512, 0, 0],
        step_y: [0, 0, 512],
    };

    /// Row `y` of the marble preset's check plane, `width` pixels.
    pub fn marble_span(y: u16, width: u16) -> Span {
        let p = MARBLE_PLANE;
        let at = |k: usize| {
            p.origin[k]
                .wrapping_add(p.step_x[k] / 2)
                .wrapping_add(p.step_y[k].wrapping_mul(2 * i32::from(y) + 1) / 2)
        };
        Span {
            s0: TexPoint::from_bits(at(0), at(1), at(2)),
            ds: TexPoint::from_bits(p.step_x[0], p.step_x[1], p.step_x[2]),
            dsdy: TexPoint::from_bits(p.step_y[0], p.step_y[1], p.step_y[2]),
            len: width,
        }
    }

    /// The marble colour stage: the preset's keys in a 256-entry table (nearest, `mod`) with the
    /// summed-area filter, computed at compile time (`None` only if the keys were invalid).
    #[cfg(feature = "csat")]
    pub const MARBLE_STAGE: Option<crate::filter::ColorStage<256>> =
        marble_stage(crate::filter::Antialias::Csat);

    /// The marble colour stage with the pre-filtered RGB565 ramp instead of the summed-area
    /// filter (the same table), computed at compile time.
    #[cfg(feature = "ramp")]
    pub const MARBLE_RAMP_STAGE: Option<crate::filter::ColorStage<256>> =
        marble_stage(crate::filter::Antialias::Ramp);

    #[cfg(any(feature = "csat", feature = "ramp"))]
    const fn marble_stage(aa: crate::filter::Antialias) -> Option<crate::filter::ColorStage<256>> {
        use crate::color::Rgba8888;
        use crate::filter::ColorStage;
        use crate::table::{ColorTable, TableLookup};
        const N_KEYS: usize = crate::presets::MARBLE_KEYS.len();
        let k = &crate::presets::MARBLE_KEYS;
        let mut keys = [(crate::format::TexValue::ZERO, Rgba8888::BLACK); N_KEYS];
        let mut i = 0;
        while i < N_KEYS {
            let c = k[i].1;
            keys[i] = (
                crate::format::TexValue::from_bits(k[i].0 as i32),
                Rgba8888::new(c[0], c[1], c[2], c[3]),
            );
            i += 1;
        }
        match ColorTable::<256>::from_keys(&keys) {
            Ok(t) => match ColorStage::new(t, TableWrap::Mod, TableLookup::Nearest, aa) {
                Ok(s) => Some(s),
                Err(_) => None,
            },
            Err(_) => None,
        }
    }

    /// The marble preset as a texture: [`marble_model`] and [`MARBLE_STAGE`], the L2 gradient
    /// norm, evaluated in `mode`.
    #[cfg(feature = "csat")]
    pub fn marble_csat(
        hash: HashKind,
        mode: crate::span::EvalMode,
    ) -> Option<super::Texture<TERMS, 256>> {
        Some(marble_with(hash, mode, MARBLE_STAGE?))
    }

    /// `marble_csat` (feature `csat`) with [`MARBLE_RAMP_STAGE`]: the same samples, coloured
    /// through the pre-filtered RGB565 ramp (approximate, [`crate::filter::ramp`]).
    #[cfg(feature = "ramp")]
    pub fn marble_ramp(
        hash: HashKind,
        mode: crate::span::EvalMode,
    ) -> Option<super::Texture<TERMS, 256>> {
        Some(marble_with(hash, mode, MARBLE_RAMP_STAGE?))
    }

    /// [`marble_model`] coloured by `stage`, the L2 gradient norm, evaluated in `mode`.
    #[cfg(any(feature = "csat", feature = "ramp"))]
    fn marble_with(
        hash: HashKind,
        mode: crate::span::EvalMode,
        stage: crate::filter::ColorStage<256>,
    ) -> super::Texture<TERMS, 256> {
        super::Texture::new(
            super::Shader::Model(marble_model(hash)),
            stage,
            crate::filter::GradientNorm::L2,
            mode,
        )
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        // The hashes grow with the features.
        #[allow(clippy::single_element_loop)]
        #[test]
        fn marble_workload_is_the_preset() {
            for hash in [
                HashKind::Integer,
                #[cfg(feature = "perm-hash")]
                HashKind::Permutation,
            ] {
                let p = crate::presets::marble(hash);
                assert_eq!(marble_model(hash), p.model);
                assert_eq!(MARBLE_PLANE, p.plane);
                assert_eq!(p.keys, &crate::presets::MARBLE_KEYS[..]);
                assert_eq!(p.table_size, 256);
            }
        }
    }
}
