//! Text in the report's images, drawn with embedded-graphics' mono fonts (`FONT_6X10` at scale 1,
//! `FONT_10X20` at scale 2 and above) into an RGB buffer (no system fonts needed).
//!
//! Guarantees: drawing is clipped to the buffer (text partly or wholly outside it draws what is
//! inside, never panics); [`text_width`] and [`text_height`] are the exact extent the font gives.

use std::convert::Infallible;

use embedded_graphics::mono_font::ascii::{FONT_10X20, FONT_6X10};
use embedded_graphics::mono_font::{MonoFont, MonoTextStyle};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::text::{Baseline, Text};

/// The font of a scale: 6 x 10 at 1, 10 x 20 from 2.
fn font(scale: u32) -> &'static MonoFont<'static> {
    if scale >= 2 {
        &FONT_10X20
    } else {
        &FONT_6X10
    }
}

/// Width of `text` in pixels at `scale` (the character cells, without the spacing after the last).
pub fn text_width(text: &str, scale: u32) -> u32 {
    let f = font(scale);
    let n = text.chars().count() as u32;
    (n * (f.character_size.width + f.character_spacing)).saturating_sub(f.character_spacing)
}

/// Height of a line of text at `scale`.
pub fn text_height(scale: u32) -> u32 {
    font(scale).character_size.height
}

/// An RGB buffer (3 bytes a pixel, rows of `width` pixels) as an embedded-graphics `DrawTarget`;
/// pixels outside it are dropped.
struct RgbBuffer<'a> {
    buf: &'a mut [u8],
    width: u32,
    height: u32,
}

impl OriginDimensions for RgbBuffer<'_> {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for RgbBuffer<'_> {
    type Color = Rgb888;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Self::Color>>,
    {
        for Pixel(p, c) in pixels {
            if p.x < 0 || p.y < 0 || p.x >= self.width as i32 || p.y >= self.height as i32 {
                continue;
            }
            let i = (p.y as usize * self.width as usize + p.x as usize) * 3;
            if let Some(px) = self.buf.get_mut(i..i + 3) {
                px.copy_from_slice(&[c.r(), c.g(), c.b()]);
            }
        }
        Ok(())
    }
}

/// Draws `text` with its top-left corner at `(x, y)` into an RGB buffer `width` pixels wide
/// (clipped), in the font of `scale`.
#[allow(clippy::too_many_arguments)]
pub fn draw_text(
    buf: &mut [u8],
    width: u32,
    height: u32,
    x: i32,
    y: i32,
    text: &str,
    scale: u32,
    rgb: [u8; 3],
) {
    let mut target = RgbBuffer { buf, width, height };
    let style = MonoTextStyle::new(font(scale), Rgb888::new(rgb[0], rgb[1], rgb[2]));
    let Ok(_) = Text::with_baseline(text, Point::new(x, y), style, Baseline::Top).draw(&mut target);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_and_clips() {
        let (w, h) = (40u32, 12u32);
        let mut buf = vec![0u8; (w * h * 3) as usize];
        draw_text(&mut buf, w, h, 1, 1, "F=4", 1, [255, 255, 255]);
        let lit = buf.chunks(3).filter(|p| p[0] == 255).count();
        assert!(lit > 20, "{lit}");
        // Nothing is drawn outside the text's cells.
        let right = 1 + text_width("F=4", 1);
        for y in 0..h {
            for x in right..w {
                assert_eq!(buf[((y * w + x) * 3) as usize], 0, "({x}, {y})");
            }
        }
        // Off-image text is clipped, never panics.
        draw_text(&mut buf, w, h, -100, -100, "ABC", 3, [1, 2, 3]);
        draw_text(&mut buf, w, h, 35, 8, "XYZ", 2, [1, 2, 3]);
        assert_eq!(text_width("AB", 1), 12);
        assert_eq!(text_height(1), 10);
        assert_eq!(text_height(2), 20);
    }
}
