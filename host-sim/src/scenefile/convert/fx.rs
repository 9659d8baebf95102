//! The validated scene in fixed point ([`SceneDef`]): what the conversion makes once, at load,
//! and the scene builder reads every frame (animatable values kept as raw `i64`).

use super::*;

/// The camera's projection, animatable values raw.
#[derive(Clone, Copy, Debug)]
pub(crate) enum ProjFx {
    /// Vertical field of view in angle units (`2^32` per turn).
    Perspective { fov: i64 },
    /// Half view height, raw `Q16.16`.
    Orthographic { half_height: i64 },
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct CameraFx {
    pub eye: [i64; 3],
    pub target: [i64; 3],
    pub up: [i64; 3],
    pub projection: ProjFx,
    pub near: i32,
    pub far: i32,
}

/// One noise term or a sum of octaves of a custom model.
#[derive(Clone, Copy, Debug)]
pub(crate) enum TermFx {
    Noise {
        amplitude: Amplitude,
        transform: Affine3,
        kind: BasisKind,
        fade: Fade,
        hash: Option<HashKind>,
        turbulence: bool,
    },
    Octaves {
        count: u8,
        amplitude: Amplitude,
        base: Affine3,
        rotate: bool,
        kind: BasisKind,
        fade: Fade,
        hash: Option<HashKind>,
        turbulence: bool,
    },
}

#[derive(Clone, Debug)]
pub(crate) struct MaterialFx {
    pub name: &'static str,
    pub preset: Option<&'static str>,
    pub keys: Option<&'static [Key]>,
    pub squared_keys: Option<bool>,
    pub wrap: Option<TableWrap>,
    pub quadric: Option<Quadric>,
    pub terms: Option<Vec<TermFx>>,
    pub hash: Option<HashKind>,
    /// Factor on every noise amplitude, raw `Q16.16`.
    pub amplitude: i64,
    /// Phase, raw `Q16.16`.
    pub phase: i64,
    /// Direction the phase moves the pattern, raw `Q16.16`.
    pub phase_direction: [i32; 3],
    pub span: Range<usize>,
    pub amplitude_span: Option<Range<usize>>,
}

#[derive(Clone, Debug)]
pub(crate) struct ObjectFx {
    pub mesh: Mesh,
    pub position: [i64; 3],
    /// Angle units per axis.
    pub rotation: [i64; 3],
    pub scale: [i64; 3],
    pub pivot: [i64; 3],
    pub world_texture: bool,
    pub tex_matrix: [[i64; 3]; 3],
    pub tex_translate: [i64; 3],
    pub slot: u8,
    pub blend: Blend,
    pub perspective: Perspective,
    pub cull: CullMode,
    pub depth_test: bool,
    pub depth_write: bool,
    /// `Some`: drawn from a baked atlas.
    pub shading: Option<crate::atlas::shading::AtlasShading>,
}

/// What an animation track drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Target {
    Eye,
    LookAt,
    Fov,
    HalfHeight,
    Position(usize),
    Rotation(usize),
    Scale(usize),
    TexTranslate(usize),
    Phase(usize),
    Amplitude(usize),
}

#[derive(Clone, Debug)]
pub(crate) struct Track {
    pub target: Target,
    pub from: [i64; 3],
    pub to: [i64; 3],
    pub start: u32,
    pub end: u32,
    pub looped: bool,
    pub span: Range<usize>,
    pub field: String,
}

/// A validated scene file, in fixed point.
#[derive(Clone, Debug)]
pub(crate) struct SceneDef {
    pub name: &'static str,
    pub width: u16,
    pub height: u16,
    pub background: [u8; 4],
    pub frames: u32,
    pub still: u32,
    pub camera: CameraFx,
    pub camera_span: Range<usize>,
    /// The materials used by objects, in slot order.
    pub materials: Vec<MaterialFx>,
    pub objects: Vec<ObjectFx>,
    pub tracks: Vec<Track>,
    /// The lights (`[lighting]`, `[[lights]]`; none: unlit).
    pub lighting: texcore::light::Lighting<{ texcore::scene::MAX_LIGHTS }>,
}
