//! The renderer's tests: streamed and banded frames, bins, lighting, outputs and counters.

extern crate std;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::filter::{Antialias, ColorStage, GradientNorm};
use crate::format::TexPoint;
use crate::hash::HashKind;
use crate::raster::Perspective;
use crate::span::EvalMode;
use crate::table::{ColorTable, TableLookup, TableWrap};

/// A full-screen quad with s = x / size, t = y / size at the corners, plus optional objects
/// (quads of two triangles each, drawn in order).
pub(super) struct Quads {
    pub(super) size: u16,
    pub(super) objects: Vec<(DrawObject, [ScreenVertex; 4])>,
}

fn corner(x: i32, y: i32, s: i32, t: i32, z: u16) -> ScreenVertex {
    ScreenVertex::from_bits(x << 4, y << 4, z, 1 << 30, TexPoint::from_bits(s, t, 32768))
}

fn full(size: u16, obj: DrawObject, z: u16) -> (DrawObject, [ScreenVertex; 4]) {
    let n = i32::from(size);
    (
        obj,
        [
            corner(0, 0, 0, 0, z),
            corner(n, 0, 65536, 0, z),
            corner(n, n, 65536, 65536, z),
            corner(0, n, 0, 65536, z),
        ],
    )
}

impl TriangleSource for Quads {
    fn size(&self) -> (u16, u16) {
        (self.size, self.size)
    }
    fn background(&self) -> Rgba8888 {
        Rgba8888::new(1, 2, 3, 255)
    }
    fn object_count(&self) -> usize {
        self.objects.len()
    }
    fn object(&self, i: usize) -> Option<DrawObject> {
        self.objects.get(i).map(|o| o.0)
    }
    fn for_each_triangle<F: FnMut(usize, &[ScreenVertex; 3])>(&self, mut f: F) {
        for (i, (_, v)) in self.objects.iter().enumerate() {
            f(i, &[v[0], v[1], v[2]]);
            f(i, &[v[0], v[2], v[3]]);
        }
    }
}

fn affine() -> TriangleOptions {
    TriangleOptions {
        perspective: Perspective::Affine,
        ..TriangleOptions::default()
    }
}

fn zone_texture(aa: Antialias) -> Texture<8, 256> {
    let p = crate::presets::zoneplate();
    let stage = ColorStage::new(
        ColorTable::zebra().unwrap(),
        TableWrap::Mod,
        TableLookup::Nearest,
        aa,
    )
    .unwrap();
    Texture::new(
        Shader::Model(p.model),
        stage,
        GradientNorm::L2,
        EvalMode::Auto,
    )
}

#[cfg(feature = "csat")]
fn marble_texture() -> Texture<8, 256> {
    crate::ready::Material::preset(crate::ready::PresetName::Marble)
        .texture(Antialias::Csat)
        .unwrap()
}

pub(super) fn render_full(
    r: &Renderer<'_, 8, 256>,
    scene: &Quads,
    rows: u16,
) -> (Vec<Rgba8888>, RenderStats) {
    let n = usize::from(scene.size);
    let mut img = vec![Rgba8888::BLACK; n * n];
    let mut sink = RgbaBuffer::new(&mut img, scene.size, 0, scene.size).unwrap();
    let stats = if rows == 0 {
        r.render_streamed(scene, &mut sink).unwrap()
    } else {
        let mut band = vec![Rgba8888::BLACK; n * usize::from(rows)];
        let mut depth = vec![0u16; n * usize::from(rows)];
        r.render_banded(scene, &mut band, &mut depth, rows, &mut sink)
            .unwrap()
    };
    (img, stats)
}

#[cfg(feature = "csat")]
#[test]
fn zone_plate_pixels_and_stages() {
    let tex = [zone_texture(Antialias::None)];
    let r = Renderer::new(&tex);
    let scene = Quads {
        size: 256,
        objects: vec![full(
            256,
            DrawObject {
                raster: affine(),
                ..DrawObject::default()
            },
            0,
        )],
    };
    let (img, stats) = render_full(&r, &scene, 0);
    for y in 0..256usize {
        for x in 0..256usize {
            let s = (x as f64 + 0.5) / 256.0;
            let t = (y as f64 + 0.5) / 256.0;
            let f = 50.0 * (s * s + t * t);
            let white = f.rem_euclid(1.0) < 0.5;
            let want = if white {
                Rgba8888::WHITE
            } else {
                Rgba8888::BLACK
            };
            assert_eq!(img[y * 256 + x], want, "({x}, {y}) f = {f}");
        }
    }
    assert_eq!(stats.shade.span.pixels, 65536);
    assert_eq!(stats.shade.span.noise_evaluations, 0);
    assert_eq!(stats.shade.span.gradient_evaluations, 0);
    assert_eq!(stats.shade.filter_lookups, 0);
    assert_eq!(stats.raster.divides, 0);
    assert_eq!(stats.blended_pixels, 0);
    // Filtered: gradients and filter look-ups run.
    let tex = [zone_texture(Antialias::Csat)];
    let (_, st) = render_full(&Renderer::new(&tex), &scene, 0);
    assert_eq!(st.shade.filter_lookups, 65536);
    assert!(st.shade.span.gradient_evaluations >= 65536);
    assert_eq!(st.shade.span.noise_evaluations, 0);
}

#[cfg(feature = "csat")]
#[test]
fn bands_equal_streaming() {
    let tex = [marble_texture()];
    let r = Renderer::new(&tex);
    let scene = Quads {
        size: 64,
        objects: vec![full(
            64,
            DrawObject {
                raster: affine(),
                ..DrawObject::default()
            },
            0,
        )],
    };
    let (a, _) = render_full(&r, &scene, 0);
    for rows in [1u16, 7, 16, 64, 100] {
        let (b, st) = render_full(&r, &scene, rows);
        assert_eq!(a, b, "band rows {rows}");
        assert_eq!(st.bands, u32::from(64u16.div_ceil(rows.min(64))));
    }
}

#[cfg(feature = "csat")]
#[test]
fn depth_and_blending() {
    let tex = [marble_texture(), zone_texture(Antialias::None)];
    let r = Renderer::new(&tex);
    // Marble in front (z = 100), zone plate behind (z = 200) drawn second: depth keeps marble.
    let near = DrawObject {
        texture: 0,
        depth: true,
        raster: affine(),
        ..DrawObject::default()
    };
    let far = DrawObject {
        texture: 1,
        depth: true,
        raster: affine(),
        ..DrawObject::default()
    };
    let scene = Quads {
        size: 32,
        objects: vec![full(32, near, 100), full(32, far, 200)],
    };
    let only_near = Quads {
        size: 32,
        objects: vec![full(32, near, 100)],
    };
    let (a, st) = render_full(&r, &scene, 8);
    let (b, _) = render_full(&r, &only_near, 8);
    assert!(a == b, "the far quad showed through");
    assert!(st.raster.depth_failed > 0);
    assert!(
        r.render_streamed(
            &scene,
            &mut RgbaBuffer::new(&mut [Rgba8888::BLACK; 1024], 32, 0, 32).unwrap()
        ) == Err(RenderError::NeedsBands)
    );
    // An opaque-alpha texture blended over is identical to opaque; blending is counted.
    let over = DrawObject {
        texture: 0,
        blend: Blend::Over,
        raster: affine(),
        ..DrawObject::default()
    };
    let (c, st) = render_full(
        &r,
        &Quads {
            size: 32,
            objects: vec![full(32, over, 0)],
        },
        8,
    );
    assert_eq!(c, b);
    assert_eq!(st.blended_pixels, 32 * 32);
}

#[test]
fn bad_slots_are_errors() {
    let tex = [zone_texture(Antialias::None)];
    let r = Renderer::new(&tex);
    let scene = Quads {
        size: 8,
        objects: vec![full(
            8,
            DrawObject {
                texture: 3,
                ..DrawObject::default()
            },
            0,
        )],
    };
    let mut img = [Rgba8888::BLACK; 64];
    let mut sink = RgbaBuffer::new(&mut img, 8, 0, 8).unwrap();
    assert_eq!(
        r.render_streamed(&scene, &mut sink),
        Err(RenderError::NoSuchTexture { object: 0, slot: 3 })
    );
    let mut band = [Rgba8888::BLACK; 4];
    assert_eq!(
        r.render_banded(&scene, &mut band, &mut [], 4, &mut sink),
        Err(RenderError::NoSuchTexture { object: 0, slot: 3 })
    );
}

#[cfg(feature = "csat")]
#[test]
fn filter_width_output() {
    let tex = [zone_texture(Antialias::Csat)];
    let r = Renderer::new(&tex).with_output(Output::FilterWidth);
    let scene = Quads {
        size: 256,
        objects: vec![full(
            256,
            DrawObject {
                raster: affine(),
                ..DrawObject::default()
            },
            0,
        )],
    };
    let (img, _) = render_full(&r, &scene, 0);
    // w = N |grad f| = 256 * 100 * sqrt(s^2 + t^2) / 256: darkest at the origin corner,
    // brighter along the diagonal, and monotone along the first row.
    assert!(img[0].r < 5, "{:?}", img[0]);
    let row: Vec<u8> = (0..256).map(|x| img[x].r).collect();
    assert!(row.windows(2).all(|w| w[0] <= w[1]));
    // At s = 0.5 (x = 128, t ~ 0): w = 100 * 0.5 = 50 entries -> grey (49/255)*255 = 49.
    assert!((i32::from(img[128].r) - 49).abs() <= 1, "{}", img[128].r);
}

#[cfg(all(feature = "embedded-graphics", feature = "csat"))]
#[test]
fn draw_target_sink_equals_buffer() {
    use embedded_graphics_core::draw_target::DrawTarget;
    use embedded_graphics_core::geometry::{OriginDimensions, Size};
    use embedded_graphics_core::pixelcolor::Rgb565 as EgRgb565;
    use embedded_graphics_core::primitives::PointsIter;
    use embedded_graphics_core::Pixel;

    struct Display {
        pixels: Vec<u16>,
        calls: usize,
    }
    impl OriginDimensions for Display {
        fn size(&self) -> Size {
            Size::new(64, 64)
        }
    }
    impl DrawTarget for Display {
        type Color = EgRgb565;
        type Error = core::convert::Infallible;
        fn draw_iter<I: IntoIterator<Item = Pixel<EgRgb565>>>(
            &mut self,
            it: I,
        ) -> Result<(), Self::Error> {
            use embedded_graphics_core::prelude::IntoStorage;
            for Pixel(p, c) in it {
                if (0..64).contains(&p.x) && (0..64).contains(&p.y) {
                    self.pixels[(p.y * 64 + p.x) as usize] = c.into_storage();
                }
            }
            Ok(())
        }
        fn fill_contiguous<I: IntoIterator<Item = EgRgb565>>(
            &mut self,
            area: &embedded_graphics_core::primitives::Rectangle,
            colors: I,
        ) -> Result<(), Self::Error> {
            self.calls += 1;
            self.draw_iter(area.points().zip(colors).map(|(p, c)| Pixel(p, c)))
        }
    }

    let tex = [marble_texture()];
    let r = Renderer::new(&tex);
    let scene = Quads {
        size: 64,
        objects: vec![full(
            64,
            DrawObject {
                raster: affine(),
                ..DrawObject::default()
            },
            0,
        )],
    };
    let mut disp = Display {
        pixels: vec![0; 64 * 64],
        calls: 0,
    };
    let mut sink = crate::sink::DrawTargetSink::new(&mut disp);
    let st = r.render_streamed(&scene, &mut sink).unwrap();
    assert!(!sink.had_error());
    let mut buf = vec![0u16; 64 * 64];
    let mut bsink = crate::sink::Rgb565Buffer::new(&mut buf, 64, 0, 64).unwrap();
    r.render_streamed(&scene, &mut bsink).unwrap();
    // One fill_contiguous per segment: two triangles, so two segments per row, plus one
    // background fill per row (fill_solid).
    assert!(disp.pixels == buf, "DrawTarget and buffer differ");
    assert_eq!(disp.calls, st.raster.segments as usize + 64);
    // An RGB565 band hands each finished row to the display as it is: one call a row, the
    // same pixels.
    let mut disp = Display {
        pixels: vec![0; 64 * 64],
        calls: 0,
    };
    let mut sink = crate::sink::DrawTargetSink::new(&mut disp);
    let mut band = vec![0u16; 64 * 8];
    r.render_banded_rgb565(&scene, &mut band, &mut [], 8, &mut sink)
        .unwrap();
    assert!(!sink.had_error());
    assert!(
        disp.pixels == buf,
        "RGB565 band to DrawTarget and buffer differ"
    );
    assert_eq!(disp.calls, 64);
}

/// Built-in scene `name` at its still frame, and its textures ([`scene_textures`]).
fn still_scene(name: &str) -> (crate::scene::Scene, Vec<Texture<8, 256>>) {
    let s = crate::scene::by_name(name).unwrap();
    let s = s.at_frame(s.still());
    let tex = scene_textures(&s);
    (s, tex)
}

/// A texture for every slot of `scene`: its preset's model and colour keys (the slot's own
/// keys if it has some), nearest look-up, no antialiasing; the zone plate for materials
/// that are not plain presets.
fn scene_textures(scene: &crate::scene::Scene) -> Vec<Texture<8, 256>> {
    scene
        .slots
        .iter()
        .map(|slot| {
            let Some(p) = crate::presets::by_name(slot.material, HashKind::default()) else {
                return zone_texture(Antialias::None);
            };
            crate::ready::Material::model(p.model, slot.keys.unwrap_or(p.keys))
                .texture(Antialias::None)
                .unwrap()
        })
        .collect()
}

/// Rows `rows` of `scene` in bands of `band_rows` with `bins` entries of bins (`None`:
/// [`Renderer::render_banded_rows`]): the whole image (rows outside `rows` black), its
/// checksum and the stats.
fn render_scene<S: TriangleSource>(
    r: &Renderer<'_, 8, 256>,
    scene: &S,
    rows: core::ops::Range<u16>,
    band_rows: u16,
    bins: Option<usize>,
) -> (Vec<Rgba8888>, u32, RenderStats) {
    let (w, h) = scene.size();
    let n = usize::from(w) * usize::from(band_rows);
    let mut band = vec![Rgba8888::BLACK; n];
    let mut depth = vec![0u16; n];
    let mut img = vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
    struct Tee<'a, 'b>(RgbaBuffer<'a>, &'b mut crate::sink::ChecksumSink);
    impl PixelSink for Tee<'_, '_> {
        fn write_span(&mut self, x: u16, y: u16, px: &[Rgba8888]) {
            self.0.write_span(x, y, px);
            self.1.write_span(x, y, px);
        }
    }
    let mut check = crate::sink::ChecksumSink::new();
    let mut tee = Tee(RgbaBuffer::new(&mut img, w, 0, h).unwrap(), &mut check);
    let stats = match bins {
        None => r.render_banded_rows(scene, rows, &mut band, &mut depth, band_rows, &mut tee),
        Some(k) => {
            let mut bins = vec![GroupRows::EMPTY; k];
            let mut bins = FrameBins::new(&mut bins);
            r.render_banded_rows_binned(
                scene, rows, &mut band, &mut depth, band_rows, &mut bins, &mut tee,
            )
        }
    }
    .unwrap();
    (img, check.checksum(), stats)
}

/// Binning changes no pixel (nor the checksum) of the built-in scenes, for band heights of
/// 1, 7, 8 and 64 rows, whole frames and strips, and bins for all groups, half of them, one
/// or none; it only skips work, and the stats differ as documented.
#[test]
fn binned_equals_unbinned() {
    for name in crate::scene::BUILTIN {
        let (s, tex) = still_scene(name);
        let r = Renderer::new(&tex);
        let groups = s.quad_count();
        let h = s.size().1;
        for band_rows in [1u16, 7, 8, 64] {
            for rows in [0..h, 56..120, 3..h - 5] {
                // Band height 1 walks the scene once per row: whole frames only.
                if band_rows == 1 && rows != (0..h) && name != "marble" {
                    continue;
                }
                let (a, ca, sa) = render_scene(&r, &s, rows.clone(), band_rows, None);
                for k in [groups, groups + 5, groups / 2, 1, 0] {
                    let what = format!("{name} rows {rows:?} band {band_rows} bins {k}");
                    let (b, cb, sb) = render_scene(&r, &s, rows.clone(), band_rows, Some(k));
                    assert!(a == b, "{what}: pixels differ");
                    assert_eq!(ca, cb, "{what}");
                    assert_eq!(sa.bands, sb.bands, "{what}");
                    assert_eq!(sa.shade, sb.shade, "{what}");
                    assert_eq!(sa.blended_pixels, sb.blended_pixels, "{what}");
                    let (ra, rb) = (sa.raster, sb.raster);
                    let fewer = ra.triangles - rb.triangles;
                    assert_eq!(ra.offscreen - rb.offscreen, fewer, "{what}");
                    assert_eq!(
                        Counters {
                            triangles: ra.triangles,
                            offscreen: ra.offscreen,
                            ..rb
                        },
                        ra,
                        "{what}"
                    );
                    assert_eq!(sa.skipped_groups, 0);
                    if k == 0 || sb.bands == 1 {
                        assert_eq!(sb.skipped_groups, 0, "{what}");
                        assert_eq!(fewer, 0, "{what}");
                    }
                    if k >= groups && sb.bands > 2 && s.quad_count() > 1 {
                        assert!(sb.skipped_groups > 0, "{what}: nothing skipped");
                        assert!(fewer > 0, "{what}");
                    }
                }
            }
        }
    }
}

/// The bins hold, for each group, the rows its triangles' pixel centres can lie on: every
/// segment the rasterizer emits for a group lies within them, and a group that emits no
/// triangle has none; filled by rendering one strip, they cover the whole image.
#[test]
fn bins_cover_every_segment() {
    for name in ["marble", "moonrise", "seascape"] {
        let (s, tex) = still_scene(name);
        let (w, h) = s.size();
        let mut table = vec![GroupRows::new(7, 3); s.quad_count()];
        let n = usize::from(w) * 8;
        let (mut band, mut depth) = (vec![Rgba8888::BLACK; n], vec![0u16; n]);
        let mut sink = crate::sink::ChecksumSink::new();
        let mut fb = FrameBins::new(&mut table);
        // A strip: the bins still cover the whole image.
        Renderer::new(&tex)
            .render_banded_rows_binned(&s, 56..120, &mut band, &mut depth, 8, &mut fb, &mut sink)
            .unwrap();
        assert!(fb.is_filled_for((w, h)), "{name}");
        let bins = fb.rows();
        let mut emitted = vec![false; bins.len()];
        let mut rast = Rasterizer::new(Rect::from_size(w, h));
        s.for_each_triangle_grouped(
            |_| true,
            |g, o, t| {
                emitted[g] = true;
                let opts = s.objects[o].options();
                rast.draw(t, &opts, &mut |seg: &Segment| {
                    let (a, b) = bins[g].rows().expect("a drawn group has rows");
                    assert!((a..=b).contains(&seg.y), "{name}: group {g} row {}", seg.y);
                });
            },
        );
        for (g, e) in emitted.iter().enumerate() {
            if !e {
                assert!(bins[g].is_empty(), "{name}: group {g}");
            }
        }
        if name == "seascape" {
            // Part of the horizon plane lies outside the view.
            assert!(bins.iter().any(|b| b.is_empty()), "{name}");
        }
        assert!(bins.iter().any(|b| !b.is_empty()), "{name}");
    }
}

/// A frame rendered as strips that share one [`FrameBins`] walks the whole scene once (the
/// first strip's first band, or [`Renderer::bin`] before it) and gives the pixels of one
/// unbinned whole-frame render; `bin` fills exactly the bins a render fills; a scene of
/// another size is binned again, and `reset` forgets the filling.
#[test]
fn strips_share_one_binning_walk() {
    for name in ["marble", "moonrise", "seascape"] {
        let (s, tex) = still_scene(name);
        let (w, h) = s.size();
        let r = Renderer::new(&tex);
        let (whole, _, sw) = render_scene(&r, &s, 0..h, 8, None);
        let strips = [0..56u16, 56..120, 120..176, 176..h];
        let alone: Vec<RenderStats> = strips
            .iter()
            .map(|rows| render_scene(&r, &s, rows.clone(), 8, None).2)
            .collect();
        let n = usize::from(w) * 8;
        let (mut band, mut depth) = (vec![Rgba8888::BLACK; n], vec![0u16; n]);
        // Fresh bins per strip (each strip walks the whole scene) against shared ones, filled
        // by the first strip or by `bin` beforehand.
        let mut walked = Vec::new();
        for shared in [None, Some(false), Some(true)] {
            let mut img = vec![Rgba8888::BLACK; usize::from(w) * usize::from(h)];
            let mut table = vec![GroupRows::EMPTY; s.quad_count()];
            let mut fb = FrameBins::new(&mut table);
            if shared == Some(true) {
                r.bin(&s, &mut fb).unwrap();
                assert!(fb.is_filled_for((w, h)));
            }
            let mut triangles = 0;
            let mut skipped = 0;
            for (k, rows) in strips.iter().cloned().enumerate() {
                if shared.is_none() {
                    fb.reset();
                }
                let mut sink = RgbaBuffer::new(&mut img, w, 0, h).unwrap();
                let st = r
                    .render_banded_rows_binned(
                        &s, rows, &mut band, &mut depth, 8, &mut fb, &mut sink,
                    )
                    .unwrap();
                assert_eq!(st.shade, alone[k].shade, "{name} {shared:?} strip {k}");
                triangles += st.raster.triangles;
                skipped += st.skipped_groups;
            }
            assert!(img == whole, "{name} {shared:?}: pixels differ");
            walked.push((triangles, skipped));
        }
        // Sharing skips work; filling by `bin` first skips the first strip's binning walk
        // too (the walk itself is not a render and draws nothing).
        let (fresh, first, pre) = (walked[0], walked[1], walked[2]);
        assert!(first.0 < fresh.0 && first.1 > fresh.1, "{name}: {walked:?}");
        assert!(pre.0 < first.0 && pre.1 > first.1, "{name}: {walked:?}");
        assert!(
            fresh.0 < sw.raster.triangles,
            "{name}: unbinned bands walk every group"
        );

        // `bin` fills what a render fills, for any rows rendered.
        let mut a = vec![GroupRows::new(1, 2); s.quad_count()];
        let mut b = vec![GroupRows::EMPTY; s.quad_count()];
        let mut fa = FrameBins::new(&mut a);
        r.bin(&s, &mut fa).unwrap();
        let mut fb = FrameBins::new(&mut b);
        let mut sink = crate::sink::ChecksumSink::new();
        r.render_banded_rows_binned(&s, 120..128, &mut band, &mut depth, 8, &mut fb, &mut sink)
            .unwrap();
        assert_eq!(fa.rows(), fb.rows(), "{name}");
        assert!(!fa.is_filled_for((w + 1, h)));
        fa.reset();
        assert!(!fa.is_filled_for((w, h)));
    }
}

/// The provided grouped walk: one group per triangle, `keep` asked once per triangle in
/// order, declined triangles left out.
#[test]
fn default_grouped_walk() {
    let obj = DrawObject::default();
    let scene = Quads {
        size: 16,
        objects: vec![full(16, obj, 0), full(8, obj, 1)],
    };
    let mut all = Vec::new();
    scene.for_each_triangle(|o, t| all.push((o, *t)));
    let mut asked = Vec::new();
    let mut got = Vec::new();
    scene.for_each_triangle_grouped(
        |g| {
            asked.push(g);
            g != 1
        },
        |g, o, t| got.push((g, o, *t)),
    );
    assert_eq!(asked, [0, 1, 2, 3]);
    let want: Vec<_> = all
        .iter()
        .enumerate()
        .filter(|(g, _)| *g != 1)
        .map(|(g, (o, t))| (g, *o, *t))
        .collect();
    assert_eq!(got, want);
}

/// A source with the provided grouped walk renders the same binned (one bin per triangle).
#[cfg(feature = "csat")]
#[test]
fn binned_quads_equal_unbinned() {
    let tex = [marble_texture(), zone_texture(Antialias::None)];
    let r = Renderer::new(&tex);
    let near = DrawObject {
        texture: 0,
        depth: true,
        raster: affine(),
        ..DrawObject::default()
    };
    let over = DrawObject {
        texture: 1,
        blend: Blend::Over,
        raster: affine(),
        ..DrawObject::default()
    };
    let mut small = full(12, over, 0);
    for v in &mut small.1 {
        v.y = crate::raster::ScreenCoord::from_bits(v.y.to_bits() + (20 << 4));
    }
    let scene = Quads {
        size: 40,
        objects: vec![full(40, near, 100), small],
    };
    for band_rows in [1u16, 7, 8, 64] {
        let (a, ca, _) = render_scene(&r, &scene, 0..40, band_rows, None);
        for k in [4usize, 3, 1, 0] {
            let (b, cb, sb) = render_scene(&r, &scene, 0..40, band_rows, Some(k));
            assert!(a == b && ca == cb, "band {band_rows} bins {k}");
            if k == 4 && band_rows < 20 {
                assert!(sb.skipped_groups > 0);
            }
        }
    }
}
