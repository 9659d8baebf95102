//! The renderer: screen triangles in, shaded rows out.
//!
//! A [`TriangleSource`] (a scene) yields screen-space triangles tagged with an object; each object
//! names a texture slot, a [`Blend`] mode, whether it uses the depth buffer, and its rasterizer
//! options. The renderer rasterizes each triangle into linear segments, evaluates each segment with
//! the slot's [`Texture`] (forward-differenced span evaluation and the colour stage) and writes the
//! pixels to a [`PixelSink`].
//!
//! Only the stages a scene calls for run, and the choice is made per scene or per segment, never
//! per pixel:
//! - [`Renderer::render_streamed`]: scenes with neither depth nor blending stream each segment's
//!   pixels straight to the sink (no frame buffer, no depth buffer: a display driver receives rows);
//! - [`Renderer::render_banded`]: scenes with overlap or alpha render band by band into a
//!   caller-owned RGBA band and depth band, then flush each row to the sink; blending runs only for
//!   [`Blend::Over`] objects, the depth test only for objects that ask for it;
//! - a texture without antialiasing computes no gradients, a model without noise no noise, an
//!   affine object no perspective divides (see [`crate::texture`], [`crate::span`],
//!   [`crate::raster`]).
//!
//! [`RenderStats`] counts the work of every stage, so tests can prove what did not run. Nothing
//! here allocates or panics.

use crate::color::Rgba8888;
use crate::filter::filter_width;
use crate::format::FilterWidth;
use crate::raster::{
    Counters, DepthBuffer, Rasterizer, Rect, ScreenVertex, Segment, TriangleOptions,
};
use crate::sink::{PixelSink, RgbaBuffer};
use crate::span::{EvalOptions, Span, SpanEvaluator};
use crate::texture::{ShadeStats, Shader, Texture, TextureEvaluator};

/// Most texture slots a scene may use.
pub const MAX_TEXTURES: usize = 8;

/// How an object's pixels combine with what is already there.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Blend {
    /// Replace.
    #[default]
    Opaque,
    /// Alpha-composite over the pixels behind (straight alpha, [`crate::color::over`]).
    Over,
}

/// How the renderer draws one object.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DrawObject {
    /// Texture slot.
    pub texture: usize,
    /// Blend mode.
    pub blend: Blend,
    /// Test and write the depth buffer.
    pub depth: bool,
    /// Rasterizer options (perspective mode, culling, depth function).
    pub raster: TriangleOptions,
}

/// A scene as the renderer sees it.
pub trait TriangleSource {
    /// Image size in pixels.
    fn size(&self) -> (u16, u16);
    /// Background colour.
    fn background(&self) -> Rgba8888;
    /// Number of objects.
    fn object_count(&self) -> usize;
    /// How object `i` is drawn (`None` past the end).
    fn object(&self, i: usize) -> Option<DrawObject>;
    /// Calls `f` with every screen triangle and its object index, in drawing order.
    fn for_each_triangle<F: FnMut(usize, &[ScreenVertex; 3])>(&self, f: F);
}

/// What the pixels show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Output {
    /// The texture's colours.
    #[default]
    Color,
    /// The filter width as grey: black = 1 entry, white = the whole table (Hart et al. fig. 9c).
    FilterWidth,
}

/// Why a frame could not be rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RenderError {
    /// An object names a texture slot that does not exist.
    NoSuchTexture {
        /// The object.
        object: usize,
        /// The slot it names.
        slot: usize,
    },
    /// More texture slots than [`MAX_TEXTURES`].
    TooManyTextures,
    /// The scene needs depth or blending: use [`Renderer::render_banded`].
    NeedsBands,
    /// The band or depth buffers are too small for one row of the image.
    BufferTooSmall,
}

/// A [`crate::scene::Scene`] as drawn (the scene as it is: apply [`crate::scene::Scene::at_frame`]
/// first for an animation frame). Objects use the depth buffer when they test or write depth.
impl TriangleSource for crate::scene::Scene {
    fn size(&self) -> (u16, u16) {
        crate::scene::Scene::size(self)
    }

    fn background(&self) -> Rgba8888 {
        Rgba8888::from_array(self.background)
    }

    fn object_count(&self) -> usize {
        self.objects.len()
    }

    fn object(&self, i: usize) -> Option<DrawObject> {
        let o = self.objects.get(i)?;
        Some(DrawObject {
            texture: usize::from(o.slot),
            blend: match o.blend {
                crate::scene::Blend::Opaque => Blend::Opaque,
                crate::scene::Blend::Over => Blend::Over,
            },
            depth: o.depth_test || o.depth_write,
            raster: o.options(),
        })
    }

    fn for_each_triangle<F: FnMut(usize, &[ScreenVertex; 3])>(&self, mut f: F) {
        self.for_each_triangle_static(&mut f);
    }
}

/// Counters of every stage of a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RenderStats {
    /// Rasterizer counters (triangles, segments, perspective divides, ...).
    pub raster: Counters,
    /// Texture counters (pixels, spans, cell set-ups, noise and gradient evaluations, look-ups).
    pub shade: ShadeStats,
    /// Pixels composited with [`Blend::Over`].
    pub blended_pixels: u64,
    /// Bands rendered (0 when streamed).
    pub bands: u32,
}

/// Pixels shaded per chunk before they are handed on: segments up to this length (any display
/// row up to 512 pixels) reach the sink in one call; longer ones in chunks of this size.
pub const CHUNK: usize = 512;

/// Renders scenes with a set of textures.
#[derive(Debug)]
pub struct Renderer<'t, const T: usize, const N: usize> {
    textures: &'t [Texture<T, N>],
    output: Output,
}

/// Per-slot evaluators, created once per frame.
struct Slots<'t, const T: usize, const N: usize> {
    evals: heapless::Vec<TextureEvaluator<'t, T, N>, MAX_TEXTURES>,
    widths: heapless::Vec<Option<WidthEval<'t, T, N>>, MAX_TEXTURES>,
}

/// Evaluates filter widths for [`Output::FilterWidth`].
struct WidthEval<'t, const T: usize, const N: usize> {
    tex: &'t Texture<T, N>,
    eval: Option<SpanEvaluator<'t, T>>,
}

impl<'t, const T: usize, const N: usize> Renderer<'t, T, N> {
    /// A renderer for `textures` (slot `i` is `textures[i]`).
    pub fn new(textures: &'t [Texture<T, N>]) -> Self {
        Renderer {
            textures,
            output: Output::Color,
        }
    }

    /// The same renderer showing `output`.
    pub fn with_output(mut self, output: Output) -> Self {
        self.output = output;
        self
    }

    fn check<S: TriangleSource>(&self, scene: &S) -> Result<bool, RenderError> {
        if self.textures.len() > MAX_TEXTURES {
            return Err(RenderError::TooManyTextures);
        }
        let mut needs_bands = false;
        for i in 0..scene.object_count() {
            if let Some(o) = scene.object(i) {
                if o.texture >= self.textures.len() {
                    return Err(RenderError::NoSuchTexture {
                        object: i,
                        slot: o.texture,
                    });
                }
                needs_bands |= o.depth || o.blend == Blend::Over;
            }
        }
        Ok(needs_bands)
    }

    /// Whether `scene` needs [`Renderer::render_banded`] (depth or blending).
    pub fn needs_bands<S: TriangleSource>(&self, scene: &S) -> Result<bool, RenderError> {
        self.check(scene)
    }

    fn slots(&self) -> Slots<'t, T, N> {
        let mut evals = heapless::Vec::new();
        let mut widths = heapless::Vec::new();
        for t in self.textures.iter().take(MAX_TEXTURES) {
            let _ = evals.push(t.evaluator());
            let w = match self.output {
                Output::Color => None,
                Output::FilterWidth => Some(WidthEval {
                    tex: t,
                    eval: match t.shader() {
                        Shader::Model(m) => Some(SpanEvaluator::new(
                            m,
                            EvalOptions {
                                gradients: true,
                                ..t.options()
                            },
                        )),
                        #[cfg(feature = "perturb")]
                        Shader::Perturbed(_) => None,
                    },
                }),
            };
            let _ = widths.push(w);
        }
        Slots { evals, widths }
    }

    /// Renders with no frame buffer: each segment's pixels go straight to `sink` (after the
    /// background, row by row). Objects must be opaque and not use depth; later objects overwrite
    /// earlier ones.
    pub fn render_streamed<S: TriangleSource, P: PixelSink>(
        &self,
        scene: &S,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        if self.check(scene)? {
            return Err(RenderError::NeedsBands);
        }
        let (w, h) = scene.size();
        let bg = scene.background();
        for y in 0..h {
            sink.fill_span(0, y, w, bg);
        }
        let mut slots = self.slots();
        let mut raster = Rasterizer::new(Rect::from_size(w, h));
        let mut stats = RenderStats::default();
        scene.for_each_triangle(|obj, tri| {
            let Some(o) = scene.object(obj) else { return };
            let mut seg_sink = |seg: &Segment| {
                shade_segment(&mut slots, o.texture, self.output, seg, |x, chunk| {
                    sink.write_span(x, seg.y, chunk)
                });
            };
            raster.draw(tri, &o.raster, &mut seg_sink);
        });
        stats.raster = raster.counters();
        stats.shade = slots_stats(&slots);
        Ok(stats)
    }

    /// Renders in bands of `band_rows` rows through `band` (RGBA, at least `width * band_rows`
    /// pixels) and `depth` (at least `width * band_rows` entries when any object uses depth),
    /// flushing each finished row to `sink`.
    pub fn render_banded<S: TriangleSource, P: PixelSink>(
        &self,
        scene: &S,
        band: &mut [Rgba8888],
        depth: &mut [u16],
        band_rows: u16,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        let h = scene.size().1;
        self.render_banded_rows(scene, 0..h, band, depth, band_rows, sink)
    }

    /// [`Renderer::render_banded`] restricted to the image rows `rows` (clipped to the image):
    /// the same scene geometry, with the rasteriser clipped to those rows, so the rows written to
    /// `sink` are exactly the rows `rows` of the whole image (a frame can be rendered as several
    /// independent horizontal strips, e.g. to bound the work of one call).
    pub fn render_banded_rows<S: TriangleSource, P: PixelSink>(
        &self,
        scene: &S,
        rows: core::ops::Range<u16>,
        band: &mut [Rgba8888],
        depth: &mut [u16],
        band_rows: u16,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        self.check(scene)?;
        let (w, h) = scene.size();
        let (first, end) = (rows.start.min(h), rows.end.min(h));
        let uses_depth =
            (0..scene.object_count()).any(|i| scene.object(i).is_some_and(|o| o.depth));
        let rows = band_rows.max(1).min(h.max(1));
        let mut buf = RgbaBuffer::new(band, w, 0, rows).ok_or(RenderError::BufferTooSmall)?;
        let need = usize::from(w) * usize::from(rows);
        if uses_depth && depth.len() < need {
            return Err(RenderError::BufferTooSmall);
        }
        let depth = if uses_depth {
            depth.get_mut(..need)
        } else {
            None
        };
        let mut depth = depth.and_then(|d| DepthBuffer::new(d, Rect::new(0, 0, w, rows)));
        let mut slots = self.slots();
        let mut stats = RenderStats::default();
        let mut raster = Rasterizer::new(Rect::from_size(w, h));
        let bg = scene.background();
        let mut y0 = first;
        while y0 < end {
            let y1 = y0.saturating_add(rows).min(end);
            let band_rect = Rect::new(0, y0, w, y1);
            raster.set_clip(band_rect);
            buf.set_y0(y0);
            buf.clear(bg);
            if let Some(d) = depth.as_mut() {
                d.set_rect(band_rect);
                d.clear(u16::MAX);
            }
            let mut blended = 0u64;
            scene.for_each_triangle(|obj, tri| {
                let Some(o) = scene.object(obj) else { return };
                let mut seg_sink = |seg: &Segment| {
                    shade_segment(&mut slots, o.texture, self.output, seg, |x, chunk| {
                        if o.blend == Blend::Over {
                            blended += chunk.len() as u64;
                            buf.blend_span(x, seg.y, chunk);
                        } else {
                            buf.write_span(x, seg.y, chunk);
                        }
                    });
                };
                match (o.depth, depth.as_mut()) {
                    (true, Some(d)) => raster.draw_depth(tri, &o.raster, d, &mut seg_sink),
                    _ => raster.draw(tri, &o.raster, &mut seg_sink),
                }
            });
            stats.blended_pixels += blended;
            for y in y0..y1 {
                if let Some(row) = buf.row(y) {
                    sink.write_span(0, y, row);
                }
            }
            stats.bands += 1;
            y0 = y1;
        }
        stats.raster = raster.counters();
        stats.shade = slots_stats(&slots);
        Ok(stats)
    }
}

fn slots_stats<const T: usize, const N: usize>(slots: &Slots<'_, T, N>) -> ShadeStats {
    let mut s = ShadeStats::default();
    for e in &slots.evals {
        s.add(&e.stats());
    }
    for w in slots.widths.iter().flatten() {
        if let Some(e) = &w.eval {
            s.span.add(e.stats());
        }
    }
    s
}

/// `log2 N` of a power of two.
const fn log2(n: usize) -> u32 {
    usize::BITS - 1 - n.leading_zeros()
}

/// Shades one segment into chunks of at most [`CHUNK`] pixels, calling `out(x, chunk)`.
fn shade_segment<const T: usize, const N: usize, O: FnMut(u16, &[Rgba8888])>(
    slots: &mut Slots<'_, T, N>,
    slot: usize,
    output: Output,
    seg: &Segment,
    mut out: O,
) {
    let span = Span {
        s0: seg.s0,
        ds: seg.ds,
        dsdy: seg.dsdy,
        len: seg.len,
    };
    let mut chunk = [Rgba8888::TRANSPARENT; CHUNK];
    let mut n = 0usize;
    let mut x = seg.x0;
    let mut push = |c: Rgba8888| {
        if let Some(p) = chunk.get_mut(n) {
            *p = c;
        }
        n += 1;
        if n == CHUNK {
            out(x, &chunk);
            x = x.saturating_add(CHUNK as u16);
            n = 0;
        }
    };
    match output {
        Output::Color => {
            if let Some(e) = slots.evals.get_mut(slot) {
                e.shade(&span, &mut push);
            }
        }
        Output::FilterWidth => {
            if let Some(Some(we)) = slots.widths.get_mut(slot) {
                width_span(we, &span, &mut push);
            }
        }
    }
    if let Some(rest) = chunk.get(..n).filter(|r| !r.is_empty()) {
        out(x, rest);
    }
}

/// The filter width of each pixel of `span` as grey: `(w - 1) * 255 / (N - 1)`, clamped.
fn width_span<const T: usize, const N: usize, F: FnMut(Rgba8888)>(
    we: &mut WidthEval<'_, T, N>,
    span: &Span,
    mut emit: F,
) {
    let lg = log2(N);
    let norm = we.tex.norm();
    let grey = |w: FilterWidth| {
        let one = 1u64 << 16;
        let w = u64::from(w.to_bits()).max(one) - one;
        let den = ((N as u64).max(2) - 1) << 16;
        let v = (w * 255 + den / 2) / den;
        let v = v.min(255) as u8;
        Rgba8888::new(v, v, v, 255)
    };
    match we.eval.as_mut() {
        Some(e) => {
            let extra = e.extra_width48(span);
            let e16 = (extra >> 32).clamp(0, i64::from(u32::MAX)) as u64;
            let extra_raw = (e16 << lg).min(u64::from(u32::MAX)) as u32;
            e.eval(span, |s| {
                let w = filter_width(s.gx, s.gy, norm, lg).to_bits();
                emit(grey(FilterWidth::from_bits(w.saturating_add(extra_raw))))
            });
        }
        None => {
            for _ in 0..span.len {
                emit(Rgba8888::new(255, 0, 255, 255));
            }
        }
    }
}

#[cfg(test)]
// Without `csat` the tests that shade through the summed-area filter are left out.
#[cfg_attr(not(feature = "csat"), allow(dead_code, unused_imports))]
mod tests {
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

    /// A full-screen quad with s = x / size, t = y / size at the corners, plus optional objects.
    struct Quads {
        size: u16,
        objects: Vec<(DrawObject, [ScreenVertex; 4])>,
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
        let p = crate::presets::marble(HashKind::default());
        let keys: Vec<_> = p
            .keys
            .iter()
            .map(|(k, c)| {
                (
                    crate::format::TexValue::from_bits(*k as i32),
                    Rgba8888::from_array(*c),
                )
            })
            .collect();
        let stage = ColorStage::new(
            ColorTable::from_keys(&keys).unwrap(),
            TableWrap::Mod,
            TableLookup::Nearest,
            Antialias::Csat,
        )
        .unwrap();
        Texture::new(
            Shader::Model(p.model),
            stage,
            GradientNorm::L2,
            EvalMode::Auto,
        )
    }

    fn render_full(
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

    #[cfg(feature = "embedded-graphics")]
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
    }
}
