//! The scenes of Hart et al. (1999), figures 1 to 9, as [`Scene`]s.
//!
//! | scene | figure | objects (material) | triangles | frames (animation) |
//! |---|---|---|---|---|
//! | `wood` | 1, carved wooden teapot | teapot level 5 (`wood`) | 1560 | 64 (the teapot turns) |
//! | `marble` | 2, marble teapot sculpture | teapot level 4 on a cube pedestal, one block of `marble` | 992 + 12 | 64 (noise amplitude grows 0 to 1; still: last frame) |
//! | `seascape` | 3 | cloud plane at altitude 25 (`clouds`), sea plane (`water`), both 24000 units wide | 968 + 968 | 64 (clouds and waves drift) |
//! | `fire` | 4 | one screen-filling quad (`fire`) | 2 | 64 (phase) |
//! | `planet` | 5 | sphere (`planet`), cloud sphere over it (`planet-clouds`, alpha over) | 960 + 960 | 128 (both spin) |
//! | `moonrise` | 6 | sea plane (`water`), highlight (2 triangles, `marble` with transparent keys), moon (`clouds` with moon keys), cloud polygon (`planet-clouds` with night keys) | 968 + 2 + 960 + 2 | 128 (the moon rises) |
//! | `zoneplate` | 8 | orthographic full-screen quad, `s, t` in `[0, 1]` (`zoneplate`) | 2 | 1 |
//! | `torus` | 9 | wood torus, ring axis through its left side (`wood`) | 1280 | 1 |
//!
//! Triangle counts are mesh triangles before rejection and clipping. Images are 320x240 except
//! the zone plate (256x256). All parameters are integers (`Q16.16`, thousandths via [`milli`],
//! angles in degrees or turns): no floating point is involved.

use super::camera::{focal_from_fov, Camera};
use super::math::{milli, units, Angle, Vec3, ONE};
use super::mesh::Mesh;
use super::{Blend, Object, Scene, SceneError, TextureSlot};
use crate::format::MatrixEntry;
use crate::presets::Key;
use crate::raster::{CullMode, Perspective};
use crate::transform::Affine3;

/// Names of the built-in scenes, in figure order.
pub const BUILTIN: [&str; 8] = [
    "wood",
    "marble",
    "seascape",
    "fire",
    "planet",
    "moonrise",
    "zoneplate",
    "torus",
];

/// Names of the built-in animations that are not figures of the paper (section 4.4's tests).
pub const ANIMATIONS: [&str; 1] = ["flight"];

/// A built-in scene or animation ([`BUILTIN`], [`ANIMATIONS`]) by name.
pub fn by_name(name: &str) -> Option<Scene> {
    let scene = match name {
        "wood" => wood(),
        "marble" => marble(),
        "seascape" => seascape(),
        "fire" => fire(),
        "planet" => planet(),
        "moonrise" => moonrise(),
        "zoneplate" => zoneplate(),
        "torus" => torus(),
        "flight" => flight(),
        _ => return None,
    };
    // Every built-in scene is within the scene's capacities (`tests::builtins_build`).
    scene.ok()
}

/// Display width of the built-in scenes.
pub const WIDTH: u16 = 320;
/// Display height of the built-in scenes.
pub const HEIGHT: u16 = 240;

/// An affine texture mapping from rows and translation in thousandths.
const fn tex_map(rows: [[i32; 3]; 3], t: [i32; 3]) -> Affine3 {
    const fn e(v: i32) -> MatrixEntry {
        MatrixEntry::from_bits(milli(v))
    }
    Affine3::new(
        [
            [e(rows[0][0]), e(rows[0][1]), e(rows[0][2])],
            [e(rows[1][0]), e(rows[1][1]), e(rows[1][2])],
            [e(rows[2][0]), e(rows[2][1]), e(rows[2][2])],
        ],
        [e(t[0]), e(t[1]), e(t[2])],
    )
}

/// Adds `d` (raw `Q16.16`) times `frame` to a texture mapping's translation (wrapping).
fn drift(map: &Affine3, d: [i32; 3], frame: u32) -> Affine3 {
    let t = map.translation();
    let f = frame as i32;
    let add = |k: usize| MatrixEntry::from_bits(t[k].to_bits().wrapping_add(d[k].wrapping_mul(f)));
    map.with_translation([add(0), add(1), add(2)])
}

/// A perspective 320x240 camera with the y axis up.
const fn camera(eye: Vec3, target: Vec3, fov_degrees: i32, near: i32, far: i32) -> Camera {
    Camera::perspective(
        eye,
        target,
        Vec3::Y,
        focal_from_fov(Angle::from_degrees(fov_degrees)),
        near,
        far,
        WIDTH,
        HEIGHT,
    )
}

/// The teapot stood up in a y-up world (its z becomes y), centred on its bounding box.
fn teapot_upright() -> Affine3 {
    Affine3::rotate_x(Angle::from_degrees(-90))
        .then(&Affine3::translate(Vec3::milli(-215, -1575, 0)))
}

// ---------------------------------------------------------------------------------------------
// Figure 1: carved wooden teapot.

/// Figure 1: a teapot carved from a log, `f = s^2 + t^2 + n(4s, 4t, r)`. The rings' axis runs
/// along the teapot's y (across the spout-handle plane), 2.5 units below its base, so the grain
/// shows as arcs of concentric rings; turns once over the 64 frames.
pub fn wood() -> Result<Scene, SceneError> {
    let mut s = Scene::new(
        "wood",
        camera(
            Vec3::milli(0, 2900, 7900),
            Vec3::milli(0, -100, 0),
            40,
            milli(500),
            units(60),
        ),
    );
    s.background = [28, 24, 30, 255];
    s.set_frames(64, 0)?;
    let slot = s.add_slot(TextureSlot::preset("wood"))?;
    let mut o = Object::new(Mesh::Teapot { level: 5 });
    o.slot = slot;
    o.transform = teapot_upright().then(&Affine3::rotate_y(Angle::from_degrees(-20)));
    // s = 0.75 (x + 0.4), t = 0.75 (z + 2.5), r = 0.75 y (object space, z up).
    o.tex_map = tex_map([[750, 0, 0], [0, 0, 750], [0, 750, 0]], [300, 1875, 0]);
    s.add(o)?;
    s.animate = Some(|s, frame| {
        if let Some(o) = s.objects.get_mut(0) {
            let a = Angle::from_turns(frame as i64, 64);
            o.transform = o.transform.then(&Affine3::rotate_y(a));
        }
    });
    Ok(s)
}

// ---------------------------------------------------------------------------------------------
// Figure 2: marble.

/// The world-space block of marble both marble objects are cut from: `s = 1.2 x`, `t = 1.2 y`,
/// `r = 0.6 x + 0.75 y + 0.35 z + 0.3` (veins are the planes of constant `r`, tilted, one per
/// 1.1 units).
pub const MARBLE_BLOCK: Affine3 = tex_map(
    [[1200, 0, 0], [0, 1200, 0], [600, 750, 350]],
    [3100, 500, 300],
);

/// Figure 2: a marble teapot standing on a marble cube, both cut from one block
/// ([`MARBLE_BLOCK`]), so the veins run continuously across the cube's edges and from the
/// pedestal into the teapot. `f = r + sum_i 2^-i n(2^i s)`; the animation grows the noise
/// amplitude from 0 to 1 (the forming of the ripples); the still is the last frame.
pub fn marble() -> Result<Scene, SceneError> {
    let mut s = Scene::new(
        "marble",
        camera(
            Vec3::milli(4700, 3100, 8000),
            Vec3::milli(0, -250, 0),
            40,
            milli(500),
            units(60),
        ),
    );
    s.background = [36, 38, 48, 255];
    s.set_frames(64, 63)?;
    let slot = s.add_slot(TextureSlot::preset("marble"))?;
    // Pedestal: a cube of side 2.5, top face at y = 0.
    let mut cube = Object::new(Mesh::Cube {
        half: milli(1250),
        divisions: 1,
    });
    cube.slot = slot;
    cube.cull = CullMode::Clockwise;
    cube.transform = Affine3::translate(Vec3::milli(0, -1250, 0));
    let cube = cube.with_world_texture(&MARBLE_BLOCK);
    // Teapot at 3/4 size, its base (radius 1.07) on the pedestal.
    let mut pot = Object::new(Mesh::Teapot { level: 4 });
    pot.slot = slot;
    pot.transform = Affine3::rotate_x(Angle::from_degrees(-90))
        .then(&Affine3::scale(MatrixEntry::from_bits(3 * ONE / 4)))
        .then(&Affine3::rotate_y(Angle::from_degrees(-25)))
        .then(&Affine3::translate(Vec3::milli(-100, 0, 0)));
    let pot = pot.with_world_texture(&MARBLE_BLOCK);
    s.add(cube)?;
    s.add(pot)?;
    s.animate = Some(|s, frame| {
        let frames = s.frames().max(2) as i64;
        if let Some(slot) = s.slots.get_mut(0) {
            slot.amplitude = (frame as i64 * ONE as i64 / (frames - 1)) as i32;
        }
    });
    Ok(s)
}

// ---------------------------------------------------------------------------------------------
// Figure 3: seascape.

/// Half-size of the horizon planes (sea, sky): 12000 units.
pub const HORIZON_HALF_SIZE: i32 = 12_000 << 16;
/// Grid rings of the horizon planes (innermost cell 5.9 units, outermost 6000).
pub const HORIZON_RINGS: u8 = 11;

/// Sea waves stretched along x: `s = x / 16`, `t = z / 5`, `r = 0.3`.
const SEA_MAP: Affine3 = tex_map([[62, 0, 0], [0, 0, 200], [0, 0, 0]], [0, 0, 300]);

const fn horizon_plane() -> Mesh {
    Mesh::Plane {
        half_size: HORIZON_HALF_SIZE,
        rings: HORIZON_RINGS,
    }
}

/// Figure 3: a high cloud plane (altitude 25, `clouds`) over a sea plane (`water`), both
/// reaching the horizon; perspective-correct (`Every16`; exact along rows of a horizontal
/// plane), so the clouds grow dense towards the horizon. The eye is 1.5 units above the sea,
/// looking 2.6 degrees up (horizon a little below the image centre). The clouds and the waves
/// drift over the 64 frames.
pub fn seascape() -> Result<Scene, SceneError> {
    let mut s = Scene::new(
        "seascape",
        camera(
            Vec3::milli(0, 1500, 0),
            Vec3::milli(0, 2400, -20000),
            50,
            milli(250),
            units(20000),
        ),
    );
    // The half-pixel gap between the two planes' far edges at the horizon.
    s.background = [150, 170, 200, 255];
    s.set_frames(64, 0)?;
    let sky = s.add_slot(TextureSlot::preset("clouds"))?;
    let sea = s.add_slot(TextureSlot::preset("water"))?;
    let mut clouds = Object::new(horizon_plane());
    clouds.slot = sky;
    // Face down, 25 units up.
    clouds.transform =
        Affine3::rotate_x(Angle::HALF).then(&Affine3::translate(Vec3::milli(0, 25_000, 0)));
    // s = x / 50, t = z / 50, r = 0.5 (clouds some 25 units across, as high as the layer).
    clouds.tex_map = tex_map([[20, 0, 0], [0, 0, 20], [0, 0, 0]], [0, 0, 500]);
    clouds.depth_test = false;
    clouds.depth_write = false;
    let mut water = Object::new(horizon_plane());
    water.slot = sea;
    water.tex_map = SEA_MAP;
    water.depth_test = false;
    water.depth_write = false;
    s.add(clouds)?;
    s.add(water)?;
    s.animate = Some(|s, frame| {
        if let Some(o) = s.objects.get_mut(0) {
            o.tex_map = drift(&o.tex_map, [milli(4), milli(2), 0], frame);
        }
        if let Some(o) = s.objects.get_mut(1) {
            o.tex_map = drift(&o.tex_map, [0, -milli(10), milli(4)], frame);
        }
    });
    Ok(s)
}

// ---------------------------------------------------------------------------------------------
// Section 4.4: the flight towards the horizon.

/// The eye's speed in the [`flight`]: half a unit a frame towards the horizon (raw 16.16).
pub const FLIGHT_SPEED: i32 = milli(500);

/// Section 4.4's animation test: the [`seascape`]'s cloud and sea planes and view, the eye flying
/// towards the horizon (along `-z`) at [`FLIGHT_SPEED`] for 128 frames (64 units), no wind. Both
/// planes are infinite to the eye, so flying is moving their textures towards the eye: an eye
/// moved by `-D` along the world's `z` sees at each screen point the texture coordinate
/// `M R^T (p - D z) + t`, so each plane's texture translation moves by `-D M R^T z` (`M` its
/// texture mapping, `R` its rotation), with the planes' meshes and the perspective set-up
/// unchanged from frame to frame. The still is frame 0 (the seascape without wind).
pub fn flight() -> Result<Scene, SceneError> {
    let mut s = seascape()?;
    s.name = "flight";
    s.set_frames(128, 0)?;
    s.animate = Some(|s, frame| {
        for o in s.objects.iter_mut() {
            let m = o.tex_map.matrix();
            // R^T z: the world's z in object space (the third row of the rotation).
            let z = o.transform.matrix()[2].map(|e| e.to_bits());
            // Iterators, not indices: no bounds check at any opt-level (the firmware's
            // panic-never check links this).
            let d = m.map(|row| {
                let u: i64 = row
                    .iter()
                    .zip(&z)
                    .map(|(e, zj)| (i64::from(e.to_bits()) * i64::from(*zj)) >> 16)
                    .sum();
                (-(u * i64::from(FLIGHT_SPEED)) >> 16) as i32
            });
            o.tex_map = drift(&o.tex_map, d, frame);
        }
    });
    Ok(s)
}

// ---------------------------------------------------------------------------------------------
// Figure 4: fire.

/// Figure 4: fire on a single polygon filling the image, `f = t + 0.8 sum_i 2^-i
/// n(2^i (s, t - phase, r))` with `t` from 0 at the bottom to 1.27 at the top; the phase advances
/// 1/32 per frame (slot parameter `phase`).
pub fn fire() -> Result<Scene, SceneError> {
    // Quad 4.6 x 3.5 at z = 0, seen from z = 5 with focal 3.03 (half-height 1.65 at distance 5):
    // its edges are just outside the image.
    const HALF_HEIGHT: i64 = milli(1650) as i64;
    let focal = (5 * ONE as i64 * ONE as i64 / HALF_HEIGHT) as i32;
    let cam = Camera::perspective(
        Vec3::units(0, 0, 5),
        Vec3::ZERO,
        Vec3::Y,
        focal,
        milli(500),
        units(20),
        WIDTH,
        HEIGHT,
    );
    let mut s = Scene::new("fire", cam);
    s.background = [0, 0, 0, 255];
    s.set_frames(64, 0)?;
    let slot = s.add_slot(TextureSlot::preset("fire"))?;
    let mut o = Object::new(Mesh::Quad {
        corners: [
            Vec3::milli(-2300, -1750, 0),
            Vec3::milli(2300, -1750, 0),
            Vec3::milli(2300, 1750, 0),
            Vec3::milli(-2300, 1750, 0),
        ],
    });
    o.slot = slot;
    o.perspective = Perspective::Affine; // parallel to the screen: affine is exact
    o.depth_test = false;
    o.depth_write = false;
    // s = x / 3 + 0.5, t = (y + 1.75) / 2.7, r = 0.5.
    o.tex_map = tex_map([[333, 0, 0], [0, 370, 0], [0, 0, 0]], [500, 648, 500]);
    s.add(o)?;
    s.animate = Some(|s, frame| {
        if let Some(slot) = s.slots.get_mut(0) {
            slot.phase = (frame as i32).wrapping_mul(ONE / 32);
        }
    });
    Ok(s)
}

// ---------------------------------------------------------------------------------------------
// Figure 5: planet.

/// Figure 5: a planet (`planet`, cartographic legend) with a cloud layer rendered over it with
/// alpha (`planet-clouds`) on a slightly larger sphere; axis tilted 20 degrees; both spin (the
/// clouds faster) over the 128 frames. Back faces culled.
pub fn planet() -> Result<Scene, SceneError> {
    let mut s = Scene::new(
        "planet",
        camera(
            Vec3::milli(0, 600, 4200),
            Vec3::ZERO,
            40,
            milli(1000),
            units(10),
        ),
    );
    s.background = [0, 0, 0, 255];
    s.set_frames(128, 0)?;
    let ground = s.add_slot(TextureSlot::preset("planet"))?;
    let air = s.add_slot(TextureSlot::preset("planet-clouds"))?;
    let tilt = Affine3::rotate_z(Angle::from_degrees(20));
    let mut p = Object::new(Mesh::Sphere {
        radius: ONE,
        stacks: 16,
        slices: 32,
    });
    p.slot = ground;
    p.cull = CullMode::Clockwise;
    p.transform = tilt;
    p.tex_map = tex_map(
        [[1000, 0, 0], [0, 1000, 0], [0, 0, 1000]],
        [5300, 1700, 9100],
    );
    let mut c = Object::new(Mesh::Sphere {
        radius: milli(1030),
        stacks: 16,
        slices: 32,
    });
    c.slot = air;
    c.blend = Blend::Over;
    c.cull = CullMode::Clockwise;
    c.depth_write = false;
    c.transform = tilt;
    c.tex_map = tex_map(
        [[1200, 0, 0], [0, 1200, 0], [0, 0, 1200]],
        [2000, 7000, -3000],
    );
    s.add(p)?;
    s.add(c)?;
    s.animate = Some(|s, frame| {
        for (k, turns) in [(0usize, 1i64), (1, 2)] {
            if let Some(o) = s.objects.get_mut(k) {
                let a = Angle::from_turns(frame as i64 * turns, 128);
                o.transform = Affine3::rotate_y(a).then(&o.transform);
            }
        }
    });
    Ok(s)
}

// ---------------------------------------------------------------------------------------------
// Figure 6: moonrise.

/// Grey maria to bright highlands (clamped) for the moon.
pub const MOON_KEYS: [Key; 3] = [
    (0, [88, 88, 96, 255]),
    (29491, [172, 170, 164, 255]),
    (65536, [238, 236, 224, 255]),
];
/// Moonlight glints on the water: a mod table, transparent except a bright band (alpha up to
/// 0.9) around 1/2, used with the marble model so that the bands are wavy streaks.
pub const MOON_GLINT_KEYS: [Key; 7] = [
    (0, [255, 236, 180, 0]),
    (27853, [255, 236, 180, 0]),
    (30802, [255, 242, 200, 150]),
    (32768, [255, 250, 228, 235]),
    (34734, [255, 242, 200, 150]),
    (37683, [255, 236, 180, 0]),
    (65536, [255, 236, 180, 0]),
];
/// Thin night clouds: clear below 0.45, then grey to 80% opaque (clamped).
pub const NIGHT_CLOUD_KEYS: [Key; 3] = [
    (0, [96, 98, 120, 0]),
    (29491, [96, 98, 120, 0]),
    (65536, [176, 178, 194, 204]),
];

/// Figure 6, entirely from textures: a sea plane to the horizon (`water`), the moon's highlight
/// faked with two triangles on the water (the marble model with a partially transparent table,
/// alpha over), the moon (a sphere with a fractal texture: `clouds` with moon keys) and a cloud
/// polygon perpendicular to the view in front of it (`planet-clouds` with night keys, alpha
/// over). Drawn in that order without depth; the moon rises over the 128 frames.
pub fn moonrise() -> Result<Scene, SceneError> {
    let mut s = Scene::new(
        "moonrise",
        camera(
            Vec3::milli(0, 2000, 0),
            Vec3::milli(0, 8000, -100_000),
            45,
            milli(250),
            units(20000),
        ),
    );
    s.background = [8, 12, 36, 255];
    s.set_frames(128, 0)?;
    let sea = s.add_slot(TextureSlot::preset("water"))?;
    let glint = s.add_slot(TextureSlot::preset("marble").with_keys(&MOON_GLINT_KEYS))?;
    let moon_tex = s.add_slot(TextureSlot::preset("clouds").with_keys(&MOON_KEYS))?;
    let cloud_tex =
        s.add_slot(TextureSlot::preset("planet-clouds").with_keys(&NIGHT_CLOUD_KEYS))?;

    let mut water = Object::new(horizon_plane());
    water.slot = sea;
    water.tex_map = SEA_MAP;
    water.depth_test = false;
    water.depth_write = false;

    // The highlight: a trapezoid on the water under the moon (x = 12 at distance 260), as wide
    // on screen as the moon far away and twice as wide near the eye.
    let mut glow = Object::new(Mesh::Quad {
        corners: [
            Vec3::milli(-1000, 20, -6000),
            Vec3::milli(1550, 20, -6000),
            Vec3::milli(35_500, 20, -250_000),
            Vec3::milli(-12_500, 20, -250_000),
        ],
    });
    glow.slot = glint;
    glow.blend = Blend::Over;
    glow.depth_test = false;
    glow.depth_write = false;
    // Streaks across the path: r = -z / 2.5 (a band per 2.5 units of distance), s = x / 3,
    // t = z / 10.
    glow.tex_map = tex_map([[333, 0, 0], [0, 0, 100], [0, 0, -400]], [0, 0, 0]);

    let mut moon = Object::new(Mesh::Sphere {
        radius: units(25),
        stacks: 16,
        slices: 32,
    });
    moon.slot = moon_tex;
    moon.cull = CullMode::Clockwise;
    moon.depth_test = false;
    moon.depth_write = false;
    moon.transform = Affine3::translate(Vec3::milli(12_000, 43_000, -260_000));
    // Fractal detail a few times across the disc.
    moon.tex_map = tex_map([[80, 0, 0], [0, 80, 0], [0, 0, 80]], [7000, 3000, 1000]);

    // Clouds: a polygon facing the eye at distance 200, from just above the horizon to the top.
    let mut clouds = Object::new(Mesh::Quad {
        corners: [
            Vec3::milli(-300_000, 3000, -200_000),
            Vec3::milli(300_000, 3000, -200_000),
            Vec3::milli(300_000, 200_000, -200_000),
            Vec3::milli(-300_000, 200_000, -200_000),
        ],
    });
    clouds.slot = cloud_tex;
    clouds.blend = Blend::Over;
    clouds.depth_test = false;
    clouds.depth_write = false;
    // Stretched horizontally: s = x / 40, t = y / 12.
    clouds.tex_map = tex_map([[25, 0, 0], [0, 83, 0], [0, 0, 0]], [0, 0, 300]);

    s.add(water)?;
    s.add(glow)?;
    s.add(moon)?;
    s.add(clouds)?;
    s.animate = Some(|s, frame| {
        // Rise 12 units over the animation.
        if let Some(o) = s.objects.get_mut(2) {
            let dy = (frame as i64 * units(12) as i64 / 128) as i32;
            let [x, y, z] = o.transform.translation();
            let y = MatrixEntry::from_bits(y.to_bits().wrapping_add(dy));
            o.transform = o.transform.with_translation([x, y, z]);
        }
    });
    Ok(s)
}

// ---------------------------------------------------------------------------------------------
// Figure 8: zone plate.

/// Figure 8: the zone plate `f = 50 s^2 + 50 t^2` over the unit square at 256x256. An
/// orthographic camera looks at the quad `[0, 1]^2` (z = 0) so that its corners are exactly the
/// image corners and the texture coordinates are `s = x`, `t = y` of the world: pixel `(x, y)`
/// gets `s = (x + 0.5) / 256`, `t = (y + 0.5) / 256` exactly (affine interpolation; `t` grows
/// downwards).
pub fn zoneplate() -> Result<Scene, SceneError> {
    let centre = Vec3::milli(500, 500, 0);
    let cam = Camera::orthographic(
        Vec3::milli(500, 500, -1000),
        centre,
        Vec3::new(0, -ONE, 0),
        ONE / 2,
        milli(500),
        units(2),
        256,
        256,
    );
    let mut s = Scene::new("zoneplate", cam);
    s.background = [128, 128, 128, 255];
    let slot = s.add_slot(TextureSlot::preset("zoneplate"))?;
    let mut o = Object::new(Mesh::Quad {
        corners: [
            Vec3::units(0, 0, 0),
            Vec3::units(1, 0, 0),
            Vec3::units(1, 1, 0),
            Vec3::units(0, 1, 0),
        ],
    });
    o.slot = slot;
    o.perspective = Perspective::Affine;
    o.depth_test = false;
    o.depth_write = false;
    s.add(o)?;
    Ok(s)
}

// ---------------------------------------------------------------------------------------------
// Figure 9: torus.

/// Figure 9: a wood torus (`wood`, `f = s^2 + t^2 + n(4s, 4t, r)`) whose ring axis is vertical
/// through the left side of the torus (`s = 2.5 (x + 1)`, `t = 2.5 z`, `r = 2.5 y`): the rings
/// are wide on the left and ever finer to the right (quadric aliasing), the noise is uniform
/// (noise aliasing) and the silhouette compresses the texture (coordinate aliasing). Seen from
/// 40 degrees above. Back faces culled.
pub fn torus() -> Result<Scene, SceneError> {
    let mut s = Scene::new(
        "torus",
        camera(
            Vec3::milli(0, 2450, 2900),
            Vec3::milli(0, -100, 0),
            40,
            milli(500),
            units(20),
        ),
    );
    s.background = [40, 40, 48, 255];
    let slot = s.add_slot(TextureSlot::preset("wood"))?;
    let mut o = Object::new(Mesh::Torus {
        major: ONE,
        minor: milli(380),
        major_segments: 40,
        minor_segments: 16,
    });
    o.slot = slot;
    o.cull = CullMode::Clockwise;
    o.tex_map = tex_map([[2500, 0, 0], [0, 0, 2500], [0, 2500, 0]], [2500, 0, 0]);
    s.add(o)?;
    Ok(s)
}
