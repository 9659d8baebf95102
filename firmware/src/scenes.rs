//! Whole scenes through `texcore::render::Renderer::render_banded` into a `ChecksumSink`, with a
//! small band (RGBA band + depth band in caller-owned memory, no frame buffer), at display size
//! (shared with the host, like `planes`).
//!
//! [`render_checksum`] renders any [`TriangleSource`] this way. Until the built-in scenes
//! (`texcore::scene`: wood, marble, seascape, fire, planet, moonrise, zoneplate, torus) are on
//! `main`, the device renders [`SCENES`]: interim scenes defined here from the presets, a
//! perspective floor and a depth-tested, alpha-blended overlay, so the banded renderer, depth and
//! blending run on the device today. When the built-in scenes land, each becomes one more entry
//! here (`scene:<name>`), rendered through the same function.

use texcore::color::Rgba8888;
use texcore::filter::Antialias;
use texcore::hash::HashKind;
use texcore::raster::{Perspective, ScreenVertex, TriangleOptions};
use texcore::render::{Blend, DrawObject, Renderer, TriangleSource};
use texcore::sink::ChecksumSink;
use texcore::TexPoint;

use super::planes::{material, texture, DeviceTexture};

/// Display width.
pub const WIDTH: u16 = 320;
/// Display height.
pub const HEIGHT: u16 = 240;
/// Rows per band.
pub const BAND_ROWS: u16 = 8;
/// Pixels of the RGBA band and entries of the depth band: one band of the widest scene.
pub const BAND_PIXELS: usize = WIDTH as usize * BAND_ROWS as usize;

/// One scene workload.
#[derive(Clone, Copy)]
pub struct SceneJob {
    /// Name (the job is `scene:<name>`).
    pub name: &'static str,
    /// Image size.
    pub size: (u16, u16),
    /// The workload: `(hash, work, band, depth)`; with `work == false` only the textures and the
    /// scene are built (see `stages`).
    pub run: fn(HashKind, bool, &mut [Rgba8888], &mut [u16]) -> u32,
}

/// Every scene the device renders.
pub const SCENES: [SceneJob; 2] = [
    SceneJob {
        name: "floor",
        size: (WIDTH, HEIGHT),
        run: floor,
    },
    SceneJob {
        name: "overlay",
        size: (WIDTH, HEIGHT),
        run: overlay,
    },
];

/// The scene called `name`.
pub fn scene(name: &str) -> Option<&'static SceneJob> {
    SCENES.iter().find(|s| s.name == name)
}

/// Renders `scene` with `textures` in bands of [`BAND_ROWS`] rows through `band` and `depth`;
/// returns the image checksum (0 if the renderer refused the scene).
#[inline(never)]
pub fn render_checksum<S: TriangleSource>(
    scene: &S,
    textures: &[DeviceTexture],
    band: &mut [Rgba8888],
    depth: &mut [u16],
) -> u32 {
    let mut sink = ChecksumSink::new();
    match Renderer::new(textures).render_banded(scene, band, depth, BAND_ROWS, &mut sink) {
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
    texture(material(name, hash)?, Antialias::Csat)
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
