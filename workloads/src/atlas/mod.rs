//! Drawing a built-in scene from meshed texture atlases on the device (Carr & Hart 2002): every
//! mesh quad of the scene gets a block of a [`SIDE`] x [`SIDE`] RGB565 atlas in RAM (a uniform
//! layout, [`UniformLayout`]), the object's texture is baked into it once with texcore's bake
//! kernel (`texcore::atlas::bake`: row spans of the span evaluator, the filter width from the
//! texel's footprint on the surface), then the frame is drawn in bands of
//! [`DRAW_ROWS`] rows with texcore's textured-triangle path (`Rasterizer::draw_textured`:
//! the rasterizer's coverage and depth test, atlas coordinates interpolated
//! perspective-correctly at every pixel, the nearest atlas texel written into the band).
//!
//! The frame is walked once: the scene's walk projects every quad, and the quads drawn are kept
//! in a *frame list* ([`FrameQuad`]: projected corners, 48 bytes a quad) from which every band
//! draws the quads that touch it (found through a band index, `BandIndex`), so no band walks
//! the scene, generates a mesh quad or projects a corner again (a frame the list cannot hold
//! exactly takes the general way: every band walks the quads its bins name, as the procedural
//! renderer does).
//!
//! Memory: the atlas is caller-owned frame memory like the band buffers (32 KB for 128 x 128
//! RGB565, on the job's stack), not texture-unit state. The RGB565 band ([`DRAW_PIXELS`] x 2
//! bytes, taller bands than the procedural renderer's: a triangle is set up once per band it
//! touches) is the caller's: on the device the suite's static RGBA and depth bands, which the
//! atlas jobs do not otherwise use, hold it (exactly their 15 KB). Its depth band, the frame list
//! ([`FRAME_QUADS`] entries, 24.8 KB) and its band index ([`FRAME_REFS`] entries, 1.6 KB) are on
//! the stack, the quad bins are the suite's. On the Cortex-M4F the draw job peaks at about
//! 102 KB of the 109 KB stack (the scene walk's corner store included).
//!
//! Atlas coordinates of a screen vertex: the scene's walk hands over screen triangles whose
//! vertices carry solid coordinates. A vertex of an unclipped triangle carries exactly the solid
//! coordinates of one of its quad's corners, whose atlas position is known; a vertex made by
//! clipping gets its atlas position from its barycentric coordinates in the quad half's solid
//! triangle (integer, `Q16` fractions). The half of a screen triangle is the one whose corners
//! its vertices are, or (clipped) the one whose solid triangle holds its centroid.
//!
//! Exactness: integer arithmetic only, the same code on the host and both devices, so the
//! device's checksums equal the host's (`tests/tests/firmware_qemu.rs`). Atlas drawing is an
//! approximation of procedural shading (a *named* mode); its error against the procedural frame
//! is measured on the host (`texsim render --via-atlas`, `docs/atlas.md`). Every object is drawn
//! opaque. Nothing allocates; nothing panics.

use texcore::atlas::{bake, AtlasTriangle, Half};
use texcore::color::Rgba8888;
use texcore::format::TexPoint;
use texcore::hash::HashKind;
use texcore::raster::{
    DepthBuffer, DepthFunc, InvW, Rasterizer, Rect, ScreenCoord, ScreenVertex, Texture565,
    TriangleOptions, TriangleSetup,
};
use texcore::render::{GroupRows, TriangleSource};
use texcore::scene::{Object, Scene};
use texcore::sink::ChecksumSink;

use crate::scenes::{builtin_frame, slot_texture, FRAME_START, WIDTH};

/// Side of the device atlas in texels.
pub const SIDE: u16 = 128;
/// Texels of the device atlas (`SIDE * SIDE`, 32 KB of RGB565).
pub const TEXELS: usize = SIDE as usize * SIDE as usize;
/// Gutter of the device layout: 0, the paper's atlas for nearest look-ups.
pub const GUTTER: u8 = 0;
/// Rows of a band of the atlas draw (a triangle is set up once per band it touches: 24-row
/// bands drew the marble frame in 70.7 instructions a pixel on the Cortex-M4F where 16-row
/// bands took 71.6).
pub const DRAW_ROWS: u16 = 24;
/// Pixels of a band of the atlas draw (and entries of its depth band): the widest scene's.
pub const DRAW_PIXELS: usize = WIDTH as usize * DRAW_ROWS as usize;
/// The built-in scene the atlas jobs draw.
pub const SCENE: &str = "marble";

/// The RGB565 texels of a device atlas, row-major.
pub type AtlasTexels = [u16; TEXELS];

mod bake;
mod frame;
mod layout;

pub use bake::{atlas_checksum, bake_scene, owned_texels, scene_layout};
pub use frame::{
    draw_scene, draw_scene_in, draw_scene_rows, draw_scene_rows_with, FrameQuad, FRAME_QUADS,
    FRAME_REFS,
};
pub use layout::UniformLayout;
use layout::*;

/// `atlas:<SCENE>-bake` (with `work`) and its set-up: the scene's frame and its textures built,
/// the atlas zeroed; with `work` the bake, and the checksum of the whole atlas.
#[inline(never)]
pub fn bake_job(hash: HashKind, work: bool) -> u32 {
    let Some(scene) = builtin_frame(SCENE) else {
        return 0;
    };
    let scene = core::hint::black_box(scene);
    let mut atlas = [0u16; TEXELS];
    let n = bake_scene(&scene, hash, &mut atlas, work);
    if !work {
        return n;
    }
    n ^ atlas_checksum(core::hint::black_box(&atlas))
}

/// `atlas:<SCENE>` (with `work`) and its set-up: the scene's frame, textures and atlas baked;
/// with `work` the frame drawn from the atlas into the RGB565 band `band` ([`draw_scene_in`]),
/// returning the frame's checksum (the set-up returns the texels baked).
#[inline(never)]
pub fn draw_job(hash: HashKind, work: bool, bins: &mut [GroupRows], band: &mut [u16]) -> u32 {
    let Some(scene) = builtin_frame(SCENE) else {
        return 0;
    };
    let scene = core::hint::black_box(scene);
    let mut atlas = [0u16; TEXELS];
    let n = bake_scene(&scene, hash, &mut atlas, true);
    let atlas = core::hint::black_box(&atlas);
    if !work {
        return n;
    }
    draw_scene_in(&scene, atlas, bins, band)
}

#[cfg(test)]
mod tests;
