//! The RGB565 band against the RGBA8888 band: the same rows reduced, bit for bit, for every
//! built-in scene with every filter, in bands and strips, with widths from differences and lit;
//! a blended scene refused; the sinks' RGB565 paths.

extern crate std;
use std::format;
use std::vec;
use std::vec::Vec;

use super::*;
use crate::color::Rgb565;
use crate::filter::Antialias;
use crate::hash::HashKind;
use crate::sink::{ChecksumSink, Rgb565Buffer};

use super::tests::Quads;

/// A texture for every slot of `scene` with filter `aa` (its preset's model and keys; the
/// marble preset for a slot that is not a plain preset).
fn textures(scene: &crate::scene::Scene, aa: Antialias) -> Vec<Texture<8, 256>> {
    scene
        .slots
        .iter()
        .map(|slot| {
            let p = crate::presets::by_name(slot.material, HashKind::default())
                .or_else(|| crate::presets::by_name("marble", HashKind::default()))
                .unwrap();
            crate::ready::Material::model(p.model, slot.keys.unwrap_or(p.keys))
                .texture(aa)
                .unwrap()
        })
        .collect()
}

/// The filters compiled in.
#[cfg_attr(
    not(any(feature = "csat", feature = "mip", feature = "ramp")),
    allow(unused_mut)
)]
fn filters() -> Vec<Antialias> {
    let mut v = vec![Antialias::None];
    #[cfg(feature = "csat")]
    v.push(Antialias::Csat);
    #[cfg(feature = "mip")]
    v.push(Antialias::Mip);
    #[cfg(feature = "ramp")]
    v.push(Antialias::Ramp);
    v
}

/// What a render hands its sink: the image as RGB565 (rows outside `rows` 0), the checksum and
/// the stats.
struct Frame {
    pixels: Vec<u16>,
    checksum: u32,
    stats: RenderStats,
}

/// A full-frame RGB565 buffer and a checksum, fed together.
struct Tee<'a, 'b>(Rgb565Buffer<'a>, &'b mut ChecksumSink);

impl PixelSink for Tee<'_, '_> {
    fn write_span(&mut self, x: u16, y: u16, px: &[Rgba8888]) {
        self.0.write_span(x, y, px);
        self.1.write_span(x, y, px);
    }

    fn write_rgb565_span(&mut self, x: u16, y: u16, bits: &[u16]) {
        self.0.write_rgb565_span(x, y, bits);
        self.1.write_rgb565_span(x, y, bits);
    }
}

/// Rows `rows` of `scene` through `r` in bands of `band_rows`, with bins of every group, into an
/// RGBA8888 band (`rgb565 == false`) or an RGB565 band.
fn render<S: TriangleSource>(
    r: &Renderer<'_, 8, 256>,
    scene: &S,
    rows: core::ops::Range<u16>,
    band_rows: u16,
    groups: usize,
    rgb565: bool,
) -> Result<Frame, RenderError> {
    let (w, h) = scene.size();
    let n = usize::from(w) * usize::from(band_rows);
    let mut depth = vec![0u16; n];
    let mut pixels = vec![0u16; usize::from(w) * usize::from(h)];
    let mut check = ChecksumSink::new();
    let mut tee = Tee(Rgb565Buffer::new(&mut pixels, w, 0, h).unwrap(), &mut check);
    let mut bins = vec![GroupRows::EMPTY; groups];
    let mut bins = FrameBins::new(&mut bins);
    let stats = if rgb565 {
        let mut band = vec![0u16; n];
        r.render_banded_rows_binned_rgb565(
            scene, rows, &mut band, &mut depth, band_rows, &mut bins, &mut tee,
        )?
    } else {
        let mut band = vec![Rgba8888::BLACK; n];
        r.render_banded_rows_binned(
            scene, rows, &mut band, &mut depth, band_rows, &mut bins, &mut tee,
        )?
    };
    Ok(Frame {
        pixels,
        checksum: check.checksum(),
        stats,
    })
}

/// Both bands agree: the pixels, the checksum and every counter.
fn assert_same<S: TriangleSource>(
    r: &Renderer<'_, 8, 256>,
    scene: &S,
    rows: core::ops::Range<u16>,
    band_rows: u16,
    groups: usize,
    what: &str,
) {
    let a = render(r, scene, rows.clone(), band_rows, groups, false).unwrap();
    let blended = (0..scene.object_count())
        .find(|&i| scene.object(i).is_some_and(|o| o.blend == Blend::Over));
    if let Some(object) = blended {
        // Refused (the overlay scene's clouds blend).
        let b = render(r, scene, rows, band_rows, groups, true).err();
        assert_eq!(b, Some(RenderError::NeedsRgbaBand { object }), "{what}");
        return;
    }
    let b = render(r, scene, rows, band_rows, groups, true).unwrap();
    assert!(a.pixels == b.pixels, "{what}: pixels differ");
    assert_eq!(a.checksum, b.checksum, "{what}");
    assert_eq!(a.stats, b.stats, "{what}");
    assert!(a.pixels.iter().any(|&p| p != 0), "{what}: nothing drawn");
}

/// Every built-in scene at its still frame, with every filter compiled in, whole frames in
/// bands of 8 and 5 rows and a strip: the RGB565 band's rows are the RGBA8888 band's reduced.
#[test]
fn rgb565_band_is_the_rgba_band_reduced() {
    for name in crate::scene::BUILTIN {
        let s = crate::scene::by_name(name).unwrap();
        let s = s.at_frame(s.still());
        let h = s.size().1;
        let groups = s.quad_count();
        for aa in filters() {
            let tex = textures(&s, aa);
            let r = Renderer::new(&tex);
            for (rows, band_rows) in [(0..h, 8u16), (0..h, 5), (37..h - 11, 8)] {
                let what = format!("{name} {aa:?} rows {rows:?} band {band_rows}");
                assert_same(&r, &s, rows, band_rows, groups, &what);
            }
        }
    }
}

/// With filter widths from differences (the ramp's one-read RGB565 path among them), and the
/// filter-width output: the same rows reduced.
#[cfg(feature = "differences")]
#[test]
fn rgb565_band_with_differences_and_widths() {
    use crate::span::FaceCache;
    use crate::texture::DifferenceMemory;
    for name in crate::scene::BUILTIN {
        let s = crate::scene::by_name(name).unwrap();
        let s = s.at_frame(s.still());
        let h = s.size().1;
        let groups = s.quad_count();
        for aa in filters().into_iter().filter(|&a| a != Antialias::None) {
            let tex = textures(&s, aa);
            let mut mem = DifferenceMemory::<512>::new();
            let mut faces = FaceCache::<64, 8>::new();
            let r = Renderer::new(&tex).with_differences(&mut mem, &mut faces);
            let what = format!("{name} {aa:?} differences");
            assert_same(&r, &s, 0..h, 8, groups, &what);
            // Bands of other heights (the device's RGB565 frames take 32 rows, its RGBA band
            // 8): the same pixels and checksum.
            let a = render(&r, &s, 0..h, 8, groups, false).unwrap();
            for rows in [16, 32] {
                match render(&r, &s, 0..h, rows, groups, true) {
                    Err(RenderError::NeedsRgbaBand { .. }) => {}
                    b => {
                        let b = b.unwrap();
                        assert!(
                            a.pixels == b.pixels,
                            "{what}: {rows}-row RGB565 bands differ"
                        );
                        assert_eq!(a.checksum, b.checksum, "{what}: {rows}-row RGB565 bands");
                    }
                }
            }
            let r = Renderer::new(&tex).with_output(Output::FilterWidth);
            let what = format!("{name} {aa:?} widths");
            assert_same(&r, &s, 0..h, 8, groups, &what);
        }
    }
}

/// A lit scene: lit in RGBA8888 and reduced as it is written, the same rows as the RGBA band
/// reduced at its flush.
#[cfg(feature = "lighting")]
#[test]
fn rgb565_band_lit() {
    use crate::light::{Light, Lighting};
    use crate::scene::math::ONE;
    use crate::scene::Vec3;
    for name in ["marble", "wood", "torus"] {
        let s = crate::scene::by_name(name).unwrap();
        let mut s = s.at_frame(s.still());
        let mut l = Lighting::new().with_ambient([ONE / 8; 3]).unwrap();
        l.try_add(Light::directional(Vec3::units(-1, 1, 1), [ONE; 3], ONE).unwrap())
            .unwrap();
        s.set_lighting(l);
        let h = s.size().1;
        let groups = s.quad_count();
        for aa in filters() {
            let tex = textures(&s, aa);
            let r = Renderer::new(&tex);
            let a = render(&r, &s, 0..h, 8, groups, false).unwrap();
            assert!(a.stats.lit_pixels > 0, "{name}: nothing lit");
            assert_same(&r, &s, 0..h, 8, groups, &format!("{name} {aa:?} lit"));
        }
    }
}

/// A scene with a blended object is refused by the RGB565 band (nothing written), with an error
/// that names the object; the RGBA band draws it.
#[test]
fn a_blended_scene_needs_the_rgba_band() {
    let s = crate::scene::by_name("marble").unwrap();
    let tex = textures(&s, Antialias::None);
    let r = Renderer::new(&tex);
    let over = DrawObject {
        blend: Blend::Over,
        ..DrawObject::default()
    };
    let opaque = DrawObject::default();
    let corner =
        |x: i32, y: i32| ScreenVertex::from_bits(x, y, 0, 1 << 30, crate::format::TexPoint::ZERO);
    let quad = [
        corner(0, 0),
        corner(256, 0),
        corner(256, 256),
        corner(0, 256),
    ];
    let scene = Quads {
        size: 16,
        objects: vec![(opaque, quad), (over, quad)],
    };
    let e = render(&r, &scene, 0..16, 8, 0, true).err();
    assert_eq!(e, Some(RenderError::NeedsRgbaBand { object: 1 }));
    let msg = format!("{}", RenderError::NeedsRgbaBand { object: 1 });
    assert!(msg.contains("object 1") && msg.contains("RGBA"), "{msg}");
    // Nothing reached the sink.
    let mut sink = ChecksumSink::new();
    let mut band = [0u16; 256];
    let got = r.render_banded_rgb565(&scene, &mut band, &mut [], 16, &mut sink);
    assert!(got.is_err());
    assert_eq!(sink.pixels(), 0);
    assert!(render(&r, &scene, 0..16, 8, 0, false).is_ok());
    // Without the blended object it draws.
    let scene = Quads {
        size: 16,
        objects: vec![(opaque, quad)],
    };
    assert_same(&r, &scene, 0..16, 8, 0, "one opaque quad");
    // A band too small for one row is refused.
    let mut band = [0u16; 15];
    assert_eq!(
        r.render_banded_rgb565(&scene, &mut band, &mut [], 1, &mut sink),
        Err(RenderError::BufferTooSmall)
    );
}

/// The sinks' RGB565 paths: a sink that takes only RGBA8888 receives the pixels widened (in
/// chunks, at the right positions, a run longer than a chunk included); the checksum of RGB565
/// pixels is the checksum of their widened colours; the RGB565 buffer copies them, clipped.
#[test]
fn sinks_take_rgb565_spans() {
    let bits: Vec<u16> = (0..100u32)
        .map(|i| (i.wrapping_mul(0x9E37_79B9) >> 16) as u16)
        .collect();
    let mut img = vec![Rgba8888::TRANSPARENT; 120];
    let mut rgba = RgbaBuffer::new(&mut img, 120, 3, 1).unwrap();
    rgba.write_rgb565_span(7, 3, &bits);
    for (i, p) in img.iter().enumerate() {
        let want = match i.checked_sub(7).and_then(|k| bits.get(k)) {
            Some(&b) => Rgb565(b).to_rgba8888(),
            None => Rgba8888::TRANSPARENT,
        };
        assert_eq!(*p, want, "pixel {i}");
    }
    let wide: Vec<Rgba8888> = bits.iter().map(|&b| Rgb565(b).to_rgba8888()).collect();
    let (mut a, mut b) = (ChecksumSink::new(), ChecksumSink::new());
    a.write_span(0, 0, &wide);
    b.write_rgb565_span(0, 0, &bits);
    assert_eq!(a.checksum(), b.checksum());
    assert_eq!(a.pixels(), b.pixels());
    let mut out = vec![0u16; 64];
    let mut buf = Rgb565Buffer::new(&mut out, 32, 10, 2).unwrap();
    buf.write_rgb565_span(20, 11, &bits);
    buf.write_rgb565_span(0, 12, &bits);
    buf.write_rgb565_span(40, 10, &bits);
    assert_eq!(&out[..32], &[0u16; 32]);
    assert_eq!(&out[32..52], &[0u16; 20]);
    assert_eq!(&out[52..], &bits[..12]);
}

/// Blending into an RGB565 buffer blends against the stored pixel widened and reduces the
/// result: an opaque colour replaces, a transparent one leaves the pixel, half alpha lands
/// between.
#[test]
fn rgb565_buffer_blends_against_its_pixels() {
    let mut out = vec![Rgb565::WHITE.to_bits(); 4];
    let mut buf = Rgb565Buffer::new(&mut out, 4, 0, 1).unwrap();
    let red = Rgba8888::new(255, 0, 0, 255);
    let clear = Rgba8888::new(0, 0, 255, 0);
    let half = Rgba8888::new(0, 0, 0, 128);
    buf.blend_span(1, 0, &[red, clear, half, red, red]);
    assert_eq!(out[0], Rgb565::WHITE.to_bits());
    assert_eq!(out[1], red.to_rgb565().to_bits());
    assert_eq!(out[2], Rgb565::WHITE.to_bits());
    let want = crate::color::over(half, Rgba8888::WHITE)
        .to_rgb565()
        .to_bits();
    assert_eq!(out[3], want);
    assert!(want != Rgb565::WHITE.to_bits() && want != 0);
}
