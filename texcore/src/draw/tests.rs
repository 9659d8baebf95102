//! The embedded-graphics drawables against `MockDisplay` pixel art, the span evaluator's
//! colours and the fills of `PrimitiveStyle`.

extern crate std;
use std::vec::Vec;

use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::{BinaryColor, Gray8, Rgb565};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::PrimitiveStyle;

use super::mapping::f32_to_q16;
use super::*;
use crate::filter::{Antialias, ColorStage, GradientNorm};
use crate::format::TexValue;
use crate::model::TextureModel;
use crate::quadric::Quadric;
use crate::ready::{Material, PresetName};
use crate::scene::math::Angle;
use crate::span::EvalMode;
use crate::table::{ColorTable, TableLookup, TableWrap};
use crate::texture::Shader;

/// `f = s` (the quadric `s`), two-entry clamp table: black for `s < 1/2`, white after.
fn split_texture() -> Texture<8, 2> {
    use crate::format::QuadricCoeff;
    let z = QuadricCoeff::ZERO;
    let q = Quadric::linear(QuadricCoeff::ONE, z, z, z);
    let model = TextureModel::new(q, TableWrap::Clamp);
    let table = ColorTable::from_entries([Rgba8888::BLACK, Rgba8888::WHITE]).unwrap();
    let stage = ColorStage::new(
        table,
        TableWrap::Clamp,
        TableLookup::Nearest,
        Antialias::None,
    )
    .unwrap();
    Texture::new(
        Shader::Model(model),
        stage,
        GradientNorm::L2,
        EvalMode::Auto,
    )
}

#[test]
fn rgb565_conversion_is_texcores() {
    for v in 0..=255u8 {
        let c = Rgba8888::new(v, v, v, 255);
        let eg: Rgb565 = display_color(c);
        let tc = c.to_rgb565();
        let eg_bits = embedded_graphics::pixelcolor::raw::RawU16::from(eg).into_inner();
        assert_eq!(eg_bits, tc.to_bits(), "channel value {v}");
        let c = Rgba8888::new(v, 255 - v, v / 3, 0);
        let eg: Rgb565 = display_color(c);
        let eg_bits = embedded_graphics::pixelcolor::raw::RawU16::from(eg).into_inner();
        assert_eq!(eg_bits, c.to_rgb565().to_bits());
    }
}

/// Pixel art: a circle and a rectangle split black/white at `s = 1/2` (8 pixels per unit:
/// the edge between columns 3 and 4 of the anchor).
#[test]
fn mock_display_pixel_art() {
    let tex = split_texture();
    let style = TextureStyle::new(&tex, PlaneMapping::scaled(8));
    let mut display = MockDisplay::<BinaryColor>::new();
    Rectangle::new(Point::new(0, 0), Size::new(8, 3))
        .into_styled(style)
        .draw(&mut display)
        .unwrap();
    Circle::new(Point::new(1, 4), 6)
        .into_styled(style)
        .draw(&mut display)
        .unwrap();
    display.assert_pattern(&[
        "....####", //
        "....####", //
        "....####", //
        "        ", //
        "  ..##  ", //
        " ...### ", //
        " ...### ", //
        " ...### ", //
        " ...### ", //
        "  ..##  ", //
    ]);
    // Moving the anchor moves the texture with the shape.
    let mut display = MockDisplay::<BinaryColor>::new();
    Rectangle::new(Point::new(2, 0), Size::new(8, 1))
        .into_styled(TextureStyle::new(
            &tex,
            PlaneMapping::scaled(8).at(Point::new(2, 0)),
        ))
        .draw(&mut display)
        .unwrap();
    display.assert_pattern(&["  ....####"]);
}

/// The textured shapes cover exactly the pixels of a `PrimitiveStyle` fill.
#[test]
fn shapes_cover_the_filled_pixels() {
    let tex = split_texture();
    let style = TextureStyle::new(&tex, PlaneMapping::scaled(1));
    let check = |draw_tex: &dyn Fn(&mut MockDisplay<BinaryColor>),
                 draw_fill: &dyn Fn(&mut MockDisplay<BinaryColor>)| {
        let mut a = MockDisplay::<BinaryColor>::new();
        draw_tex(&mut a);
        let mut b = MockDisplay::<BinaryColor>::new();
        draw_fill(&mut b);
        // Scale 1 pixel per unit puts every pixel at s >= 1/2: all white (On).
        assert_eq!(a, b);
    };
    let fill = PrimitiveStyle::with_fill(BinaryColor::On);
    let tri = Triangle::new(Point::new(1, 1), Point::new(30, 8), Point::new(9, 40));
    check(&|d| tri.into_styled(style).draw(d).unwrap(), &|d| {
        tri.into_styled(fill).draw(d).unwrap()
    });
    let e = Ellipse::new(Point::new(3, 2), Size::new(40, 17));
    check(&|d| e.into_styled(style).draw(d).unwrap(), &|d| {
        e.into_styled(fill).draw(d).unwrap()
    });
    let r = RoundedRectangle::with_equal_corners(
        Rectangle::new(Point::new(2, 2), Size::new(30, 20)),
        Size::new(6, 6),
    );
    check(&|d| r.into_styled(style).draw(d).unwrap(), &|d| {
        r.into_styled(fill).draw(d).unwrap()
    });
    // Partly off the display (negative coordinates and past 64): clipped, no error.
    let c = Circle::new(Point::new(-10, 40), 40);
    let mut a = MockDisplay::<BinaryColor>::new();
    c.into_styled(style).draw(&mut a).unwrap();
    let mut b = MockDisplay::<BinaryColor>::new();
    b.set_allow_out_of_bounds_drawing(true);
    c.into_styled(fill).draw(&mut b).unwrap();
    assert_eq!(a, b);
}

/// The colours are the evaluator's for the same spans, in every colour type; a rectangle
/// wider than a chunk equals its rows shaded as whole spans.
#[test]
fn colours_are_the_texture_spans() {
    let marble = Material::preset(PresetName::Marble)
        .texture::<256>(Antialias::None)
        .unwrap();
    let mapping = PlaneMapping::scaled(40)
        .rotated(Angle::from_degrees(30))
        .at(Point::new(3, 1));
    let (w, h) = (60u32, 50u32);
    let mut want = Vec::new();
    for y in 0..h as i32 {
        marble
            .evaluator()
            .shade(&mapping.span(0, y, w as u16), |c| want.push(c));
    }
    let mut d = MockDisplay::<Rgb565>::new();
    Rectangle::new(Point::zero(), Size::new(w, h))
        .into_styled(TextureStyle::new(&marble, mapping))
        .draw(&mut d)
        .unwrap();
    let mut g = MockDisplay::<Gray8>::new();
    Circle::new(Point::zero(), 50)
        .into_styled(TextureStyle::new(&marble, mapping))
        .draw(&mut g)
        .unwrap();
    for y in 0..h as i32 {
        for x in 0..w as i32 {
            let c = want[(y as u32 * w + x as u32) as usize];
            assert_eq!(d.get_pixel(Point::new(x, y)), Some(display_color(c)));
            if let Some(gc) = g.get_pixel(Point::new(x, y)) {
                assert_eq!(gc, display_color::<Gray8>(c));
            }
        }
    }
}

/// Shapes drawn through their area's plane set-up equal their rows shaded span by span,
/// also where the mapping's coordinates wrap inside the area (no plane: the spans are set
/// up one by one) or come within a pixel of wrapping (a plane whose origin has wrapped).
#[cfg(feature = "csat")]
#[test]
fn plane_set_up_areas_equal_their_spans() {
    let marble = Material::preset(PresetName::Marble)
        .texture::<256>(Antialias::Csat)
        .unwrap();
    // 40 pixels a texture unit: about 1600 raw units a pixel.
    let base = PlaneMapping::scaled(40).rotated(Angle::from_degrees(10));
    let (w, h) = (40i32, 30i32);
    for (origin, anchor, plane) in [
        ([0, 0, 0], 2, true),
        ([i32::MAX - 70_000, -(1 << 20), 7], 2, true),
        // Every pixel of the area past the wrap: the plane's origin has wrapped.
        ([i32::MAX - 100_000, 0, 0], -100, true),
        ([i32::MAX - 30_000, 0, 0], 2, false),
        ([0, i32::MAX - 10_000, 0], 2, false),
    ] {
        let mapping = base.with_origin(origin).at(Point::new(anchor, 3));
        let area = Rectangle::new(Point::zero(), Size::new(w as u32, h as u32));
        assert_eq!(mapping.span_plane(&area).is_some(), plane, "{origin:?}");
        let mut want = Vec::new();
        for y in 0..h {
            marble
                .evaluator()
                .shade(&mapping.span(0, y, w as u16), |c| want.push(c));
        }
        let mut d = MockDisplay::<Rgb888>::new();
        area.into_styled(TextureStyle::new(&marble, mapping))
            .draw(&mut d)
            .unwrap();
        let mut e = MockDisplay::<Rgb888>::new();
        Circle::new(Point::new(1, 0), 29)
            .into_styled(TextureStyle::new(&marble, mapping))
            .draw(&mut e)
            .unwrap();
        for y in 0..h {
            for x in 0..w {
                let c = display_color(want[(y * w + x) as usize]);
                assert_eq!(d.get_pixel(Point::new(x, y)), Some(c), "{origin:?}");
                if let Some(ec) = e.get_pixel(Point::new(x, y)) {
                    assert_eq!(ec, c, "{origin:?} {x} {y}");
                }
            }
        }
    }
}

/// The widths from differences (`TextureStyle::with_differences`): a rectangle's and a
/// circle's pixels are their row runs shaded by `TextureEvaluator::shade_differences`
/// through one memory, in row order, rows counted from the visible part's top-left (a
/// rectangle partly off the display too); the same pixels as the exact style, and colours
/// near its; a shape wider than `W` and an unfiltered texture are drawn as without it.
#[cfg(all(feature = "differences", feature = "csat"))]
#[test]
fn difference_styles_shade_their_runs() {
    use std::collections::BTreeMap;
    let marble = Material::preset(PresetName::Marble)
        .texture::<256>(Antialias::Csat)
        .unwrap();
    let mapping = PlaneMapping::scaled(24)
        .rotated(Angle::from_degrees(20))
        .at(Point::new(3, 1));
    let exact = TextureStyle::new(&marble, mapping);
    let diff = exact.with_differences::<64>();
    // The reference: each row run of `points` (row order) through one memory.
    let reference = |points: &[Point], top_left: Point| {
        let mut mem = crate::texture::DifferenceMemory::<64>::new();
        let mut ev = marble.evaluator();
        let mut out = BTreeMap::new();
        let mut i = 0;
        while i < points.len() {
            let (y, x0) = (points[i].y, points[i].x);
            let mut n = 1;
            while points.get(i + n) == Some(&Point::new(x0 + n as i32, y)) {
                n += 1;
            }
            let span = mapping.span(x0, y, n as u16);
            let (dx, dy) = ((x0 - top_left.x) as u16, (y - top_left.y) as u16);
            let mut x = x0;
            assert!(ev.shade_differences(&mut mem, dx, dy, &span, |c| {
                out.insert((x, y), display_color::<Rgb888>(c));
                x += 1;
            }));
            i += n;
        }
        out
    };
    let drawn = |d: &MockDisplay<Rgb888>| {
        let mut m = BTreeMap::new();
        for y in 0..64 {
            for x in 0..64 {
                if let Some(c) = d.get_pixel(Point::new(x, y)) {
                    m.insert((x, y), c);
                }
            }
        }
        m
    };
    let rect = Rectangle::new(Point::new(-7, 5), Size::new(50, 40));
    let circle = Circle::new(Point::new(10, 12), 45);
    let visible = |pts: Vec<Point>| -> Vec<Point> {
        pts.into_iter()
            .filter(|p| (0..64).contains(&p.x) && (0..64).contains(&p.y))
            .collect()
    };
    let mut close = (0usize, 0usize);
    let mut shapes = 0;
    for (points, top_left) in [
        (visible(rect.points().collect()), Point::new(0, 5)),
        (
            visible(circle.points().collect()),
            circle.bounding_box().top_left,
        ),
    ] {
        let (mut d, mut e) = (MockDisplay::<Rgb888>::new(), MockDisplay::<Rgb888>::new());
        if shapes == 0 {
            rect.into_styled(diff).draw(&mut d).unwrap();
            rect.into_styled(exact).draw(&mut e).unwrap();
        } else {
            circle.into_styled(diff).draw(&mut d).unwrap();
            circle.into_styled(exact).draw(&mut e).unwrap();
        }
        shapes += 1;
        let (got, want, ex) = (drawn(&d), reference(&points, top_left), drawn(&e));
        assert_eq!(got, want, "shape {shapes}");
        assert!(
            got.keys().eq(ex.keys()),
            "shape {shapes}: the exact style's pixels"
        );
        for (k, c) in &got {
            let x = ex[k];
            let most = c
                .r()
                .abs_diff(x.r())
                .max(c.g().abs_diff(x.g()))
                .max(c.b().abs_diff(x.b()));
            close.0 += usize::from(most <= 8);
            close.1 += 1;
        }
    }
    // Near the exact widths' colours: 95% of the pixels within 8 steps in every channel.
    // (3282 of 3317 when this was written.)
    assert!(close.0 * 100 >= close.1 * 95, "{close:?}");
    // Wider than the memory, and unfiltered: as without the differences.
    let narrow = exact.with_differences::<32>();
    let (mut a, mut b) = (MockDisplay::<Rgb888>::new(), MockDisplay::<Rgb888>::new());
    rect.into_styled(narrow).draw(&mut a).unwrap();
    rect.into_styled(exact).draw(&mut b).unwrap();
    assert_eq!(drawn(&a), drawn(&b));
    let split = split_texture();
    let (mut a, mut b) = (MockDisplay::<Rgb888>::new(), MockDisplay::<Rgb888>::new());
    let plain = TextureStyle::new(&split, mapping);
    circle
        .into_styled(plain.with_differences::<64>())
        .draw(&mut a)
        .unwrap();
    circle.into_styled(plain).draw(&mut b).unwrap();
    assert_eq!(drawn(&a), drawn(&b));
}

/// A 300 x 3 frame (rows longer than [`RUN_CHUNK`]).
#[cfg(feature = "csat")]
struct Wide(Vec<Option<Rgb888>>);

#[cfg(feature = "csat")]
impl Dimensions for Wide {
    fn bounding_box(&self) -> Rectangle {
        Rectangle::new(Point::zero(), Size::new(300, 3))
    }
}

#[cfg(feature = "csat")]
impl DrawTarget for Wide {
    type Color = Rgb888;
    type Error = core::convert::Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        px: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in px {
            if (0..300).contains(&p.x) && (0..3).contains(&p.y) {
                self.0[(p.y * 300 + p.x) as usize] = Some(c);
            }
        }
        Ok(())
    }
}

/// Rows longer than a chunk, shaded in pieces (the rectangle's iterator and a circle's
/// runs), equal whole-row spans.
#[cfg(feature = "csat")]
#[test]
fn chunked_rows_equal_whole_spans() {
    let marble = Material::preset(PresetName::Marble)
        .texture::<256>(Antialias::Csat)
        .unwrap();
    let mapping = PlaneMapping::scaled(50)
        .rotated(Angle::from_degrees(-20))
        .at(Point::new(150, -1));
    let mut want = Vec::new();
    for y in 0..3 {
        marble.evaluator().shade(&mapping.span(0, y, 300), |c| {
            want.push(Some(display_color(c)))
        });
    }
    let mut frame = Wide(std::vec![None; 900]);
    Rectangle::new(Point::new(-5, 0), Size::new(400, 3))
        .into_styled(TextureStyle::new(&marble, mapping))
        .draw(&mut frame)
        .unwrap();
    assert_eq!(frame.0, want);
    let mut frame = Wide(std::vec![None; 900]);
    Ellipse::new(Point::new(-20, -40), Size::new(340, 82))
        .into_styled(TextureStyle::new(&marble, mapping))
        .draw(&mut frame)
        .unwrap();
    assert_eq!(frame.0[300..600], want[300..600]);
}

#[test]
fn f32_set_up_conversion_rounds_to_nearest() {
    // Against f64's round (ties away from zero), which is exact for every f32.
    let mut rng = crate::test_rng::XorShift32::new(0x9E37_79B9);
    let mut values = std::vec![0.5f32, -0.5, 1.5, -2.5, 0.49999997, 8388609.0, -8388609.0];
    values.extend([1.0e30, -1.0e30, f32::MAX, f32::MIN, f32::INFINITY, 3.0e9]);
    for _ in 0..20_000 {
        let v = f32::from_bits(rng.next_u32());
        if v.is_finite() {
            values.push(v);
        }
    }
    for v in values {
        let want = (v as f64).round();
        let want = want.clamp(i64::MIN as f64, i64::MAX as f64) as i64;
        assert_eq!(f32_to_nearest_i64(v), want, "{v:e}");
    }
    assert_eq!(f32_to_nearest_i64(f32::NAN), 0);
    assert_eq!(f32_to_q16(1.0e10), i32::MAX);
    assert_eq!(f32_to_q16(-1.0e10), i32::MIN);
    assert_eq!(f32_to_q16(1.0 / 131072.0), 1, "a tie rounds away from zero");
}

#[test]
fn mapping_set_up() {
    let m = PlaneMapping::scaled(256);
    assert_eq!(m.plane().step_x, [256, 0, 0]);
    let q = m.rotated(Angle::QUARTER);
    assert_eq!(q.plane().step_x, [0, 256, 0]);
    assert_eq!(q.plane().step_y, [-256, 0, 0]);
    assert_eq!(m.rotated_turns(0.25), q);
    assert_eq!(m.rotated_turns(1.25), q);
    assert_eq!(m.zoomed(2.0).plane().step_x, [512, 0, 0]);
    // The (s, t) plane's normal is r: the phase moves r.
    assert_eq!(m.phased(0.5).plane().origin, [0, 0, 65536]);
    assert_eq!(m.rotated_turns(-0.75), q);
    assert_eq!(m.rotated_turns(f32::NAN), m);
    assert_eq!(m.rotated_turns(3.0e9), m, "whole turns only");
    // 0.3 in 16.16 is 19660.8: rounded to 19661, not truncated to 19660.
    let one = PlaneMapping::scaled(1);
    assert_eq!(one.zoomed(0.3).plane().step_x, [19661, 0, 0]);
    assert_eq!(m.zoomed(f32::INFINITY), m.with_zoom(i32::MAX));
    assert_eq!(m.phased(-0.25).plane().origin, [0, 0, 16384]);
    assert_eq!(m.phased(f32::NAN), m);
    assert_eq!(m.with_phase(-32768).plane().origin, [0, 0, 0]);
    let sp = m.at(Point::new(10, 0)).span(10, 0, 4);
    assert_eq!(sp.s0, TexPoint::from_bits(128, 128, 32768));
    let _ = TexValue::ZERO;
}

/// A display error stops drawing and comes back as `D::Error`.
#[test]
fn display_errors_propagate() {
    struct Failing;
    impl Dimensions for Failing {
        fn bounding_box(&self) -> Rectangle {
            Rectangle::new(Point::zero(), Size::new(16, 16))
        }
    }
    impl DrawTarget for Failing {
        type Color = Rgb565;
        type Error = &'static str;
        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
            &mut self,
            _: I,
        ) -> Result<(), &'static str> {
            Err("bus error")
        }
    }
    let tex = split_texture();
    let style = TextureStyle::new(&tex, PlaneMapping::scaled(8));
    let r = Rectangle::new(Point::zero(), Size::new(4, 4)).into_styled(style);
    assert_eq!(r.draw(&mut Failing), Err("bus error"));
    let c = Circle::new(Point::zero(), 5).into_styled(style);
    assert_eq!(c.draw(&mut Failing), Err("bus error"));
    let scene = crate::scene::by_name("zoneplate").unwrap();
    let ts: TexturedScene<'_, _, Rgb565, 8, 2> =
        TexturedScene::new(&scene, core::slice::from_ref(&tex));
    assert_eq!(ts.draw(&mut Failing), Err("bus error"));
}

/// A scene drawn as a `Drawable` equals the renderer's buffer render.
#[test]
fn textured_scene_equals_buffer_render() {
    use crate::sink::RgbaBuffer;
    for name in ["zoneplate", "marble"] {
        let scene = crate::scene::by_name(name).unwrap();
        let scene = scene.at_frame(scene.still());
        let textures: Vec<Texture<8, 256>> = scene
            .slots
            .iter()
            .map(|s| {
                Material::by_name(s.material, crate::hash::HashKind::default())
                    .unwrap()
                    .with_keys(
                        s.keys.unwrap_or(
                            Material::by_name(s.material, crate::hash::HashKind::default())
                                .unwrap()
                                .keys(),
                        ),
                    )
                    .texture(Antialias::None)
                    .unwrap()
            })
            .collect();
        let (w, h) = scene.size();
        let mut img = std::vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
        let mut buf = RgbaBuffer::new(&mut img, w, 0, h).unwrap();
        let r = Renderer::new(&textures);
        let mut band = std::vec![Rgba8888::BLACK; usize::from(w) * 8];
        let mut depth = std::vec![0u16; usize::from(w) * 8];
        r.render_banded(&scene, &mut band, &mut depth, 8, &mut buf)
            .unwrap();
        let mut d = MockDisplay::<Rgb888>::new();
        d.set_allow_overdraw(true);
        d.set_allow_out_of_bounds_drawing(true);
        // MockDisplay is 64 x 64: compare its part of the frame.
        let ts: TexturedScene<'_, _, Rgb888, 8, 256> = TexturedScene::new(&scene, &textures);
        ts.draw(&mut d).unwrap().unwrap();
        for y in 0..64 {
            for x in 0..64 {
                let c = img[y * usize::from(w) + x];
                assert_eq!(
                    d.get_pixel(Point::new(x as i32, y as i32)),
                    Some(Rgb888::new(c.r, c.g, c.b)),
                    "{name} ({x}, {y})"
                );
            }
        }
    }
}

/// With the widths from differences a scene drawn as a `Drawable` equals the renderer's
/// streamed render with a memory of its own (bands of 12 rows' room drawn as bands of 8),
/// differs from the gradients' frame, and a memory narrower than the scene is refused.
#[cfg(all(feature = "differences", feature = "csat"))]
#[test]
fn textured_scene_with_differences_equals_the_renderer() {
    use crate::sink::RgbaBuffer;
    let scene = crate::scene::by_name("marble").unwrap();
    let scene = scene.at_frame(scene.still());
    let textures: Vec<Texture<8, 256>> = scene
        .slots
        .iter()
        .map(|s| {
            let m = Material::by_name(s.material, crate::hash::HashKind::default()).unwrap();
            let keys = s.keys.unwrap_or(m.keys());
            m.with_keys(keys).texture(Antialias::Csat).unwrap()
        })
        .collect();
    let (w, h) = scene.size();
    let mut img = std::vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
    let mut buf = RgbaBuffer::new(&mut img, w, 0, h).unwrap();
    let mut mem = crate::texture::DifferenceMemory::<320>::new();
    let mut faces = crate::span::FaceCache::<16, 8>::new();
    let r = Renderer::new(&textures).with_differences(&mut mem, &mut faces);
    let mut band = std::vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
    let mut depth = std::vec![0u16; usize::from(w) * usize::from(h)];
    r.render_banded(&scene, &mut band, &mut depth, h, &mut buf)
        .unwrap();
    /// A whole frame as a display.
    struct Frame(u32, Vec<Rgb888>);
    impl OriginDimensions for Frame {
        fn size(&self) -> Size {
            Size::new(self.0, self.1.len() as u32 / self.0)
        }
    }
    impl DrawTarget for Frame {
        type Color = Rgb888;
        type Error = core::convert::Infallible;
        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
            &mut self,
            pixels: I,
        ) -> Result<(), Self::Error> {
            for Pixel(p, c) in pixels {
                let i = p.y as usize * self.0 as usize + p.x as usize;
                if let Some(px) = self.1.get_mut(i) {
                    *px = c;
                }
            }
            Ok(())
        }
    }
    let n = usize::from(w) * usize::from(h);
    let mut d = Frame(u32::from(w), std::vec![Rgb888::BLACK; n]);
    let ts: TexturedScene<'_, _, Rgb888, 8, 256, { 320 * 12 }> =
        TexturedScene::new(&scene, &textures);
    ts.with_differences::<320>().draw(&mut d).unwrap().unwrap();
    let mut plain = Frame(u32::from(w), std::vec![Rgb888::BLACK; n]);
    ts.draw(&mut plain).unwrap().unwrap();
    let want: Vec<Rgb888> = img.iter().map(|c| Rgb888::new(c.r, c.g, c.b)).collect();
    assert!(d.1 == want);
    let differ = d.1.iter().zip(&plain.1).filter(|(a, b)| a != b).count();
    assert!(differ > 1000, "{differ}");
    let mut d = MockDisplay::<Rgb888>::new();
    d.set_allow_out_of_bounds_drawing(true);
    let ts: TexturedScene<'_, _, Rgb888, 8, 256> = TexturedScene::new(&scene, &textures);
    assert_eq!(
        ts.with_differences::<64>()
            .draw(&mut d)
            .unwrap()
            .unwrap_err(),
        RenderError::MemoryTooNarrow {
            width: w,
            memory: 64
        }
    );
}
