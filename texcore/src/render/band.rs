//! The band a banded render draws into, by pixel format ([`Band`]): an RGBA8888 band
//! ([`RgbaBuffer`]) or an RGB565 band ([`Rgb565Buffer`]), and the colour a segment's chunks are
//! shaded in ([`ChunkColor`]: the band's own pixel, so an RGB565 band's segments are shaded
//! straight to RGB565).
//!
//! # Guarantees
//!
//! - An RGB565 band holds, at every pixel an opaque object writes, the RGBA8888 band's colour
//!   reduced ([`Rgba8888::to_rgb565`]), bit for bit: its chunks are shaded by
//!   `TextureEvaluator::shade565` (the `shade` colours reduced, bit for bit), or, lit, shaded and
//!   lit in RGBA8888 and reduced as they are written. The rows it flushes are the RGBA8888
//!   band's flushed rows reduced, so a sink that reduces (as [`crate::sink::ChecksumSink`] and
//!   the display sinks do) receives the same pixels either way.
//! - Blending ([`Blend::Over`](super::Blend::Over)) needs the source's alpha: a banded render
//!   into an RGB565 band refuses a scene with a blended object
//!   ([`RenderError::NeedsRgbaBand`](super::RenderError::NeedsRgbaBand)).
//! - Nothing here allocates or panics; writes are clipped to the band.

use super::*;
use crate::color::Rgb565;
use crate::sink::Rgb565Buffer;
use crate::texture::SpanColor;

/// The colour a segment is shaded in, chunk by chunk: the pixel of the band it goes to.
pub(super) trait ChunkColor: SpanColor + Copy + Default {
    /// A chunk's initial pixel (overwritten before it is read).
    const BLANK: Self;

    /// `c` in this format.
    fn from_rgba(c: Rgba8888) -> Self;

    /// The colours of `span` through `e`, in order.
    fn shade_span<const T: usize, const N: usize, F: FnMut(Self)>(
        e: &mut TextureEvaluator<'_, T, N>,
        span: &Span,
        emit: F,
    );

    /// Multiplies the pixels `x..` of row `y` by `light` (nothing for an unlit walk).
    fn light<L: SegmentLight>(light: L, x: u16, y: u16, px: &mut [Self]);
}

impl ChunkColor for Rgba8888 {
    const BLANK: Self = Rgba8888::TRANSPARENT;

    #[inline(always)]
    fn from_rgba(c: Rgba8888) -> Self {
        c
    }

    #[inline(always)]
    fn shade_span<const T: usize, const N: usize, F: FnMut(Self)>(
        e: &mut TextureEvaluator<'_, T, N>,
        span: &Span,
        emit: F,
    ) {
        e.shade(span, emit);
    }

    #[inline(always)]
    fn light<L: SegmentLight>(light: L, x: u16, y: u16, px: &mut [Self]) {
        light.light_span(x, y, px);
    }
}

impl ChunkColor for Rgb565 {
    const BLANK: Self = Rgb565::BLACK;

    #[inline(always)]
    fn from_rgba(c: Rgba8888) -> Self {
        c.to_rgb565()
    }

    #[inline(always)]
    fn shade_span<const T: usize, const N: usize, F: FnMut(Self)>(
        e: &mut TextureEvaluator<'_, T, N>,
        span: &Span,
        emit: F,
    ) {
        e.shade565(span, emit);
    }

    /// Widened, lit and reduced again (a band draw lights in RGBA8888 instead: see
    /// [`BandDraw::triangle`](super::draw::BandDraw::triangle)).
    #[inline(always)]
    fn light<L: SegmentLight>(light: L, x: u16, y: u16, px: &mut [Self]) {
        if !L::LIGHTS {
            return;
        }
        let mut wide = [Rgba8888::TRANSPARENT; CHUNK];
        let mut at = x;
        for part in px.chunks_mut(CHUNK) {
            let Some(w) = wide.get_mut(..part.len()) else {
                return;
            };
            for (d, s) in w.iter_mut().zip(part.iter()) {
                *d = s.to_rgba8888();
            }
            light.light_span(at, y, w);
            for (d, s) in part.iter_mut().zip(w.iter()) {
                *d = s.to_rgb565();
            }
            at = at.saturating_add(part.len() as u16);
        }
    }
}

/// A band of a banded render: rows `y0 .. y0 + height` of the image in one pixel format.
pub(super) trait Band {
    /// The band's pixel, in which unlit segments are shaded.
    type Px: ChunkColor;

    #[cfg(feature = "differences")]
    /// What the band stores a pixel as.
    type Raw;

    #[cfg(feature = "differences")]
    /// The stored form of `p`.
    fn to_raw(p: Self::Px) -> Self::Raw;

    #[cfg(feature = "differences")]
    /// The storage of pixels `x .. x + len` of row `y`, if all of them are inside the band.
    fn raw_row(&mut self, x: u16, y: u16, len: u16) -> Option<&mut [Self::Raw]>;

    /// The band's width in pixels.
    fn width(&self) -> u16;

    /// The band's rows.
    fn height(&self) -> u16;

    /// Moves the band to rows from `y0`.
    fn set_y0(&mut self, y0: u16);

    /// Fills the band with the background `c`.
    fn clear(&mut self, c: Rgba8888);

    /// Writes pixels `x..` of row `y`.
    fn write(&mut self, x: u16, y: u16, px: &[Self::Px]);

    /// Writes RGBA8888 pixels `x..` of row `y` (a lit chunk).
    fn write_rgba(&mut self, x: u16, y: u16, px: &[Rgba8888]);

    /// Composites pixels `x..` of row `y` over the band (alpha "over").
    fn blend(&mut self, x: u16, y: u16, px: &[Self::Px]);

    /// Composites RGBA8888 pixels `x..` of row `y` over the band (a lit chunk).
    fn blend_rgba(&mut self, x: u16, y: u16, px: &[Rgba8888]);

    /// Hands rows `rows` to `sink`.
    fn flush<P: PixelSink>(&self, rows: core::ops::Range<u16>, sink: &mut P);
}

impl Band for RgbaBuffer<'_> {
    type Px = Rgba8888;
    #[cfg(feature = "differences")]
    type Raw = Rgba8888;

    #[cfg(feature = "differences")]
    #[inline(always)]
    fn to_raw(p: Rgba8888) -> Rgba8888 {
        p
    }

    #[cfg(feature = "differences")]
    #[inline(always)]
    fn raw_row(&mut self, x: u16, y: u16, len: u16) -> Option<&mut [Rgba8888]> {
        let x = usize::from(x);
        self.row_mut(y)?.get_mut(x..x + usize::from(len))
    }

    #[inline(always)]
    fn width(&self) -> u16 {
        RgbaBuffer::width(self)
    }

    #[inline(always)]
    fn height(&self) -> u16 {
        RgbaBuffer::height(self)
    }

    #[inline(always)]
    fn set_y0(&mut self, y0: u16) {
        RgbaBuffer::set_y0(self, y0);
    }

    #[inline(always)]
    fn clear(&mut self, c: Rgba8888) {
        RgbaBuffer::clear(self, c);
    }

    #[inline(always)]
    fn write(&mut self, x: u16, y: u16, px: &[Rgba8888]) {
        self.write_span(x, y, px);
    }

    #[inline(always)]
    fn write_rgba(&mut self, x: u16, y: u16, px: &[Rgba8888]) {
        self.write_span(x, y, px);
    }

    #[inline(always)]
    fn blend(&mut self, x: u16, y: u16, px: &[Rgba8888]) {
        self.blend_span(x, y, px);
    }

    #[inline(always)]
    fn blend_rgba(&mut self, x: u16, y: u16, px: &[Rgba8888]) {
        self.blend_span(x, y, px);
    }

    #[inline(always)]
    fn flush<P: PixelSink>(&self, rows: core::ops::Range<u16>, sink: &mut P) {
        flush_rows(self, rows, sink);
    }
}

impl Band for Rgb565Buffer<'_> {
    type Px = Rgb565;
    #[cfg(feature = "differences")]
    type Raw = u16;

    #[cfg(feature = "differences")]
    #[inline(always)]
    fn to_raw(p: Rgb565) -> u16 {
        p.to_bits()
    }

    #[cfg(feature = "differences")]
    #[inline(always)]
    fn raw_row(&mut self, x: u16, y: u16, len: u16) -> Option<&mut [u16]> {
        let x = usize::from(x);
        self.row_mut(y)?.get_mut(x..x + usize::from(len))
    }

    #[inline(always)]
    fn width(&self) -> u16 {
        Rgb565Buffer::width(self)
    }

    #[inline(always)]
    fn height(&self) -> u16 {
        Rgb565Buffer::height(self)
    }

    #[inline(always)]
    fn set_y0(&mut self, y0: u16) {
        Rgb565Buffer::set_y0(self, y0);
    }

    #[inline(always)]
    fn clear(&mut self, c: Rgba8888) {
        Rgb565Buffer::clear(self, c.to_rgb565());
    }

    #[inline(always)]
    fn write(&mut self, x: u16, y: u16, px: &[Rgb565]) {
        write_rgb565(self, x, y, px);
    }

    #[inline(always)]
    fn write_rgba(&mut self, x: u16, y: u16, px: &[Rgba8888]) {
        self.write_span(x, y, px);
    }

    /// An RGB565 pixel is opaque: composited "over", it replaces what is behind it.
    #[inline(always)]
    fn blend(&mut self, x: u16, y: u16, px: &[Rgb565]) {
        write_rgb565(self, x, y, px);
    }

    #[inline(always)]
    fn blend_rgba(&mut self, x: u16, y: u16, px: &[Rgba8888]) {
        self.blend_span(x, y, px);
    }

    #[inline(always)]
    fn flush<P: PixelSink>(&self, rows: core::ops::Range<u16>, sink: &mut P) {
        flush_rows_rgb565(self, rows, sink);
    }
}

/// Writes `px` to pixels `x..` of row `y` of `buf`, clipped.
#[inline(always)]
fn write_rgb565(buf: &mut Rgb565Buffer<'_>, x: u16, y: u16, px: &[Rgb565]) {
    let x0 = usize::from(x);
    if let Some(dst) = buf.row_mut(y).and_then(|r| r.get_mut(x0..)) {
        for (d, s) in dst.iter_mut().zip(px) {
            *d = s.to_bits();
        }
    }
}

/// Writes the rows `rows` of `buf` to `sink` (out of line, as [`flush_rows`]).
#[inline(never)]
fn flush_rows_rgb565<P: PixelSink>(
    buf: &Rgb565Buffer<'_>,
    rows: core::ops::Range<u16>,
    sink: &mut P,
) {
    for y in rows {
        if let Some(row) = buf.row(y) {
            sink.write_rgb565_span(0, y, row);
        }
    }
}
