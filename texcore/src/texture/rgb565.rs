//! Shading straight to RGB565: [`TextureEvaluator::shade565`], [`TextureSpans::shade565`] and
//! [`TextureRows::next_shade565`](super::TextureRows::next_shade565), for displays that take
//! RGB565 pixels.
//!
//! # Guarantees
//!
//! - Every pixel is the colour of the same span's `shade` reduced by
//!   [`Rgba8888::to_rgb565`](crate::color::Rgba8888::to_rgb565), bit for bit, with every filter
//!   (tested per filter): with `Antialias::Ramp` (feature `ramp`) it is the ramp's sample,
//!   which `shade` expands exactly, and with any other filter it is `shade`'s colour reduced.
//! - With the ramp, a pixel costs one read of the pre-filtered RGB565 ramp: the level comes from
//!   the gradient's squared L2 norm without its square root ([`crate::filter::ramp`]), and no
//!   colour is reduced; other norms take the width as `shade` does.

#[cfg(feature = "ramp")]
use super::Inner;
use super::{Source, TextureEvaluator, TextureSpans, Walk};
use crate::color::Rgb565;
#[cfg(feature = "ramp")]
use crate::filter::{ColorStage, GradientNorm, WidthStream};
#[cfg(feature = "ramp")]
use crate::span::SampleChunk;
use crate::span::{SetupFrom, Span};

/// The RGB565 colours of a chunk of samples with gradients through a ramp stage (`stage.ramp()`
/// is `Some`): each pixel's level from its gradient (and the chunk's spread), then one read.
#[cfg(feature = "ramp")]
#[inline(always)]
pub(super) fn ramp_chunk<const N: usize, F: FnMut(Rgb565)>(
    stage: &ColorStage<N>,
    norm: GradientNorm,
    c: &SampleChunk,
    emit: &mut F,
) {
    let Some((t, r)) = stage.ramp() else {
        return;
    };
    let extra = c.extra_width48();
    if norm == GradientNorm::L2 && super::log2(N) <= 15 {
        // The level from the squared norm, one read a pixel.
        r.shade_l2(c.f(), c.gx(), c.gy(), extra, emit);
    } else {
        let wrap = stage.wrap();
        let mut widths = WidthStream::new(norm, super::log2(N));
        for ((&f, &gx), &gy) in c.f().iter().zip(c.gx()).zip(c.gy()) {
            emit(r.lookup(t.coord(f, wrap), widths.width_with(gx, gy, extra)));
        }
    }
}

impl<'t, const T: usize, const N: usize> TextureEvaluator<'t, T, N> {
    /// Shades `span` straight to RGB565, calling `emit` with each pixel in order: the colours of
    /// [`TextureEvaluator::shade`] reduced to RGB565, bit for bit (see the module
    /// documentation); with `Antialias::Ramp` (feature `ramp`) one ramp read a pixel.
    pub fn shade565<F: FnMut(Rgb565)>(&mut self, span: &Span, emit: F) {
        self.shade565_with(span, SetupFrom::Span, emit);
    }

    /// [`TextureEvaluator::shade565`] with the model's set-up from `from` (as `shade_with`).
    #[cfg_attr(not(texcore_lean), allow(unused_mut))]
    pub(super) fn shade565_with<F: FnMut(Rgb565), S: Source<'t, T>>(
        &mut self,
        span: &Span,
        mut from: S,
        mut emit: F,
    ) {
        #[cfg(feature = "ramp")]
        if self.tex.stage.ramp().is_some() {
            self.ramp_with(span, from, emit);
            return;
        }
        #[cfg(texcore_lean)]
        {
            let _ = &mut from;
            self.shade(span, |c| emit(c.to_rgb565()));
        }
        #[cfg(not(texcore_lean))]
        self.shade_with(span, from, |c| emit(c.to_rgb565()));
    }

    /// The colours of a span of a texture with [`Antialias::Ramp`](crate::filter::Antialias):
    /// with the L2 norm each level from the squared gradients (`Ramp565::shade_l2`, no root),
    /// else at the stream's width; the ramp's own RGB565 samples, those of
    /// `ColorStage::shade565` (and, widened, of `ColorStage::shade`).
    #[cfg(feature = "ramp")]
    #[cfg_attr(texcore_lean, allow(unused_mut))]
    pub(super) fn ramp_with<F: FnMut(Rgb565), S: Source<'t, T>>(
        &mut self,
        span: &Span,
        mut from: S,
        mut emit: F,
    ) {
        self.filter_lookups += u64::from(span.len);
        let (stage, norm) = (&self.tex.stage, self.tex.norm);
        match &mut self.inner {
            Inner::Model(e) => {
                let mut each = |c: &SampleChunk| ramp_chunk(stage, norm, c, &mut emit);
                #[cfg(texcore_lean)]
                {
                    let _ = &mut from;
                    e.eval_chunks(span, &mut each);
                }
                #[cfg(not(texcore_lean))]
                from.chunks(e, span, &mut each);
            }
            #[cfg(feature = "perturb")]
            Inner::Perturbed(e) => {
                let extra = e.extra_width48(span);
                let mut widths = WidthStream::new(norm, super::log2(N));
                e.eval(span, |s| {
                    emit(stage.shade565(s.f, widths.width_with(s.gx, s.gy, extra)));
                });
            }
        }
    }
}

impl<const T: usize, const N: usize> TextureSpans<'_, '_, '_, T, N> {
    /// [`TextureSpans::shade`] straight to RGB565: the span's colours reduced to RGB565, bit for
    /// bit ([`TextureEvaluator::shade565`]).
    pub fn shade565<F: FnMut(Rgb565)>(&mut self, x: u16, y: u16, len: u16, emit: F) {
        let Some(span) = self.walk.plane().plane().span(x, y, len) else {
            return;
        };
        self.ev
            .shade565_with(&span, Walk(&mut self.walk, x, y), emit);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use crate::span::{EvalMode, RowCache};
    use crate::texture::workload::marble_span;
    use crate::texture::Texture;

    fn textures() -> Vec<Texture<8, 256>> {
        crate::texture::tests::zebra_textures(EvalMode::Fd)
    }

    #[test]
    fn shade565_is_shade_reduced() {
        for tex in textures() {
            for y in [0u16, 17, 200] {
                for len in [1u16, 16, 256] {
                    let span = marble_span(y, len);
                    let mut want = Vec::new();
                    tex.evaluator().shade(&span, |c| want.push(c.to_rgb565()));
                    let mut got = Vec::new();
                    let mut ev = tex.evaluator();
                    ev.shade565(&span, |c| got.push(c));
                    assert_eq!(got, want, "{:?}", tex.stage().antialias());
                    let mut stats = tex.evaluator();
                    stats.shade(&span, |_| {});
                    assert_eq!(ev.stats(), stats.stats());
                }
            }
        }
    }

    #[test]
    fn rows_and_spans_shade565_are_shade565() {
        for tex in textures() {
            let first = marble_span(0, 64);
            let mut cache = RowCache::<64>::new();
            let mut ev = tex.evaluator();
            let mut rows = ev.rows(&first, &mut cache);
            let mut span = first;
            for _ in 0..5 {
                let mut want = Vec::new();
                tex.evaluator().shade565(&span, |c| want.push(c));
                let mut got = Vec::new();
                rows.next_shade565(|c| got.push(c));
                assert_eq!(got, want, "{:?}", tex.stage().antialias());
                span = span.next_row();
            }
        }
    }

    /// The ramp's pixels differ from the summed-area filter's only as the approximation allows:
    /// on the marble rows most pixels agree to a few RGB565 steps.
    #[cfg(all(feature = "ramp", feature = "csat"))]
    #[test]
    fn the_ramp_is_near_the_summed_area_filter() {
        use crate::filter::{Antialias, ColorStage, GradientNorm};
        use crate::hash::HashKind;
        use crate::table::{ColorTable, TableLookup, TableWrap};
        use crate::texture::workload::marble_model;
        use crate::texture::Shader;
        let table = ColorTable::<256>::zebra().unwrap();
        let make = |aa| {
            let stage = ColorStage::new(table, TableWrap::Mod, TableLookup::Nearest, aa).unwrap();
            let model = marble_model(HashKind::Integer);
            Texture::new(Shader::Model(model), stage, GradientNorm::L2, EvalMode::Fd)
        };
        let (ramp, csat) = (make(Antialias::Ramp), make(Antialias::Csat));
        let (mut near, mut all) = (0, 0);
        for y in 0..32 {
            let span = marble_span(y * 7, 256);
            let mut a = Vec::new();
            ramp.evaluator().shade565(&span, |c| a.push(c));
            let mut b = Vec::new();
            csat.evaluator().shade565(&span, |c| b.push(c));
            for (p, q) in a.iter().zip(&b) {
                let d = (i32::from(p.r()) - i32::from(q.r())).abs()
                    + (i32::from(p.g()) - i32::from(q.g())).abs()
                    + (i32::from(p.b()) - i32::from(q.b())).abs();
                near += usize::from(d <= 6);
                all += 1;
            }
        }
        assert!(near * 10 >= all * 9, "{near} of {all}");
    }
}
