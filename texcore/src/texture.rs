//! A configured texture: a shader (texture model or perturbed material) and a colour stage,
//! evaluated span by span into colours.
//!
//! The pipeline of a [`Texture`] is fixed when it is built, never tested per pixel:
//! - with [`Antialias::None`] the span evaluator computes no gradients (the gradient stage does not
//!   run) and colours come from the plain table look-up;
//! - otherwise the filter width `w = N * norm(gx, gy)` (plus the width of culled octaves) feeds the
//!   colour table's box or MIP filter;
//! - a model with no noise terms runs no noise stage, a zero quadric no quadric stage (see
//!   [`crate::span`]).
//!
//! Every mode of the span evaluator gives the same samples, so [`EvalMode::Direct`] and
//! [`EvalMode::Fd`] give the same colours.

use crate::color::Rgba8888;
use crate::filter::{filter_width, Antialias, ColorStage, GradientNorm};
use crate::format::FilterWidth;
#[cfg(feature = "perturb")]
use crate::material::{MaterialEvaluator, PerturbedMaterial};
use crate::model::TextureModel;
use crate::span::{EvalMode, EvalOptions, Span, SpanEvaluator, SpanStats};

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
                cull: true,
            },
        }
    }

    /// The same texture with octave culling switched on or off.
    pub fn with_culling(mut self, cull: bool) -> Self {
        self.opts.cull = cull;
        self
    }

    /// The same texture with another evaluation mode.
    pub fn with_mode(mut self, mode: EvalMode) -> Self {
        self.opts.mode = mode;
        self
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

impl<const T: usize, const N: usize> TextureEvaluator<'_, T, N> {
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
    pub fn shade<F: FnMut(Rgba8888)>(&mut self, span: &Span, mut emit: F) {
        let stage = &self.tex.stage;
        let n = u64::from(span.len);
        if stage.antialias() == Antialias::None {
            self.plain_lookups += n;
            let f = |s: crate::span::Sample| emit(stage.shade_unfiltered(s.f));
            match &mut self.inner {
                Inner::Model(e) => {
                    e.eval(span, f);
                }
                #[cfg(feature = "perturb")]
                Inner::Perturbed(e) => {
                    e.eval(span, f);
                }
            }
            return;
        }
        self.filter_lookups += n;
        let norm = self.tex.norm;
        let lg = log2(N);
        // Width of the octaves culled past Nyquist: (2 sum |a_k|, 16 fraction bits) * N, saturating.
        let extra48 = match &self.inner {
            Inner::Model(e) => e.extra_width48(span),
            #[cfg(feature = "perturb")]
            Inner::Perturbed(e) => e.extra_width48(span),
        };
        let e16 = (extra48 >> 32).clamp(0, i64::from(u32::MAX)) as u64;
        let extra_raw = (e16 << lg).min(u64::from(u32::MAX)) as u32;
        let mut shade = |s: crate::span::Sample| {
            let w = filter_width(s.gx, s.gy, norm, lg).to_bits();
            emit(stage.shade(s.f, FilterWidth::from_bits(w.saturating_add(extra_raw))))
        };
        match &mut self.inner {
            Inner::Model(e) => {
                e.eval(span, &mut shade);
            }
            #[cfg(feature = "perturb")]
            Inner::Perturbed(e) => {
                e.eval(span, &mut shade);
            }
        }
    }
}
