//! Pixel sinks: where rendered rows go.
//!
//! [`PixelSink`] has one required method, [`PixelSink::write_span`] (a run of pixels of one row),
//! and two overridable fast paths, [`PixelSink::fill_span`] (a run of one colour), in the manner
//! of `embedded_graphics::DrawTarget::fill_contiguous`, and [`PixelSink::write_rgb565_span`] (a
//! run of RGB565 pixels, what an RGB565 frame hands over). Implementations:
//! - [`RgbaBuffer`]: an RGBA8888 buffer over a caller-owned slice (a whole frame, or a band);
//! - [`Rgb565Buffer`]: an RGB565 buffer over a caller-owned `u16` slice;
//! - [`ChecksumSink`]: only a checksum, for comparing device and host renders;
//! - `DrawTargetSink` (feature `embedded-graphics`): one `fill_contiguous` per span, so a display
//!   driver receives whole rows.
//!
//! Guarantees: sinks clip every write to their rectangle and never panic, whatever the
//! coordinates.

use crate::color::{Rgb565, Rgba8888};

/// A destination for rows of pixels.
pub trait PixelSink {
    /// Writes `colors` to pixels `x .. x + colors.len()` of row `y`.
    fn write_span(&mut self, x: u16, y: u16, colors: &[Rgba8888]);

    /// Writes the RGB565 pixels `bits` (raw, [`Rgb565::to_bits`]: the layout of a display's
    /// frame memory) to pixels `x .. x + bits.len()` of row `y`. The default widens them
    /// ([`Rgb565::to_rgba8888`], opaque) through [`PixelSink::write_span`] in chunks of 32; a sink
    /// that stores or hashes RGB565 overrides it and takes them as they are. Either way an RGB565
    /// pixel reduced by the sink ([`Rgba8888::to_rgb565`]) comes back unchanged.
    fn write_rgb565_span(&mut self, x: u16, y: u16, bits: &[u16]) {
        let mut wide = [Rgba8888::TRANSPARENT; 32];
        let mut at = x;
        for part in bits.chunks(32) {
            let Some(w) = wide.get_mut(..part.len()) else {
                return;
            };
            for (d, &s) in w.iter_mut().zip(part) {
                *d = Rgb565(s).to_rgba8888();
            }
            self.write_span(at, y, w);
            at = at.saturating_add(part.len() as u16);
        }
    }

    /// Fills `len` pixels of row `y` from `x` with one colour. The default writes chunks through
    /// [`PixelSink::write_span`].
    fn fill_span(&mut self, x: u16, y: u16, len: u16, color: Rgba8888) {
        let chunk = [color; 32];
        let mut done = 0u16;
        while done < len {
            let n = (len - done).min(32);
            self.write_span(x.saturating_add(done), y, &chunk[..usize::from(n)]);
            done += n;
        }
    }
}

/// The part of `[x, x + n)` inside `[0, width)`: (first pixel, offset into the input, count).
#[inline]
fn clip_run(x: u16, n: usize, width: u16) -> Option<(usize, usize, usize)> {
    let x = usize::from(x);
    let w = usize::from(width);
    if x >= w || n == 0 {
        return None;
    }
    Some((x, 0, n.min(w - x)))
}

/// An RGBA8888 image over a caller-owned slice: rows `y0 .. y0 + height` of a `width`-pixel image
/// (a full frame with `y0 = 0`, or one band).
#[derive(Debug)]
pub struct RgbaBuffer<'a> {
    data: &'a mut [Rgba8888],
    width: u16,
    y0: u16,
    height: u16,
}

impl<'a> RgbaBuffer<'a> {
    /// A buffer of `width x height` pixels for rows starting at `y0`; `None` if the slice is too
    /// small.
    pub fn new(data: &'a mut [Rgba8888], width: u16, y0: u16, height: u16) -> Option<Self> {
        if data.len() < usize::from(width) * usize::from(height) {
            return None;
        }
        Some(RgbaBuffer {
            data,
            width,
            y0,
            height,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u16 {
        self.width
    }

    /// First row.
    pub fn y0(&self) -> u16 {
        self.y0
    }

    /// Number of rows.
    pub fn height(&self) -> u16 {
        self.height
    }

    /// Moves the buffer to rows `y0 .. y0 + height` (band rendering); the contents are kept.
    pub fn set_y0(&mut self, y0: u16) {
        self.y0 = y0;
    }

    /// The pixels of row `y` (absolute), if inside.
    pub fn row(&self, y: u16) -> Option<&[Rgba8888]> {
        let r = usize::from(y.checked_sub(self.y0)?);
        if r >= usize::from(self.height) {
            return None;
        }
        let w = usize::from(self.width);
        self.data.get(r * w..(r + 1) * w)
    }

    /// Mutable pixels of row `y` (absolute), if inside.
    pub fn row_mut(&mut self, y: u16) -> Option<&mut [Rgba8888]> {
        let r = usize::from(y.checked_sub(self.y0)?);
        if r >= usize::from(self.height) {
            return None;
        }
        let w = usize::from(self.width);
        self.data.get_mut(r * w..(r + 1) * w)
    }

    /// Fills every pixel.
    pub fn clear(&mut self, c: Rgba8888) {
        let n = usize::from(self.width) * usize::from(self.height);
        for p in self.data.iter_mut().take(n) {
            *p = c;
        }
    }

    /// Composites `colors` over pixels `x ..` of row `y` (alpha "over").
    pub fn blend_span(&mut self, x: u16, y: u16, colors: &[Rgba8888]) {
        let width = self.width;
        if let (Some(row), Some((x0, off, n))) = (self.row_mut(y), clip_run(x, colors.len(), width))
        {
            if let (Some(dst), Some(src)) = (row.get_mut(x0..x0 + n), colors.get(off..off + n)) {
                for (d, s) in dst.iter_mut().zip(src) {
                    *d = crate::color::over(*s, *d);
                }
            }
        }
    }
}

impl PixelSink for RgbaBuffer<'_> {
    fn write_span(&mut self, x: u16, y: u16, colors: &[Rgba8888]) {
        let width = self.width;
        if let (Some(row), Some((x0, off, n))) = (self.row_mut(y), clip_run(x, colors.len(), width))
        {
            if let (Some(dst), Some(src)) = (row.get_mut(x0..x0 + n), colors.get(off..off + n)) {
                dst.copy_from_slice(src);
            }
        }
    }

    fn fill_span(&mut self, x: u16, y: u16, len: u16, color: Rgba8888) {
        let width = self.width;
        if let (Some(row), Some((x0, _, n))) =
            (self.row_mut(y), clip_run(x, usize::from(len), width))
        {
            for p in row.iter_mut().skip(x0).take(n) {
                *p = color;
            }
        }
    }
}

/// An RGB565 image (display format) over a caller-owned slice, rows `y0 .. y0 + height`.
#[derive(Debug)]
pub struct Rgb565Buffer<'a> {
    data: &'a mut [u16],
    width: u16,
    y0: u16,
    height: u16,
}

impl<'a> Rgb565Buffer<'a> {
    /// A buffer of `width x height` pixels for rows from `y0`; `None` if the slice is too small.
    pub fn new(data: &'a mut [u16], width: u16, y0: u16, height: u16) -> Option<Self> {
        if data.len() < usize::from(width) * usize::from(height) {
            return None;
        }
        Some(Rgb565Buffer {
            data,
            width,
            y0,
            height,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> u16 {
        self.width
    }

    /// First row.
    pub fn y0(&self) -> u16 {
        self.y0
    }

    /// Number of rows.
    pub fn height(&self) -> u16 {
        self.height
    }

    /// Moves the buffer to rows from `y0`.
    pub fn set_y0(&mut self, y0: u16) {
        self.y0 = y0;
    }

    /// The pixels of row `y` (absolute), if inside.
    pub fn row(&self, y: u16) -> Option<&[u16]> {
        let r = usize::from(y.checked_sub(self.y0)?);
        if r >= usize::from(self.height) {
            return None;
        }
        let w = usize::from(self.width);
        self.data.get(r * w..(r + 1) * w)
    }

    /// Mutable pixels of row `y` (absolute), if inside.
    pub fn row_mut(&mut self, y: u16) -> Option<&mut [u16]> {
        let r = usize::from(y.checked_sub(self.y0)?);
        if r >= usize::from(self.height) {
            return None;
        }
        let w = usize::from(self.width);
        self.data.get_mut(r * w..(r + 1) * w)
    }

    /// Fills every pixel.
    pub fn clear(&mut self, c: Rgb565) {
        let n = usize::from(self.width) * usize::from(self.height);
        if let Some(d) = self.data.get_mut(..n) {
            crate::raster::fill_u16(d, c.to_bits());
        }
    }

    /// Composites `colors` over pixels `x ..` of row `y` (alpha "over", [`crate::color::over`])
    /// against the stored RGB565 pixels widened ([`Rgb565::to_rgba8888`]), the result reduced
    /// ([`Rgba8888::to_rgb565`]): what blending into an RGB565 frame can do. (An RGBA8888 frame
    /// reduced afterwards can differ where several blends stack: it keeps 8 bits a channel
    /// between them.)
    pub fn blend_span(&mut self, x: u16, y: u16, colors: &[Rgba8888]) {
        let width = self.width;
        if let (Some(row), Some((x0, off, n))) = (self.row_mut(y), clip_run(x, colors.len(), width))
        {
            if let (Some(dst), Some(src)) = (row.get_mut(x0..x0 + n), colors.get(off..off + n)) {
                for (d, s) in dst.iter_mut().zip(src) {
                    let under = Rgb565(*d).to_rgba8888();
                    *d = crate::color::over(*s, under).to_rgb565().to_bits();
                }
            }
        }
    }
}

impl PixelSink for Rgb565Buffer<'_> {
    fn write_span(&mut self, x: u16, y: u16, colors: &[Rgba8888]) {
        let width = self.width;
        if let (Some(row), Some((x0, off, n))) = (self.row_mut(y), clip_run(x, colors.len(), width))
        {
            for (d, s) in row[x0..x0 + n].iter_mut().zip(&colors[off..off + n]) {
                *d = s.to_rgb565().to_bits();
            }
        }
    }

    fn write_rgb565_span(&mut self, x: u16, y: u16, bits: &[u16]) {
        let width = self.width;
        if let (Some(row), Some((x0, off, n))) = (self.row_mut(y), clip_run(x, bits.len(), width)) {
            if let (Some(dst), Some(src)) = (row.get_mut(x0..x0 + n), bits.get(off..off + n)) {
                dst.copy_from_slice(src);
            }
        }
    }
}

/// An `embedded_graphics` draw target as a sink: every span becomes one `fill_contiguous` call of
/// RGB565 pixels (one call per row run, which display drivers stream as a window write).
#[cfg(feature = "embedded-graphics")]
#[derive(Debug)]
pub struct DrawTargetSink<'d, D> {
    target: &'d mut D,
    error: bool,
}

#[cfg(feature = "embedded-graphics")]
impl<'d, D> DrawTargetSink<'d, D>
where
    D: embedded_graphics_core::draw_target::DrawTarget<
        Color = embedded_graphics_core::pixelcolor::Rgb565,
    >,
{
    /// Wraps a draw target.
    pub fn new(target: &'d mut D) -> Self {
        DrawTargetSink {
            target,
            error: false,
        }
    }

    /// Whether any draw call returned an error.
    pub fn had_error(&self) -> bool {
        self.error
    }
}

#[cfg(feature = "embedded-graphics")]
impl<D> PixelSink for DrawTargetSink<'_, D>
where
    D: embedded_graphics_core::draw_target::DrawTarget<
        Color = embedded_graphics_core::pixelcolor::Rgb565,
    >,
{
    fn write_span(&mut self, x: u16, y: u16, colors: &[Rgba8888]) {
        use embedded_graphics_core::geometry::{Point, Size};
        use embedded_graphics_core::primitives::Rectangle;
        let n = colors.len().min(usize::from(u16::MAX)) as u32;
        let area = Rectangle::new(Point::new(i32::from(x), i32::from(y)), Size::new(n, 1));
        let pixels = colors
            .iter()
            .map(|c| embedded_graphics_core::pixelcolor::Rgb565::from(c.to_rgb565()));
        if self.target.fill_contiguous(&area, pixels).is_err() {
            self.error = true;
        }
    }

    /// The pixels as they are, one `fill_contiguous` call.
    fn write_rgb565_span(&mut self, x: u16, y: u16, bits: &[u16]) {
        use embedded_graphics_core::geometry::{Point, Size};
        use embedded_graphics_core::primitives::Rectangle;
        let n = bits.len().min(usize::from(u16::MAX)) as u32;
        let area = Rectangle::new(Point::new(i32::from(x), i32::from(y)), Size::new(n, 1));
        let pixels = bits
            .iter()
            .map(|&b| embedded_graphics_core::pixelcolor::Rgb565::from(Rgb565(b)));
        if self.target.fill_contiguous(&area, pixels).is_err() {
            self.error = true;
        }
    }

    fn fill_span(&mut self, x: u16, y: u16, len: u16, color: Rgba8888) {
        use embedded_graphics_core::geometry::{Point, Size};
        use embedded_graphics_core::primitives::Rectangle;
        let area = Rectangle::new(
            Point::new(i32::from(x), i32::from(y)),
            Size::new(u32::from(len), 1),
        );
        let c = embedded_graphics_core::pixelcolor::Rgb565::from(color.to_rgb565());
        if self.target.fill_solid(&area, c).is_err() {
            self.error = true;
        }
    }
}

/// A sink that keeps only a checksum of the image: FNV-1a (32 bit) over the RGB565 pixels
/// (little-endian bytes) in the order they arrive. Rendering writes every row once, top to bottom
/// (banded) or object by object (streamed), so compare checksums of the same render path; the
/// device and the host use this same sink, so their checksums of a scene must be equal.
///
/// The checksum is the whole state of the hash, so an image written in several parts by
/// separate calls (horizontal strips of a banded render, top to bottom) gets the checksum of the
/// whole image when each part continues the previous one's with [`ChecksumSink::resume`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChecksumSink {
    hash: u32,
    pixels: u64,
}

impl Default for ChecksumSink {
    fn default() -> Self {
        ChecksumSink {
            hash: 0x811C_9DC5,
            pixels: 0,
        }
    }
}

impl ChecksumSink {
    /// A fresh checksum.
    pub fn new() -> Self {
        Self::default()
    }

    /// Continues a checksum: the sink is in the state it was in when it returned `checksum`
    /// (its pixel count starts again at 0). `resume(ChecksumSink::new().checksum())` is a fresh
    /// sink.
    pub fn resume(checksum: u32) -> Self {
        ChecksumSink {
            hash: checksum,
            pixels: 0,
        }
    }

    /// The checksum so far.
    pub fn checksum(&self) -> u32 {
        self.hash
    }

    /// Pixels seen.
    pub fn pixels(&self) -> u64 {
        self.pixels
    }

    /// Adds one RGB565 pixel.
    #[inline]
    pub fn add_rgb565(&mut self, p: u16) {
        self.hash = fnv1a_rgb565(self.hash, p);
        self.pixels += 1;
    }

    /// Adds RGB565 pixels in order: the same checksum as [`ChecksumSink::add_rgb565`] on each,
    /// in a loop that takes four pixels a turn.
    #[inline]
    pub fn add_rgb565_row(&mut self, pixels: &[u16]) {
        let mut h = self.hash;
        let mut quads = pixels.chunks_exact(4);
        for quad in &mut quads {
            if let [a, b, c, d] = *quad {
                h = fnv1a_rgb565(fnv1a_rgb565(fnv1a_rgb565(fnv1a_rgb565(h, a), b), c), d);
            }
        }
        for &p in quads.remainder() {
            h = fnv1a_rgb565(h, p);
        }
        self.hash = h;
        self.pixels += pixels.len() as u64;
    }
}

/// FNV-1a's 32-bit prime.
const FNV_PRIME: u32 = 0x0100_0193;

/// FNV-1a continued from `hash` over the two bytes of the RGB565 pixel `p`, low byte first.
#[inline(always)]
const fn fnv1a_rgb565(hash: u32, p: u16) -> u32 {
    let h = (hash ^ (p & 0xFF) as u32).wrapping_mul(FNV_PRIME);
    (h ^ (p >> 8) as u32).wrapping_mul(FNV_PRIME)
}

impl PixelSink for ChecksumSink {
    fn write_span(&mut self, _x: u16, _y: u16, colors: &[Rgba8888]) {
        // The hash in a register for the span and the count added once: the same checksum as
        // `add_rgb565` on each pixel.
        let mut h = self.hash;
        for c in colors {
            h = fnv1a_rgb565(h, c.to_rgb565().to_bits());
        }
        self.hash = h;
        self.pixels += colors.len() as u64;
    }

    /// The pixels as they are: the checksum [`PixelSink::write_span`] gives their widened
    /// colours (`to_rgba8888().to_rgb565()` is the pixel itself).
    /// The pixels as they are ([`ChecksumSink::add_rgb565_row`]): the checksum
    /// [`PixelSink::write_span`] gives their widened colours.
    fn write_rgb565_span(&mut self, _x: u16, _y: u16, bits: &[u16]) {
        self.add_rgb565_row(bits);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksum_is_fnv1a_of_rgb565_bytes() {
        let mut c = ChecksumSink::new();
        c.write_span(0, 0, &[Rgba8888::WHITE, Rgba8888::BLACK]);
        // FNV-1a of [ff, ff, 00, 00]
        let mut h: u32 = 0x811C_9DC5;
        for b in [0xFFu8, 0xFF, 0, 0] {
            h ^= u32::from(b);
            h = h.wrapping_mul(0x0100_0193);
        }
        assert_eq!(c.checksum(), h);
        assert_eq!(c.pixels(), 2);
    }

    #[test]
    fn checksum_resumes_across_parts() {
        let rows = [
            [Rgba8888::WHITE, Rgba8888::new(1, 2, 3, 255)],
            [Rgba8888::new(200, 100, 50, 255), Rgba8888::BLACK],
            [Rgba8888::new(9, 99, 199, 255), Rgba8888::WHITE],
        ];
        let mut whole = ChecksumSink::new();
        for (y, r) in (0..).zip(&rows) {
            whole.write_span(0, y, r);
        }
        let mut top = ChecksumSink::resume(ChecksumSink::new().checksum());
        top.write_span(0, 0, &rows[0]);
        let mut rest = ChecksumSink::resume(top.checksum());
        rest.write_span(0, 1, &rows[1]);
        rest.write_span(0, 2, &rows[2]);
        assert_eq!(rest.checksum(), whole.checksum());
        assert_eq!(rest.pixels(), 4);
        assert_eq!(ChecksumSink::resume(0x811C_9DC5), ChecksumSink::new());
    }

    #[test]
    fn a_row_is_its_pixels_one_by_one() {
        let mut rng = crate::test_rng::XorShift32::new(0x2545_F491);
        let pixels: [u16; 37] = core::array::from_fn(|_| rng.next_u32() as u16);
        // Every length, odd and even, from every resumed state.
        for n in 0..=pixels.len() {
            for start in [0x811C_9DC5, 0, 0xDEAD_BEEF] {
                let mut one = ChecksumSink::resume(start);
                for &p in &pixels[..n] {
                    one.add_rgb565(p);
                }
                let mut row = ChecksumSink::resume(start);
                row.add_rgb565_row(&pixels[..n]);
                assert_eq!(row, one, "{n} pixels from {start:#x}");
            }
        }
    }

    #[test]
    fn rgba_buffer_clips_and_bands() {
        let mut data = [Rgba8888::BLACK; 8 * 2];
        let mut b = RgbaBuffer::new(&mut data, 8, 10, 2).unwrap();
        let red = Rgba8888::new(255, 0, 0, 255);
        b.write_span(6, 10, &[red; 5]); // clipped to 2 pixels
        b.write_span(0, 9, &[red; 3]); // above the band: ignored
        b.write_span(0, 12, &[red; 3]); // below: ignored
        b.fill_span(65535, 11, 65535, red); // far right: ignored
        b.fill_span(1, 11, 2, red);
        let row10 = b.row(10).unwrap();
        assert_eq!(row10[5], Rgba8888::BLACK);
        assert_eq!(row10[6], red);
        assert_eq!(row10[7], red);
        let row11 = b.row(11).unwrap();
        assert_eq!(&row11[..4], &[Rgba8888::BLACK, red, red, Rgba8888::BLACK]);
        assert!(RgbaBuffer::new(&mut [Rgba8888::BLACK; 3], 2, 0, 2).is_none());
    }

    #[test]
    fn blending_over() {
        let mut data = [Rgba8888::new(0, 0, 255, 255); 4];
        let mut b = RgbaBuffer::new(&mut data, 4, 0, 1).unwrap();
        b.blend_span(
            1,
            0,
            &[
                Rgba8888::new(255, 255, 255, 0),
                Rgba8888::new(255, 255, 255, 255),
            ],
        );
        let r = b.row(0).unwrap();
        assert_eq!(r[1], Rgba8888::new(0, 0, 255, 255));
        assert_eq!(r[2], Rgba8888::new(255, 255, 255, 255));
    }

    #[test]
    fn rgb565_buffer() {
        let mut data = [0u16; 4];
        let mut b = Rgb565Buffer::new(&mut data, 4, 0, 1).unwrap();
        b.fill_span(1, 0, 2, Rgba8888::WHITE);
        assert_eq!(data, [0, 0xFFFF, 0xFFFF, 0]);
    }
}
