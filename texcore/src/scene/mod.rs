//! Scenes: procedural meshes, cameras and clipping that turn the figures of Hart et al. (1999)
//! into screen triangles for the [rasterizer](crate::raster).
//!
//! Geometry only: a [`Scene`] says which triangles to draw, with which solid texture coordinates,
//! drawing options and texture slot; the renderer owns colours (materials are named by
//! [preset](crate::presets) name in each [`TextureSlot`]).
//!
//! Everything is integer arithmetic (`no_std`, no allocation, no floating point), so a scene
//! yields bit-identical triangles on the host, a Cortex-M4F and an rv32imc; nothing panics for any
//! input. Meshes are generated on the fly every frame (a few hundred bytes of stack), quad by
//! quad; [`Scene::for_each_triangle_by_quad`] lets a caller skip quads before any work is done
//! for them (the binned banded renderer, [`crate::render::Renderer::render_banded_rows_binned`],
//! generates each quad only for the bands it can touch).
//!
//! | module | contents |
//! |---|---|
//! | [`math`] | `Q16.16` vectors (affine maps: [`Affine3`]), angles in turns, sine/cosine, `isqrt` |
//! | [`camera`] | perspective/orthographic cameras, projection, near/far/guard-band clipping |
//! | [`mesh`] | teapot, sphere, torus, cube, quad and horizon plane as triangle iterators |
//! | [`teapot`] | the Utah teapot's 32 Bezier patches and exact tessellation |
//! | [`builtin`] | the paper's scenes (`wood`, `marble`, `seascape`, `fire`, `planet`, `moonrise`, `zoneplate`, `torus`) and the animation `flight` |
//!
//! # Cost on the devices
//!
//! Scenes are walked quad by quad: the four corners of a mesh quad are generated, transformed
//! (object to world to camera, `i64` products), classified against the clip planes (outcodes
//! from 64-bit products) and projected once (one 64-bit division per vertex, the reciprocal of
//! its depth); only triangles crossing the near, far or guard-band planes take the exact `i128`
//! clipping path. Instructions per frame of the built-in scenes (QEMU instruction counts of
//! [`Scene::checksum`] at the still frame, i.e. including a byte-wise FNV hash of every
//! triangle):
//!
//! | scene | Cortex-M4F | rv32imc |
//! |---|---|---|
//! | `wood` (1560 triangles) | 7.7 M | 10.7 M |
//! | `marble` (1004) | 5.0 M | 6.9 M |
//! | `seascape` (1936 in, 487 out) | 5.5 M | 7.2 M |
//! | `fire` (2) | 27 k | 41 k |
//! | `planet` (1920) | 8.0 M | 11.1 M |
//! | `moonrise` (1932 in, 1219 out) | 6.9 M | 9.4 M |
//! | `zoneplate` (2) | 26 k | 39 k |
//! | `torus` (1280) | 5.0 M | 6.9 M |
//!
//! About a third of the teapot scenes' cost is the Bezier tessellation. No code path of a scene
//! walk can panic (checked by linking a walk over every built-in scene for both targets with a
//! panic handler that does not link), and the triangles are bit-identical on the host and both
//! devices (same checksums).
//!
//! # Example
//!
//! ```
//! use texcore::raster::{Rasterizer, Rect, Segment};
//! use texcore::scene;
//!
//! let s = scene::by_name("zoneplate").unwrap();
//! let (w, h) = s.size();
//! let mut rast = Rasterizer::new(Rect::from_size(w, h));
//! let mut pixels = 0u32;
//! let counters = s.for_each_triangle(0, |object, tri| {
//!     let opts = s.objects[object].options();
//!     rast.draw(tri, &opts, &mut |seg: &Segment| pixels += seg.len as u32);
//! });
//! assert_eq!(counters.generated, 2);
//! assert_eq!(pixels, 256 * 256);
//! ```

pub mod builtin;
pub mod camera;
mod corners;
#[cfg(feature = "lighting")]
mod lit;
pub mod math;
pub mod mesh;
pub mod teapot;
#[cfg(test)]
mod tests;

pub use builtin::{by_name, ANIMATIONS, BUILTIN};
pub use camera::{focal_from_fov, Camera, Projection, View};
pub use math::{Angle, Vec3};
pub use mesh::Mesh;

use crate::presets::Key;
use crate::raster::{CullMode, DepthFunc, Perspective, ScreenVertex, TriangleOptions};
/// Object placement and texture mapping: texcore's one affine type.
pub use crate::transform::Affine3;
use camera::{CamVertex, ClipOutcome};

/// Most objects in a scene.
pub const MAX_OBJECTS: usize = 8;
/// Most texture slots in a scene.
pub const MAX_SLOTS: usize = 6;
/// Most lights in a scene (feature `lighting`).
pub const MAX_LIGHTS: usize = 4;

/// How an object's pixels combine with the frame: the renderer's [`crate::render::Blend`] (one
/// type for both).
pub use crate::render::Blend;

/// A material for the renderer: a preset by name and the per-scene parameters that vary.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TextureSlot {
    /// Preset name ([`crate::presets::NAMES`]: `"wood"`, `"marble"`, `"fire"`, ...).
    pub material: &'static str,
    /// Factor on every noise term's amplitude, `Q16.16` (`65536` = the preset's own).
    pub amplitude: i32,
    /// Noise phase, `Q16.16` (the fire's `phase`, [`crate::presets::set_fire_phase`]); 0 for
    /// materials without one.
    pub phase: i32,
    /// Colour keys replacing the preset's (`None`: the preset's keys).
    pub keys: Option<&'static [Key]>,
}

impl TextureSlot {
    /// A preset as is.
    pub const fn preset(material: &'static str) -> TextureSlot {
        TextureSlot {
            material,
            amplitude: math::ONE,
            phase: 0,
            keys: None,
        }
    }

    /// The same slot with other colour keys.
    pub const fn with_keys(mut self, keys: &'static [Key]) -> TextureSlot {
        self.keys = Some(keys);
        self
    }
}

/// One object: a mesh placed in the world, its solid texture mapping and drawing state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Object {
    /// The mesh (object space).
    pub mesh: Mesh,
    /// Object to world.
    pub transform: Affine3,
    /// Object space to solid texture coordinates (`s = M p + t`, `Q16.16`): the texture is
    /// attached to the object.
    pub tex_map: Affine3,
    /// Index into [`Scene::slots`].
    pub slot: u8,
    /// Blending.
    pub blend: Blend,
    /// Texture-coordinate interpolation.
    pub perspective: Perspective,
    /// Back-face culling.
    pub cull: CullMode,
    /// Whether pixels are depth tested (`Less`) or always drawn.
    pub depth_test: bool,
    /// Whether drawn pixels write depth.
    pub depth_write: bool,
}

impl Object {
    /// An opaque, depth-tested, perspective-correct (`Every16`) object without culling, texture
    /// coordinates equal to object coordinates, slot 0.
    pub const fn new(mesh: Mesh) -> Object {
        Object {
            mesh,
            transform: Affine3::IDENTITY,
            tex_map: Affine3::IDENTITY,
            slot: 0,
            blend: Blend::Opaque,
            perspective: Perspective::Every16,
            cull: CullMode::None,
            depth_test: true,
            depth_write: true,
        }
    }

    /// The rasterizer options of the object's triangles.
    pub const fn options(&self) -> TriangleOptions {
        TriangleOptions {
            perspective: self.perspective,
            cull: self.cull,
            depth_func: if self.depth_test {
                DepthFunc::Less
            } else {
                DepthFunc::Always
            },
            depth_write: self.depth_write,
        }
    }

    /// Sets the texture mapping from a **world-space** one: `tex_map = world_map o transform`,
    /// so that objects sharing `world_map` are cut from one block of material. Call after
    /// setting `transform`.
    pub fn with_world_texture(mut self, world_map: &Affine3) -> Object {
        self.tex_map = self.transform.then(world_map);
        self
    }
}

/// Activity counters of one walk over a scene. All counts wrap.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SceneCounters {
    /// Objects walked.
    pub objects: u32,
    /// Mesh triangles considered.
    pub input: u32,
    /// Input triangles entirely outside the view (or clipped away to nothing).
    pub rejected: u32,
    /// Input triangles cut by the near, far or guard-band planes.
    pub clipped: u32,
    /// Screen triangles emitted.
    pub generated: u32,
}

/// Why a scene could not be changed as asked. `Display` names the problem.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SceneError {
    /// The scene already has [`MAX_OBJECTS`] objects.
    TooManyObjects,
    /// The scene already has [`MAX_SLOTS`] texture slots.
    TooManySlots,
    /// The scene already has its most lights (`MAX_LIGHTS`, feature `lighting`).
    TooManyLights,
    /// An animation of no frames.
    NoFrames,
    /// The still frame is not one of the animation's frames.
    StillOutOfRange {
        /// The still frame asked for.
        still: u32,
        /// The number of frames.
        frames: u32,
    },
}

impl core::fmt::Display for SceneError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SceneError::TooManyObjects => write!(f, "a scene has at most {MAX_OBJECTS} objects"),
            SceneError::TooManySlots => {
                write!(f, "a scene has at most {MAX_SLOTS} texture slots")
            }
            SceneError::TooManyLights => write!(f, "a scene has at most {MAX_LIGHTS} lights"),
            SceneError::NoFrames => f.write_str("an animation has at least 1 frame"),
            SceneError::StillOutOfRange { still, frames } => write!(
                f,
                "the still frame {still} is not one of the {frames} frames (0 to {})",
                frames - 1
            ),
        }
    }
}

/// A per-frame animation: edits a copy of the scene for frame `frame` (`0..frames`).
pub type AnimateFn = fn(&mut Scene, u32);

/// A scene: camera, objects, texture slots, background and animation.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Name (`wood`, `seascape`, ...).
    pub name: &'static str,
    /// The camera (with the image size).
    pub camera: Camera,
    /// Background colour, RGBA.
    pub background: [u8; 4],
    /// Number of frames of the animation (at least 1: [`Scene::set_frames`] checks it).
    frames: u32,
    /// The frame that reproduces the paper's still figure (below `frames`).
    still: u32,
    /// Objects, drawn in this order.
    pub objects: heapless::Vec<Object, MAX_OBJECTS>,
    /// Texture slots referred to by [`Object::slot`].
    pub slots: heapless::Vec<TextureSlot, MAX_SLOTS>,
    /// The animation (`None`: static).
    pub animate: Option<AnimateFn>,
    /// The lights (none: the scene is unlit and pays nothing for lighting).
    #[cfg(feature = "lighting")]
    lighting: crate::light::Lighting<MAX_LIGHTS>,
}

impl Scene {
    /// An empty scene.
    pub const fn new(name: &'static str, camera: Camera) -> Scene {
        Scene {
            name,
            camera,
            background: [0, 0, 0, 255],
            frames: 1,
            still: 0,
            objects: heapless::Vec::new(),
            slots: heapless::Vec::new(),
            animate: None,
            #[cfg(feature = "lighting")]
            lighting: crate::light::Lighting::new(),
        }
    }

    /// Image size `(width, height)`.
    pub const fn size(&self) -> (u16, u16) {
        (self.camera.width, self.camera.height)
    }

    /// Number of frames of the animation (at least 1).
    pub const fn frames(&self) -> u32 {
        self.frames
    }

    /// The frame that reproduces the paper's still figure (below [`Scene::frames`]).
    pub const fn still(&self) -> u32 {
        self.still
    }

    /// Sets the animation's length and its still frame: `frames >= 1`, `still < frames`.
    pub fn set_frames(&mut self, frames: u32, still: u32) -> Result<(), SceneError> {
        if frames == 0 {
            return Err(SceneError::NoFrames);
        }
        if still >= frames {
            return Err(SceneError::StillOutOfRange { still, frames });
        }
        self.frames = frames;
        self.still = still;
        Ok(())
    }

    /// Adds an object; returns its index, or [`SceneError::TooManyObjects`] when the scene
    /// already has [`MAX_OBJECTS`] (the scene is then unchanged).
    pub fn add(&mut self, object: Object) -> Result<usize, SceneError> {
        self.objects
            .push(object)
            .map_err(|_| SceneError::TooManyObjects)?;
        Ok(self.objects.len() - 1)
    }

    /// Adds a texture slot; returns its index, or [`SceneError::TooManySlots`] when the scene
    /// already has [`MAX_SLOTS`] (the scene is then unchanged).
    pub fn add_slot(&mut self, slot: TextureSlot) -> Result<u8, SceneError> {
        self.slots
            .push(slot)
            .map_err(|_| SceneError::TooManySlots)?;
        Ok((self.slots.len() - 1) as u8)
    }

    /// The texture slot of an object (`None` for a bad index).
    pub fn slot_of(&self, object: usize) -> Option<&TextureSlot> {
        let o = self.objects.get(object)?;
        self.slots.get(o.slot as usize)
    }

    /// The scene as it is at `frame` (taken modulo [`Scene::frames`]): camera, transforms,
    /// texture mappings and slot parameters animated.
    pub fn at_frame(&self, frame: u32) -> Scene {
        let mut s = self.clone();
        if let Some(f) = self.animate {
            f(&mut s, frame % self.frames.max(1));
        }
        s
    }

    /// Walks every object of frame `frame` in order, and every triangle of its mesh in order,
    /// and calls `f(object_index, triangle)` for each screen triangle after rejection and
    /// clipping. Deterministic: the same scene and frame give the same calls on every target.
    pub fn for_each_triangle<F: FnMut(usize, &[ScreenVertex; 3])>(
        &self,
        frame: u32,
        mut f: F,
    ) -> SceneCounters {
        let s = self.at_frame(frame);
        s.for_each_triangle_static(&mut f)
    }

    /// A 32-bit FNV-1a checksum of every screen triangle of frame `frame` (object index, then
    /// each vertex's `x`, `y`, `z`, `inv_w` and texture coordinates as raw little-endian bits):
    /// equal on every target for the same scene, so a device can be checked against the host.
    pub fn checksum(&self, frame: u32) -> u32 {
        let mut h: u32 = 0x811C_9DC5;
        let mut eat = |bytes: &[u8]| {
            for &b in bytes {
                h = (h ^ b as u32).wrapping_mul(0x0100_0193);
            }
        };
        self.for_each_triangle(frame, |o, t| {
            eat(&(o as u32).to_le_bytes());
            for v in t {
                eat(&v.x.to_bits().to_le_bytes());
                eat(&v.y.to_bits().to_le_bytes());
                eat(&v.z.to_le_bytes());
                eat(&v.inv_w.to_bits().to_le_bytes());
                for c in v.tex.to_bits() {
                    eat(&c.to_le_bytes());
                }
            }
        });
        h
    }

    /// [`Scene::for_each_triangle`] for the scene exactly as it is (no animation applied).
    pub fn for_each_triangle_static<F: FnMut(usize, &[ScreenVertex; 3])>(
        &self,
        f: &mut F,
    ) -> SceneCounters {
        self.for_each_triangle_by_quad(&mut |_| true, &mut |_, object, t| f(object, t))
    }

    /// Number of mesh quads of the scene (the sum of the objects' [`Mesh::quad_count`]): the
    /// number of groups of [`Scene::for_each_triangle_by_quad`], e.g. to size a renderer's bins
    /// ([`crate::render::GroupRows`]).
    pub fn quad_count(&self) -> usize {
        self.objects.iter().fold(0usize, |n, o| {
            n.saturating_add(o.mesh.quad_count() as usize)
        })
    }

    /// [`Scene::for_each_triangle_static`] in groups, one group per mesh quad: the quads of every
    /// object in order are numbered `0, 1, 2, ...` (object `i`'s quad `q` is group
    /// `q + ` the quad counts of the objects before `i`, see [`Scene::quad_count`]).
    ///
    /// Before the work for group `g` starts (generating the quad's corners, transforming,
    /// classifying and projecting them) `keep(g)` is asked; when it answers `false` the quad is
    /// skipped at the cost of that call. Otherwise `f(g, object, triangle)` is called for each of
    /// the quad's screen triangles (none, one, two, or whatever near/far/guard-band clipping
    /// emits from them). Guarantees:
    /// - `keep` is asked once for every group, in increasing order (not at all when the camera
    ///   has no valid view: then no object emits anything);
    /// - a group's triangles come right after its `keep`, before the next group's;
    /// - with `keep` always `true`, the triangles and object indices are exactly those of
    ///   [`Scene::for_each_triangle_static`], in the same order; otherwise they are the
    ///   subsequence belonging to the kept groups.
    ///
    /// The counters count the work of the kept groups only.
    pub fn for_each_triangle_by_quad<K, F>(&self, keep: &mut K, f: &mut F) -> SceneCounters
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3]),
    {
        self.walk_quads::<K, _, _, { corners::BAND_WALK_SLOTS }>(
            keep,
            &mut |g, o, t, _: &dyn Fn() -> [(); 3]| f(g, o, t),
            &(),
            true,
        )
    }

    /// [`Scene::for_each_triangle_by_quad`] that also tells where each triangle's vertices come
    /// from: `f(g, object, triangle, corners)` gets `Some([a, b, c])`, the indices (`0..4`) of
    /// the quad corners ([`Mesh::quad`]) that the triangle's vertices are, in order (the quad's
    /// triangles are its corners `[0, 1, 2]` and `[0, 2, 3]`), or `None` for a triangle that
    /// near/far/guard-band clipping made, whose vertices need not be corners. Everything else
    /// (which triangles, their order, the counters) is exactly
    /// [`Scene::for_each_triangle_by_quad`]'s. A caller that keeps per-corner data (atlas
    /// positions, for example) finds it without generating the quad's corners again.
    pub fn for_each_triangle_with_corners<K, F>(&self, keep: &mut K, f: &mut F) -> SceneCounters
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3], Option<[u8; 3]>),
    {
        self.walk_with_corners::<K, F, { corners::BAND_WALK_SLOTS }>(keep, f, true)
    }

    /// [`Scene::for_each_triangle_with_corners`] without the vertices' texture coordinates
    /// (every `tex` is zero): the same triangles, screen positions, depths, `1/w`, corners and
    /// counters, for a caller that takes each corner's texture position from elsewhere (an
    /// atlas layout) and so need not map every corner's solid coordinates.
    pub fn for_each_screen_triangle_with_corners<K, F>(
        &self,
        keep: &mut K,
        f: &mut F,
    ) -> SceneCounters
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3], Option<[u8; 3]>),
    {
        self.walk_with_corners::<K, F, { corners::FRAME_WALK_SLOTS }>(keep, f, false)
    }

    fn walk_with_corners<K, F, const S: usize>(
        &self,
        keep: &mut K,
        f: &mut F,
        tex: bool,
    ) -> SceneCounters
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3], Option<[u8; 3]>),
    {
        self.walk_quads::<K, _, _, S>(
            keep,
            &mut |g, o, t, corners: &dyn Fn() -> [Option<u8>; 3]| {
                let c = match corners() {
                    [Some(a), Some(b), Some(d)] => Some([a, b, d]),
                    _ => None,
                };
                f(g, o, t, c)
            },
            &CornerIndex,
            tex,
        )
    }

    /// The walk of [`Scene::for_each_triangle_by_quad`], with `corner` computing what each
    /// emitted vertex carries besides its screen position, on demand: `f` gets a function that
    /// computes the triangle's three values (each quad corner at most once per walk), so a
    /// triangle whose values are not asked for costs nothing (nor does anything for `()`). A
    /// triangle cut by clipping gets the mean of its input corners' values. Without `tex`, every
    /// vertex's texture coordinates are zero (nothing else changes).
    fn walk_quads<K, F, L, const S: usize>(
        &self,
        keep: &mut K,
        f: &mut F,
        corner: &L,
        tex: bool,
    ) -> SceneCounters
    where
        K: FnMut(usize) -> bool,
        F: FnMut(usize, usize, &[ScreenVertex; 3], &dyn Fn() -> [L::Value; 3]),
        L: CornerValue,
    {
        let mut c = SceneCounters::default();
        let view = self.camera.view();
        let mut first_group = 0usize;
        let mut store = corners::CornerStore::<S>::new();
        for (index, o) in self.objects.iter().enumerate() {
            c.objects = c.objects.wrapping_add(1);
            let quads = o.mesh.quad_count();
            let groups = first_group;
            first_group = first_group.wrapping_add(quads as usize);
            let Some(view) = view.as_ref() else {
                let n = o.mesh.triangle_count();
                c.input = c.input.wrapping_add(n);
                c.rejected = c.rejected.wrapping_add(n);
                continue;
            };
            // Quad by quad (the order of `Mesh::triangles`), so that the four corners are
            // transformed, classified and projected once for both triangles. The last quad's
            // right edge (corners 1 and 2) is kept: a grid mesh's next quad in the row has it
            // as its left edge (corners 0 and 3), and a corner at the same object-space
            // position has the same camera vertex, outcodes and projection (each a function of
            // the position and the object), so those are reused, not recomputed.
            //
            // The corners live in `store` (slot numbers in `at`), which keeps recent ones by
            // position: a quad whose top corners were the bottom corners of a quad in the row
            // above (or across a patch seam) finds them there, exactly as computed
            // (`corners`).
            let mut edge: Option<[Vec3; 2]> = None;
            let mut at = [0usize; 4];
            store.clear();
            let how = CornerHow {
                tex,
                small: o.transform.small(),
            };
            // What the mesh keeps from one quad to the next (`Mesh::quad_walked_into`).
            let mut cursor = mesh::QuadCursor::default();
            // The corners of the quad being walked, written in place by the mesh.
            let mut corners = [Vec3::ZERO; 4];
            for q in 0..quads {
                let group = groups.wrapping_add(q as usize);
                if !keep(group) {
                    continue;
                }
                if !o.mesh.quad_walked_into(q, &mut cursor, &mut corners) {
                    break;
                }
                let halves = [[0usize, 1, 2], [0, 2, 3]];
                let [c0, c1, c2, c3] = corners;
                let distinct = |a, b, d| a != b && b != d && d != a;
                let live = [distinct(c0, c1, c2), distinct(c0, c2, c3)];
                if !live[0] && !live[1] {
                    continue;
                }
                // Corner 0 is the last quad's corner 1 and corner 3 its corner 2 when their
                // positions are equal (the slots still hold what was computed for them).
                let [reuse0, reuse3] = match edge {
                    Some([e1, e2]) => [e1 == c0, e2 == c3],
                    None => [false, false],
                };
                store_quad(
                    &mut store,
                    view,
                    o,
                    &corners,
                    [reuse0, reuse3],
                    how,
                    &mut at,
                );
                edge = Some([c1, c2]);
                let values: [core::cell::Cell<Option<L::Value>>; 4] = Default::default();
                let v = |i: usize| -> L::Value {
                    let cell = &values[i & 3];
                    match cell.get() {
                        Some(x) => x,
                        None => {
                            let x = corner.at(o, &corners, i);
                            cell.set(Some(x));
                            x
                        }
                    }
                };
                for (tri, live) in halves.iter().zip(live) {
                    if !live {
                        continue;
                    }
                    c.input = c.input.wrapping_add(1);
                    // `& 3`: provably in bounds (no panic path).
                    let [a, b, d] = *tri;
                    let (a, b, d) = (a & 3, b & 3, d & 3);
                    let oc = |i: usize| store.get(at[i]).oc;
                    if oc(a).0 & oc(b).0 & oc(d).0 != 0 {
                        c.rejected = c.rejected.wrapping_add(1);
                    } else if (oc(a).1 | oc(b).1 | oc(d).1) == 0 {
                        let mut p = |i: usize| -> (ScreenVertex, u64) {
                            let w = store.get_mut(at[i]);
                            let pr = match w.projected {
                                Some(pr) => pr,
                                None => {
                                    let pr = corners::Projected::new(view.project(&w.cam));
                                    w.projected = Some(pr);
                                    pr
                                }
                            };
                            pr.vertex(&w.cam.tex)
                        };
                        let t = camera::assemble([p(a), p(b), p(d)]);
                        c.generated = c.generated.wrapping_add(1);
                        f(group, index, &t, &|| [v(a), v(b), v(d)]);
                    } else {
                        let lit = || [L::mean([v(a), v(b), v(d)]); 3];
                        let mut emit = |t: &[ScreenVertex; 3]| {
                            c.generated = c.generated.wrapping_add(1);
                            f(group, index, t, &lit);
                        };
                        let cam = |i: usize| store.get(at[i]).cam;
                        let outcome = view.clip_project(&[cam(a), cam(b), cam(d)], &mut emit);
                        match outcome {
                            ClipOutcome::Inside => {}
                            ClipOutcome::Clipped(0) => {
                                c.clipped = c.clipped.wrapping_add(1);
                                c.rejected = c.rejected.wrapping_add(1);
                            }
                            ClipOutcome::Clipped(_) => c.clipped = c.clipped.wrapping_add(1),
                            ClipOutcome::Rejected => c.rejected = c.rejected.wrapping_add(1),
                        }
                    }
                }
            }
        }
        c
    }
}

/// The slots `at` of `store` holding the corners `c` of a quad of object `o`: corner 0 is the
/// last quad's corner 1 (`at[1]`) when `reuse[0]`, corner 3 its corner 2 (`at[2]`) when
/// `reuse[1]`; every other corner is the one cached for its position (the same values) or a
/// slot none of the quad's other corners holds, filled by [`walk_corner`]. Out of line: one
/// copy for every walk.
#[inline(never)]
fn store_quad<const S: usize>(
    store: &mut corners::CornerStore<S>,
    view: &View,
    o: &Object,
    c: &[Vec3; 4],
    reuse: [bool; 2],
    how: CornerHow,
    at: &mut [usize; 4],
) {
    // The slots of the reused corners stay busy while the others are claimed.
    let mut busy = [usize::MAX; 4];
    if reuse[0] {
        busy[0] = at[1];
    }
    if reuse[1] {
        busy[3] = at[2];
    }
    for k in [0usize, 3, 1, 2] {
        let (k, p) = (k & 3, c[k & 3]);
        if busy[k] != usize::MAX {
            continue;
        }
        busy[k] = match store.find(&p) {
            Some(i) => i,
            None => {
                let i = store.claim(p, &busy);
                walk_corner(view, o, p, how, store.get_mut(i));
                i
            }
        };
    }
    *at = busy;
}

/// How a walk computes its corners: with texture coordinates (`tex`), and whether the object's
/// transform takes the `i64` products (`small`: [`Affine3::small`], found once an object).
#[derive(Clone, Copy)]
struct CornerHow {
    tex: bool,
    small: bool,
}

/// The camera vertex and outcodes of object `o`'s object-space point `p` (not yet projected),
/// into `out`; its texture coordinates zero unless `how.tex`.
#[inline(never)]
fn walk_corner(view: &View, o: &Object, p: Vec3, how: CornerHow, out: &mut corners::WalkedCorner) {
    out.cam = CamVertex {
        p: view.to_camera(o.transform.saturating_apply_with(p, how.small)),
        tex: if how.tex {
            o.tex_map
                .apply_point(crate::format::TexPoint::from_bits(p.x, p.y, p.z))
        } else {
            [0; 3]
        },
    };
    out.oc = view.outcodes(&out.cam.p);
    out.projected = None;
}

/// What a scene walk computes for each corner of a mesh quad besides its screen position.
trait CornerValue {
    /// The value (`()` for none).
    type Value: Copy;
    /// The value of corner `i` of the quad `corners` (object space) of object `o`.
    fn at(&self, o: &Object, corners: &[Vec3; 4], i: usize) -> Self::Value;
    /// The value of a vertex made by clipping: the mean of the input triangle's.
    fn mean(v: [Self::Value; 3]) -> Self::Value;
}

/// Nothing: the unlit walk.
impl CornerValue for () {
    type Value = ();
    #[inline(always)]
    fn at(&self, _: &Object, _: &[Vec3; 4], _: usize) {}
    #[inline(always)]
    fn mean(_: [(); 3]) {}
}

/// The quad corner index: what [`Scene::for_each_triangle_with_corners`] reports (`None` for a
/// vertex made by clipping).
struct CornerIndex;

impl CornerValue for CornerIndex {
    type Value = Option<u8>;
    #[inline(always)]
    fn at(&self, _: &Object, _: &[Vec3; 4], i: usize) -> Option<u8> {
        Some((i & 3) as u8)
    }
    #[inline(always)]
    fn mean(_: [Option<u8>; 3]) -> Option<u8> {
        None
    }
}

#[cfg(test)]
mod quad_group_tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    /// With every group kept, the walk by quad is exactly the plain walk (triangles, objects,
    /// order, counters); `keep` is asked once per quad, in order; declined quads leave out
    /// exactly their triangles. The walk with corners is the walk by quad, and a triangle with
    /// corners is its quad's half `[0, 1, 2]` or `[0, 2, 3]`, each vertex carrying its corner's
    /// solid coordinates; the built-in frames have triangles without corners exactly when their
    /// walk clips (the seascape's and moonrise's), so both kinds are checked.
    #[test]
    fn walk_by_quad_is_the_plain_walk() {
        let mut cornerless = 0;
        for name in BUILTIN {
            let s = by_name(name).unwrap();
            for frame in [0, s.still()] {
                let s = s.at_frame(frame);
                let mut plain = Vec::new();
                let cp = s.for_each_triangle_static(&mut |o, t| plain.push((o, *t)));
                let asked = core::cell::RefCell::new(Vec::new());
                let mut grouped = Vec::new();
                let cg = s.for_each_triangle_by_quad(
                    &mut |g| {
                        asked.borrow_mut().push(g);
                        true
                    },
                    &mut |g, o, t| {
                        // Right after its own question.
                        assert_eq!(asked.borrow().last(), Some(&g), "{name}");
                        grouped.push((g, o, *t));
                    },
                );
                let asked = asked.into_inner();
                assert_eq!(cg, cp, "{name} frame {frame}");
                let want: Vec<usize> = (0..s.quad_count()).collect();
                assert_eq!(asked, want, "{name} frame {frame}");
                let tris: Vec<_> = grouped.iter().map(|&(_, o, t)| (o, t)).collect();
                assert_eq!(tris, plain, "{name} frame {frame}");
                // Groups number the objects' quads one after the other.
                let mut starts = Vec::new();
                let mut start = 0;
                for (i, o) in s.objects.iter().enumerate() {
                    starts.push(start);
                    let end = start + o.mesh.quad_count() as usize;
                    assert!(grouped
                        .iter()
                        .filter(|&&(_, oi, _)| oi == i)
                        .all(|&(g, _, _)| (start..end).contains(&g)));
                    start = end;
                }
                // With corners: the same walk, each corner the quad's own.
                let mut with = Vec::new();
                let mut none = 0;
                let cw = s.for_each_triangle_with_corners(&mut |_| true, &mut |g, o, t, c| {
                    with.push((g, o, *t));
                    let Some(c) = c else {
                        none += 1;
                        return;
                    };
                    assert!(c == [0, 1, 2] || c == [0, 2, 3], "{name}: {c:?}");
                    let obj = &s.objects[o];
                    let quad = obj.mesh.quad((g - starts[o]) as u32).unwrap();
                    for (v, k) in t.iter().zip(c) {
                        let p = quad[usize::from(k)];
                        let solid = obj
                            .tex_map
                            .apply_point(crate::format::TexPoint::from_bits(p.x, p.y, p.z));
                        assert_eq!(v.tex.to_bits(), solid, "{name} group {g} corner {k}");
                    }
                });
                assert_eq!(cw, cg, "{name} frame {frame}");
                assert_eq!(with, grouped, "{name} frame {frame}");
                // Without texture coordinates: the same triangles and corners, `tex` zero.
                let mut screen = Vec::new();
                let mut corners_of = Vec::new();
                s.for_each_triangle_with_corners(&mut |_| true, &mut |_, _, _, c| {
                    corners_of.push(c)
                });
                let cs = s
                    .for_each_screen_triangle_with_corners(&mut |_| true, &mut |g, o, t, c| {
                        screen.push((g, o, *t, c))
                    });
                assert_eq!(cs, cw, "{name} frame {frame}");
                assert_eq!(screen.len(), with.len(), "{name} frame {frame}");
                for ((g, o, t, _), (wg, wo, wt)) in screen.iter().zip(&with) {
                    assert_eq!((g, o), (wg, wo), "{name} frame {frame}");
                    for (v, w) in t.iter().zip(wt) {
                        assert_eq!(v.tex.to_bits(), [0; 3], "{name} group {g}");
                        let mut w = *w;
                        w.tex = v.tex;
                        assert_eq!(*v, w, "{name} group {g}");
                    }
                }
                let sc: Vec<_> = screen.iter().map(|e| e.3).collect();
                assert_eq!(sc, corners_of, "{name} frame {frame}");
                assert_eq!(none > 0, cw.clipped > 0, "{name} frame {frame}: {cw:?}");
                cornerless += none;
                // Every third quad declined: the rest, in order.
                let mut asked = 0usize;
                let mut some = Vec::new();
                s.for_each_triangle_by_quad(
                    &mut |g| {
                        assert_eq!(g, asked);
                        asked += 1;
                        g % 3 != 1
                    },
                    &mut |g, o, t| some.push((g, o, *t)),
                );
                assert_eq!(asked, s.quad_count());
                let kept: Vec<_> = grouped.into_iter().filter(|t| t.0 % 3 != 1).collect();
                assert_eq!(some, kept, "{name} frame {frame}");
            }
        }
        assert!(cornerless > 0, "no built-in frame clips a triangle");
    }

    /// Without a valid view nothing is emitted and `keep` is never asked.
    #[test]
    fn no_view_asks_nothing() {
        let mut s = by_name("marble").unwrap();
        s.camera.width = 0;
        if s.camera.view().is_some() {
            return;
        }
        let (mut asked, mut emitted) = (0, 0);
        s.for_each_triangle_by_quad(
            &mut |_| {
                asked += 1;
                true
            },
            &mut |_, _, _| emitted += 1,
        );
        assert_eq!((asked, emitted), (0, 0));
    }
}
