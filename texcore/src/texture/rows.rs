//! The rows of a plane shaded one after the other: [`TextureRows`], the texture pipeline over
//! [`PlaneRows`] (the span evaluator's row schedule, `crate::span::PlaneRows`).
//!
//! # Guarantees
//!
//! - Every row's colours are those of [`TextureEvaluator::shade`] of the row's span, bit for
//!   bit (the row schedule gives the span evaluator's samples, and the colour stage is the same
//!   code; tested against `shade` row by row).
//! - Any texture is accepted: a perturbed material, or a model and plane the row schedule does
//!   not serve, is shaded span by span.

use super::{shade_chunk, Inner, Texture, TextureEvaluator};
use crate::color::{Rgb565, Rgba8888};
use crate::filter::{Antialias, WidthStream};
use crate::format::{FilterWidth, TexValue};
#[cfg(feature = "perturb")]
use crate::material::MaterialEvaluator;
use crate::span::{PlaneRows, RowCache, SampleChunk, Span, SAMPLE_CHUNK};

/// The rows of a plane, shaded one after the other with the span evaluator's row schedule kept
/// across them: made by [`TextureEvaluator::rows`].
#[derive(Debug)]
pub struct TextureRows<'e, 't, 'c, const T: usize, const N: usize> {
    tex: &'t Texture<T, N>,
    source: Source<'e, 't, 'c, T>,
    filter_lookups: &'e mut u64,
    plain_lookups: &'e mut u64,
}

/// Where a row's samples come from.
#[derive(Debug)]
enum Source<'e, 't, 'c, const T: usize> {
    /// A model: its row schedule.
    Rows(PlaneRows<'e, 't, 'c, T>),
    /// A perturbed material: span by span (its next row's span).
    #[cfg(feature = "perturb")]
    Spans(&'e mut MaterialEvaluator<'t, T>, Span),
}

impl<'t, const T: usize, const N: usize> TextureEvaluator<'t, T, N> {
    /// The rows of a plane from `first` (each next row's span is the last one's with `s0`
    /// advanced by `dsdy`), shaded through `cache` (the span evaluator's row schedule,
    /// [`crate::span::PlaneRows`]): the colours of [`TextureEvaluator::shade`] of each row's
    /// span, bit for bit. The counters ([`TextureEvaluator::stats`]) count every row.
    pub fn rows<'e, 'c, const R: usize, const W: usize>(
        &'e mut self,
        first: &Span,
        cache: &'c mut RowCache<R, W>,
    ) -> TextureRows<'e, 't, 'c, T, N> {
        let source = match &mut self.inner {
            Inner::Model(e) => Source::Rows(e.rows(first, cache)),
            #[cfg(feature = "perturb")]
            Inner::Perturbed(e) => Source::Spans(e, *first),
        };
        TextureRows {
            tex: self.tex,
            source,
            filter_lookups: &mut self.filter_lookups,
            plain_lookups: &mut self.plain_lookups,
        }
    }
}

impl<const T: usize, const N: usize> TextureRows<'_, '_, '_, T, N> {
    /// The span of the next row.
    pub fn span(&self) -> &Span {
        match &self.source {
            Source::Rows(r) => r.span(),
            #[cfg(feature = "perturb")]
            Source::Spans(_, s) => s,
        }
    }

    /// Shades the next row, calling `emit` with each pixel's colour in order (as
    /// [`TextureEvaluator::shade`]), and moves to the row after it.
    pub fn next_shade<F: FnMut(Rgba8888)>(&mut self, mut emit: F) {
        let stage = &self.tex.stage;
        let n = u64::from(self.span().len);
        if stage.antialias() == Antialias::None {
            *self.plain_lookups += n;
            let f = |s: crate::span::Sample| emit(stage.shade_unfiltered(s.f));
            match &mut self.source {
                Source::Rows(r) => {
                    r.next(f);
                }
                #[cfg(feature = "perturb")]
                Source::Spans(e, span) => {
                    e.eval(span, f);
                    *span = span.next_row();
                }
            }
            return;
        }
        *self.filter_lookups += n;
        let mut widths = WidthStream::new(self.tex.norm, super::log2(N));
        match &mut self.source {
            Source::Rows(r) => {
                let mut w = [FilterWidth::ZERO; SAMPLE_CHUNK];
                r.next_chunks(&mut |c: &SampleChunk| {
                    shade_chunk(stage, &mut widths, &mut w, c, &mut emit);
                });
            }
            #[cfg(feature = "perturb")]
            Source::Spans(e, span) => {
                let extra = e.extra_width48(span);
                e.eval(span, |s| {
                    emit(stage.shade(s.f, widths.width_with(s.gx, s.gy, extra)));
                });
                *span = span.next_row();
            }
        }
    }

    /// Counts the next row's `n` pixels as filtered or plain look-ups (rows shaded elsewhere
    /// from [`TextureRows::next_values`]).
    pub(super) fn count(&mut self, filtered: bool, n: u64) {
        if filtered {
            *self.filter_lookups += n;
        } else {
            *self.plain_lookups += n;
        }
    }

    /// The next row's values (its first `min(len, out.len())`, as
    /// [`crate::span::SpanEvaluator::eval_values`] gives them) into `out`, and moves to the row
    /// after it: the row's spread ([`crate::span::SpanInfo::extra_width48`]).
    pub(super) fn next_values(&mut self, out: &mut [TexValue]) -> i64 {
        match &mut self.source {
            Source::Rows(r) => r.next_values(out).extra_width48,
            #[cfg(feature = "perturb")]
            Source::Spans(e, span) => {
                let info = e.eval_values(span, out);
                *span = span.next_row();
                info.extra_width48
            }
        }
    }

    /// [`TextureRows::next_shade`] straight to RGB565: the row's colours reduced to RGB565, bit
    /// for bit; with `Antialias::Ramp` (feature `ramp`) one ramp read a pixel.
    pub fn next_shade565<F: FnMut(Rgb565)>(&mut self, mut emit: F) {
        #[cfg(feature = "ramp")]
        if self.tex.stage.ramp().is_some() {
            *self.filter_lookups += u64::from(self.span().len);
            let (stage, norm) = (&self.tex.stage, self.tex.norm);
            match &mut self.source {
                Source::Rows(r) => {
                    r.next_chunks(&mut |c: &SampleChunk| {
                        super::rgb565::ramp_chunk(stage, norm, c, &mut emit);
                    });
                }
                #[cfg(feature = "perturb")]
                Source::Spans(e, span) => {
                    let extra = e.extra_width48(span);
                    let mut widths = WidthStream::new(norm, super::log2(N));
                    e.eval(span, |s| {
                        emit(stage.shade565(s.f, widths.width_with(s.gx, s.gy, extra)));
                    });
                    *span = span.next_row();
                }
            }
            return;
        }
        self.next_shade(|c| emit(c.to_rgb565()));
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::vec::Vec;

    use super::*;
    use crate::filter::GradientNorm;
    use crate::format::TexPoint;
    use crate::hash::HashKind;
    use crate::span::EvalMode;
    use crate::table::TableLookup;
    use crate::texture::Shader;

    /// Rows of `tex` from `first` through [`TextureRows`] and through `shade`, compared.
    fn compare(tex: &Texture<8, 256>, first: &Span, rows: i32) {
        let mut cache = RowCache::<256, 256>::new();
        let mut ev = tex.evaluator();
        let mut plain = tex.evaluator();
        let mut r = ev.rows(first, &mut cache);
        for y in 0..rows {
            let b = first.s0.to_bits();
            let d = first.dsdy.to_bits();
            let span = Span {
                s0: TexPoint::from_bits(
                    b[0].wrapping_add(d[0].wrapping_mul(y)),
                    b[1].wrapping_add(d[1].wrapping_mul(y)),
                    b[2].wrapping_add(d[2].wrapping_mul(y)),
                ),
                ..*first
            };
            assert_eq!(r.span(), &span);
            let mut got = Vec::new();
            r.next_shade(|c| got.push(c));
            let mut want = Vec::new();
            plain.shade(&span, |c| want.push(c));
            assert_eq!(got, want, "row {y}");
        }
        drop(r);
        assert_eq!(ev.stats(), plain.stats());
    }

    // The shaders grow with the features.
    #[allow(clippy::vec_init_then_push)]
    #[test]
    fn rows_shade_as_spans() {
        let mut shaders = Vec::new();
        shaders.push(Shader::Model(
            crate::presets::marble(HashKind::Integer).model,
        ));
        shaders.push(Shader::Model(crate::texture::workload::marble_model(
            HashKind::Integer,
        )));
        #[cfg(feature = "perturb")]
        {
            let p = crate::presets::mn_marble(HashKind::Integer);
            let m = crate::material::PerturbedMaterial::<8>::new(&p, crate::table::TableWrap::Mod)
                .unwrap();
            shaders.push(Shader::Perturbed(m));
        }
        let planes = [
            // The peers' plane (rows along t), an axis-aligned plane whose rows step along r,
            // and a rotated one (never served by the schedule).
            Span {
                s0: TexPoint::from_bits(0, 0, 24248),
                ds: TexPoint::from_bits(2048, 0, 0),
                dsdy: TexPoint::from_bits(0, 2048, 0),
                len: 256,
            },
            Span {
                s0: TexPoint::from_f64(-3.3, 0.25, 0.9),
                ds: TexPoint::from_f64(0.01, 0.0, 0.0),
                dsdy: TexPoint::from_f64(0.0, 0.0, -0.013),
                len: 200,
            },
            Span {
                s0: TexPoint::from_f64(0.3, -0.2, 0.9),
                ds: TexPoint::from_f64(0.004, 0.001, -0.002),
                dsdy: TexPoint::from_f64(0.0, 0.004, 0.0),
                len: 150,
            },
        ];
        for shader in &shaders {
            for aa in super::super::tests::filters() {
                let stage = crate::ready::Material::preset_with_hash(
                    crate::ready::PresetName::Marble,
                    HashKind::Integer,
                )
                .stage(aa, TableLookup::Nearest)
                .unwrap();
                for mode in [EvalMode::Auto, EvalMode::Fd, EvalMode::Direct] {
                    let tex = Texture::new(shader.clone(), stage.clone(), GradientNorm::L2, mode);
                    for first in &planes {
                        compare(&tex, first, 12);
                    }
                }
            }
        }
    }
}
