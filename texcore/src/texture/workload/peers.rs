//! The peer-comparison workloads (`texsim report peers`, `docs/peers.md`): one plane and one
//! per-row kernel per workload, shared by the device jobs (`workloads/src/peers.rs`), the host
//! measurements and the benchmarks, so that texcore and the peer libraries measure the same
//! thing.
//!
//! The plane: [`SIZE`] x [`SIZE`] pixels, pixel `(x, y)` at `s = x/32`, `t = y/32`, `r = R`
//! (8 octave-0 cells across the image; [`R_BITS`] is `0.37` rounded to 16.16, `0.3699951..`, so
//! that `R_BITS / 65536` is exact in `f32` and the float peers sample the very same points).
//! Rows are evaluated as whole-row spans (or spans of 16 pixels for the `-span16` workloads) and
//! every sample is stored into a line buffer of 32-bit words (`value_row`: [`TexValue`]s,
//! `marble_row`: `u32`s).
//!
//! | workload | texcore | stored word |
//! |---|---|---|
//! | `value-1oct` | `n(s)`, trilinear value noise | `f` |
//! | `value-4oct` | `sum_{i<4} 2^-i n(2^i s)` | `f` |
//! | `value-4oct-grad` | the same with the filter-width gradients | `f ^ gx ^ gy` words ([`grad_word`]) |
//! | `value-4oct-span16` | `value-4oct` in spans of 16 pixels | `f` |
//! | `marble-csat-rgb565` | the marble preset (`r` + 4 octaves), csat colour table, RGB565 | RGB565 |
//! | `marble-csat-rgb565-span16` | the same in spans of 16 pixels | RGB565 |
//! | `smooth-1oct` | value noise, smooth fade `3u^2 - 2u^3` | `f` |
//! | `perlin-1oct` | Perlin's gradient noise, quintic fade | `f` |
//! | `perlin-4oct` | 4 octaves of it | `f` |
//!
//! The noise models have no quadric term (`f` is the noise sum alone).

use crate::format::{Amplitude, MatrixEntry, TexPoint, TexValue};
use crate::hash::HashKind;
use crate::model::{Octaves, TextureModel};
use crate::noise::NoiseBasis;
use crate::quadric::Quadric;
use crate::span::{
    FaceCache, RowCache, Sample, SampleChunk, Span, SpanEvaluator, SpanPlane, SpanPlaneError,
};
use crate::table::TableWrap;
use crate::transform::Affine3;

use super::TERMS;

/// Side of the plane in pixels.
pub const SIZE: u16 = 256;
/// Lattice step per pixel of octave 0, raw 16.16: 1/32.
pub const STEP: i32 = 2048;
/// The plane's `r`, raw 16.16: `0.37` rounded (`0.36999512`).
pub const R_BITS: i32 = 24248;
/// Rows of one 8-row band (the short run of the device bound test).
pub const BAND: u16 = 8;

/// A workload of the peer comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Workload {
    /// One octave of trilinear value noise.
    Value1,
    /// Four octaves.
    Value4,
    /// Four octaves with gradients.
    Value4Grad,
    /// Four octaves in 16-pixel spans.
    Value4Span16,
    /// The marble preset through csat to RGB565.
    MarbleCsat,
    /// The same in 16-pixel spans.
    MarbleCsatSpan16,
    /// One octave of smooth-fade value noise.
    Smooth1,
    /// One octave of Perlin gradient noise.
    Perlin1,
    /// Four octaves of Perlin gradient noise.
    Perlin4,
}

impl Workload {
    /// Every workload, in report order.
    pub const ALL: [Workload; 9] = [
        Workload::Value1,
        Workload::Value4,
        Workload::Value4Grad,
        Workload::Value4Span16,
        Workload::MarbleCsat,
        Workload::MarbleCsatSpan16,
        Workload::Smooth1,
        Workload::Perlin1,
        Workload::Perlin4,
    ];

    /// The name in reports (`value-1oct`, ...).
    pub const fn name(self) -> &'static str {
        match self {
            Workload::Value1 => "value-1oct",
            Workload::Value4 => "value-4oct",
            Workload::Value4Grad => "value-4oct-grad",
            Workload::Value4Span16 => "value-4oct-span16",
            Workload::MarbleCsat => "marble-csat-rgb565",
            Workload::MarbleCsatSpan16 => "marble-csat-rgb565-span16",
            Workload::Smooth1 => "smooth-1oct",
            Workload::Perlin1 => "perlin-1oct",
            Workload::Perlin4 => "perlin-4oct",
        }
    }

    /// The workload called `name`.
    pub fn by_name(name: &str) -> Option<Workload> {
        Workload::ALL.into_iter().find(|w| w.name() == name)
    }

    /// Pixels per span: [`SIZE`], or 16.
    pub const fn span_len(self) -> u16 {
        match self {
            Workload::Value4Span16 | Workload::MarbleCsatSpan16 => 16,
            _ => SIZE,
        }
    }

    /// Octaves of the noise sum.
    pub const fn octaves(self) -> u8 {
        match self {
            Workload::Value1 | Workload::Smooth1 | Workload::Perlin1 => 1,
            _ => 4,
        }
    }

    /// Whether texcore computes the filter-width gradients.
    pub const fn gradients(self) -> bool {
        matches!(
            self,
            Workload::Value4Grad | Workload::MarbleCsat | Workload::MarbleCsatSpan16
        )
    }

    /// Whether the workload shades colours (the marble preset) rather than noise values.
    pub const fn is_marble(self) -> bool {
        matches!(self, Workload::MarbleCsat | Workload::MarbleCsatSpan16)
    }

    /// The noise basis of a noise workload, `None` when this build lacks it (feature
    /// `smooth-fade` / `gradient-noise`).
    pub fn basis(self, hash: HashKind) -> Option<NoiseBasis> {
        match self {
            Workload::Smooth1 => smooth_basis(hash),
            Workload::Perlin1 | Workload::Perlin4 => perlin_basis(hash),
            _ => Some(NoiseBasis::trilinear(hash)),
        }
    }
}

#[cfg(feature = "smooth-fade")]
fn smooth_basis(hash: HashKind) -> Option<NoiseBasis> {
    Some(NoiseBasis {
        kind: crate::noise::BasisKind::Value,
        fade: crate::noise::Fade::Smooth,
        hash,
    })
}

#[cfg(not(feature = "smooth-fade"))]
fn smooth_basis(_: HashKind) -> Option<NoiseBasis> {
    None
}

#[cfg(all(feature = "gradient-noise", feature = "smooth-fade"))]
fn perlin_basis(hash: HashKind) -> Option<NoiseBasis> {
    Some(NoiseBasis {
        kind: crate::noise::BasisKind::Gradient,
        fade: crate::noise::Fade::Quintic,
        hash,
    })
}

#[cfg(not(all(feature = "gradient-noise", feature = "smooth-fade")))]
fn perlin_basis(_: HashKind) -> Option<NoiseBasis> {
    None
}

/// The noise model of a noise workload: `sum_{i < octaves} 2^-i n(2^i s)` with the workload's
/// basis, no quadric, `mod` wrap. `None` for the marble workloads ([`super::marble_model`]) and
/// for a basis this build lacks.
pub fn model(w: Workload, hash: HashKind) -> Option<TextureModel<TERMS>> {
    if w.is_marble() {
        return None;
    }
    let mut m = TextureModel::new(Quadric::ZERO, TableWrap::Mod);
    m.push_octaves(&Octaves {
        count: w.octaves(),
        base: Affine3::scale(MatrixEntry::ONE),
        amplitude: Amplitude::ONE,
        rotate: false,
        basis: w.basis(hash)?,
        turbulence: false,
    })
    .ok()?;
    Some(m)
}

/// The span of `len` pixels of row `y` from pixel `x0`: pixel `(x, y)` at
/// `(x STEP, y STEP, R_BITS)`.
pub fn span(y: u16, x0: u16, len: u16) -> Span {
    Span {
        s0: TexPoint::from_bits(i32::from(x0) * STEP, i32::from(y) * STEP, R_BITS),
        ds: TexPoint::from_bits(STEP, 0, 0),
        dsdy: TexPoint::from_bits(0, STEP, 0),
        len,
    }
}

/// The stored word of a sample with gradients: `f ^ gx_lo ^ rotl(gx_hi, 8) ^ rotl(gy_lo, 16) ^
/// rotl(gy_hi, 24)`.
#[inline(always)]
pub fn grad_word(s: &Sample) -> u32 {
    let (gx, gy) = (s.gx as u64, s.gy as u64);
    (s.f.to_bits() as u32)
        ^ (gx as u32)
        ^ ((gx >> 32) as u32).rotate_left(8)
        ^ (gy as u32).rotate_left(16)
        ^ ((gy >> 32) as u32).rotate_left(24)
}

/// The [`grad_word`]s of chunk `c` stored into `line` from `*x` on, and `*x` past them.
#[inline(always)]
fn store_grad_words(line: &mut [TexValue], x: &mut usize, c: &SampleChunk) {
    if let Some(dst) = line.get_mut(*x..*x + c.len()) {
        for (d, s) in dst.iter_mut().zip(c.iter()) {
            *d = TexValue::from_bits(grad_word(&s) as i32);
        }
    }
    *x += c.len();
}

/// Entries of the face cache of the value rows ([`value_row`]): every face a row of the
/// 4-octave workloads crosses (124).
pub const FACES: usize = 128;

/// Entries of the row schedule of the whole-row value workloads ([`value_plane`]): every cell a
/// row of the 4-octave workloads crosses, plus one a term (124).
pub const ROW_EVENTS: usize = 128;

/// Fade weights of the row schedule of the whole-row value workloads ([`value_plane`]): the
/// fades along a row of one term ([`SIZE`] pixels: the smooth fade, one octave of gradient
/// noise); [`Workload::Perlin4`]'s rows keep four terms' ([`ROW_WEIGHTS_4`]).
pub const ROW_WEIGHTS: usize = SIZE as usize;

/// Fade weights of [`Workload::Perlin4`]'s rows: four terms of [`SIZE`] pixels.
pub const ROW_WEIGHTS_4: usize = 4 * SIZE as usize;

/// Rows `0..rows` of noise workload `w`, each into `line` (its first [`SIZE`] values) and then
/// handed to `each(y, line)`: the whole-row workloads through [`SpanEvaluator::rows`] (their
/// schedule kept across rows in a [`RowCache`] of [`ROW_EVENTS`] entries and [`ROW_WEIGHTS`]
/// or [`ROW_WEIGHTS_4`] fade weights; values, or [`grad_word`]s of the samples with gradients), the
/// 16-pixel-span ones span by span, left to right along each row, through
/// [`PlaneSpans`](crate::span::PlaneSpans) (each row's walk kept from span to span, the rows'
/// schedule in a [`RowCache`] of [`ROW_EVENTS`] entries). `ev` must have been built for `w`'s model with `gradients = w.gradients()`.
#[inline(always)]
pub fn value_plane<const T: usize>(
    ev: &mut SpanEvaluator<'_, T>,
    w: Workload,
    rows: u16,
    line: &mut [TexValue],
    mut each: impl FnMut(u16, &[TexValue]),
) {
    if w.span_len() == SIZE {
        let Some(line) = line.get_mut(..usize::from(SIZE)) else {
            return;
        };
        if w == Workload::Perlin4 {
            let mut cache = RowCache::<ROW_EVENTS, ROW_WEIGHTS_4>::new();
            whole_rows(ev, w, rows, line, &mut cache, each);
        } else {
            let mut cache = RowCache::<ROW_EVENTS, ROW_WEIGHTS>::new();
            whole_rows(ev, w, rows, line, &mut cache, each);
        }
    } else {
        span_rows(ev, w, rows, line, &mut each);
    }
}

/// Rows `0..rows` of the 16-pixel-span workload `w` (see [`value_plane`]); out of line, so that
/// the whole-row loop's code is the same with and without it. The values are handed over
/// through [`PlaneSpans`](crate::span::PlaneSpans) (the rows' cell schedule kept in a [`RowCache`] of [`ROW_EVENTS`]
/// entries, each row walked from span to span); with gradients, each span through
/// [`SpanEvaluator::eval_plane_chunks`].
#[inline(never)]
fn span_rows<const T: usize>(
    ev: &mut SpanEvaluator<'_, T>,
    w: Workload,
    rows: u16,
    line: &mut [TexValue],
    each: &mut impl FnMut(u16, &[TexValue]),
) {
    // The spans' terms set up once for the plane (`PlaneSetup`; the plane is always valid,
    // `the_plane_is_valid`).
    let Ok(p) = plane() else {
        return;
    };
    let setup = ev.plane_setup(&p);
    let Some(line) = line.get_mut(..usize::from(SIZE)) else {
        return;
    };
    let len = usize::from(w.span_len());
    if w.gradients() {
        for y in 0..rows {
            for (x, chunk) in (0u16..).step_by(len).zip(line.chunks_mut(len)) {
                let (n, mut at) = (chunk.len() as u16, 0);
                let mut store = |c: &SampleChunk| store_grad_words(chunk, &mut at, c);
                ev.eval_plane_chunks(&setup, x, y, n, &mut store);
            }
            each(y, line);
        }
        return;
    }
    let mut cache = RowCache::<ROW_EVENTS>::new();
    let mut spans = ev.plane_spans(&setup, &mut cache);
    for y in 0..rows {
        for (x, chunk) in (0u16..).step_by(len).zip(line.chunks_mut(len)) {
            spans.values(x, y, chunk);
        }
        each(y, line);
    }
}

/// The workloads' plane: span `(x, y)` is [`span`]`(y, x, len)`, inside [`SIZE`] x [`SIZE`].
pub fn plane() -> Result<SpanPlane, SpanPlaneError> {
    let s = span(0, 0, 0);
    SpanPlane::new(s.s0, s.ds, s.dsdy, SIZE, SIZE)
}

/// Rows `0..rows` of whole-row workload `w` through [`SpanEvaluator::rows`] with `cache` (see
/// [`value_plane`]).
#[inline(always)]
fn whole_rows<const T: usize, const W: usize>(
    ev: &mut SpanEvaluator<'_, T>,
    w: Workload,
    rows: u16,
    line: &mut [TexValue],
    cache: &mut RowCache<ROW_EVENTS, W>,
    mut each: impl FnMut(u16, &[TexValue]),
) {
    let mut plane = ev.rows(&span(0, 0, SIZE), cache);
    for y in 0..rows {
        if w.gradients() {
            let mut x = 0;
            plane.next_chunks(&mut |c: &SampleChunk| store_grad_words(line, &mut x, c));
        } else {
            plane.next_values(line);
        }
        each(y, line);
    }
}

/// Row `y` of noise workload `w` into `line` (its first [`SIZE`] values), span by span
/// ([`Workload::span_len`]): `f` through [`SpanEvaluator::eval_values_cached`] with `faces`
/// kept across the rows, or, when `w` has
/// gradients, [`grad_word`] as raw bits through [`SpanEvaluator::eval_chunks`]. `ev` must have
/// been built for `w`'s model with `gradients = w.gradients()`.
#[inline(always)]
pub fn value_row<const T: usize>(
    ev: &mut SpanEvaluator<'_, T>,
    w: Workload,
    y: u16,
    line: &mut [TexValue],
    faces: &mut FaceCache<FACES>,
) {
    row_spans(ev, w, y, line, faces);
}

/// [`value_row`]: each span of the row set up on its own, its face blends and lanes through
/// `faces`.
#[inline(always)]
fn row_spans<const T: usize>(
    ev: &mut SpanEvaluator<'_, T>,
    w: Workload,
    y: u16,
    line: &mut [TexValue],
    faces: &mut FaceCache<FACES>,
) {
    let len = w.span_len();
    let Some(line) = line.get_mut(..usize::from(SIZE)) else {
        return;
    };
    let gradients = w.gradients();
    let mut x0 = 0;
    for chunk in line.chunks_mut(usize::from(len)) {
        let span = span(y, x0, len);
        if gradients {
            let mut x = 0;
            let mut store = |c: &SampleChunk| store_grad_words(chunk, &mut x, c);
            ev.eval_chunks(&span, &mut store);
        } else {
            ev.eval_values_cached(&span, chunk, faces);
        }
        x0 += len;
    }
}

/// Rows `0..rows` of the marble workload `w`, each into `line` (each pixel's colour as RGB565,
/// zero-extended) and then handed to `each(y, line)`: the whole-row workload through
/// [`super::super::TextureEvaluator::rows`] (the span evaluator's row schedule in a
/// [`RowCache`] of [`ROW_EVENTS`] entries), the 16-pixel-span one span by span, left to right
/// along each row, through [`TextureSpans`](crate::texture::TextureSpans) (the same schedule,
/// each row's walk kept from span to span).
#[cfg(any(feature = "csat", feature = "ramp"))]
#[inline(always)]
pub fn marble_plane<const T: usize, const N: usize>(
    ev: &mut super::super::TextureEvaluator<'_, T, N>,
    w: Workload,
    rows: u16,
    line: &mut [u32],
    mut each: impl FnMut(u16, &[u32]),
) {
    // The ramp shades straight to RGB565 (one read a pixel); every other filter's colours are
    // reduced as they come (`shade565` would give the same pixels: the reduction written here
    // keeps the summed-area rows' loop as it was before the ramp existed).
    #[cfg(feature = "ramp")]
    let ramp = ev.stage().antialias() == crate::filter::Antialias::Ramp;
    #[cfg(not(feature = "ramp"))]
    let ramp = false;
    if w.span_len() == SIZE {
        let Some(line) = line.get_mut(..usize::from(SIZE)) else {
            return;
        };
        let mut cache = RowCache::<ROW_EVENTS>::new();
        let mut plane = ev.rows(&span(0, 0, SIZE), &mut cache);
        for y in 0..rows {
            let mut px = line.iter_mut();
            if ramp {
                plane.next_shade565(|c| {
                    if let Some(p) = px.next() {
                        *p = u32::from(c.to_bits());
                    }
                });
            } else {
                plane.next_shade(|c| {
                    if let Some(p) = px.next() {
                        *p = u32::from(c.to_rgb565().to_bits());
                    }
                });
            }
            each(y, line);
        }
    } else {
        // The spans' terms set up once for the plane (`PlaneSetup`; the plane is always valid,
        // `the_plane_is_valid`, and the marble is a model, not a perturbed material), shaded
        // span by span from the rows' schedule (`TextureSpans`).
        let Some(setup) = plane().ok().and_then(|p| ev.plane_setup(&p)) else {
            return;
        };
        let Some(line) = line.get_mut(..usize::from(SIZE)) else {
            return;
        };
        let len = usize::from(w.span_len());
        let mut cache = RowCache::<ROW_EVENTS>::new();
        let mut spans = ev.plane_spans(&setup, &mut cache);
        for y in 0..rows {
            for (x, chunk) in (0u16..).step_by(len).zip(line.chunks_mut(len)) {
                let mut px = chunk.iter_mut();
                let n = px.len() as u16;
                if ramp {
                    spans.shade565(x, y, n, |c| {
                        if let Some(p) = px.next() {
                            *p = u32::from(c.to_bits());
                        }
                    });
                } else {
                    spans.shade(x, y, n, |c| {
                        if let Some(p) = px.next() {
                            *p = u32::from(c.to_rgb565().to_bits());
                        }
                    });
                }
            }
            each(y, line);
        }
    }
}

/// [`marble_plane`] with the filter widths from the differences of neighbouring values
/// ([`crate::texture::DifferenceRows`], [`crate::texture::DifferenceSpans`]; approximate): the
/// values without gradients, kept for the next row in a [`DifferenceMemory`] of the plane's
/// width, each colour straight to RGB565.
///
/// [`DifferenceMemory`]: crate::texture::DifferenceMemory
#[cfg(any(feature = "csat", feature = "ramp"))]
#[inline(always)]
pub fn marble_plane_differences<const T: usize, const N: usize>(
    ev: &mut super::super::TextureEvaluator<'_, T, N>,
    w: Workload,
    rows: u16,
    line: &mut [u32],
    mut each: impl FnMut(u16, &[u32]),
) {
    let Some(line) = line.get_mut(..usize::from(SIZE)) else {
        return;
    };
    let mut mem = crate::texture::DifferenceMemory::<{ SIZE as usize }>::new();
    let mut cache = RowCache::<ROW_EVENTS>::new();
    if w.span_len() == SIZE {
        let Some(mut plane) = ev.difference_rows(&span(0, 0, SIZE), &mut cache, &mut mem) else {
            return;
        };
        for y in 0..rows {
            let mut px = line.iter_mut();
            plane.next_shade565(|c| {
                if let Some(p) = px.next() {
                    *p = u32::from(c.to_bits());
                }
            });
            each(y, line);
        }
    } else {
        let Some(setup) = plane().ok().and_then(|p| ev.plane_setup(&p)) else {
            return;
        };
        let len = usize::from(w.span_len());
        let Some(mut spans) = ev.difference_spans(&setup, &mut cache, &mut mem) else {
            return;
        };
        for y in 0..rows {
            for (x, chunk) in (0u16..).step_by(len).zip(line.chunks_mut(len)) {
                let mut px = chunk.iter_mut();
                let n = px.len() as u16;
                spans.shade565(x, y, n, |c| {
                    if let Some(p) = px.next() {
                        *p = u32::from(c.to_bits());
                    }
                });
            }
            each(y, line);
        }
    }
}

/// Row `y` of the marble workload `w` into `line`: each pixel's colour as RGB565 (zero-extended).
#[cfg(any(feature = "csat", feature = "ramp"))]
#[inline(always)]
pub fn marble_row<const T: usize, const N: usize>(
    ev: &mut super::super::TextureEvaluator<'_, T, N>,
    w: Workload,
    y: u16,
    line: &mut [u32],
) {
    let len = w.span_len();
    let mut x0 = 0;
    for chunk in line[..usize::from(SIZE)].chunks_mut(usize::from(len)) {
        let mut px = chunk.iter_mut();
        ev.shade565(&span(y, x0, len), |c| {
            if let Some(p) = px.next() {
                *p = u32::from(c.to_bits());
            }
        });
        x0 += len;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_spans_tile_the_row() {
        for w in Workload::ALL {
            assert_eq!(Workload::by_name(w.name()), Some(w));
            assert_eq!(SIZE % w.span_len(), 0);
        }
        assert_eq!(Workload::by_name("nope"), None);
        let s = span(3, 16, 16);
        assert_eq!(s.s0.to_bits(), [16 * 2048, 3 * 2048, R_BITS]);
        // R_BITS / 65536 is 0.37 to 5e-6 and exact in f32.
        assert!((f64::from(R_BITS) / 65536.0 - 0.37).abs() < 5e-6);
    }

    #[test]
    fn planes_are_their_rows() {
        use crate::span::{EvalMode, EvalOptions};
        for w in Workload::ALL {
            let Some(m) = model(w, HashKind::Integer) else {
                continue;
            };
            let opts = EvalOptions {
                mode: EvalMode::Fd,
                gradients: w.gradients(),
                cull: true,
                ..Default::default()
            };
            let mut ev = SpanEvaluator::new(&m, opts);
            let mut direct = SpanEvaluator::new(
                &m,
                EvalOptions {
                    mode: EvalMode::Direct,
                    ..opts
                },
            );
            let (mut line, mut want) = ([TexValue::ZERO; 256], [TexValue::ZERO; 256]);
            let mut faces = FaceCache::new();
            let mut seen = 0;
            value_plane(&mut ev, w, 40, &mut line, |y, got| {
                value_row(&mut direct, w, y, &mut want, &mut faces);
                assert_eq!(got, &want[..], "{w:?} row {y}");
                seen += 1;
            });
            assert_eq!(seen, 40);
        }
    }

    #[test]
    #[cfg(any(feature = "csat", feature = "ramp"))]
    fn marble_planes_are_their_rows() {
        let mode = crate::span::EvalMode::Auto;
        let textures = [
            #[cfg(feature = "csat")]
            super::super::marble_csat(HashKind::Integer, mode),
            #[cfg(feature = "ramp")]
            super::super::marble_ramp(HashKind::Integer, mode),
        ];
        for (w, tex) in [Workload::MarbleCsat, Workload::MarbleCsatSpan16]
            .into_iter()
            .flat_map(|w| textures.iter().map(move |t| (w, t)))
        {
            let Some(tex) = tex else {
                continue;
            };
            let (mut ev, mut plain) = (tex.evaluator(), tex.evaluator());
            let (mut line, mut want) = ([0u32; 256], [0u32; 256]);
            let mut seen = 0;
            marble_plane(&mut ev, w, 40, &mut line, |y, got| {
                marble_row(&mut plain, w, y, &mut want);
                assert_eq!(got, &want[..], "{w:?} row {y}");
                seen += 1;
            });
            assert_eq!(seen, 40);
        }
    }

    /// The workloads' plane is valid and its spans are [`span`]'s (the 16-pixel-span workloads
    /// take it without a fallback).
    #[test]
    fn the_plane_is_valid() {
        let p = plane().unwrap();
        assert_eq!((p.width(), p.height()), (SIZE, SIZE));
        for (x, y, len) in [(0, 0, 16), (240, 255, 16), (17, 100, 1), (0, 255, SIZE)] {
            assert_eq!(p.span(x, y, len), Some(span(y, x, len)));
        }
        assert_eq!(p.span(241, 0, 16), None);
    }

    #[test]
    fn rows_match_per_pixel_evaluation() {
        use crate::span::{EvalMode, EvalOptions};
        for w in Workload::ALL {
            let Some(m) = model(w, HashKind::Integer) else {
                assert!(w.is_marble() || w.basis(HashKind::Integer).is_none());
                continue;
            };
            let opts = |mode| EvalOptions {
                mode,
                gradients: w.gradients(),
                cull: true,
                ..Default::default()
            };
            let mut fd = SpanEvaluator::new(&m, opts(EvalMode::Fd));
            let mut direct = SpanEvaluator::new(&m, opts(EvalMode::Direct));
            let (mut a, mut b) = ([TexValue::ZERO; 256], [TexValue::ZERO; 256]);
            let (mut fa, mut fb) = (FaceCache::new(), FaceCache::new());
            for y in [0, 1, 2, 77, 78] {
                value_row(&mut fd, w, y, &mut a, &mut fa);
                value_row(&mut direct, w, y, &mut b, &mut fb);
                assert_eq!(a, b, "{w:?} row {y}");
                // Pixel 40 alone.
                let mut one = 0;
                direct.eval(&span(y, 40, 1), |s| {
                    one = if w.gradients() {
                        grad_word(&s)
                    } else {
                        s.f.to_bits() as u32
                    }
                });
                assert_eq!(a[40].to_bits() as u32, one, "{w:?}");
            }
        }
    }
}
