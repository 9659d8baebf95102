//! Validation of a parsed scene file and its conversion to fixed point, once, at load.
//!
//! Every number is range-checked here and converted to its texcore format (`Q16.16` raw values,
//! angles in `2^-32` turn); nothing is converted again per frame. Animated values are kept as
//! `i64` raw values so that the animation interpolates integers.

use std::collections::BTreeMap;
use std::ops::Range;

use texcore::format::{Amplitude, MatrixEntry, QuadricCoeff};
use texcore::hash::HashKind;
use texcore::noise::{BasisKind, Fade};
use texcore::presets::Key;
use texcore::quadric::Quadric;
use texcore::raster::{CullMode, Perspective};
use texcore::scene::{Blend, Mesh, MAX_OBJECTS, MAX_SLOTS};
use texcore::table::TableWrap;
use texcore::transform::Affine3;
use toml::Value;

use super::limits::NAME_MAX;
use super::schema::*;

mod fx;
mod material;
mod objects;
mod tracks;
mod values;

pub(crate) use fx::*;
use material::*;
use objects::*;
use tracks::*;
pub(crate) use values::*;
pub use values::{AMPLITUDE_MAX, COORD_MAX, DEGREES_MAX, FRAMES_MAX, SIZE_MAX, TERMS_MAX};

fn leak(s: &str) -> &'static str {
    Box::leak(s.to_string().into_boxed_str())
}

// ---------------------------------------------------------------------------------------------
// Conversion.

pub(crate) fn convert(file: &FileDef, default_name: &str, base: &std::path::Path) -> R<SceneDef> {
    let name = match &file.name {
        Some(n) => {
            if n.get_ref().is_empty() {
                return fail(n.span(), "name", "the scene name is empty");
            }
            if n.get_ref().len() > NAME_MAX {
                return fail(
                    n.span(),
                    "name",
                    format!(
                        "a scene name of {} bytes is too long (names are at most {NAME_MAX} bytes)",
                        n.get_ref().len()
                    ),
                );
            }
            leak(n.get_ref())
        }
        None => leak(default_name),
    };
    let width = match &file.width {
        Some(w) => int(w, "width", 1, SIZE_MAX, "width")?,
        None => 320,
    } as u16;
    let height = match &file.height {
        Some(h) => int(h, "height", 1, SIZE_MAX, "height")?,
        None => 240,
    } as u16;
    let background = match &file.background {
        Some(b) => colour(b, "background")?,
        None => [0, 0, 0, 255],
    };
    let frames = match &file.frames {
        Some(f) => int(f, "frames", 1, FRAMES_MAX, "frames")?,
        None => 1,
    } as u32;
    let still = match &file.still {
        Some(s) => int(s, "still", 0, i64::from(frames) - 1, "still")?,
        None => 0,
    } as u32;
    let camera = camera(&file.camera)?;

    // Materials: every one is validated; those used by objects get slots in order of first use.
    let mut defined: BTreeMap<&str, MaterialFx> = BTreeMap::new();
    for (mname, m) in &file.materials {
        let field = format!("materials.{mname}");
        check_name(mname, m.span(), &field)?;
        defined.insert(mname.as_str(), material(mname, m, &field)?);
    }
    let mut used: Vec<&str> = Vec::new();
    let mut objects = Vec::new();
    if file.objects.len() > MAX_OBJECTS {
        let o = &file.objects[MAX_OBJECTS];
        return fail(
            o.span(),
            format!("objects[{MAX_OBJECTS}]"),
            format!("a scene has at most {MAX_OBJECTS} objects"),
        );
    }
    let mut names: BTreeMap<String, usize> = BTreeMap::new();
    for (i, o) in file.objects.iter().enumerate() {
        let field = format!("objects[{i}]");
        let od = o.get_ref();
        let mat_name: &str = match &od.material {
            Some(m) => {
                if !defined.contains_key(m.get_ref().as_str()) {
                    let known: Vec<&str> = defined.keys().copied().collect();
                    return fail(
                        m.span(),
                        format!("{field}.material"),
                        format!(
                            "no material `{}` (defined: {})",
                            m.get_ref(),
                            if known.is_empty() {
                                "none".to_string()
                            } else {
                                known.join(", ")
                            }
                        ),
                    );
                }
                m.get_ref()
            }
            None if defined.len() == 1 => defined.keys().next().copied().unwrap_or(""),
            None => {
                return fail(
                    o.span(),
                    format!("{field}.material"),
                    if defined.is_empty() {
                        "no materials are defined (add a [materials.NAME] table)"
                    } else {
                        "missing: name one of the materials (it may be left out only when there is exactly one)"
                    },
                )
            }
        };
        let slot = match used.iter().position(|u| *u == mat_name) {
            Some(k) => k,
            None => {
                if used.len() == MAX_SLOTS {
                    let span = od.material.as_ref().map_or(o.span(), |m| m.span());
                    return fail(
                        span,
                        format!("{field}.material"),
                        format!("the objects use more than {MAX_SLOTS} materials"),
                    );
                }
                used.push(mat_name);
                used.len() - 1
            }
        };
        if let Some(n) = &od.name {
            check_name(n.get_ref(), n.span(), &format!("{field}.name"))?;
            if names.insert(n.get_ref().clone(), i).is_some() {
                return fail(
                    n.span(),
                    format!("{field}.name"),
                    format!("another object is already named `{}`", n.get_ref()),
                );
            }
        }
        objects.push(object(o, &field, slot as u8, base)?);
    }
    let materials: Vec<MaterialFx> = used
        .iter()
        .filter_map(|u| defined.get(u).cloned())
        .collect();

    let mut def = SceneDef {
        name,
        width,
        height,
        background,
        frames,
        still,
        camera,
        camera_span: file.camera.span(),
        materials,
        objects,
        tracks: Vec::new(),
        lighting: super::lights::lighting(file.lighting.as_ref(), &file.lights)?,
    };
    for (i, t) in file.animate.iter().enumerate() {
        let tr = track(t, &format!("animate[{i}]"), &def, &names, &used, &defined)?;
        def.tracks.push(tr);
    }
    Ok(def)
}

fn camera(c: &S<CameraDef>) -> R<CameraFx> {
    let d = c.get_ref();
    let eye = coord3(&d.eye, "camera.eye")?;
    let target = match &d.target {
        Some(t) => coord3(t, "camera.target")?,
        None => [0; 3],
    };
    let up = match &d.up {
        Some(u) => {
            let v = coord3(u, "camera.up")?;
            if v == [0; 3] {
                return fail(u.span(), "camera.up", "the up vector is zero");
            }
            v
        }
        None => [0, 65536, 0],
    };
    if eye == target {
        let span = d.target.as_ref().map_or(d.eye.span(), |t| t.span());
        return fail(
            span,
            "camera.target",
            "the camera looks at its own eye (target == eye)",
        );
    }
    let near = match &d.near {
        // The smallest positive 16.16 step; anything smaller rounds to zero.
        Some(n) => real(
            n,
            "camera.near",
            |x| q16(x) >= 1 && x < COORD_MAX,
            "1/65536 = 0.0000153 <= near < 32767",
        )?,
        None => 0.1,
    };
    let far = match &d.far {
        Some(f) => real(
            f,
            "camera.far",
            |x| x > 0.0 && x <= COORD_MAX,
            "0 < far <= 32767",
        )?,
        None => 1000.0,
    };
    let (near_q, far_q) = (q16(near), q16(far));
    if near_q < 1 || far_q <= near_q {
        let span = d
            .far
            .as_ref()
            .or(d.near.as_ref())
            .map_or(c.span(), |s| s.span());
        return fail(
            span,
            if d.far.is_some() {
                "camera.far"
            } else {
                "camera.near"
            },
            format!(
                "far ({}) must be beyond near ({})",
                number(far),
                number(near)
            ),
        );
    }
    let projection = match d.projection.as_ref().map(|p| *p.get_ref()) {
        None | Some(ProjectionDef::Perspective) => {
            if let Some(h) = &d.half_height {
                return fail(
                    h.span(),
                    "camera.half_height",
                    "only an orthographic camera has a half height (set projection = \"orthographic\")",
                );
            }
            let fov = match &d.fov {
                Some(f) => real(
                    f,
                    "camera.fov",
                    |x| x > 0.0 && x < 180.0,
                    "0 < fov < 180 degrees",
                )?,
                None => 40.0,
            };
            ProjFx::Perspective {
                fov: angle_units(fov),
            }
        }
        Some(ProjectionDef::Orthographic) => {
            if let Some(f) = &d.fov {
                return fail(
                    f.span(),
                    "camera.fov",
                    "an orthographic camera has no field of view (give half_height)",
                );
            }
            let Some(h) = &d.half_height else {
                return fail(
                    c.span(),
                    "camera.half_height",
                    "missing: an orthographic camera needs half_height",
                );
            };
            let hh = real(
                h,
                "camera.half_height",
                |x| x > 0.0 && x <= COORD_MAX,
                "0 < half_height <= 32767",
            )?;
            if q16(hh) < 1 {
                return fail(
                    h.span(),
                    "camera.half_height",
                    format!("{} is out of range (0 < half_height <= 32767)", number(hh)),
                );
            }
            ProjFx::Orthographic {
                half_height: q16(hh),
            }
        }
    };
    Ok(CameraFx {
        eye,
        target,
        up,
        projection,
        near: near_q as i32,
        far: far_q as i32,
    })
}
