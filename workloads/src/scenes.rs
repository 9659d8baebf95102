//! Whole scenes through `texcore::render::Renderer::render_banded` into a `ChecksumSink`, with a
//! small band (RGBA band + depth band in caller-owned memory, no frame buffer), at display size
//! (shared with the host, like `planes`).
//!
//! [`render_checksum`] renders any [`TriangleSource`] this way. The device renders [`SCENES`]:
//! two scenes defined here from the presets, a perspective floor and a depth-tested,
//! alpha-blended overlay; and every built-in scene of `texcore::scene::builtin`
//! ([`BUILTIN_SCENES`], at its still frame and own size, one csat texture per slot as
//! `host_sim::scenes::slot_material` builds it) in [`STRIPS`] horizontal strips
//! ([`builtin_strip`]), each continuing the previous strip's checksum so that the last strip's
//! is the checksum of the whole frame; those render with their mesh quads binned into bands
//! (`Renderer::render_banded_rows_binned`, [`SCENE_GROUPS`] bins, one walk over the scene per
//! frame), which changes no pixel. With feature `lighting` also [`LIT_SCENES`]: a built-in scene
//! with lights, its whole frame in one job ([`lit_frame_job`]).

use texcore::color::Rgba8888;
use texcore::filter::Antialias;
use texcore::format::Amplitude;
use texcore::hash::HashKind;
use texcore::material::PerturbedMaterial;
use texcore::presets;
use texcore::raster::{Perspective, ScreenVertex, TriangleOptions};
#[cfg(feature = "rgb565-frames")]
use texcore::render::RenderError;
use texcore::render::{Blend, DrawObject, FrameBins, GroupRows, Renderer, TriangleSource};
use texcore::scene::{builtin, Scene, TextureSlot};
use texcore::sink::ChecksumSink;
#[cfg(feature = "approximate")]
use texcore::span::FaceCache;
use texcore::table::KeySpacing;
#[cfg(feature = "approximate")]
use texcore::texture::DifferenceMemory;
use texcore::texture::Shader;
use texcore::TexPoint;

use crate::planes::{material, texture, DeviceTexture, Material};

/// Display width.
pub const WIDTH: u16 = 320;
/// Display height.
pub const HEIGHT: u16 = 240;
/// Rows per band.
pub const BAND_ROWS: u16 = 8;
/// Pixels of the RGBA band and entries of the depth band: one band of the widest scene.
pub const BAND_PIXELS: usize = WIDTH as usize * BAND_ROWS as usize;
/// Rows per band of the RGB565 frames (feature `rgb565-frames`): four times [`BAND_ROWS`] (the
/// bytes of two RGBA bands), so a triangle is set up, and its quad walked, in a quarter as many
/// bands. The approximate frames, which take it, hold one slot texture
/// ([`APPROXIMATE_SLOTS`]) where the other frames hold [`SCENE_SLOTS`]: the stack of the three
/// they do not hold takes the taller band.
pub const RGB565_BAND_ROWS: u16 = 4 * BAND_ROWS;
/// Pixels of the RGB565 band (feature `rgb565-frames`): one band of the widest scene.
pub const RGB565_BAND_PIXELS: usize = WIDTH as usize * RGB565_BAND_ROWS as usize;
/// Rows of the device's static RGBA band ([`BAND_ROWS`]). With `rgb565-frames` only a scene
/// that blends takes it (the RGB565 band is refused to those), in bands of 2 rows: the bytes
/// saved hold the RGB565 frames' taller depth band ([`DEPTH_PIXELS`]).
pub const RGBA_BAND_ROWS: u16 = if cfg!(feature = "rgb565-frames") {
    2
} else {
    BAND_ROWS
};
/// Pixels of the device's static RGBA band ([`RGBA_BAND_ROWS`] rows of the widest scene).
pub const RGBA_BAND_PIXELS: usize = WIDTH as usize * RGBA_BAND_ROWS as usize;
/// Entries of the device's static depth band: [`BAND_PIXELS`], or with `rgb565-frames` one
/// band of [`RGB565_BAND_ROWS`] rows.
pub const DEPTH_PIXELS: usize = if cfg!(feature = "rgb565-frames") {
    RGB565_BAND_PIXELS
} else {
    BAND_PIXELS
};

/// Rows of a band of `pixels` pixels (a band buffer's length) for a scene `width` pixels wide,
/// at most `rows`.
fn band_rows(pixels: usize, width: u16, rows: u16) -> u16 {
    let r = pixels / usize::from(width.max(1));
    u16::try_from(r).unwrap_or(u16::MAX).min(rows)
}

/// One scene workload.
#[derive(Clone, Copy)]
pub struct SceneJob {
    /// Name (the job is `scene:<name>`).
    pub name: &'static str,
    /// Image size.
    pub size: (u16, u16),
    /// Whether the Cortex-M4F firmware runs it: its counter (the SysTick vernier under QEMU)
    /// measures at most 2^24 * 40 = 671 088 640 instructions per job, and a frame of the heavier
    /// scenes needs more (rv32imc's 64-bit `minstret` has no such limit, so it runs them all).
    pub m4f: bool,
    /// The workload: `(hash, work, band, depth)`; with `work == false` only the textures and the
    /// scene are built (see `stages`).
    pub run: fn(HashKind, bool, &mut [Rgba8888], &mut [u16]) -> u32,
}

/// Every scene the device renders.
pub const SCENES: [SceneJob; 2] = [
    SceneJob {
        name: "floor",
        size: (WIDTH, HEIGHT),
        m4f: true,
        run: floor,
    },
    SceneJob {
        name: "overlay",
        size: (WIDTH, HEIGHT),
        m4f: true,
        run: overlay,
    },
];

/// The built-in scenes of `texcore::scene::builtin`, in that module's order: every one runs on
/// both devices, each frame as [`STRIPS`] jobs (see [`builtin_strip`]).
pub const BUILTIN_SCENES: [&str; 8] = builtin::BUILTIN;

/// Horizontal strips per built-in scene frame, each one device job: the Cortex-M4F counter (the
/// SysTick vernier under QEMU) measures at most 2^24 * 40 = 671 088 640 instructions per job,
/// and a whole frame of the heavier scenes needs more (rv32imc's 64-bit `minstret` has no such
/// limit; both devices run the same strips).
pub const STRIPS: usize = 4;

/// Texture capacity of the built-in scene jobs: the most slots a built-in scene uses
/// (`moonrise`). A scene with more would not render (its checksum would be 0); the host test
/// `every_builtin_scene_fits_the_device` checks that none has.
pub const SCENE_SLOTS: usize = 4;

/// Bins of the built-in scene jobs ([`GroupRows`], 4 bytes each): one per mesh quad of the
/// built-in scene with the most (`planet`, 1024; `moonrise` 998, `seascape` 968). The renderer
/// walks a scene once per frame to bin its quads into bands (`texcore::render::FrameBins`) and
/// then, per band, only the quads that can touch it; a scene with more quads than bins renders the same pixels, walking the
/// quads past the bins in every band. The host test `every_builtin_scene_fits_the_device`
/// checks that every built-in scene fits.
pub const SCENE_GROUPS: usize = 1024;

/// The textures of a built-in scene's slots (about 8 KB each, csat), at most `S`
/// ([`SCENE_SLOTS`] by default).
pub type SlotTextures<const S: usize = SCENE_SLOTS> = heapless::Vec<DeviceTexture, S>;

/// The checksum a frame's first strip continues: the checksum of no pixels.
pub const FRAME_START: u32 = 0x811C_9DC5;

/// The frame of built-in scene `name` the device renders: its still frame, the one
/// `texsim render <name>` renders by default.
pub fn builtin_frame(name: &str) -> Option<Scene> {
    builtin::by_name(name).map(|s| s.at_frame(s.still()))
}

/// The rows of strip `k` (of [`STRIPS`]) of an image `height` rows high: from `height * k /
/// STRIPS` rounded down to a multiple of [`BAND_ROWS`] to the next strip's start (the image's
/// end for the last). Strips start on band boundaries, so together they render exactly the
/// bands of one `render_banded` call over the whole image (240 rows are 56 + 64 + 56 + 64; the
/// frame walks the whole scene once to bin its quads, see [`builtin_strip`]).
pub fn strip_rows(height: u16, k: usize) -> core::ops::Range<u16> {
    let at = |k: usize| {
        if k >= STRIPS {
            return height;
        }
        let y = usize::from(height) * k / STRIPS;
        (y - y % usize::from(BAND_ROWS)) as u16
    };
    at(k)..at(k + 1)
}

/// The built-in scene and strip of a job name's scene part (`wood@2`): the scene's name and the
/// strip index, if `what` names a built-in scene and a strip below [`STRIPS`].
pub fn builtin_strip_job(what: &str) -> Option<(&'static str, usize)> {
    let (name, k) = what.split_once('@')?;
    let k: usize = k.parse().ok()?;
    let name = BUILTIN_SCENES.iter().find(|n| **n == name)?;
    (k < STRIPS).then_some((name, k))
}

/// How a frame's textures are filtered and their filter widths taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameMode {
    /// Csat with the noise's gradients: the exact filter, as `texsim render` draws by default.
    Exact,
    /// The approximate mode of `texsim render --aa ramp`: the pre-filtered RGB565 ramp, its
    /// level from the noise's gradients (feature `approximate`).
    #[cfg(feature = "approximate")]
    Ramp,
    /// The approximate mode of `texsim render --aa ramp --widths differences`: the ramp with
    /// filter widths from the differences of neighbouring values (`Renderer::with_differences`,
    /// feature `approximate`).
    #[cfg(feature = "approximate")]
    RampDifferences,
}

impl FrameMode {
    /// The filter of the slot textures.
    fn antialias(self) -> Antialias {
        match self {
            FrameMode::Exact => Antialias::Csat,
            #[cfg(feature = "approximate")]
            FrameMode::Ramp | FrameMode::RampDifferences => Antialias::Ramp,
        }
    }
}

/// Builds the texture of every slot of `scene` into `textures` (false if one cannot be built or
/// there are more than its `S`).
#[inline(never)]
fn slot_textures<const S: usize>(
    scene: &Scene,
    hash: HashKind,
    aa: Antialias,
    textures: &mut SlotTextures<S>,
) -> bool {
    textures.clear();
    for slot in &scene.slots {
        let Some(t) = slot_texture_with(slot, hash, aa) else {
            return false;
        };
        if textures.push(t).is_err() {
            return false;
        }
    }
    true
}

/// Strip `k` of the frame of built-in scene `name` ([`builtin_frame`]): builds the scene and its
/// slot textures, renders the strip's rows ([`strip_rows`]) through
/// `Renderer::render_banded_rows_binned` (quads binned into `bins`, see [`SCENE_GROUPS`]) in
/// bands of [`BAND_ROWS`] rows into a `ChecksumSink` that continues `above`, the checksum of
/// every row above the strip ([`FRAME_START`] for the first strip), and returns its checksum:
/// the checksum of rows `0 .. end of strip k`, so the last strip's is the whole frame's
/// (`texsim render <name> --checksum`). 0 if the scene or a texture cannot be built or the
/// renderer refuses it. With `work == false` only the scene and the textures are built, and
/// for `k > 0` the bins filled.
///
/// The strips together cost what one whole-frame render costs: strip 0's first band walks the
/// whole scene and fills the frame's bins (`texcore::render::FrameBins`); every later strip
/// renders with the frame's bins from its first band on. Each strip job stands alone, so a
/// strip `k > 0` fills the bins itself with `Renderer::bin` (the same walk) in both its job and
/// its set-up: the walk is in the frame's count once, in strip 0's.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub fn builtin_strip(
    name: &str,
    hash: HashKind,
    work: bool,
    k: usize,
    above: u32,
    band: &mut [Rgba8888],
    depth: &mut [u16],
    bins: &mut [GroupRows],
) -> u32 {
    let Some(scene) = builtin_frame(name) else {
        return 0;
    };
    frame_rows::<SCENE_SLOTS>(
        &scene,
        hash,
        FrameMode::Exact,
        work,
        Some(k),
        above,
        band,
        depth,
        bins,
    )
}

/// The body of [`builtin_strip`] (`strip = Some(k)`) and [`lit_frame_job`] (`None`: the whole
/// frame, as strip 0 through the last row): builds the slot textures, renders the rows and
/// returns their checksum continuing `above` (with `work == false` the set-up's checksum).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn frame_rows<const S: usize>(
    scene: &Scene,
    hash: HashKind,
    mode: FrameMode,
    work: bool,
    strip: Option<usize>,
    above: u32,
    band: &mut [Rgba8888],
    depth: &mut [u16],
    bins: &mut [GroupRows],
) -> u32 {
    // At most `S` slot textures (about 8 KB each, on this frame's stack).
    let mut textures = SlotTextures::<S>::new();
    if !slot_textures(scene, hash, mode.antialias(), &mut textures) {
        return 0;
    }
    let (textures, scene) = core::hint::black_box((&textures[..], scene));
    let n = textures.len();
    let mut draw = |renderer: &FrameRenderer<'_>| {
        draw_rows(renderer, n, scene, work, strip, above, band, depth, bins)
    };
    #[cfg(feature = "approximate")]
    if mode == FrameMode::RampDifferences {
        return difference_rows(textures, draw);
    }
    draw(&Renderer::new(textures))
}

/// The renderer of the device's frames.
type FrameRenderer<'t> = Renderer<'t, { crate::planes::TERMS }, { crate::planes::TABLE }>;

/// `draw` of [`frame_rows`] through a renderer with the filter widths from differences: its
/// [`DifferenceMemory`] of [`WIDTH`] pixels and [`FaceCache`] of [`FACE_ENTRIES`] live in this
/// frame only (out of line: no other mode's stack holds them).
#[cfg(feature = "approximate")]
#[inline(never)]
fn difference_rows(
    textures: &[DeviceTexture],
    draw: impl FnOnce(&FrameRenderer<'_>) -> u32,
) -> u32 {
    let mut mem = DifferenceMemory::<{ WIDTH as usize }>::new();
    let mut faces = FaceCache::<FACE_ENTRIES, { crate::planes::TERMS }>::new();
    draw(&Renderer::new(textures).with_differences(&mut mem, &mut faces))
}

/// The rows of [`frame_rows`] drawn by `renderer` (with `textures` slot textures): the bins
/// (strip 0's first band fills them, the later strips' set-ups), then the rows' checksum
/// continuing `above` (with `work == false` the set-up's checksum).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn draw_rows(
    renderer: &FrameRenderer<'_>,
    textures: usize,
    scene: &Scene,
    work: bool,
    strip: Option<usize>,
    above: u32,
    band: &mut [Rgba8888],
    depth: &mut [u16],
    bins: &mut [GroupRows],
) -> u32 {
    let mut bins = FrameBins::new(bins);
    // A frame walks its whole scene once: strip 0's first band bins the quads; the later
    // strips take the frame's bins, filled here (in the job and in its set-up alike, so that
    // the walk is not counted twice).
    if strip.is_some_and(|k| k > 0) && renderer.bin(scene, &mut bins).is_err() {
        return 0;
    }
    if !work {
        return scene.objects.len() as u32 ^ textures as u32;
    }
    let height = scene.size().1;
    let rows = match strip {
        Some(k) => strip_rows(height, k),
        None => 0..height,
    };
    let mut sink = ChecksumSink::resume(above);
    // An RGB565 band where the scene allows it: the renderer refuses a scene that blends before
    // it draws anything, and that one takes the RGBA band. The same checksum either way.
    #[cfg(feature = "rgb565-frames")]
    match rgb565_rows(renderer, scene, rows.clone(), depth, &mut bins, &mut sink) {
        Err(RenderError::NeedsRgbaBand { .. }) => {}
        drawn => return if drawn.is_ok() { sink.checksum() } else { 0 },
    }
    // As many rows as both bands hold (the device's RGBA band is shorter with `rgb565-frames`).
    let w = scene.size().0;
    let n = band_rows(band.len().min(depth.len()), w, BAND_ROWS);
    match renderer.render_banded_rows_binned(scene, rows, band, depth, n, &mut bins, &mut sink) {
        Ok(_) => sink.checksum(),
        Err(_) => 0,
    }
}

/// Rows `rows` of `scene` through `renderer` into an RGB565 band of [`RGB565_BAND_ROWS`] rows
/// (`Renderer::render_banded_rows_binned_rgb565`: unlit segments shaded straight to RGB565,
/// each row handed to `sink` as it is), on this frame's stack (20 KB, the bytes of two RGBA
/// bands of [`BAND_ROWS`] rows), or as many rows as `depth` holds. The sink's checksum is the RGBA
/// band's: the RGB565 rows are its rows reduced, and a frame's pixels do not depend on its
/// bands' height. A scene that blends is refused (`RenderError::NeedsRgbaBand`), nothing drawn.
#[cfg(feature = "rgb565-frames")]
#[inline(never)]
fn rgb565_rows(
    renderer: &FrameRenderer<'_>,
    scene: &Scene,
    rows: core::ops::Range<u16>,
    depth: &mut [u16],
    bins: &mut FrameBins<'_>,
    sink: &mut ChecksumSink,
) -> Result<texcore::render::RenderStats, RenderError> {
    let mut band = [0u16; RGB565_BAND_PIXELS];
    let n = band_rows(depth.len(), scene.size().0, RGB565_BAND_ROWS);
    renderer.render_banded_rows_binned_rgb565(scene, rows, &mut band, depth, n, bins, sink)
}

/// The lit scenes the device renders (feature `lighting`): `<built-in>-lit` is the built-in
/// scene with lights ([`lit_scene`]), job `scene:<name>` ([`lit_frame_job`]).
#[cfg(feature = "lighting")]
pub const LIT_SCENES: [&str; 1] = ["marble-lit"];

/// Lit scene `name` of [`LIT_SCENES`] at frame 0: built-in scene `<name without -lit>` with
/// ambient 1/8 and one white directional light from the upper left front (the lighting of
/// `texcore/benches/stages.rs`'s `marble+lit`); `None` for another name.
#[cfg(feature = "lighting")]
pub fn lit_scene(name: &str) -> Option<Scene> {
    use texcore::light::{Light, Lighting};
    use texcore::scene::{math::ONE, Vec3};
    if !LIT_SCENES.contains(&name) {
        return None;
    }
    let mut s = builtin::by_name(name.strip_suffix("-lit")?)?;
    let mut lighting = Lighting::new().with_ambient([ONE / 8; 3]).ok()?;
    let sun = Light::directional(Vec3::new(-ONE, ONE, ONE), [ONE; 3], ONE).ok()?;
    lighting.try_add(sun).ok()?;
    s.set_lighting(lighting);
    Some(s)
}

/// The frame of lit scene `name` the device renders: its still frame.
#[cfg(feature = "lighting")]
pub fn lit_frame(name: &str) -> Option<Scene> {
    lit_scene(name).map(|s| s.at_frame(s.still()))
}

/// The whole frame of lit scene `name` ([`lit_frame`]) in one job, as [`builtin_strip`] renders
/// a strip (slot textures, bins, bands of [`BAND_ROWS`] rows, `ChecksumSink` from
/// [`FRAME_START`]): the checksum of the frame (`texsim render` of the same scene), or the
/// set-up's with `work == false`; 0 if the scene or a texture cannot be built. One job fits
/// the Cortex-M4F counter's window (the unlit marble frame is about 80 million instructions).
#[cfg(feature = "lighting")]
#[inline(never)]
pub fn lit_frame_job(
    name: &str,
    hash: HashKind,
    work: bool,
    band: &mut [Rgba8888],
    depth: &mut [u16],
    bins: &mut [GroupRows],
) -> u32 {
    let Some(scene) = lit_frame(name) else {
        return 0;
    };
    whole_frame::<SCENE_SLOTS>(&scene, hash, FrameMode::Exact, work, band, depth, bins)
}

/// A whole frame in one job ([`frame_rows`] from the first row, the checksum from
/// [`FRAME_START`]).
#[cfg(any(feature = "lighting", feature = "approximate"))]
fn whole_frame<const S: usize>(
    scene: &Scene,
    hash: HashKind,
    mode: FrameMode,
    work: bool,
    band: &mut [Rgba8888],
    depth: &mut [u16],
    bins: &mut [GroupRows],
) -> u32 {
    frame_rows::<S>(
        scene,
        hash,
        mode,
        work,
        None,
        FRAME_START,
        band,
        depth,
        bins,
    )
}

/// The built-in scenes the device also renders in the approximate modes ([`APPROXIMATE_MODES`],
/// feature `approximate`), whole frames ([`approximate_frame_job`]).
#[cfg(feature = "approximate")]
pub const APPROXIMATE_SCENES: [&str; 2] = ["fire", "marble"];

/// Slot textures an approximate frame holds ([`APPROXIMATE_SCENES`] have one each: a scene with
/// more renders nothing, checksum 0; the host test `approximate_scenes_fit_their_slots` checks
/// them). The whole-suite frames hold [`SCENE_SLOTS`].
#[cfg(feature = "approximate")]
pub const APPROXIMATE_SLOTS: usize = 1;

/// The approximate modes of [`APPROXIMATE_SCENES`] and their job suffixes: job
/// `scene:<name><suffix>`, as `texsim render <name> --aa ramp` (`~ramp`) and with `--widths
/// differences` (`~ramp-diff`) draw it.
#[cfg(feature = "approximate")]
pub const APPROXIMATE_MODES: [(FrameMode, &str); 2] = [
    (FrameMode::Ramp, "~ramp"),
    (FrameMode::RampDifferences, "~ramp-diff"),
];

/// Face-cache entries of the difference frames' renderer (`texcore::span::FaceCache`, 32 bytes
/// each, on the frame's stack): the faces a row of the built-in scenes crosses (the values are
/// the same with any number; the fire frame 244.8 -> 240.3 instructions a pixel on the
/// Cortex-M4F from 128 to 256).
#[cfg(feature = "approximate")]
pub const FACE_ENTRIES: usize = 256;

/// The whole frame of built-in scene `name` ([`builtin_frame`], one of [`APPROXIMATE_SCENES`])
/// in one job in the approximate mode `mode`, as [`lit_frame_job`] renders (slot textures with
/// the ramp, bins, bands of [`BAND_ROWS`] rows, `ChecksumSink` from [`FRAME_START`]); with
/// [`FrameMode::RampDifferences`] the renderer has a [`DifferenceMemory`] of [`WIDTH`] pixels
/// and a [`FaceCache`] of [`FACE_ENTRIES`]: the checksum of the frame (`texsim render <name>
/// --aa ramp [--widths differences]`), or the set-up's with `work == false`; 0 if the scene or
/// a texture cannot be built.
#[cfg(feature = "approximate")]
#[inline(never)]
pub fn approximate_frame_job(
    name: &str,
    mode: FrameMode,
    hash: HashKind,
    work: bool,
    band: &mut [Rgba8888],
    depth: &mut [u16],
    bins: &mut [GroupRows],
) -> u32 {
    let Some(scene) = APPROXIMATE_SCENES
        .contains(&name)
        .then(|| builtin_frame(name))
        .flatten()
    else {
        return 0;
    };
    whole_frame::<APPROXIMATE_SLOTS>(&scene, hash, mode, work, band, depth, bins)
}

/// The scene called `name`.
pub fn scene(name: &str) -> Option<&'static SceneJob> {
    SCENES.iter().find(|s| s.name == name)
}

/// Renders `scene` with `textures` in bands of [`BAND_ROWS`] rows (or as many rows of the widest
/// scene as `band` and `depth` hold) through `band` and `depth`; returns the image checksum (0
/// if the renderer refused the scene).
#[inline(never)]
pub fn render_checksum<S: TriangleSource>(
    scene: &S,
    textures: &[DeviceTexture],
    band: &mut [Rgba8888],
    depth: &mut [u16],
) -> u32 {
    let mut sink = ChecksumSink::new();
    let n = band_rows(band.len().min(depth.len()), WIDTH, BAND_ROWS);
    match Renderer::new(textures).render_banded(scene, band, depth, n, &mut sink) {
        Ok(_) => sink.checksum(),
        Err(_) => 0,
    }
}

/// Quads (two triangles each) with one draw object per quad.
pub struct Quads<const Q: usize> {
    /// Image size.
    pub size: (u16, u16),
    /// Background.
    pub background: Rgba8888,
    /// Per quad: how it is drawn and its corners (clockwise from top left).
    pub quads: [(DrawObject, [ScreenVertex; 4]); Q],
}

impl<const Q: usize> TriangleSource for Quads<Q> {
    fn size(&self) -> (u16, u16) {
        self.size
    }
    fn background(&self) -> Rgba8888 {
        self.background
    }
    fn object_count(&self) -> usize {
        Q
    }
    fn object(&self, i: usize) -> Option<DrawObject> {
        self.quads.get(i).map(|q| q.0)
    }
    fn for_each_triangle<F: FnMut(usize, &[ScreenVertex; 3])>(&self, mut f: F) {
        for (i, (_, v)) in self.quads.iter().enumerate() {
            f(i, &[v[0], v[1], v[2]]);
            f(i, &[v[0], v[2], v[3]]);
        }
    }
}

/// A vertex at pixel `(x, y)` (whole pixels), depth `z`, `1/w` raw `w`, texture raw 16.16 `s`.
fn v(x: i32, y: i32, z: u16, w: u32, s: [i32; 3]) -> ScreenVertex {
    ScreenVertex::from_bits(x << 4, y << 4, z, w, TexPoint::from_bits(s[0], s[1], s[2]))
}

const FAR: u32 = 1 << 29;
const NEAR: u32 = (1 << 31) - 1;

/// A ground plane from the horizon (row 60) to the bottom of the screen, in perspective.
fn floor_quad(z: u16) -> [ScreenVertex; 4] {
    let (w, h) = (i32::from(WIDTH), i32::from(HEIGHT));
    [
        v(-w, 60, z, FAR, [-4 << 16, 8 << 16, 0]),
        v(2 * w, 60, z, FAR, [4 << 16, 8 << 16, 0]),
        v(w, h, z, NEAR, [1 << 16, 0, 0]),
        v(0, h, z, NEAR, [-1 << 16, 0, 0]),
    ]
}

fn tex(name: &str, hash: HashKind) -> Option<DeviceTexture> {
    texture(&material(name, hash)?, Antialias::Csat)
}

/// A marble floor in perspective (`Every16`), opaque, no depth: one texture, two triangles.
pub fn floor(hash: HashKind, work: bool, band: &mut [Rgba8888], depth: &mut [u16]) -> u32 {
    let Some(tex) = tex("marble", hash).map(|t| [t]) else {
        return 0;
    };
    let scene = Quads {
        size: (WIDTH, HEIGHT),
        background: Rgba8888::rgb(40, 60, 90),
        quads: [(
            DrawObject {
                texture: 0,
                blend: Blend::Opaque,
                depth: false,
                raster: TriangleOptions::new(Perspective::Every16),
            },
            floor_quad(0),
        )],
    };
    let (tex, scene) = core::hint::black_box((&tex, &scene));
    if !work {
        return scene.quads.len() as u32 ^ tex.len() as u32;
    }
    render_checksum(scene, tex, band, depth)
}

/// A wood floor (perspective, depth-tested), a planet disc-like quad standing on it (affine,
/// depth-tested, partly behind the floor's near part) and the planet's clouds blended over the
/// upper half of the screen: depth buffer and alpha blending in every band.
pub fn overlay(hash: HashKind, work: bool, band: &mut [Rgba8888], depth: &mut [u16]) -> u32 {
    let (Some(a), Some(b), Some(c)) = (
        tex("wood", hash),
        tex("planet", hash),
        tex("planet-clouds", hash),
    ) else {
        return 0;
    };
    let tex = [a, b, c];
    let depth_obj = |t: usize, p: Perspective| DrawObject {
        texture: t,
        blend: Blend::Opaque,
        depth: true,
        raster: TriangleOptions::new(p),
    };
    let (w, h) = (i32::from(WIDTH), i32::from(HEIGHT));
    let s = |a: i32, b: i32| [a << 14, b << 14, 0];
    let scene = Quads {
        size: (WIDTH, HEIGHT),
        background: Rgba8888::rgb(8, 8, 24),
        quads: [
            (depth_obj(0, Perspective::Every16), floor_quad(30000)),
            (
                depth_obj(1, Perspective::Affine),
                [
                    v(90, 20, 20000, NEAR, s(-8, -8)),
                    v(230, 20, 20000, NEAR, s(8, -8)),
                    v(230, 200, 40000, NEAR, s(8, 8)),
                    v(90, 200, 40000, NEAR, s(-8, 8)),
                ],
            ),
            (
                DrawObject {
                    texture: 2,
                    blend: Blend::Over,
                    depth: false,
                    raster: TriangleOptions::new(Perspective::Affine),
                },
                [
                    v(0, 0, 0, NEAR, s(-8, -6)),
                    v(w, 0, 0, NEAR, s(8, -6)),
                    v(w, h / 2, 0, NEAR, s(8, 0)),
                    v(0, h / 2, 0, NEAR, s(-8, 0)),
                ],
            ),
        ],
    };
    let (tex, scene) = core::hint::black_box((&tex, &scene));
    if !work {
        return scene.quads.len() as u32 ^ tex.len() as u32;
    }
    render_checksum(scene, tex, band, depth)
}

/// The texture of a scene's slot: the preset with the slot's amplitude factor, phase and keys
/// (as `host_sim::scenes::slot_material`), csat.
pub fn slot_texture(slot: &TextureSlot, hash: HashKind) -> Option<DeviceTexture> {
    slot_texture_with(slot, hash, Antialias::Csat)
}

/// [`slot_texture`] with the filter `aa`.
pub fn slot_texture_with(
    slot: &TextureSlot,
    hash: HashKind,
    aa: Antialias,
) -> Option<DeviceTexture> {
    let factor = i64::from(slot.amplitude);
    let scale = |a: Amplitude| -> Amplitude {
        Amplitude::from_bits(
            ((i64::from(a.to_bits()) * factor) >> 16).clamp(i32::MIN.into(), i32::MAX.into())
                as i32,
        )
    };
    let m = if let Some(p) = presets::by_name(slot.material, hash) {
        let mut model = p.model;
        if factor != 1 << 16 {
            for k in 0..model.terms().len() {
                let a = scale(model.terms().get(k)?.amplitude);
                model.set_amplitude(k, a).ok()?;
            }
        }
        if slot.phase != 0 && slot.material == "fire" {
            presets::set_fire_phase(&mut model, slot.phase);
        }
        Material::model(model, p.keys)
    } else {
        let p = presets::perturbed_by_name(slot.material, hash)?;
        let mut params = p.params;
        for a in &mut params.alpha {
            *a = scale(*a);
        }
        let spacing = if p.squared_keys {
            KeySpacing::Squared
        } else {
            KeySpacing::Linear
        };
        let shader = Shader::Perturbed(PerturbedMaterial::new(&params, p.wrap).ok()?);
        Material::new(shader, p.wrap, p.keys).with_spacing(spacing)
    };
    let keys = slot.keys.unwrap_or(m.keys());
    texture(&m.with_keys(keys), aa)
}
