//! Frames of a converted scene file: the animation tracks applied (integer interpolation), then
//! texcore's [`Scene`] and the host [`MaterialSpec`]s of its slots.

use texcore::format::{Amplitude, MatrixEntry};
use texcore::hash::HashKind;
use texcore::model::{NoiseTerm, Octaves, TextureModel};
use texcore::noise::NoiseBasis;
use texcore::presets::{PRESET_TERMS, UNIT_PLANE};
use texcore::quadric::Quadric;
use texcore::scene::{focal_from_fov, Angle, Camera, Object, Scene, TextureSlot, Vec3};
use texcore::table::TableWrap;
use texcore::transform::Affine3;

use super::convert::{to_affine, MaterialFx, ObjectFx, ProjFx, SceneDef, Target, TermFx, Track};
use crate::unit::{self, MaterialSpec, ShaderSpec, UnitError};

/// `round(n / d)` for `d > 0`, ties up.
fn div_round(n: i128, d: i128) -> i128 {
    (2 * n + d).div_euclid(2 * d)
}

impl Track {
    /// The track's value at `frame`: `from` before `start`, `to` from `end` on (or, looping, the
    /// value one step short of `to` at `end`), linear in between, rounded to nearest.
    pub(crate) fn value(&self, frame: u32) -> [i64; 3] {
        let f = frame.clamp(self.start, self.end);
        let num = i128::from(f - self.start);
        let den = i128::from(self.end - self.start) + i128::from(self.looped);
        [0, 1, 2].map(|k| {
            let (a, b) = (i128::from(self.from[k]), i128::from(self.to[k]));
            (a + div_round((b - a) * num, den)) as i64
        })
    }
}

fn sat(v: i64) -> i32 {
    v.clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32
}

fn vec3(v: [i64; 3]) -> Vec3 {
    Vec3::new(sat(v[0]), sat(v[1]), sat(v[2]))
}

fn angle(units: i64) -> Angle {
    Angle(units.rem_euclid(1 << 32) as u32)
}

impl SceneDef {
    /// The definition with every track applied for `frame`.
    pub(crate) fn at(&self, frame: u32) -> SceneDef {
        let mut d = self.clone();
        for t in &self.tracks {
            let v = t.value(frame);
            match t.target {
                Target::Eye => d.camera.eye = v,
                Target::LookAt => d.camera.target = v,
                Target::Fov => d.camera.projection = ProjFx::Perspective { fov: v[0] },
                Target::HalfHeight => {
                    d.camera.projection = ProjFx::Orthographic { half_height: v[0] }
                }
                Target::Position(i) => d.objects[i].position = v,
                Target::Rotation(i) => d.objects[i].rotation = v,
                Target::Scale(i) => d.objects[i].scale = v,
                Target::TexTranslate(i) => d.objects[i].tex_translate = v,
                Target::Phase(k) => d.materials[k].phase = v[0],
                Target::Amplitude(k) => d.materials[k].amplitude = v[0],
            }
        }
        d
    }

    /// The camera.
    pub(crate) fn camera(&self) -> Camera {
        let c = &self.camera;
        match c.projection {
            ProjFx::Perspective { fov } => Camera::perspective(
                vec3(c.eye),
                vec3(c.target),
                vec3(c.up),
                focal_from_fov(angle(fov)),
                c.near,
                c.far,
                self.width,
                self.height,
            ),
            ProjFx::Orthographic { half_height } => Camera::orthographic(
                vec3(c.eye),
                vec3(c.target),
                vec3(c.up),
                sat(half_height),
                c.near,
                c.far,
                self.width,
                self.height,
            ),
        }
    }

    /// texcore's scene (geometry and slots) as defined.
    pub(crate) fn scene(&self) -> Scene {
        let mut s = Scene::new(self.name, self.camera());
        s.background = self.background;
        // The scene file's loader checked `frames >= 1` and `still < frames` with their
        // locations; this cannot fail for a loaded definition.
        let _ = s.set_frames(self.frames, self.still);
        for m in &self.materials {
            let _ = s.slots.push(TextureSlot {
                material: m.preset.unwrap_or(m.name),
                amplitude: sat(m.amplitude),
                phase: sat(m.phase),
                keys: m.keys,
            });
        }
        for o in &self.objects {
            let _ = s.objects.push(o.object());
        }
        s.set_lighting(self.lighting.clone());
        s
    }

    /// The materials of the slots, with the lattice hash for those that do not name one; on
    /// failure, the slot index and the error.
    pub(crate) fn materials(
        &self,
        hash: HashKind,
    ) -> Result<Vec<MaterialSpec>, (usize, UnitError)> {
        self.materials
            .iter()
            .enumerate()
            .map(|(k, m)| m.spec(hash).map_err(|e| (k, e)))
            .collect()
    }
}

impl ObjectFx {
    /// Object to world: `p -> position + Rz Ry Rx S (p - pivot)`.
    pub(crate) fn transform(&self) -> Affine3 {
        let p = |v: [i64; 3]| vec3(v);
        Affine3::translate(p(self.pivot.map(|x| -x)))
            .then(&Affine3::scale3(
                MatrixEntry::from_bits(sat(self.scale[0])),
                MatrixEntry::from_bits(sat(self.scale[1])),
                MatrixEntry::from_bits(sat(self.scale[2])),
            ))
            .then(&Affine3::rotate_x(angle(self.rotation[0])))
            .then(&Affine3::rotate_y(angle(self.rotation[1])))
            .then(&Affine3::rotate_z(angle(self.rotation[2])))
            .then(&Affine3::translate(p(self.position)))
    }

    pub(crate) fn object(&self) -> Object {
        let mut o = Object::new(self.mesh);
        o.transform = self.transform();
        let map = to_affine(&self.tex_matrix, &self.tex_translate);
        o = if self.world_texture {
            o.with_world_texture(&map)
        } else {
            o.tex_map = map;
            o
        };
        o.slot = self.slot;
        o.blend = self.blend;
        o.perspective = self.perspective;
        o.cull = self.cull;
        o.depth_test = self.depth_test;
        o.depth_write = self.depth_write;
        o
    }
}

impl TermFx {
    fn push(&self, m: &mut TextureModel<PRESET_TERMS>, hash: HashKind) -> Result<(), UnitError> {
        match *self {
            TermFx::Noise {
                amplitude,
                transform,
                kind,
                fade,
                hash: h,
                turbulence,
            } => m.push(NoiseTerm {
                amplitude,
                transform,
                basis: NoiseBasis {
                    kind,
                    fade,
                    hash: h.unwrap_or(hash),
                },
                turbulence,
            }),
            TermFx::Octaves {
                count,
                amplitude,
                base,
                rotate,
                kind,
                fade,
                hash: h,
                turbulence,
            } => m.push_octaves(&Octaves {
                count,
                base,
                amplitude,
                rotate,
                basis: NoiseBasis {
                    kind,
                    fade,
                    hash: h.unwrap_or(hash),
                },
                turbulence,
            }),
        }
        .map_err(UnitError::Model)
    }
}

/// Moves a model's noise by `-phase * direction` in solid texture space: each term's lattice
/// translation becomes `t - M d` with `d = phase * direction` (floored products, as
/// [`texcore::presets::set_fire_phase`], which this equals for the fire preset).
fn apply_phase(model: &mut TextureModel<PRESET_TERMS>, phase: i64, dir: [i32; 3]) {
    if phase == 0 {
        return;
    }
    let d = dir.map(|k| (i128::from(k) * i128::from(phase)) >> 16);
    for k in 0..model.terms().len() {
        let tr = model.terms()[k].transform;
        let (m, t) = (tr.matrix(), tr.translation());
        let new = [0, 1, 2].map(|i| {
            let acc: i128 = (0..3).map(|j| i128::from(m[i][j].to_bits()) * d[j]).sum();
            let v = i128::from(t[i].to_bits()) - (acc >> 16);
            MatrixEntry::from_bits(v.clamp(i128::from(i32::MIN), i128::from(i32::MAX)) as i32)
        });
        let _ = model.set_translation(k, new);
    }
}

impl MaterialFx {
    /// The host material at the current parameters.
    pub(crate) fn spec(&self, hash: HashKind) -> Result<MaterialSpec, UnitError> {
        let hash = self.hash.unwrap_or(hash);
        let mut spec = match self.preset {
            Some(p) => unit::preset_material(p, hash)?,
            None => MaterialSpec {
                name: self.name.to_string(),
                shader: ShaderSpec::Model(Box::new(TextureModel::new(
                    Quadric::ZERO,
                    TableWrap::Clamp,
                ))),
                keys: Vec::new(),
                squared_keys: false,
                wrap: TableWrap::Clamp,
                plane: UNIT_PLANE,
            },
        };
        spec.name = self.name.to_string();
        if let Some(w) = self.wrap {
            spec.wrap = w;
        }
        if let Some(keys) = self.keys {
            spec.keys = keys.to_vec();
        }
        if let Some(sq) = self.squared_keys {
            spec.squared_keys = sq;
        }
        let factor = self.amplitude;
        let scale = |a: Amplitude| -> Amplitude {
            Amplitude::from_bits(
                ((i64::from(a.to_bits()) * factor) >> 16).clamp(i32::MIN.into(), i32::MAX.into())
                    as i32,
            )
        };
        match &mut spec.shader {
            ShaderSpec::Model(model) => {
                if self.quadric.is_some() || self.wrap.is_some() || self.terms.is_some() {
                    let mut m =
                        TextureModel::new(self.quadric.unwrap_or(*model.quadric()), spec.wrap);
                    match &self.terms {
                        Some(ts) => {
                            for t in ts {
                                t.push(&mut m, hash)?;
                            }
                        }
                        None => {
                            for t in model.terms() {
                                m.push(*t).map_err(UnitError::Model)?;
                            }
                        }
                    }
                    **model = m;
                }
                // As the built-in scenes' slots: the amplitude factor, then the phase.
                if factor != 1 << 16 {
                    for k in 0..model.terms().len() {
                        let a = scale(model.terms()[k].amplitude);
                        model.set_amplitude(k, a).map_err(UnitError::Model)?;
                    }
                }
                apply_phase(model, self.phase, self.phase_direction);
            }
            ShaderSpec::Perturbed(p) => {
                for a in &mut p.alpha {
                    *a = scale(*a);
                }
            }
        }
        Ok(spec)
    }
}
