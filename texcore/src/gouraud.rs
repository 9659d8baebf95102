//! Gouraud shading: the per-vertex light of a screen triangle ([`crate::light`]) interpolated
//! screen-linearly across its pixels, and the modulation of the texture colours of a span by it
//! (the lighting stage of [`crate::render`], after the colour table and before blending).
//!
//! Guarantees:
//! - Integer only: the light of a pixel is a pure function of the triangle's screen vertices,
//!   their lights and the pixel's position, the same bits on the host and every device.
//! - The light of pixel `(x, y)` is `a + bx x + by y` evaluated exactly (no overflow is
//!   possible: the plane's coefficients are clamped at construction so that every term fits),
//!   so it does not depend on how a row is split into segments or chunks: banded and streamed
//!   rendering, strips and bins all give the same pixels.
//! - Each channel is clamped to `[0, ONE]` (`Q16.16`) before it scales the colour; alpha is
//!   untouched. A triangle with no area gets the mean of its vertex lights (flat).
//! - Nothing here panics or allocates.

use crate::color::Rgba8888;
use crate::light::{modulate_channel, LightRgb};
use crate::raster::ScreenVertex;
use crate::scene::math::{div_round_128, div_round_128_rt, ONE};

/// Fractional bits kept below `Q16.16` in the plane's coefficients.
const FRAC: u32 = 16;
/// Bound on the per-pixel steps (`Q16.32`): 2^24 `ONE`s per pixel, far beyond any light change
/// that covers a pixel centre; with x, y below 2^16 every product fits in 2^56.
const STEP_MAX: i64 = 1 << 40;
/// Bound on the value at pixel (0, 0) (`Q16.32`), so that `a + bx x + by y` fits in `i64`.
const BASE_MAX: i64 = 1 << 58;

/// The light of a screen triangle as a plane over the pixel centres: per channel, the value at
/// pixel `(0, 0)` and the steps per pixel in `x` and `y`, `Q16.32`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriangleLight {
    a: [i64; 3],
    bx: [i64; 3],
    by: [i64; 3],
}

impl TriangleLight {
    /// A uniform light (every pixel gets `light`).
    pub const fn flat(light: LightRgb) -> TriangleLight {
        TriangleLight {
            a: [
                (light[0] as i64) << FRAC,
                (light[1] as i64) << FRAC,
                (light[2] as i64) << FRAC,
            ],
            bx: [0; 3],
            by: [0; 3],
        }
    }

    /// The plane through the three vertices' lights (`light[i]` at `t[i]`, each channel
    /// `Q16.16`), over pixel centres (`x + 0.5`, `y + 0.5`).
    pub fn new(t: &[ScreenVertex; 3], light: &[LightRgb; 3]) -> TriangleLight {
        let p = t.map(|v| (i128::from(v.x.to_bits()), i128::from(v.y.to_bits())));
        let (dx1, dy1) = (p[1].0 - p[0].0, p[1].1 - p[0].1);
        let (dx2, dy2) = (p[2].0 - p[0].0, p[2].1 - p[0].1);
        let det = dx1 * dy2 - dx2 * dy1;
        if det == 0 {
            let mean = core::array::from_fn(|c| {
                let s: i64 = light.iter().map(|l| i64::from(l[c])).sum();
                (s / 3) as i32
            });
            return TriangleLight::flat(mean);
        }
        let mut out = TriangleLight::flat(light[0]);
        #[allow(clippy::needless_range_loop)] // `c` indexes four arrays in step
        for c in 0..3 {
            let l0 = i128::from(light[0][c]);
            let (dl1, dl2) = (i128::from(light[1][c]) - l0, i128::from(light[2][c]) - l0);
            // Per 1/16 pixel: (dl1 dy2 - dl2 dy1) / det; per pixel 16 times that; FRAC more bits.
            let sx = div_round_128_rt((dl1 * dy2 - dl2 * dy1) << (FRAC + 4), det);
            let sy = div_round_128_rt((dl2 * dx1 - dl1 * dx2) << (FRAC + 4), det);
            let sx = sx.clamp(-i128::from(STEP_MAX), i128::from(STEP_MAX));
            let sy = sy.clamp(-i128::from(STEP_MAX), i128::from(STEP_MAX));
            // Pixel (0, 0)'s centre is at 8/16 of a pixel: offsets from vertex 0 in pixels.
            let a = (l0 << FRAC) + div_round_128(sx * (8 - p[0].0) + sy * (8 - p[0].1), 16);
            out.a[c] = a.clamp(-i128::from(BASE_MAX), i128::from(BASE_MAX)) as i64;
            out.bx[c] = sx as i64;
            out.by[c] = sy as i64;
        }
        out
    }

    /// The light at pixel `(x, y)`, each channel `Q16.16` clamped to `[0, ONE]`.
    pub fn at(&self, x: u16, y: u16) -> LightRgb {
        core::array::from_fn(|c| {
            to_q16(self.a[c] + self.bx[c] * i64::from(x) + self.by[c] * i64::from(y))
        })
    }

    /// Multiplies the colours of the pixels `x, x + 1, ...` of row `y` by their light.
    pub fn modulate_span(&self, x: u16, y: u16, px: &mut [Rgba8888]) {
        let mut l: [i64; 3] = core::array::from_fn(|c| {
            self.a[c] + self.bx[c] * i64::from(x) + self.by[c] * i64::from(y)
        });
        for p in px.iter_mut() {
            p.r = modulate_channel(p.r, to_q16(l[0]));
            p.g = modulate_channel(p.g, to_q16(l[1]));
            p.b = modulate_channel(p.b, to_q16(l[2]));
            // Exact: x stays below 2^16 within a row, so no step overflows.
            for (lc, bx) in l.iter_mut().zip(self.bx) {
                *lc += bx;
            }
        }
    }
}

/// `Q16.32` to `Q16.16`, rounded, clamped to `[0, ONE]`.
const fn to_q16(v: i64) -> i32 {
    let r = (v + (1 << (FRAC - 1))) >> FRAC;
    if r < 0 {
        0
    } else if r > ONE as i64 {
        ONE
    } else {
        r as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::TexPoint;

    fn v(x: i32, y: i32) -> ScreenVertex {
        ScreenVertex::from_bits(x * 16, y * 16, 0, 1 << 31, TexPoint::from_bits(0, 0, 0))
    }

    #[test]
    fn vertices_get_their_light_and_the_plane_is_linear() {
        // Vertices at pixel corners; light ramps in x from 0 to ONE over 64 pixels.
        let t = [v(0, 0), v(64, 0), v(0, 64)];
        let l = [[0; 3], [ONE; 3], [0; 3]];
        let tl = TriangleLight::new(&t, &l);
        // Pixel 31's centre is at x = 31.5: 31.5 / 64 of ONE.
        assert_eq!(tl.at(31, 5)[0], (ONE as i64 * 63 / 128) as i32);
        assert_eq!(tl.at(0, 0)[1], ONE / 128);
        // Independent of y, clamped past the end.
        assert_eq!(tl.at(10, 0), tl.at(10, 40));
        assert_eq!(tl.at(200, 0), [ONE; 3]);
    }

    #[test]
    fn span_modulation_is_split_independent() {
        let t = [v(3, 1), v(90, 20), v(17, 70)];
        let l = [
            [ONE / 5, ONE, 0],
            [ONE, ONE / 3, ONE / 2],
            [0, ONE / 2, ONE],
        ];
        let tl = TriangleLight::new(&t, &l);
        let base = [Rgba8888::new(200, 150, 255, 77); 40];
        let mut whole = base;
        tl.modulate_span(10, 30, &mut whole);
        let mut parts = base;
        let (a, b) = parts.split_at_mut(13);
        tl.modulate_span(10, 30, a);
        tl.modulate_span(23, 30, b);
        assert_eq!(whole, parts);
        for (i, p) in whole.iter().enumerate() {
            let li = tl.at(10 + i as u16, 30);
            assert_eq!(p.r, modulate_channel(200, li[0]));
            assert_eq!(p.g, modulate_channel(150, li[1]));
            assert_eq!(p.b, modulate_channel(255, li[2]));
            assert_eq!(p.a, 77);
        }
        // Not uniform: the light varies across the span.
        assert_ne!(whole[0], whole[39]);
    }

    #[test]
    fn degenerate_and_extreme_triangles_do_not_panic() {
        let l = [[ONE; 3], [0; 3], [ONE / 2; 3]];
        let flat = TriangleLight::new(&[v(5, 5), v(5, 5), v(5, 5)], &l);
        assert_eq!(flat.at(0, 0), [ONE / 2; 3]);
        let sliver = TriangleLight::new(
            &[
                ScreenVertex::from_bits(i32::MIN, 0, 0, 1, TexPoint::from_bits(0, 0, 0)),
                ScreenVertex::from_bits(i32::MAX, 1, 0, 1, TexPoint::from_bits(0, 0, 0)),
                ScreenVertex::from_bits(0, 2, 0, 1, TexPoint::from_bits(0, 0, 0)),
            ],
            &l,
        );
        let mut px = [Rgba8888::WHITE; 8];
        sliver.modulate_span(u16::MAX - 8, u16::MAX, &mut px);
        let _ = sliver.at(u16::MAX, u16::MAX);
    }

    // The stage in the renderer.
    extern crate std;
    use crate::filter::Antialias;
    use crate::light::{Light, Lighting};
    use crate::ready::{Material, PresetName};
    use crate::render::{FrameBins, GroupRows, RenderStats, Renderer, TriangleSource};
    use crate::scene::{self, Camera, Mesh, Object, Scene, TextureSlot, Vec3};
    use crate::sink::RgbaBuffer;
    use crate::texture::Texture;
    use std::vec;
    use std::vec::Vec;

    /// The whole 48-row image as one strip.
    const WHOLE: &[core::ops::Range<u16>] = &[0..48, 48..48];

    type Tex = Texture<{ crate::presets::PRESET_TERMS }, 256>;

    fn marble() -> Vec<Tex> {
        vec![Material::preset(PresetName::Marble)
            .texture::<256>(Antialias::None)
            .unwrap()]
    }

    /// A sphere filling most of a 48 x 48 image, without depth (so it can stream too).
    fn sphere() -> Scene {
        let cam = Camera::perspective(
            Vec3::units(0, 0, 4),
            Vec3::ZERO,
            Vec3::Y,
            scene::focal_from_fov(scene::Angle::from_degrees(40)),
            ONE / 4,
            100 * ONE,
            48,
            48,
        );
        let mut s = Scene::new("lit", cam);
        s.add_slot(TextureSlot::preset("marble")).unwrap();
        let mut o = Object::new(Mesh::Sphere {
            radius: ONE,
            stacks: 10,
            slices: 12,
        });
        o.cull = crate::raster::CullMode::Clockwise;
        o.depth_test = false;
        o.depth_write = false;
        s.add(o).unwrap();
        s
    }

    fn banded<S: TriangleSource>(
        s: &S,
        strips: &[core::ops::Range<u16>],
    ) -> (Vec<Rgba8888>, RenderStats) {
        let tex = marble();
        let r = Renderer::new(&tex);
        let (w, h) = s.size();
        let mut img = vec![Rgba8888::TRANSPARENT; usize::from(w) * usize::from(h)];
        let mut sink = RgbaBuffer::new(&mut img, w, 0, h).unwrap();
        let mut band = vec![Rgba8888::BLACK; usize::from(w) * 8];
        let mut depth = vec![0u16; usize::from(w) * 8];
        let mut rows = vec![GroupRows::EMPTY; 256];
        let mut bins = FrameBins::new(&mut rows);
        let mut stats = RenderStats::default();
        for strip in strips {
            let st = r
                .render_banded_rows_binned(
                    s,
                    strip.clone(),
                    &mut band,
                    &mut depth,
                    8,
                    &mut bins,
                    &mut sink,
                )
                .unwrap();
            stats.lit_pixels += st.lit_pixels;
            stats.shade.span.pixels += st.shade.span.pixels;
        }
        (img, stats)
    }

    fn streamed(s: &Scene) -> (Vec<Rgba8888>, RenderStats) {
        let tex = marble();
        let r = Renderer::new(&tex);
        let (w, h) = s.size();
        let mut img = vec![Rgba8888::TRANSPARENT; usize::from(w) * usize::from(h)];
        let mut sink = RgbaBuffer::new(&mut img, w, 0, h).unwrap();
        let st = r.render_streamed(s, &mut sink).unwrap();
        (img, st)
    }

    /// Ambient light only (a light of no colour): every drawn pixel is the unlit one times the
    /// ambient, exactly; the background is untouched; every shaded pixel is counted as lit.
    #[test]
    fn ambient_scales_every_drawn_pixel() {
        let s = sphere();
        let (plain, st0) = banded(&s, WHOLE);
        assert_eq!(st0.lit_pixels, 0);
        let mut lit = s.clone();
        let mut l = Lighting::new().with_ambient([ONE / 2; 3]).unwrap();
        l.try_add(Light::directional(Vec3::Z, [0; 3], ONE).unwrap())
            .unwrap();
        lit.set_lighting(l);
        let (img, st) = banded(&lit, WHOLE);
        assert!(st.lit_pixels > 48 * 48 / 3, "{}", st.lit_pixels);
        assert_eq!(st.lit_pixels, st.shade.span.pixels);
        let bg = Rgba8888::from_array(s.background);
        let mut drawn = 0;
        for (p, q) in plain.iter().zip(&img) {
            if *p == bg {
                assert_eq!(q, p);
            } else {
                drawn += 1;
                let want = crate::light::modulate([p.r, p.g, p.b], [ONE / 2; 3]);
                assert_eq!([q.r, q.g, q.b, q.a], [want[0], want[1], want[2], p.a]);
            }
        }
        assert!(drawn > 500);
    }

    /// A light from the left: the left of the sphere is brighter; streamed, banded and banded
    /// in binned strips give the same pixels.
    #[test]
    fn directional_light_shades_the_sphere_the_same_in_every_renderer() {
        let mut s = sphere();
        s.add_light(Light::directional(Vec3::new(-ONE, 0, ONE / 2), [ONE; 3], ONE).unwrap())
            .unwrap();
        let (img, st) = banded(&s, WHOLE);
        let (strips, _) = banded(&s, &[0..13, 13..30, 30..48]);
        let (stream, sst) = streamed(&s);
        assert_eq!(img, strips);
        assert_eq!(img, stream);
        assert_eq!(st.lit_pixels, sst.lit_pixels);
        let luma = |x0: usize, x1: usize| -> u32 {
            (16..32)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .map(|(x, y)| {
                    let p = img[y * 48 + x];
                    u32::from(p.r) + u32::from(p.g) + u32::from(p.b)
                })
                .sum()
        };
        let (left, right) = (luma(12, 20), luma(28, 36));
        assert!(left > 2 * right, "{left} {right}");
    }

    /// A scene without lights takes the unlit walk: the lit walk is never asked for, no pixel
    /// is lit, and the pixels are those of the plain scene.
    #[test]
    fn unlit_scene_never_walks_lit() {
        struct Spy<'a>(&'a Scene, core::cell::Cell<u32>);
        impl TriangleSource for Spy<'_> {
            fn size(&self) -> (u16, u16) {
                self.0.size()
            }
            fn background(&self) -> Rgba8888 {
                TriangleSource::background(self.0)
            }
            fn object_count(&self) -> usize {
                TriangleSource::object_count(self.0)
            }
            fn object(&self, i: usize) -> Option<crate::render::DrawObject> {
                TriangleSource::object(self.0, i)
            }
            fn for_each_triangle<F: FnMut(usize, &[ScreenVertex; 3])>(&self, f: F) {
                TriangleSource::for_each_triangle(self.0, f)
            }
            fn is_lit(&self) -> bool {
                TriangleSource::is_lit(self.0)
            }
            fn for_each_lit_triangle_grouped<K, F>(&self, keep: K, f: F)
            where
                K: FnMut(usize) -> bool,
                F: FnMut(usize, usize, &[ScreenVertex; 3], &dyn Fn() -> [LightRgb; 3]),
            {
                self.1.set(self.1.get() + 1);
                TriangleSource::for_each_lit_triangle_grouped(self.0, keep, f)
            }
        }
        let s = sphere();
        let spy = Spy(&s, core::cell::Cell::new(0));
        let (img, st) = banded(&spy, WHOLE);
        assert_eq!((spy.1.get(), st.lit_pixels), (0, 0));
        assert_eq!(img, banded(&s, WHOLE).0);
        let mut lit = s.clone();
        lit.add_light(Light::directional(Vec3::Z, [ONE; 3], ONE).unwrap())
            .unwrap();
        let spy = Spy(&lit, core::cell::Cell::new(0));
        let (_, st) = banded(&spy, WHOLE);
        assert!(spy.1.get() > 0 && st.lit_pixels > 0);
    }
}
