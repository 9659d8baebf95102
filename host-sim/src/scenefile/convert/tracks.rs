//! Animation tracks: which parameter a track drives, its values range-checked as that parameter's
//! own, and its frames.

use super::*;

/// How a parameter's values are read: `(vector?, converter)`.
#[derive(Clone, Copy)]
pub(super) enum Kind {
    /// Three world coordinates.
    Coord3,
    /// Three angles in degrees.
    Degrees3,
    /// A scale: a number or three.
    Scale3,
    /// A field of view in degrees.
    Fov,
    /// A positive length.
    Length,
    /// A `Q16.16` real in `±32767`.
    Real,
    /// An amplitude factor.
    AmplitudeFactor,
}

pub(super) const PARAMS: &str = "camera.eye, camera.target, camera.fov, camera.half_height, \
objects.OBJECT.position, objects.OBJECT.rotation, objects.OBJECT.scale, \
objects.OBJECT.texture.translate, materials.MATERIAL.phase, materials.MATERIAL.amplitude";

pub(super) fn track_value(v: &S<Value>, field: &str, kind: Kind) -> R<[i64; 3]> {
    let vec3 = |v: &S<Value>| -> R<[f64; 3]> {
        if !matches!(v.get_ref(), Value::Array(_)) {
            return fail(
                v.span(),
                field,
                format!(
                    "expected an array of 3 numbers, found {}",
                    describe(v.get_ref())
                ),
            );
        }
        num_or_vec3(v, field)
    };
    let scalar = |v: &S<Value>| -> R<f64> {
        match v.get_ref() {
            Value::Integer(i) => Ok(*i as f64),
            Value::Float(f) => Ok(*f),
            x => fail(
                v.span(),
                field,
                format!("expected a number, found {}", describe(x)),
            ),
        }
    };
    let check = |x: f64, ok: bool, range: &str| -> R<()> {
        if !x.is_finite() || !ok {
            return fail(
                v.span(),
                field,
                format!("{} is out of range ({range})", number(x)),
            );
        }
        Ok(())
    };
    Ok(match kind {
        Kind::Coord3 => {
            let a = vec3(v)?;
            for x in a {
                check(x, coord_ok(x), COORD_RANGE)?;
            }
            a.map(q16)
        }
        Kind::Degrees3 => {
            let a = vec3(v)?;
            for x in a {
                check(x, x.abs() <= DEGREES_MAX, "|degrees| <= 360000")?;
            }
            a.map(angle_units)
        }
        Kind::Scale3 => {
            let a = reals3(
                v,
                field,
                |x| x != 0.0 && coord_ok(x),
                "0 < |scale| <= 32767",
            )?;
            let q = a.map(q16);
            if q.contains(&0) {
                return fail(v.span(), field, "the scale rounds to zero");
            }
            q
        }
        Kind::Fov => {
            let x = scalar(v)?;
            check(x, x > 0.0 && x < 180.0, "0 < fov < 180 degrees")?;
            [angle_units(x); 3]
        }
        Kind::Length => {
            let x = scalar(v)?;
            check(
                x,
                x > 0.0 && x <= COORD_MAX && q16(x) >= 1,
                "0 < half_height <= 32767",
            )?;
            [q16(x); 3]
        }
        Kind::Real => {
            let x = scalar(v)?;
            check(x, coord_ok(x), COORD_RANGE)?;
            [q16(x); 3]
        }
        Kind::AmplitudeFactor => {
            let x = scalar(v)?;
            check(x, x.abs() <= AMPLITUDE_MAX, "|amplitude| <= 512")?;
            [q16(x); 3]
        }
    })
}

pub(super) fn track(
    t: &S<TrackDef>,
    field: &str,
    def: &SceneDef,
    names: &BTreeMap<String, usize>,
    used: &[&str],
    defined: &BTreeMap<&str, MaterialFx>,
) -> R<Track> {
    let d = t.get_ref();
    let pf = format!("{field}.param");
    if def.frames < 2 {
        return fail(
            t.span(),
            field,
            "a scene with one frame cannot be animated (set `frames`)",
        );
    }
    let p = d.param.get_ref().as_str();
    let parts: Vec<&str> = p.split('.').collect();
    let unknown = || -> R<Track> {
        fail(
            d.param.span(),
            pf.clone(),
            format!("`{p}` is not an animatable parameter (one of: {PARAMS})"),
        )
    };
    let (target, kind) = match parts.as_slice() {
        ["camera", "eye"] => (Target::Eye, Kind::Coord3),
        ["camera", "target"] => (Target::LookAt, Kind::Coord3),
        ["camera", "fov"] => {
            if !matches!(def.camera.projection, ProjFx::Perspective { .. }) {
                return fail(
                    d.param.span(),
                    pf,
                    "the camera is orthographic: it has no fov",
                );
            }
            (Target::Fov, Kind::Fov)
        }
        ["camera", "half_height"] => {
            if !matches!(def.camera.projection, ProjFx::Orthographic { .. }) {
                return fail(
                    d.param.span(),
                    pf,
                    "the camera is perspective: it has no half_height",
                );
            }
            (Target::HalfHeight, Kind::Length)
        }
        ["objects", obj, rest @ ..] => {
            let index = match names.get(*obj) {
                Some(i) => *i,
                None => match obj.parse::<usize>() {
                    Ok(i) if i < def.objects.len() => i,
                    _ => {
                        return fail(
                            d.param.span(),
                            pf,
                            format!(
                                "no object `{obj}` (objects are named by `name` or by index 0..{})",
                                def.objects.len()
                            ),
                        )
                    }
                },
            };
            match rest {
                ["position"] => (Target::Position(index), Kind::Coord3),
                ["rotation"] => (Target::Rotation(index), Kind::Degrees3),
                ["scale"] => (Target::Scale(index), Kind::Scale3),
                ["texture", "translate"] => (Target::TexTranslate(index), Kind::Coord3),
                _ => return unknown(),
            }
        }
        ["materials", mat, rest @ ..] => {
            let Some(m) = defined.get(*mat) else {
                return fail(d.param.span(), pf, format!("no material `{mat}`"));
            };
            let Some(slot) = used.iter().position(|u| u == mat) else {
                return fail(
                    d.param.span(),
                    pf,
                    format!("material `{mat}` is not used by any object"),
                );
            };
            match rest {
                ["phase"] => {
                    if m.preset.is_some_and(|p| p.starts_with("mn-")) {
                        return fail(
                            d.param.span(),
                            pf,
                            format!("material `{mat}` is a perturbed material: it has no phase"),
                        );
                    }
                    (Target::Phase(slot), Kind::Real)
                }
                ["amplitude"] => (Target::Amplitude(slot), Kind::AmplitudeFactor),
                _ => return unknown(),
            }
        }
        _ => return unknown(),
    };
    let from = track_value(&d.from, &format!("{field}.from"), kind)?;
    let to = track_value(&d.to, &format!("{field}.to"), kind)?;
    let last = i64::from(def.frames) - 1;
    let start = match &d.start {
        Some(s) => int(s, &format!("{field}.start"), 0, last - 1, "start")?,
        None => 0,
    };
    let end = match &d.end {
        Some(e) => {
            let v = int(e, &format!("{field}.end"), 0, last, "end")?;
            if v <= start {
                return fail(
                    e.span(),
                    format!("{field}.end"),
                    format!("end ({v}) must be after start ({start})"),
                );
            }
            v
        }
        None => last,
    };
    Ok(Track {
        target,
        from,
        to,
        start: start as u32,
        end: end as u32,
        looped: d.looped.as_ref().is_some_and(|b| *b.get_ref()),
        span: t.span(),
        field: field.to_string(),
    })
}
