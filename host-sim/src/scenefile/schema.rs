//! The scene file as TOML: serde structures, every field spanned so that semantic errors can
//! name the line and column they come from. Unknown fields are errors everywhere.
//!
//! Integers that have a documented range are read as `i64` and checked by [`super::convert`], so
//! that every range error reads the same way; numbers are read as `f64` (TOML integers are
//! accepted wherever a number is) and converted to fixed point once, there.

use std::collections::BTreeMap;

use serde::de::{self, MapAccess, Visitor};
use serde::Deserialize;
use toml::{Spanned, Value};

/// A value with its byte span in the file.
pub type S<T> = Spanned<T>;

/// A colour key: `[position, "#rrggbbaa"]`.
pub type KeyDef = S<(S<f64>, S<String>)>;
/// Matrix rows.
pub type Rows = S<Vec<Vec<f64>>>;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FileDef {
    pub name: Option<S<String>>,
    pub width: Option<S<i64>>,
    pub height: Option<S<i64>>,
    pub background: Option<S<String>>,
    pub frames: Option<S<i64>>,
    pub still: Option<S<i64>>,
    pub camera: S<CameraDef>,
    #[serde(default)]
    pub materials: BTreeMap<String, S<MaterialDef>>,
    #[serde(default)]
    pub objects: Vec<S<ObjectDef>>,
    #[serde(default)]
    pub animate: Vec<S<TrackDef>>,
    pub lighting: Option<S<super::lights::LightingDef>>,
    #[serde(default)]
    pub lights: Vec<S<super::lights::LightDef>>,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ProjectionDef {
    Perspective,
    Orthographic,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDef {
    pub projection: Option<S<ProjectionDef>>,
    pub eye: S<[f64; 3]>,
    pub target: Option<S<[f64; 3]>>,
    pub up: Option<S<[f64; 3]>>,
    pub fov: Option<S<f64>>,
    pub half_height: Option<S<f64>>,
    pub near: Option<S<f64>>,
    pub far: Option<S<f64>>,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum WrapDef {
    Mod,
    Clamp,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SpacingDef {
    Linear,
    Squared,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum HashDef {
    Perm,
    Int,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum BasisDef {
    Value,
    Gradient,
    Mnoise,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum FadeDef {
    Linear,
    Smooth,
    Quintic,
}

/// A material (texture slot).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialDef {
    pub preset: Option<S<String>>,
    pub amplitude: Option<S<f64>>,
    pub phase: Option<S<f64>>,
    pub phase_direction: Option<S<[f64; 3]>>,
    pub keys: Option<S<Vec<KeyDef>>>,
    pub key_spacing: Option<S<SpacingDef>>,
    pub wrap: Option<S<WrapDef>>,
    pub quadric: Option<S<Vec<f64>>>,
    pub hash: Option<S<HashDef>>,
    pub noise: Option<Vec<S<NoiseDef>>>,
    pub octaves: Option<Vec<S<OctavesDef>>>,
}

/// One noise term.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseDef {
    pub amplitude: Option<S<f64>>,
    pub scale: Option<S<Value>>,
    pub matrix: Option<S<Vec<Vec<f64>>>>,
    pub translate: Option<S<[f64; 3]>>,
    pub basis: Option<S<BasisDef>>,
    pub fade: Option<S<FadeDef>>,
    pub hash: Option<S<HashDef>>,
    pub turbulence: Option<S<bool>>,
}

/// A sum of octaves.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OctavesDef {
    pub count: S<i64>,
    pub amplitude: Option<S<f64>>,
    pub frequency: Option<S<Value>>,
    pub matrix: Option<S<Vec<Vec<f64>>>>,
    pub translate: Option<S<[f64; 3]>>,
    pub rotate: Option<S<bool>>,
    pub basis: Option<S<BasisDef>>,
    pub fade: Option<S<FadeDef>>,
    pub hash: Option<S<HashDef>>,
    pub turbulence: Option<S<bool>>,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum BlendDef {
    Opaque,
    Over,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum PerspectiveDef {
    Exact,
    Every8,
    Every16,
    Affine,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum CullDef {
    None,
    Cw,
    Ccw,
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SpaceDef {
    Object,
    World,
}

/// An object.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDef {
    pub name: Option<S<String>>,
    pub mesh: S<MeshDef>,
    pub material: Option<S<String>>,
    pub position: Option<S<[f64; 3]>>,
    pub rotation: Option<S<[f64; 3]>>,
    pub scale: Option<S<Value>>,
    pub pivot: Option<S<[f64; 3]>>,
    pub texture: Option<S<TextureDef>>,
    pub blend: Option<S<BlendDef>>,
    pub perspective: Option<S<PerspectiveDef>>,
    pub cull: Option<S<CullDef>>,
    pub depth_test: Option<S<bool>>,
    pub depth_write: Option<S<bool>>,
    pub shading: Option<S<crate::atlas::shading::ShadingDef>>,
    pub atlas: Option<S<crate::atlas::shading::AtlasDef>>,
}

/// The texture mapping of an object.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDef {
    pub space: Option<S<SpaceDef>>,
    pub scale: Option<S<Value>>,
    pub matrix: Option<S<Vec<Vec<f64>>>>,
    pub translate: Option<S<[f64; 3]>>,
}

/// A mesh: `"cube"` (all defaults), a table `{ kind = "sphere", radius = 2 }`, or a mesh file
/// `{ file = "bunny.obj" }` (OBJ or PLY, relative to the scene file).
#[derive(Debug, Default)]
pub struct MeshDef {
    pub kind: Option<S<String>>,
    pub file: Option<S<String>>,
    pub level: Option<S<i64>>,
    pub radius: Option<S<f64>>,
    pub stacks: Option<S<i64>>,
    pub slices: Option<S<i64>>,
    pub major: Option<S<f64>>,
    pub minor: Option<S<f64>>,
    pub major_segments: Option<S<i64>>,
    pub minor_segments: Option<S<i64>>,
    pub half: Option<S<f64>>,
    pub divisions: Option<S<i64>>,
    pub corners: Option<S<Vec<[f64; 3]>>>,
    pub half_size: Option<S<f64>>,
    pub rings: Option<S<i64>>,
}

/// The table form of [`MeshDef`].
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshTable {
    kind: Option<S<String>>,
    file: Option<S<String>>,
    level: Option<S<i64>>,
    radius: Option<S<f64>>,
    stacks: Option<S<i64>>,
    slices: Option<S<i64>>,
    major: Option<S<f64>>,
    minor: Option<S<f64>>,
    major_segments: Option<S<i64>>,
    minor_segments: Option<S<i64>>,
    half: Option<S<f64>>,
    divisions: Option<S<i64>>,
    corners: Option<S<Vec<[f64; 3]>>>,
    half_size: Option<S<f64>>,
    rings: Option<S<i64>>,
}

impl<'de> Deserialize<'de> for MeshDef {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = MeshDef;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a mesh kind (\"teapot\", \"sphere\", ...) or a table with `kind`")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<MeshDef, E> {
                // The span is filled in from the enclosing field by the converter.
                Ok(MeshDef {
                    kind: Some(Spanned::new(0..0, v.to_string())),
                    ..MeshDef::default()
                })
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<MeshDef, A::Error> {
                let t = MeshTable::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(MeshDef {
                    kind: t.kind,
                    file: t.file,
                    level: t.level,
                    radius: t.radius,
                    stacks: t.stacks,
                    slices: t.slices,
                    major: t.major,
                    minor: t.minor,
                    major_segments: t.major_segments,
                    minor_segments: t.minor_segments,
                    half: t.half,
                    divisions: t.divisions,
                    corners: t.corners,
                    half_size: t.half_size,
                    rings: t.rings,
                })
            }
        }
        d.deserialize_any(V)
    }
}

/// An animation track.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackDef {
    pub param: S<String>,
    pub from: S<Value>,
    pub to: S<Value>,
    pub start: Option<S<i64>>,
    pub end: Option<S<i64>>,
    #[serde(rename = "loop")]
    pub looped: Option<S<bool>>,
}
