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
//!   [`Blend::Over`] objects, the depth test only for objects that ask for it; every band walks
//!   the whole scene;
//! - [`Renderer::render_banded_rows_binned`]: the same pixels, bit for bit, with the scene's
//!   triangle groups (a [`crate::scene::Scene`]'s mesh quads) binned into bands once per frame
//!   in caller-owned [`FrameBins`] (4 bytes per group), so that each band generates only the
//!   groups that can touch it ([`TriangleSource::for_each_triangle_grouped`]), and a frame
//!   rendered as several strips walks the whole scene once;
//! - [`Renderer::render_banded_rows_binned_rgb565`] (and [`Renderer::render_banded_rgb565`]): the
//!   same rows reduced to RGB565, bit for bit, through an RGB565 band of half the bytes, for a
//!   display that takes RGB565 and a scene that does not blend: the alpha channel and the 8-bit
//!   colours are a stage such a scene does not use, so its unlit segments are shaded straight
//!   to RGB565 (one ramp read a pixel with `Antialias::Ramp`) and its rows reach the sink
//!   without a conversion ([`PixelSink::write_rgb565_span`]);
//! - a texture without antialiasing computes no gradients, a model without noise no noise, an
//!   affine object no perspective divides (see [`crate::texture`], [`crate::span`],
//!   [`crate::raster`]).
//!
//! [`RenderStats`] counts the work of every stage, so tests can prove what did not run. Nothing
//! here allocates or panics.

use crate::color::Rgba8888;
use crate::filter::filter_width_spread;
use crate::format::FilterWidth;
use crate::raster::{
    Counters, DepthBuffer, Rasterizer, Rect, ScreenVertex, Segment, TriangleOptions,
};
use crate::sink::{PixelSink, Rgb565Buffer, RgbaBuffer};
#[cfg(feature = "differences")]
use crate::span::FaceCache;
use crate::span::{EvalOptions, Span, SpanEvaluator};
#[cfg(feature = "differences")]
use crate::texture::{DifferenceMemory, MemoryRows};
use crate::texture::{ShadeStats, Shader, Texture, TextureEvaluator};

mod band;
mod bins;
#[cfg(all(test, feature = "differences", feature = "csat"))]
mod difference_tests;
mod draw;
mod light;
#[cfg(test)]
mod rgb565_tests;
mod segment;
#[cfg(test)]
// Without `csat` the tests that shade through the summed-area filter are left out.
#[cfg_attr(not(feature = "csat"), allow(dead_code, unused_imports))]
mod tests;

use band::Band;
use bins::triangle_rows;
pub use bins::{FrameBins, GroupRows};
use draw::{flush_rows, BandDraw, StreamDraw};
use light::{SegmentLight, Unlit, WalkLight};
#[cfg(feature = "differences")]
pub use segment::DIFFERENCE_MIN_ROWS;
use segment::{slots_stats, Slots, WidthEval};

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

    /// [`TriangleSource::for_each_triangle`] in groups, skipping the groups `keep` declines.
    ///
    /// A group is the unit a source can leave out before doing any work for it; groups are
    /// numbered `0, 1, 2, ...` in drawing order. `keep(g)` is asked at most once per group, in
    /// increasing order of `g`, before any of the group's triangles; when it answers `true`,
    /// `f(g, object, triangle)` is called with each of the group's triangles, before the next
    /// group is asked about; when it answers `false` the group emits nothing. A source may leave
    /// out the question for a group it knows to emit nothing. Implementations must guarantee:
    /// - with `keep` always `true`, exactly the calls of [`TriangleSource::for_each_triangle`]
    ///   (same triangles, object indices and order);
    /// - otherwise exactly the subsequence of those calls that belongs to the kept groups;
    /// - the same grouping on every walk of the same source.
    ///
    /// The provided implementation makes each triangle its own group: it still generates every
    /// triangle and only leaves out the calls of `f`. Sources that can skip work override it
    /// (a [`crate::scene::Scene`] groups by mesh quad and skips a declined quad before
    /// generating it).
    fn for_each_triangle_grouped<K, F>(&self, mut keep: K, mut f: F)
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3]),
    {
        let mut group = 0usize;
        self.for_each_triangle(|object, t| {
            if keep(group) {
                f(group, object, t);
            }
            group = group.wrapping_add(1);
        });
    }

    /// Whether the triangles carry light: the renderer then walks
    /// [`TriangleSource::for_each_lit_triangle_grouped`] and runs its lighting stage
    /// ([`crate::gouraud`]); otherwise it takes the unlit walk and the stage does no work.
    #[cfg(feature = "lighting")]
    fn is_lit(&self) -> bool {
        false
    }

    /// [`TriangleSource::for_each_triangle_grouped`] with a function giving the light at each
    /// vertex of the triangle (`Q16.16` per channel, `ONE` = the texture's colour), which the
    /// renderer calls only for a triangle that covers a pixel of the band. The provided
    /// implementation gives full light everywhere.
    #[cfg(feature = "lighting")]
    fn for_each_lit_triangle_grouped<K, F>(&self, keep: K, mut f: F)
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3], &dyn Fn() -> [crate::light::LightRgb; 3]),
    {
        let full = || [[crate::scene::math::ONE; 3]; 3];
        self.for_each_triangle_grouped(keep, |g, o, t| f(g, o, t, &full));
    }
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
    /// An object blends ([`Blend::Over`]), which needs its colours' alpha: render the scene
    /// into an RGBA band ([`Renderer::render_banded_rows_binned`]), not an RGB565 one.
    NeedsRgbaBand {
        /// The first blended object.
        object: usize,
    },
    /// The difference memory given to `Renderer::with_differences` (feature `differences`)
    /// is narrower than the image.
    MemoryTooNarrow {
        /// The image's width in pixels.
        width: u16,
        /// The memory's width in pixels.
        memory: usize,
    },
}

/// What a scene's objects call for ([`Renderer::check`]).
#[derive(Clone, Copy, Debug)]
struct SceneUse {
    /// Some object tests and writes the depth buffer.
    depth: bool,
    /// The first object that blends ([`Blend::Over`]).
    blended: Option<usize>,
}

impl SceneUse {
    /// Depth or blending: the scene needs bands.
    fn needs_bands(self) -> bool {
        self.depth || self.blended.is_some()
    }
}

/// The width of `scene` and the rows of a band of (at most) `band_rows` rows: at least one, at
/// most the image's height.
fn band_size<S: TriangleSource>(scene: &S, band_rows: u16) -> (u16, u16) {
    let (w, h) = scene.size();
    (w, band_rows.max(1).min(h.max(1)))
}

impl core::fmt::Display for RenderError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            RenderError::NoSuchTexture { object, slot } => write!(
                f,
                "object {object} uses texture slot {slot}, which does not exist"
            ),
            RenderError::TooManyTextures => {
                write!(f, "more than {MAX_TEXTURES} texture slots")
            }
            RenderError::NeedsBands => {
                f.write_str("the scene needs a depth buffer or blending: render it in bands")
            }
            RenderError::BufferTooSmall => {
                f.write_str("the band or depth buffer is too small for one row of the image")
            }
            RenderError::NeedsRgbaBand { object } => write!(
                f,
                "object {object} blends, which needs an RGBA band: an RGB565 band has no alpha"
            ),
            RenderError::MemoryTooNarrow { width, memory } => write!(
                f,
                "the difference memory holds rows of {memory} pixels, the image is {width} wide"
            ),
        }
    }
}

impl core::error::Error for RenderError {}

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
            blend: o.blend,
            depth: o.depth_test || o.depth_write,
            raster: o.options(),
        })
    }

    fn for_each_triangle<F: FnMut(usize, &[ScreenVertex; 3])>(&self, mut f: F) {
        self.for_each_triangle_static(&mut f);
    }

    /// One group per mesh quad ([`crate::scene::Scene::for_each_triangle_by_quad`]): a declined
    /// quad costs the `keep` call only.
    fn for_each_triangle_grouped<K, F>(&self, mut keep: K, mut f: F)
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3]),
    {
        self.for_each_triangle_by_quad(&mut keep, &mut f);
    }

    #[cfg(feature = "lighting")]
    fn is_lit(&self) -> bool {
        crate::scene::Scene::is_lit(self)
    }

    /// Per-vertex light from the scene's lights ([`crate::scene::Scene::for_each_lit_triangle_by_quad`]).
    #[cfg(feature = "lighting")]
    fn for_each_lit_triangle_grouped<K, F>(&self, mut keep: K, mut f: F)
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3], &dyn Fn() -> [crate::light::LightRgb; 3]),
    {
        self.for_each_lit_triangle_by_quad(&mut keep, &mut f);
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
    /// Triangle groups left out of a band by [`Renderer::render_banded_rows_binned`], summed
    /// over bands (0 without bins). Their triangles were not generated for that band, so they
    /// are missing from `raster.triangles` and `raster.offscreen` (unbinned, each of them
    /// would have been counted as submitted and offscreen there).
    pub skipped_groups: u64,
    /// Pixels multiplied by their light (the lighting stage, feature `lighting`): 0 for a
    /// scene without lights, and in builds without the feature.
    pub lit_pixels: u64,
}

/// Pixels shaded per chunk before they are handed on: segments up to this length reach the sink
/// in one call; longer ones in chunks of this size. The chunk lives on the stack and is cleared
/// once per segment, so it is kept short (segments of perspective triangles are at most 16
/// pixels between divides, and most are shorter).
pub const CHUNK: usize = 64;

/// Renders scenes with a set of textures.
#[derive(Debug)]
pub struct Renderer<'t, const T: usize, const N: usize> {
    textures: &'t [Texture<T, N>],
    output: Output,
    /// The memory of the filter widths from differences, when the renderer takes them so.
    #[cfg(feature = "differences")]
    differences: DifferenceSlot<'t>,
}

/// The memory of [`Renderer::with_differences`]: taken by a frame's render and put back after
/// it (the render methods borrow the renderer shared).
#[cfg(feature = "differences")]
#[derive(Default)]
struct DifferenceSlot<'t>(core::cell::Cell<Option<MemoryRows<'t>>>);

#[cfg(feature = "differences")]
impl core::fmt::Debug for DifferenceSlot<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let m = self.0.take();
        let width = m.as_ref().map(MemoryRows::width);
        self.0.set(m);
        f.debug_struct("DifferenceSlot")
            .field("width", &width)
            .finish()
    }
}

impl<'t, const T: usize, const N: usize> Renderer<'t, T, N> {
    /// A renderer for `textures` (slot `i` is `textures[i]`).
    pub fn new(textures: &'t [Texture<T, N>]) -> Self {
        Renderer {
            textures,
            output: Output::Color,
            #[cfg(feature = "differences")]
            differences: DifferenceSlot::default(),
        }
    }

    /// The same renderer taking every filtered texture's filter widths from the differences of
    /// neighbouring values instead of the noise's gradients (feature `differences`; a named
    /// approximate mode, `texture::DifferenceSpans` for planes; `docs/model.md` 8.4.1): each
    /// segment's values are evaluated without gradients and pixel `(x, y)`'s width is the
    /// stage's width of `(f(x + 1, y) - f(x, y), f(x, y) - f(x, y - 1))`, both neighbours taken
    /// within the pixel's triangle, as a GPU's `ddx`/`ddy`: a segment's last pixel takes its
    /// left neighbour's horizontal difference; a pixel whose triangle lacks the pixel above
    /// takes the vertical difference of the segment's nearest pixel that has it, and a segment
    /// with none (a triangle's first row, and the first row of every tile of
    /// [`crate::texture::TILE_ROWS`] rows) is evaluated once more one row up
    /// ([`TextureEvaluator::shade_differences`]). So the colours are the same streamed and in
    /// bands of any multiple of that many rows. A triangle spanning fewer than
    /// [`DIFFERENCE_MIN_ROWS`] rows (its vertices' vertical extent) takes the gradients' widths
    /// instead: on so few rows the re-evaluated row above costs more than the gradients save,
    /// and the differences of its edge pixels are the coarsest. `mem` holds the row above; a frame wider than
    /// `W` pixels is refused ([`RenderError::MemoryTooNarrow`]). The filter-width output
    /// ([`Output::FilterWidth`]) still shows the gradients' widths. The colours are the same on
    /// every target.
    ///
    /// What it costs and saves (`docs/cycles.md`, `scene:<name>~ramp-diff`): the colour stage's
    /// root (and with the ramp, one read a pixel); the values alone cost about what the values
    /// and gradients cost on the exact path, and the rows above each triangle's and each tile's
    /// first row are evaluated once more. The built-in fire (large triangles) is 40% cheaper
    /// with the ramp; a fine mesh (the marble scene, most of its triangles short) about 6%.
    ///
    /// `faces` keeps the face blends of the noise's axis-aligned terms across segments
    /// ([`FaceCache`]: the same values, bit for bit, with fewer hashes whatever its size;
    /// `FaceCache::<1, 0>` keeps next to nothing): rows of a triangle, and the triangles of
    /// one surface, cross the same cell faces.
    #[cfg(feature = "differences")]
    pub fn with_differences<const W: usize, const F: usize, const L: usize>(
        self,
        mem: &'t mut DifferenceMemory<W>,
        faces: &'t mut FaceCache<F, L>,
    ) -> Self {
        mem.forget();
        self.differences.0.set(Some(mem.rows_mut(faces.parts())));
        self
    }

    /// Gives the frame's difference memory back (see [`DifferenceSlot`]).
    #[cfg_attr(not(feature = "differences"), allow(unused_variables))]
    fn put_back(&self, slots: &mut Slots<'t, T, N>) {
        #[cfg(feature = "differences")]
        if let Some(m) = slots.mem.take() {
            self.differences.0.set(Some(m));
        }
    }

    /// The same renderer showing `output`.
    pub fn with_output(mut self, output: Output) -> Self {
        self.output = output;
        self
    }

    /// Checks `scene` against this renderer (texture slots, the difference memory's width) and
    /// finds what its objects call for.
    fn check<S: TriangleSource>(&self, scene: &S) -> Result<SceneUse, RenderError> {
        if self.textures.len() > MAX_TEXTURES {
            return Err(RenderError::TooManyTextures);
        }
        #[cfg(feature = "differences")]
        {
            let m = self.differences.0.take();
            let memory = m.as_ref().map(MemoryRows::width);
            self.differences.0.set(m);
            let width = scene.size().0;
            if let Some(memory) = memory.filter(|&w| w < usize::from(width)) {
                return Err(RenderError::MemoryTooNarrow { width, memory });
            }
        }
        let mut uses = SceneUse {
            depth: false,
            blended: None,
        };
        for i in 0..scene.object_count() {
            if let Some(o) = scene.object(i) {
                if o.texture >= self.textures.len() {
                    return Err(RenderError::NoSuchTexture {
                        object: i,
                        slot: o.texture,
                    });
                }
                uses.depth |= o.depth;
                if o.blend == Blend::Over && uses.blended.is_none() {
                    uses.blended = Some(i);
                }
            }
        }
        Ok(uses)
    }

    /// Whether `scene` needs [`Renderer::render_banded`] (depth or blending).
    pub fn needs_bands<S: TriangleSource>(&self, scene: &S) -> Result<bool, RenderError> {
        self.check(scene).map(SceneUse::needs_bands)
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
        Slots {
            evals,
            widths,
            #[cfg(feature = "differences")]
            mem: self.differences.0.take(),
            #[cfg(feature = "differences")]
            short: false,
        }
    }

    /// Renders with no frame buffer: each segment's pixels go straight to `sink` (after the
    /// background, row by row). Objects must be opaque and not use depth; later objects overwrite
    /// earlier ones.
    pub fn render_streamed<S: TriangleSource, P: PixelSink>(
        &self,
        scene: &S,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        if self.check(scene)?.needs_bands() {
            return Err(RenderError::NeedsBands);
        }
        let (w, h) = scene.size();
        let bg = scene.background();
        for y in 0..h {
            sink.fill_span(0, y, w, bg);
        }
        let mut draw = StreamDraw {
            scene,
            slots: self.slots(),
            output: self.output,
            raster: Rasterizer::new(Rect::from_size(w, h)),
            sink,
            lit: 0,
        };
        // One drawing per walk, each compiled for its light (see `WalkLight`).
        #[cfg(feature = "lighting")]
        if scene.is_lit() {
            scene.for_each_lit_triangle_grouped(
                |_| true,
                |_, obj, tri, l| draw.triangle(obj, tri, l),
            );
        } else {
            scene.for_each_triangle(|obj, tri| draw.triangle(obj, tri, Unlit));
        }
        #[cfg(not(feature = "lighting"))]
        scene.for_each_triangle(|obj, tri| draw.triangle(obj, tri, Unlit));
        self.put_back(&mut draw.slots);
        Ok(RenderStats {
            raster: draw.raster.counters(),
            shade: slots_stats(&draw.slots),
            lit_pixels: draw.lit,
            ..RenderStats::default()
        })
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
    ///
    /// Every band walks the whole scene; [`Renderer::render_banded_rows_binned`] renders the same
    /// pixels walking it once.
    pub fn render_banded_rows<S: TriangleSource, P: PixelSink>(
        &self,
        scene: &S,
        rows: core::ops::Range<u16>,
        band: &mut [Rgba8888],
        depth: &mut [u16],
        band_rows: u16,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        self.render_banded_rows_binned(
            scene,
            rows,
            band,
            depth,
            band_rows,
            &mut FrameBins::new(&mut []),
            sink,
        )
    }

    /// Fills `bins` for `scene` by one walk over all its groups (generating every triangle,
    /// rasterizing none), so that every [`Renderer::render_banded_rows_binned`] call with them
    /// walks only the groups that touch each band, from its first band on: a frame rendered in
    /// strips then pays for one walk, not one per strip. The same walk as the first band of
    /// an unfilled render makes, so the bins equal the ones that render would fill.
    pub fn bin<S: TriangleSource>(
        &self,
        scene: &S,
        bins: &mut FrameBins<'_>,
    ) -> Result<(), RenderError> {
        self.check(scene)?;
        let (w, h) = scene.size();
        let image = 0..h;
        for b in bins.rows.iter_mut() {
            *b = GroupRows::EMPTY;
        }
        let rows = &mut *bins.rows;
        scene.for_each_triangle_grouped(
            |_| true,
            |g, _, tri| {
                if let (Some(b), Some((r0, r1))) = (rows.get_mut(g), triangle_rows(tri, &image, w))
                {
                    b.include(r0, r1);
                }
            },
        );
        bins.filled = Some((w, h));
        Ok(())
    }

    /// [`Renderer::render_banded_rows`] with the scene's triangle groups binned into bands in
    /// `bins` ([`FrameBins`]: caller-owned, one [`GroupRows`] per group; see
    /// [`TriangleSource::for_each_triangle_grouped`]).
    ///
    /// Unless `bins` are filled already (by an earlier call for the same frame, or by
    /// [`Renderer::bin`]), the first band's walk over the scene takes every group and records
    /// in the bins the image rows that group `g`'s triangles can cover ([`GroupRows`]: from
    /// their vertices' vertical extent, the pixel-centre convention of the rasterizer's
    /// bounding-box rejection, over the whole image, not only `rows`); every other band asks
    /// the scene only for the groups whose rows meet the band, so a [`crate::scene::Scene`]
    /// generates, transforms and projects each quad only for the bands it can touch instead of
    /// for every band, and a frame rendered as several strips with the same bins walks the
    /// whole scene once. Groups past the table's end are always walked (too few bins cost
    /// speed, not correctness; an empty table is [`Renderer::render_banded_rows`]);
    /// [`crate::scene::Scene::quad_count`] is the number a scene needs.
    ///
    /// Guarantees: the pixels written to `sink` are bit-identical to
    /// [`Renderer::render_banded_rows`]'s for every table length, filled or not (under the
    /// [`FrameBins`] contract), since a group left out of a band cannot cover a pixel centre
    /// of it, and the groups a band walks reach the rasterizer in the same order (same depth
    /// tests, same blending order). [`RenderStats`] differ only in
    /// [`RenderStats::skipped_groups`] and in the triangles the skipped groups would have added
    /// to `raster.triangles` and `raster.offscreen`. On return the bins are filled for `scene`
    /// (unless `rows` held no image row). The source must give the same triangles on every
    /// walk (as any deterministic source does). No allocation, no panics.
    #[allow(clippy::too_many_arguments)]
    pub fn render_banded_rows_binned<S: TriangleSource, P: PixelSink>(
        &self,
        scene: &S,
        rows: core::ops::Range<u16>,
        band: &mut [Rgba8888],
        depth: &mut [u16],
        band_rows: u16,
        bins: &mut FrameBins<'_>,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        let uses = self.check(scene)?;
        let (w, band_rows) = band_size(scene, band_rows);
        let buf = RgbaBuffer::new(band, w, 0, band_rows).ok_or(RenderError::BufferTooSmall)?;
        self.render_bands(scene, uses, rows, buf, depth, bins, sink)
    }

    /// [`Renderer::render_banded`] into an RGB565 band (`band`: at least `width * band_rows`
    /// pixels, raw [`crate::color::Rgb565`] bits), each finished row handed to the sink's
    /// [`PixelSink::write_rgb565_span`]. See
    /// [`Renderer::render_banded_rows_binned_rgb565`].
    pub fn render_banded_rgb565<S: TriangleSource, P: PixelSink>(
        &self,
        scene: &S,
        band: &mut [u16],
        depth: &mut [u16],
        band_rows: u16,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        let h = scene.size().1;
        let mut bins = FrameBins::new(&mut []);
        self.render_banded_rows_binned_rgb565(scene, 0..h, band, depth, band_rows, &mut bins, sink)
    }

    /// [`Renderer::render_banded_rows_binned`] into an RGB565 band (`band`: at least
    /// `width * band_rows` pixels, raw [`crate::color::Rgb565`] bits), for a display that takes
    /// RGB565: an unlit object's segments are shaded straight to RGB565
    /// (`TextureEvaluator::shade565`: one ramp read a pixel with `Antialias::Ramp`), the band
    /// holds half the bytes, and each finished row goes to the sink's
    /// [`PixelSink::write_rgb565_span`] as it is (the RGBA band reduces every pixel at the flush
    /// instead).
    ///
    /// Guarantees: the rows the sink receives are [`Renderer::render_banded_rows_binned`]'s rows
    /// reduced to RGB565 ([`Rgba8888::to_rgb565`]), bit for bit, lit or not (a lit object is
    /// shaded and lit in RGBA8888 and reduced as it is written), so a [`crate::sink::ChecksumSink`]
    /// gives the same checksum either way. A scene with a blended object ([`Blend::Over`])
    /// needs its colours' alpha: [`RenderError::NeedsRgbaBand`], nothing drawn.
    #[allow(clippy::too_many_arguments)]
    pub fn render_banded_rows_binned_rgb565<S: TriangleSource, P: PixelSink>(
        &self,
        scene: &S,
        rows: core::ops::Range<u16>,
        band: &mut [u16],
        depth: &mut [u16],
        band_rows: u16,
        bins: &mut FrameBins<'_>,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        let uses = self.check(scene)?;
        if let Some(object) = uses.blended {
            return Err(RenderError::NeedsRgbaBand { object });
        }
        let (w, band_rows) = band_size(scene, band_rows);
        let buf = Rgb565Buffer::new(band, w, 0, band_rows).ok_or(RenderError::BufferTooSmall)?;
        self.render_bands(scene, uses, rows, buf, depth, bins, sink)
    }

    /// The banded render of [`Renderer::render_banded_rows_binned`] into the band `buf` (its
    /// rows of the image's width, [`band_size`]), for a scene [`Renderer::check`] passed with
    /// `uses`.
    #[allow(clippy::too_many_arguments)]
    fn render_bands<S: TriangleSource, P: PixelSink, B: Band>(
        &self,
        scene: &S,
        uses: SceneUse,
        rows: core::ops::Range<u16>,
        buf: B,
        depth: &mut [u16],
        bins: &mut FrameBins<'_>,
        sink: &mut P,
    ) -> Result<RenderStats, RenderError> {
        let (w, h) = scene.size();
        let reuse = bins.is_filled_for((w, h));
        let (first, end) = (rows.start.min(h), rows.end.min(h));
        let uses_depth = uses.depth;
        let rows = buf.height();
        let need = usize::from(w) * usize::from(rows);
        if uses_depth && depth.len() < need {
            return Err(RenderError::BufferTooSmall);
        }
        let depth = if uses_depth {
            depth.get_mut(..need)
        } else {
            None
        };
        let depth = depth.and_then(|d| DepthBuffer::new(d, Rect::new(0, 0, w, rows)));
        let mut stats = RenderStats::default();
        let bg = scene.background();
        let filled = &mut bins.filled;
        // Shared by the `keep` and the triangle callbacks of one walk.
        let bins = core::cell::Cell::from_mut(&mut *bins.rows).as_slice_of_cells();
        let mut draw = BandDraw {
            scene,
            slots: self.slots(),
            output: self.output,
            raster: Rasterizer::new(Rect::from_size(w, h)),
            buf,
            depth,
            binning: None,
            image: 0..h,
            blended: 0,
            lit: 0,
        };
        let mut y0 = first;
        while y0 < end {
            let y1 = y0.saturating_add(rows).min(end);
            let band_rect = Rect::new(0, y0, w, y1);
            draw.raster.set_clip(band_rect);
            draw.buf.set_y0(y0);
            draw.buf.clear(bg);
            if let Some(d) = draw.depth.as_mut() {
                d.set_rect(band_rect);
                d.clear(u16::MAX);
            }
            // Unless they are filled already, the first band's walk takes every group and fills
            // the bins (with the rows of the whole image, so that they serve any later call).
            let binning = !reuse && y0 == first;
            if binning {
                for b in bins {
                    b.set(GroupRows::EMPTY);
                }
                *filled = Some((w, h));
            }
            draw.binning = binning.then_some(bins);
            let mut skipped = 0u64;
            let keep = |g: usize| {
                let take = binning || bins.get(g).is_none_or(|b| b.get().touches(y0, y1));
                skipped += u64::from(!take);
                take
            };
            // One walk per light, each compiled on its own (see `BandDraw::walk_unlit`).
            #[cfg(feature = "lighting")]
            if scene.is_lit() {
                draw.walk_lit(keep);
            } else {
                draw.walk_unlit(keep);
            }
            #[cfg(not(feature = "lighting"))]
            draw.walk_unlit(keep);
            stats.skipped_groups += skipped;
            draw.buf.flush(y0..y1, sink);
            stats.bands += 1;
            y0 = y1;
        }
        self.put_back(&mut draw.slots);
        stats.blended_pixels = draw.blended;
        stats.lit_pixels = draw.lit;
        stats.raster = draw.raster.counters();
        stats.shade = slots_stats(&draw.slots);
        Ok(stats)
    }
}
