//! Scenes: procedural meshes, cameras and clipping that turn the figures of Hart et al. (1999)
//! into screen triangles for the [rasterizer](crate::raster).
//!
//! Geometry only: a [`Scene`] says which triangles to draw, with which solid texture coordinates,
//! drawing options and texture slot; the renderer owns colours (materials are named by
//! [preset](crate::presets) name in each [`TextureSlot`]).
//!
//! Everything is integer arithmetic (`no_std`, no allocation, no floating point), so a scene
//! yields bit-identical triangles on the host, a Cortex-M4F and an rv32imc; nothing panics for any
//! input. Meshes are generated on the fly every frame (a few hundred bytes of stack).
//!
//! | module | contents |
//! |---|---|
//! | [`math`] | `Q16.16` vectors and affine transforms, angles in turns, sine/cosine, `isqrt` |
//! | [`camera`] | perspective/orthographic cameras, projection, near/far/guard-band clipping |
//! | [`mesh`] | teapot, sphere, torus, cube, quad and horizon plane as triangle iterators |
//! | [`teapot`] | the Utah teapot's 32 Bezier patches and exact tessellation |
//! | [`builtin`] | the paper's scenes (`wood`, `marble`, `seascape`, `fire`, `planet`, `moonrise`, `zoneplate`, `torus`) |
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
pub mod math;
pub mod mesh;
pub mod teapot;

pub use builtin::{by_name, BUILTIN};
pub use camera::{focal_from_fov, Camera, Projection, View};
pub use math::{Angle, Transform, Vec3};
pub use mesh::Mesh;

use crate::presets::Key;
use crate::raster::{CullMode, DepthFunc, Perspective, ScreenVertex, TriangleOptions};
use crate::transform::Affine3;
use camera::{CamVertex, ClipOutcome};

/// Most objects in a scene.
pub const MAX_OBJECTS: usize = 8;
/// Most texture slots in a scene.
pub const MAX_SLOTS: usize = 6;

/// How an object's pixels combine with the frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Blend {
    /// Replace.
    #[default]
    Opaque,
    /// Porter-Duff "over" with the colour table's alpha.
    Over,
}

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
    pub transform: Transform,
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
            transform: Transform::IDENTITY,
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
        self.tex_map = self.transform.to_affine3().then(world_map);
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
    /// Number of frames of the animation (at least 1).
    pub frames: u32,
    /// The frame that reproduces the paper's still figure.
    pub still: u32,
    /// Objects, drawn in this order.
    pub objects: heapless::Vec<Object, MAX_OBJECTS>,
    /// Texture slots referred to by [`Object::slot`].
    pub slots: heapless::Vec<TextureSlot, MAX_SLOTS>,
    /// The animation (`None`: static).
    pub animate: Option<AnimateFn>,
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
        }
    }

    /// Image size `(width, height)`.
    pub const fn size(&self) -> (u16, u16) {
        (self.camera.width, self.camera.height)
    }

    /// Adds an object (ignored when full); returns its index.
    pub fn add(&mut self, object: Object) -> usize {
        let _ = self.objects.push(object);
        self.objects.len().saturating_sub(1)
    }

    /// Adds a texture slot (ignored when full); returns its index.
    pub fn add_slot(&mut self, slot: TextureSlot) -> u8 {
        let _ = self.slots.push(slot);
        self.slots.len().saturating_sub(1) as u8
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

    /// [`Scene::for_each_triangle`] for the scene exactly as it is (no animation applied).
    pub fn for_each_triangle_static<F: FnMut(usize, &[ScreenVertex; 3])>(
        &self,
        f: &mut F,
    ) -> SceneCounters {
        let mut c = SceneCounters::default();
        let view = self.camera.view();
        for (index, o) in self.objects.iter().enumerate() {
            c.objects = c.objects.wrapping_add(1);
            for tri in o.mesh.triangles() {
                c.input = c.input.wrapping_add(1);
                let Some(view) = view.as_ref() else {
                    c.rejected = c.rejected.wrapping_add(1);
                    continue;
                };
                let cam = tri.map(|p| {
                    let tex = o
                        .tex_map
                        .apply_point(crate::format::TexPoint::from_bits(p.x, p.y, p.z));
                    CamVertex {
                        p: view.to_camera(o.transform.apply(p)),
                        tex,
                    }
                });
                let mut emit = |t: &[ScreenVertex; 3]| {
                    c.generated = c.generated.wrapping_add(1);
                    f(index, t);
                };
                let outcome = view.clip_project(&cam, &mut emit);
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
        c
    }
}
