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
use crate::sink::{PixelSink, RgbaBuffer};
#[cfg(feature = "differences")]
use crate::span::FaceCache;
use crate::span::{EvalOptions, Span, SpanEvaluator};
#[cfg(feature = "differences")]
use crate::texture::{DifferenceMemory, MemoryRows};
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

/// How a walk over the scene lights its triangles, as a type, so that each walk's drawing is
/// compiled for its own case: the unlit walk's [`Unlit`] has no value and no code (no light
/// plane, no option to test, no lighting stage: the same code as a build without the `lighting`
/// feature); the lit walk's vertex-light function (feature `lighting`) computes a triangle's
/// light plane at its first segment (a triangle with none in the band costs nothing) and
/// multiplies each chunk of its pixels by it.
trait WalkLight: Copy {
    /// Whether the walk lights its pixels (counted in [`RenderStats::lit_pixels`]).
    const LIT: bool;
    /// Where a triangle's light plane is kept between its segments.
    type Plane: Default;
    /// The light of one segment of the triangle.
    type Segment<'p>: SegmentLight
    where
        Self: 'p;
    /// The light of triangle `tri`'s segments, computed into `plane` at the first one.
    fn segment<'p>(self, plane: &'p mut Self::Plane, tri: &[ScreenVertex; 3]) -> Self::Segment<'p>;
}

/// The light of one segment's pixels (see [`WalkLight`]).
trait SegmentLight: Copy {
    /// The lighting stage: multiplies the pixels `x..` of row `y` by the light.
    fn light_span(self, x: u16, y: u16, px: &mut [Rgba8888]);
}

/// No light: the unlit walk (and every walk of a build without the `lighting` feature).
#[derive(Clone, Copy, Debug, Default)]
struct Unlit;

impl WalkLight for Unlit {
    const LIT: bool = false;
    type Plane = ();
    type Segment<'p> = Unlit;

    #[inline(always)]
    fn segment(self, _: &mut (), _: &[ScreenVertex; 3]) -> Unlit {
        Unlit
    }
}

impl SegmentLight for Unlit {
    #[inline(always)]
    fn light_span(self, _: u16, _: u16, _: &mut [Rgba8888]) {}
}

/// The lights of a triangle's three vertices (`Q16.16` per channel).
#[cfg(feature = "lighting")]
type VertexLights = [crate::light::LightRgb; 3];

/// The lit walk: the scene's function giving the triangle's vertex lights
/// ([`TriangleSource::for_each_lit_triangle_grouped`]).
#[cfg(feature = "lighting")]
impl WalkLight for &dyn Fn() -> VertexLights {
    const LIT: bool = true;
    type Plane = Option<crate::gouraud::TriangleLight>;
    type Segment<'p>
        = &'p crate::gouraud::TriangleLight
    where
        Self: 'p;

    #[inline(always)]
    fn segment<'p>(
        self,
        plane: &'p mut Self::Plane,
        tri: &[ScreenVertex; 3],
    ) -> &'p crate::gouraud::TriangleLight {
        plane.get_or_insert_with(|| crate::gouraud::TriangleLight::new(tri, &self()))
    }
}

#[cfg(feature = "lighting")]
impl SegmentLight for &crate::gouraud::TriangleLight {
    #[inline(always)]
    fn light_span(self, x: u16, y: u16, px: &mut [Rgba8888]) {
        self.modulate_span(x, y, px);
    }
}

/// The image rows a group of triangles (see [`TriangleSource::for_each_triangle_grouped`]) can
/// cover, as recorded by [`Renderer::render_banded_rows_binned`]: an inclusive row range, or
/// empty. Four bytes.
///
/// Invariant: either [`GroupRows::EMPTY`] (the only empty value), or `first <= last`. As
/// recorded by the renderer, every pixel centre of the rendered rows and columns that the
/// group's triangles can cover lies on a row in `first..=last`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GroupRows {
    first: u16,
    last: u16,
}

impl GroupRows {
    /// No rows: the group covers no pixel centre.
    pub const EMPTY: GroupRows = GroupRows {
        first: u16::MAX,
        last: 0,
    };

    /// The rows `first..=last` (empty if `first > last`).
    pub const fn new(first: u16, last: u16) -> GroupRows {
        if first > last {
            GroupRows::EMPTY
        } else {
            GroupRows { first, last }
        }
    }

    /// Whether no row is covered.
    pub const fn is_empty(&self) -> bool {
        self.first > self.last
    }

    /// The first and last row covered (`None` when empty).
    pub const fn rows(&self) -> Option<(u16, u16)> {
        if self.is_empty() {
            None
        } else {
            Some((self.first, self.last))
        }
    }

    /// Whether a row of `y0..y1` is covered.
    #[inline]
    pub const fn touches(&self, y0: u16, y1: u16) -> bool {
        // Empty is `first == u16::MAX >= y1`.
        self.first < y1 && self.last >= y0 && y0 < y1
    }

    /// The smallest range covering both `self` and `first..=last` (`first <= last`).
    #[inline]
    fn include(&mut self, first: u16, last: u16) {
        if self.is_empty() {
            *self = GroupRows { first, last };
        } else {
            self.first = self.first.min(first);
            self.last = self.last.max(last);
        }
    }
}

impl Default for GroupRows {
    /// [`GroupRows::EMPTY`].
    fn default() -> Self {
        GroupRows::EMPTY
    }
}

/// The bins of one frame: a caller-owned table of [`GroupRows`] (one per triangle group, 4
/// bytes each) and whether a walk over the whole scene has filled it, and for which image size.
///
/// A frame rendered in several calls (horizontal strips, e.g. to bound the work of one call or
/// to stream a display in parts) walks the whole scene only once: the first
/// [`Renderer::render_banded_rows_binned`] call (or [`Renderer::bin`]) fills the bins with the
/// rows each group can cover anywhere in the image, and every later call with the same bins
/// takes each band's groups from them from its first band on.
///
/// Guarantees: bins are filled only by a walk over every group of a scene, recording the
/// rows of the whole image (never only of the rows that call rendered), so filled bins are
/// valid for any rows of that scene's frame. Contract: the bins describe the triangles of the
/// walk that filled them. Call [`FrameBins::reset`] before rendering another scene of the same
/// size, or the same scene after its triangles changed (a new camera or animation time): with
/// stale bins a band may leave out a group that covers it. A scene of another size is binned
/// again without a reset.
#[derive(Debug)]
pub struct FrameBins<'b> {
    rows: &'b mut [GroupRows],
    /// The image size of the scene whose walk filled `rows`; `None`: not filled.
    filled: Option<(u16, u16)>,
}

impl<'b> FrameBins<'b> {
    /// Bins in `rows`, not filled (any contents: the first walk overwrites every entry).
    /// Groups past `rows.len()` are walked in every band (too few bins cost speed, never
    /// pixels); [`crate::scene::Scene::quad_count`] is the number a scene needs. An empty table
    /// bins nothing: every band walks the whole scene.
    pub fn new(rows: &'b mut [GroupRows]) -> Self {
        FrameBins { rows, filled: None }
    }

    /// Forgets the filling: the next render (or [`Renderer::bin`]) walks the whole scene again.
    pub fn reset(&mut self) {
        self.filled = None;
    }

    /// Whether a walk has filled the bins (for a scene of image size `size`).
    pub fn is_filled_for(&self, size: (u16, u16)) -> bool {
        self.filled == Some(size)
    }

    /// The bins: entry `g` holds the rows group `g` can cover once filled.
    pub fn rows(&self) -> &[GroupRows] {
        self.rows
    }
}

/// The rows of `rows` (non-empty) that triangle `t` can cover a pixel centre of, as a range
/// that meets every band in which the rasterizer's bounding-box test
/// (`Rasterizer::misses`, pixel centres at `16 p + 8` in 28.4 fixed point) lets `t` through: the
/// rows from `ceil((y0 - 8) / 16)` to `floor((y1 - 8) / 16)` of its vertical extent `y0..=y1`,
/// or, when that extent holds no pixel centre, the two rows whose centres bracket it; clamped
/// to `rows`. `None` if the range misses `rows` or the horizontal extent misses every pixel
/// centre of the columns `0..width`: then that test rejects `t` in every band of `rows`.
fn triangle_rows(
    t: &[ScreenVertex; 3],
    rows: &core::ops::Range<u16>,
    width: u16,
) -> Option<(u16, u16)> {
    let [x0, x1, y0, y1] = crate::raster::bounding_box(t).map(i64::from);
    if x1 < 8 || x0 > 16 * i64::from(width) - 8 {
        return None;
    }
    let (below, above) = ((y0 + 7) >> 4, (y1 - 8) >> 4);
    let first = below.min(above).max(i64::from(rows.start));
    let last = below.max(above).min(i64::from(rows.end) - 1);
    (first <= last).then_some((first as u16, last as u16))
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
    /// The difference memory given to `Renderer::with_differences` (feature `differences`)
    /// is narrower than the image.
    MemoryTooNarrow {
        /// The image's width in pixels.
        width: u16,
        /// The memory's width in pixels.
        memory: usize,
    },
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

/// Per-slot evaluators, created once per frame.
struct Slots<'t, const T: usize, const N: usize> {
    evals: heapless::Vec<TextureEvaluator<'t, T, N>, MAX_TEXTURES>,
    widths: heapless::Vec<Option<WidthEval<'t, T, N>>, MAX_TEXTURES>,
    /// The frame's difference memory ([`Renderer::with_differences`]).
    #[cfg(feature = "differences")]
    mem: Option<MemoryRows<'t>>,
}

impl<const T: usize, const N: usize> Slots<'_, T, N> {
    /// A new triangle: the differences start again (they are taken within one triangle).
    #[inline(always)]
    fn new_triangle(&mut self) {
        #[cfg(feature = "differences")]
        if let Some(m) = self.mem.as_mut() {
            m.forget();
        }
    }
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
    /// bands of any multiple of that many rows. `mem` holds the row above; a frame wider than
    /// `W` pixels is refused ([`RenderError::MemoryTooNarrow`]). The filter-width output
    /// ([`Output::FilterWidth`]) still shows the gradients' widths. The colours are the same on
    /// every target.
    ///
    /// What it costs and saves (`docs/cycles.md`, `scene:<name>~ramp-diff`): the colour stage's
    /// root (and with the ramp, one read a pixel); the values alone cost about what the values
    /// and gradients cost on the exact path, and the rows above each triangle's and each tile's
    /// first row are evaluated once more. The built-in fire (two large triangles) is 40% cheaper
    /// with the ramp; a fine mesh (the marble scene) about as dear as its exact frame.
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

    fn check<S: TriangleSource>(&self, scene: &S) -> Result<bool, RenderError> {
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
        Slots {
            evals,
            widths,
            #[cfg(feature = "differences")]
            mem: self.differences.0.take(),
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
        if self.check(scene)? {
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
        self.check(scene)?;
        let (w, h) = scene.size();
        let reuse = bins.is_filled_for((w, h));
        let (first, end) = (rows.start.min(h), rows.end.min(h));
        let uses_depth =
            (0..scene.object_count()).any(|i| scene.object(i).is_some_and(|o| o.depth));
        let rows = band_rows.max(1).min(h.max(1));
        let buf = RgbaBuffer::new(band, w, 0, rows).ok_or(RenderError::BufferTooSmall)?;
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
            flush_rows(&draw.buf, y0..y1, sink);
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

/// What the streamed renderer draws a triangle with ([`Renderer::render_streamed`]).
struct StreamDraw<'a, 't, S, P, const T: usize, const N: usize> {
    scene: &'a S,
    slots: Slots<'t, T, N>,
    output: Output,
    raster: Rasterizer,
    sink: &'a mut P,
    /// Pixels lit.
    lit: u64,
}

impl<S: TriangleSource, P: PixelSink, const T: usize, const N: usize>
    StreamDraw<'_, '_, S, P, T, N>
{
    /// Draws triangle `tri` of object `obj` straight to the sink, lit by `light`.
    #[inline(always)]
    fn triangle<W: WalkLight>(&mut self, obj: usize, tri: &[ScreenVertex; 3], light: W) {
        let Some(o) = self.scene.object(obj) else {
            return;
        };
        let (slots, output, sink, lit) =
            (&mut self.slots, self.output, &mut *self.sink, &mut self.lit);
        slots.new_triangle();
        let mut plane = W::Plane::default();
        let mut seg_sink = |seg: &Segment| {
            let light = light.segment(&mut plane, tri);
            shade_segment(slots, o.texture, output, seg, light, |x, chunk| {
                if W::LIT {
                    *lit += chunk.len() as u64;
                }
                sink.write_span(x, seg.y, chunk)
            });
        };
        self.raster.draw(tri, &o.raster, &mut seg_sink);
    }
}

/// What the banded renderer draws a triangle with ([`Renderer::render_banded_rows_binned`]).
struct BandDraw<'a, 't, S, const T: usize, const N: usize> {
    scene: &'a S,
    slots: Slots<'t, T, N>,
    output: Output,
    raster: Rasterizer,
    buf: RgbaBuffer<'a>,
    depth: Option<DepthBuffer<'a>>,
    /// The bins this band's walk fills (the first band's, unless they were filled already).
    binning: Option<&'a [core::cell::Cell<GroupRows>]>,
    /// The image's rows (what the bins record).
    image: core::ops::Range<u16>,
    /// Pixels composited with [`Blend::Over`].
    blended: u64,
    /// Pixels lit.
    lit: u64,
}

impl<S: TriangleSource, const T: usize, const N: usize> BandDraw<'_, '_, S, T, N> {
    /// One band's walk over the scene without light: the groups `keep` takes, each triangle
    /// drawn by [`BandDraw::triangle`]. Out of line, as is [`BandDraw::walk_lit`], so that each
    /// walk is compiled on its own: the unlit walk is the same code whether the lit one exists
    /// (feature `lighting`) or not.
    #[inline(never)]
    fn walk_unlit<K: FnMut(usize) -> bool>(&mut self, keep: K) {
        let scene = self.scene;
        scene.for_each_triangle_grouped(keep, |g, obj, tri| self.triangle(g, obj, tri, Unlit));
    }

    /// One band's walk over the scene with its lights (see [`BandDraw::walk_unlit`]).
    #[cfg(feature = "lighting")]
    #[inline(never)]
    fn walk_lit<K: FnMut(usize) -> bool>(&mut self, keep: K) {
        let scene = self.scene;
        scene.for_each_lit_triangle_grouped(keep, |g, obj, tri, l| self.triangle(g, obj, tri, l));
    }

    /// Draws triangle `tri` (group `g`, object `obj`) into the band, lit by `light`, recording
    /// its rows in the bins when this walk fills them.
    #[inline(always)]
    fn triangle<W: WalkLight>(&mut self, g: usize, obj: usize, tri: &[ScreenVertex; 3], light: W) {
        if let Some(b) = self.binning.and_then(|bins| bins.get(g)) {
            if let Some((r0, r1)) = triangle_rows(tri, &self.image, self.buf.width()) {
                let mut r = b.get();
                r.include(r0, r1);
                b.set(r);
            }
        }
        let Some(o) = self.scene.object(obj) else {
            return;
        };
        let (slots, output, buf) = (&mut self.slots, self.output, &mut self.buf);
        slots.new_triangle();
        let (blended, lit) = (&mut self.blended, &mut self.lit);
        let mut plane = W::Plane::default();
        let mut seg_sink = |seg: &Segment| {
            let light = light.segment(&mut plane, tri);
            shade_segment(slots, o.texture, output, seg, light, |x, chunk| {
                if W::LIT {
                    *lit += chunk.len() as u64;
                }
                if o.blend == Blend::Over {
                    *blended += chunk.len() as u64;
                    buf.blend_span(x, seg.y, chunk);
                } else {
                    buf.write_span(x, seg.y, chunk);
                }
            });
        };
        match (o.depth, self.depth.as_mut()) {
            (true, Some(d)) => self.raster.draw_depth(tri, &o.raster, d, &mut seg_sink),
            _ => self.raster.draw(tri, &o.raster, &mut seg_sink),
        }
    }
}

/// Writes the rows `rows` of `buf` to `sink`. Out of line, so that the sink's per-pixel loop is
/// compiled apart from the band loop's state.
#[inline(never)]
fn flush_rows<P: PixelSink>(buf: &RgbaBuffer<'_>, rows: core::ops::Range<u16>, sink: &mut P) {
    for y in rows {
        if let Some(row) = buf.row(y) {
            sink.write_span(0, y, row);
        }
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
fn shade_segment<const T: usize, const N: usize, L: SegmentLight, O: FnMut(u16, &[Rgba8888])>(
    slots: &mut Slots<'_, T, N>,
    slot: usize,
    output: Output,
    seg: &Segment,
    light: L,
    mut out: O,
) {
    let span = Span {
        s0: seg.s0,
        ds: seg.ds,
        dsdy: seg.dsdy,
        len: seg.len,
    };
    // Widths from differences for a filtered texture (an unfiltered one needs no widths, and
    // no row above): the segment's colours a chunk at a time.
    #[cfg(feature = "differences")]
    if let (Output::Color, Some(m), Some(e)) =
        (output, slots.mem.as_mut(), slots.evals.get_mut(slot))
    {
        if e.stage().antialias() != crate::filter::Antialias::None {
            let piece = |off: u16, px: &mut [Rgba8888]| {
                let x = seg.x0.saturating_add(off);
                light.light_span(x, seg.y, px);
                out(x, px);
            };
            if e.differences_pieces::<_, _, CHUNK>(m, seg.x0, seg.y, &span, piece) {
                return;
            }
        }
    }
    let mut chunk = [Rgba8888::TRANSPARENT; CHUNK];
    let mut n = 0usize;
    let mut x = seg.x0;
    let mut push = |c: Rgba8888| {
        if let Some(p) = chunk.get_mut(n) {
            *p = c;
        }
        n += 1;
        if n == CHUNK {
            light.light_span(x, seg.y, &mut chunk);
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
    if let Some(rest) = chunk.get_mut(..n).filter(|r| !r.is_empty()) {
        light.light_span(x, seg.y, rest);
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
            e.eval(span, |s| {
                emit(grey(filter_width_spread(s.gx, s.gy, extra, norm, lg)))
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
                .render_banded_rows_binned(
                    &s,
                    56..120,
                    &mut band,
                    &mut depth,
                    8,
                    &mut fb,
                    &mut sink,
                )
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

    #[test]
    fn group_rows() {
        let e = GroupRows::EMPTY;
        assert!(e.is_empty() && e.rows().is_none());
        assert_eq!(GroupRows::default(), e);
        assert_eq!(GroupRows::new(5, 4), e);
        for (y0, y1) in [(0, 0), (0, 1), (0, u16::MAX), (u16::MAX - 1, u16::MAX)] {
            assert!(!e.touches(y0, y1));
        }
        let r = GroupRows::new(8, 15);
        assert_eq!(r.rows(), Some((8, 15)));
        assert!(!r.touches(0, 8) && r.touches(0, 9) && r.touches(15, 16) && !r.touches(16, 24));
        assert!(!r.touches(10, 10), "an empty band touches nothing");
        let mut x = e;
        x.include(3, 4);
        assert_eq!(x, GroupRows::new(3, 4));
        x.include(9, 9);
        assert_eq!(x, GroupRows::new(3, 9));
        x.include(0, 1);
        assert_eq!(x, GroupRows::new(0, 9));
        assert_eq!(core::mem::size_of::<GroupRows>(), 4);
    }

    /// `triangle_rows` follows the rasterizer's pixel-centre convention (centres at 16 p + 8).
    #[test]
    fn triangle_rows_pixel_centres() {
        let t = |y0: i32, y1: i32, x0: i32, x1: i32| {
            let v = |x, y| ScreenVertex::from_bits(x, y, 0, 1 << 30, TexPoint::ZERO);
            [v(x0, y0), v(x1, y0), v(x0, y1)]
        };
        let all = 0..100u16;
        // Exactly on a centre: included on both ends.
        assert_eq!(triangle_rows(&t(8, 24, 0, 64), &all, 10), Some((0, 1)));
        // Just past a centre: excluded.
        assert_eq!(triangle_rows(&t(9, 39, 0, 64), &all, 10), Some((1, 1)));
        assert_eq!(triangle_rows(&t(9, 40, 0, 64), &all, 10), Some((1, 2)));
        // No centre between: the two rows around (the rasterizer's box test lets it through
        // in a band holding both).
        assert_eq!(triangle_rows(&t(9, 23, 0, 64), &all, 10), Some((0, 1)));
        assert_eq!(triangle_rows(&t(9, 23, 0, 64), &(1..9), 10), Some((1, 1)));
        assert_eq!(triangle_rows(&t(9, 23, 0, 64), &(2..9), 10), None);
        // Negative coordinates round the right way; clamped to the rows.
        assert_eq!(triangle_rows(&t(-100, 40, 0, 64), &all, 10), Some((0, 2)));
        assert_eq!(
            triangle_rows(&t(-100, 40, 0, 64), &(1..2), 10),
            Some((1, 1))
        );
        assert_eq!(triangle_rows(&t(-100, 7, 0, 64), &all, 10), None);
        assert_eq!(
            triangle_rows(&t(0, 16 * 200, 0, 64), &(90..100), 10),
            Some((90, 99))
        );
        // Left or right of every column centre of a 10-pixel row.
        assert_eq!(triangle_rows(&t(0, 64, -50, 7), &all, 10), None);
        assert_eq!(triangle_rows(&t(0, 64, -50, 8), &all, 10), Some((0, 3)));
        assert_eq!(triangle_rows(&t(0, 64, 153, 400), &all, 10), None);
        assert_eq!(triangle_rows(&t(0, 64, 152, 400), &all, 10), Some((0, 3)));
        // Extremes do not overflow.
        assert_eq!(
            triangle_rows(&t(i32::MIN, i32::MAX, i32::MIN, i32::MAX), &all, u16::MAX),
            Some((0, 99))
        );
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
}

/// The renderer's filter widths from differences against a reference made from the rasterizer's
/// segments, and the same colours streamed and in bands.
#[cfg(all(test, feature = "differences", feature = "csat"))]
mod difference_tests {
    extern crate std;
    use std::collections::BTreeMap;
    use std::vec;
    use std::vec::Vec;

    use super::*;
    use crate::filter::{Antialias, WidthStream};
    use crate::format::{TexPoint, TexValue};
    use crate::raster::Perspective;
    use crate::span::FaceCache;
    use crate::texture::{DifferenceMemory, TILE_ROWS};

    use super::tests::Quads;

    /// A corner at pixel `(x, y)` (1/16 pixel units) with `1/w = q` and texture point `s`.
    fn corner(x: i32, y: i32, z: u16, q: u32, s: [f64; 3]) -> ScreenVertex {
        ScreenVertex::from_bits(x, y, z, q, TexPoint::from_f64(s[0], s[1], s[2]))
    }

    fn object(texture: usize, perspective: Perspective, depth: bool) -> DrawObject {
        DrawObject {
            texture,
            depth,
            raster: TriangleOptions {
                perspective,
                ..TriangleOptions::default()
            },
            ..DrawObject::default()
        }
    }

    /// The scenes: a full affine quad, a receding perspective quad, small and sliver quads
    /// off the pixel grid, and one that leaves the image.
    fn scenes() -> Vec<Quads> {
        let aff = Perspective::Affine;
        let per = Perspective::Every16;
        vec![
            Quads {
                size: 64,
                objects: vec![(
                    object(0, aff, false),
                    [
                        corner(0, 0, 0, 1 << 30, [0.0, 0.5, 0.25]),
                        corner(1024, 0, 0, 1 << 30, [4.0, 0.5, 0.25]),
                        corner(1024, 1024, 0, 1 << 30, [4.0, 3.5, 0.25]),
                        corner(0, 1024, 0, 1 << 30, [0.0, 3.5, 0.25]),
                    ],
                )],
            },
            Quads {
                size: 48,
                objects: vec![
                    (
                        object(0, per, false),
                        [
                            corner(-37, 21, 0, 1 << 30, [-3.0, 0.2, -5.0]),
                            corner(811, 45, 0, 1 << 28, [9.0, 0.2, -5.0]),
                            corner(760, 700, 0, 1 << 28, [9.0, 6.7, -5.0]),
                            corner(3, 771, 0, 1 << 30, [-3.0, 6.7, -5.0]),
                        ],
                    ),
                    (
                        object(1, aff, false),
                        [
                            corner(100, 90, 0, 1 << 30, [1.0, 2.0, 3.0]),
                            corner(230, 130, 0, 1 << 30, [1.5, 2.0, 3.0]),
                            corner(240, 141, 0, 1 << 30, [1.5, 2.2, 3.0]),
                            corner(101, 103, 0, 1 << 30, [1.0, 2.2, 3.0]),
                        ],
                    ),
                    // Flat: its rows reach past the row above by more than a 16-pixel
                    // piece.
                    (
                        object(0, per, false),
                        [
                            corner(750, 320, 0, 1 << 30, [0.0, 1.0, 0.0]),
                            corner(765, 320, 0, 1 << 28, [5.0, 1.0, 0.0]),
                            corner(765, 370, 0, 1 << 28, [5.0, 1.5, 0.5]),
                            corner(0, 355, 0, 1 << 30, [0.0, 1.5, 0.5]),
                        ],
                    ),
                    (
                        object(0, per, false),
                        [
                            corner(500, 400, 0, 1 << 29, [0.0, 0.0, 0.0]),
                            corner(900, 420, 0, 1 << 30, [2.0, 0.0, 0.0]),
                            corner(880, 900, 0, 1 << 30, [2.0, 2.0, 1.0]),
                            corner(520, 880, 0, 1 << 29, [0.0, 2.0, 1.0]),
                        ],
                    ),
                ],
            },
        ]
    }

    fn textures() -> Vec<Texture<8, 256>> {
        use crate::ready::{Material, PresetName};
        vec![
            Material::preset(PresetName::Marble)
                .texture(Antialias::Csat)
                .unwrap(),
            Material::preset(PresetName::Wood)
                .texture(Antialias::Mip)
                .unwrap(),
        ]
    }

    /// The streamed frame of `scene` with widths from differences, by hand: each triangle's
    /// segments from the rasterizer, each pixel's value from the span evaluator, the pixel
    /// above from the same triangle's row above unless the pixel is on a tile's first row; a
    /// pixel the row above does not have takes the vertical difference of the nearest one that
    /// has it, and a segment none of whose pixels has it is evaluated one row up; the colour
    /// is the stage's at the width of the differences.
    fn reference(scene: &Quads, tex: &[Texture<8, 256>]) -> Vec<Rgba8888> {
        let n = usize::from(scene.size);
        let mut img = vec![scene.background(); n * n];
        let mut raster = Rasterizer::new(Rect::from_size(scene.size, scene.size));
        scene.for_each_triangle(|obj, tri| {
            let o = scene.object(obj).unwrap();
            let t = &tex[o.texture];
            let Shader::Model(m) = t.shader() else {
                unreachable!()
            };
            let mut ev = SpanEvaluator::new(m, t.options());
            let mut values = |span: &Span| {
                let mut out = vec![TexValue::ZERO; usize::from(span.len)];
                let extra = ev.eval_values(span, &mut out).extra_width48;
                (out, extra)
            };
            let mut segs = Vec::new();
            raster.draw(tri, &o.raster, &mut |s: &Segment| segs.push(*s));
            let mut held: BTreeMap<(u16, u16), TexValue> = BTreeMap::new();
            for seg in segs {
                let span = Span {
                    s0: seg.s0,
                    ds: seg.ds,
                    dsdy: seg.dsdy,
                    len: seg.len,
                };
                let (f, extra) = values(&span);
                let bits = |v: TexValue| v.to_bits();
                // The same triangle's values of the row above, unless on a tile's first row.
                let kept: Vec<Option<TexValue>> = (0..seg.len)
                    .map(|i| {
                        let x = seg.x0 + i;
                        (seg.y % TILE_ROWS != 0)
                            .then(|| held.get(&(x, seg.y - 1)).copied())
                            .flatten()
                    })
                    .collect();
                let first = kept.iter().position(Option::is_some);
                let last = kept.iter().rposition(Option::is_some);
                let above: Vec<TexValue> = match (first, last) {
                    // None kept: the segment one row up.
                    (None, _) | (_, None) => values(&span.prev_row()).0,
                    // The others take the vertical difference of the nearest kept one.
                    (Some(a), Some(b)) => {
                        let dy = |k: usize| bits(f[k]).wrapping_sub(bits(kept[k].unwrap()));
                        (0..f.len())
                            .map(|i| match kept[i] {
                                Some(v) => v,
                                None => {
                                    let d = if i < a { dy(a) } else { dy(b) };
                                    TexValue::from_bits(bits(f[i]).wrapping_sub(d))
                                }
                            })
                            .collect()
                    }
                };
                for (i, &v) in f.iter().enumerate() {
                    held.insert((seg.x0 + i as u16, seg.y), v);
                }
                for i in 0..f.len() {
                    let dx = match (f.get(i + 1), i.checked_sub(1)) {
                        (Some(&r), _) => bits(r).wrapping_sub(bits(f[i])),
                        (None, Some(l)) => bits(f[i]).wrapping_sub(bits(f[l])),
                        (None, None) => 0,
                    };
                    let dy = bits(f[i]).wrapping_sub(bits(above[i]));
                    let w = WidthStream::new(t.norm(), 8).width_with(
                        i64::from(dx) << 32,
                        i64::from(dy) << 32,
                        extra,
                    );
                    let at = usize::from(seg.y) * n + usize::from(seg.x0) + i;
                    img[at] = t.stage().shade(f[i], w);
                }
            }
        });
        img
    }

    /// The frame of `scene` streamed (`rows` 0) or in bands of `rows` rows.
    fn render(r: &Renderer<'_, 8, 256>, scene: &Quads, rows: u16) -> Vec<Rgba8888> {
        super::tests::render_full(r, scene, rows).0
    }

    #[test]
    fn differences_are_the_reference_streamed_and_in_bands() {
        let tex = textures();
        let mut mem = DifferenceMemory::<64>::new();
        let mut faces = FaceCache::<64, 8>::new();
        let r = Renderer::new(&tex).with_differences(&mut mem, &mut faces);
        for (k, scene) in scenes().iter().enumerate() {
            let want = reference(scene, &tex);
            assert_eq!(render(&r, scene, 0), want, "scene {k} streamed");
            for rows in [8, 16, 24, 64] {
                assert_eq!(render(&r, scene, rows), want, "scene {k}, bands of {rows}");
            }
            // The frame differs from the gradients' (the mode is on).
            let plain = Renderer::new(&tex);
            assert_ne!(render(&plain, scene, 0), want, "scene {k}");
        }
    }

    #[test]
    fn depth_tested_scenes_agree_in_bands() {
        let tex = textures();
        let mut mem = DifferenceMemory::<48>::new();
        let mut faces = FaceCache::<1, 0>::new();
        let r = Renderer::new(&tex).with_differences(&mut mem, &mut faces);
        let mut scene = scenes().remove(1);
        for (i, (o, v)) in scene.objects.iter_mut().enumerate() {
            o.depth = true;
            for c in v.iter_mut() {
                *c = ScreenVertex::from_bits(
                    c.x.to_bits(),
                    c.y.to_bits(),
                    1000 - 100 * i as u16,
                    c.inv_w.to_bits(),
                    c.tex,
                );
            }
        }
        let want = render(&r, &scene, 48);
        for rows in [8, 16, 24] {
            assert_eq!(render(&r, &scene, rows), want, "bands of {rows}");
        }
    }

    #[test]
    fn a_narrow_memory_is_refused_and_kept() {
        let tex = textures();
        let mut mem = DifferenceMemory::<32>::new();
        let mut faces = FaceCache::<16, 8>::new();
        let r = Renderer::new(&tex).with_differences(&mut mem, &mut faces);
        let wide = scenes().remove(0);
        let mut img = vec![Rgba8888::BLACK; 64 * 64];
        let mut sink = RgbaBuffer::new(&mut img, 64, 0, 64).unwrap();
        let e = r.render_streamed(&wide, &mut sink).unwrap_err();
        assert_eq!(
            e,
            RenderError::MemoryTooNarrow {
                width: 64,
                memory: 32
            }
        );
        assert!(e.to_string().contains("32 pixels"));
        // The memory is still the renderer's: a narrow enough scene renders as the reference.
        let mut narrow = scenes().remove(1);
        narrow.size = 32;
        assert_eq!(render(&r, &narrow, 0), reference(&narrow, &tex));
        assert_eq!(render(&r, &narrow, 8), reference(&narrow, &tex));
    }
}
