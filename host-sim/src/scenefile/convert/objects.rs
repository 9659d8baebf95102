//! Objects and their meshes: built-in shapes with their parameters, or mesh files loaded
//! relative to the scene file.

use super::*;

/// The fields each mesh kind takes.
pub(super) const MESH_FIELDS: [(&str, &[&str]); 6] = [
    ("teapot", &["level"]),
    ("sphere", &["radius", "stacks", "slices"]),
    (
        "torus",
        &["major", "minor", "major_segments", "minor_segments"],
    ),
    ("cube", &["half", "divisions"]),
    ("quad", &["corners"]),
    ("plane", &["half_size", "rings"]),
];

/// A mesh file (`mesh = { file = ... }`, relative to `base`) as a packed mesh. The packed bytes
/// live as long as the process (scenes hold `'static` meshes).
pub(super) fn mesh_file(
    m: &S<MeshDef>,
    f: &S<String>,
    field: &str,
    base: &std::path::Path,
) -> R<Mesh> {
    if m.get_ref().kind.is_some() {
        return fail(
            f.span(),
            format!("{field}.file"),
            "a mesh is either a `kind` or a `file`, not both",
        );
    }
    let path = base.join(f.get_ref());
    let loaded = crate::mesh::load(&path)
        .and_then(|t| t.pack(&path.display().to_string()))
        .map_err(|e| e.to_string());
    let bytes = match loaded {
        Ok(b) => b,
        Err(e) => return fail(f.span(), format!("{field}.file"), e),
    };
    let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
    match texcore::packed_mesh::PackedMesh::new(bytes) {
        Ok(p) => Ok(Mesh::Packed(p)),
        Err(e) => fail(
            f.span(),
            format!("{field}.file"),
            format!("{}: {e}", path.display()),
        ),
    }
}

pub(super) fn mesh(m: &S<MeshDef>, field: &str, base: &std::path::Path) -> R<Mesh> {
    let d = m.get_ref();
    if let Some(f) = &d.file {
        return mesh_file(m, f, field, base);
    }
    let (kind, kind_span) = match &d.kind {
        Some(k) if !k.span().is_empty() => (k.get_ref().as_str(), k.span()),
        Some(k) => (k.get_ref().as_str(), m.span()),
        None => ("", m.span()),
    };
    let Some((_, allowed)) = MESH_FIELDS.iter().find(|(k, _)| *k == kind) else {
        let kinds: Vec<&str> = MESH_FIELDS.iter().map(|(k, _)| *k).collect();
        return fail(
            kind_span,
            format!("{field}.kind"),
            format!("unknown mesh `{kind}` (known: {})", kinds.join(", ")),
        );
    };
    let present: [(&str, Option<Range<usize>>); 13] = [
        ("level", d.level.as_ref().map(|v| v.span())),
        ("radius", d.radius.as_ref().map(|v| v.span())),
        ("stacks", d.stacks.as_ref().map(|v| v.span())),
        ("slices", d.slices.as_ref().map(|v| v.span())),
        ("major", d.major.as_ref().map(|v| v.span())),
        ("minor", d.minor.as_ref().map(|v| v.span())),
        (
            "major_segments",
            d.major_segments.as_ref().map(|v| v.span()),
        ),
        (
            "minor_segments",
            d.minor_segments.as_ref().map(|v| v.span()),
        ),
        ("half", d.half.as_ref().map(|v| v.span())),
        ("divisions", d.divisions.as_ref().map(|v| v.span())),
        ("corners", d.corners.as_ref().map(|v| v.span())),
        ("half_size", d.half_size.as_ref().map(|v| v.span())),
        ("rings", d.rings.as_ref().map(|v| v.span())),
    ];
    for (name, span) in present {
        if let Some(span) = span {
            if !allowed.contains(&name) {
                return fail(
                    span,
                    format!("{field}.{name}"),
                    format!(
                        "a {kind} mesh has no {name} (it takes: {})",
                        allowed.join(", ")
                    ),
                );
            }
        }
    }
    let size = |v: Option<&S<f64>>, name: &str, default: f64| -> R<i32> {
        match v {
            None => Ok(q16(default) as i32),
            Some(x) => {
                let r = real(
                    x,
                    &format!("{field}.{name}"),
                    |x| x > 0.0 && x <= COORD_MAX,
                    &format!("0 < {name} <= 32767"),
                )?;
                Ok(q16(r).max(1) as i32)
            }
        }
    };
    let count = |v: Option<&S<i64>>, name: &str, default: i64, lo: i64, hi: i64| -> R<i64> {
        match v {
            None => Ok(default),
            Some(x) => int(x, &format!("{field}.{name}"), lo, hi, name),
        }
    };
    Ok(match kind {
        "teapot" => Mesh::Teapot {
            level: count(d.level.as_ref(), "level", 4, 1, 16)? as u8,
        },
        "sphere" => Mesh::Sphere {
            radius: size(d.radius.as_ref(), "radius", 1.0)?,
            stacks: count(d.stacks.as_ref(), "stacks", 16, 2, 1024)? as u16,
            slices: count(d.slices.as_ref(), "slices", 32, 3, 1024)? as u16,
        },
        "torus" => Mesh::Torus {
            major: size(d.major.as_ref(), "major", 1.0)?,
            minor: size(d.minor.as_ref(), "minor", 0.4)?,
            major_segments: count(d.major_segments.as_ref(), "major_segments", 40, 3, 1024)? as u16,
            minor_segments: count(d.minor_segments.as_ref(), "minor_segments", 16, 3, 1024)? as u16,
        },
        "cube" => Mesh::Cube {
            half: size(d.half.as_ref(), "half", 1.0)?,
            divisions: count(d.divisions.as_ref(), "divisions", 1, 1, 64)? as u8,
        },
        "quad" => {
            let Some(c) = &d.corners else {
                return fail(
                    m.span(),
                    format!("{field}.corners"),
                    "missing: a quad mesh needs its 4 corners",
                );
            };
            if c.get_ref().len() != 4 {
                return fail(
                    c.span(),
                    format!("{field}.corners"),
                    format!("expected 4 corners, found {}", c.get_ref().len()),
                );
            }
            let mut corners = [texcore::scene::Vec3::ZERO; 4];
            for (k, p) in c.get_ref().iter().enumerate() {
                let v = coord3(&S::new(c.span(), *p), &format!("{field}.corners[{k}]"))?;
                corners[k] = texcore::scene::Vec3::new(v[0] as i32, v[1] as i32, v[2] as i32);
            }
            Mesh::Quad { corners }
        }
        _ => Mesh::Plane {
            half_size: size(d.half_size.as_ref(), "half_size", 12000.0)?,
            rings: count(d.rings.as_ref(), "rings", 11, 1, 20)? as u8,
        },
    })
}

pub(super) fn object(
    o: &S<ObjectDef>,
    field: &str,
    slot: u8,
    base: &std::path::Path,
) -> R<ObjectFx> {
    let d = o.get_ref();
    let mesh = mesh(&d.mesh, &format!("{field}.mesh"), base)?;
    let position = match &d.position {
        Some(p) => coord3(p, &format!("{field}.position"))?,
        None => [0; 3],
    };
    let rotation = match &d.rotation {
        Some(r) => {
            let mut out = [0i64; 3];
            for (k, x) in r.get_ref().iter().enumerate() {
                if !x.is_finite() || x.abs() > DEGREES_MAX {
                    return fail(
                        r.span(),
                        format!("{field}.rotation[{k}]"),
                        format!("{} is out of range (|degrees| <= 360000)", number(*x)),
                    );
                }
                out[k] = angle_units(*x);
            }
            out
        }
        None => [0; 3],
    };
    let scale = match &d.scale {
        Some(s) => {
            let k = reals3(
                s,
                &format!("{field}.scale"),
                |x| x != 0.0 && coord_ok(x),
                "0 < |scale| <= 32767",
            )?;
            let q = k.map(q16);
            if q.contains(&0) {
                return fail(
                    s.span(),
                    format!("{field}.scale"),
                    "the scale rounds to zero",
                );
            }
            q
        }
        None => [65536; 3],
    };
    let pivot = match &d.pivot {
        Some(p) => coord3(p, &format!("{field}.pivot"))?,
        None => [0; 3],
    };
    let (world_texture, tex_matrix, tex_translate) = match &d.texture {
        Some(t) => {
            let td = t.get_ref();
            let f = format!("{field}.texture");
            let (m, tr) = affine(
                td.scale.as_ref(),
                "scale",
                td.matrix.as_ref(),
                td.translate.as_ref(),
                &f,
            )?;
            (
                td.space
                    .as_ref()
                    .is_some_and(|s| *s.get_ref() == SpaceDef::World),
                m,
                tr,
            )
        }
        None => (false, [[65536, 0, 0], [0, 65536, 0], [0, 0, 65536]], [0; 3]),
    };
    Ok(ObjectFx {
        mesh,
        position,
        rotation,
        scale,
        pivot,
        world_texture,
        tex_matrix,
        tex_translate,
        slot,
        blend: match d.blend.as_ref().map(|b| *b.get_ref()) {
            None | Some(BlendDef::Opaque) => Blend::Opaque,
            Some(BlendDef::Over) => Blend::Over,
        },
        perspective: match d.perspective.as_ref().map(|p| *p.get_ref()) {
            Some(PerspectiveDef::Exact) => Perspective::Exact,
            Some(PerspectiveDef::Every8) => Perspective::Every8,
            None | Some(PerspectiveDef::Every16) => Perspective::Every16,
            Some(PerspectiveDef::Affine) => Perspective::Affine,
        },
        cull: match d.cull.as_ref().map(|c| *c.get_ref()) {
            None | Some(CullDef::None) => CullMode::None,
            Some(CullDef::Cw) => CullMode::Clockwise,
            Some(CullDef::Ccw) => CullMode::CounterClockwise,
        },
        depth_test: d.depth_test.as_ref().is_none_or(|b| *b.get_ref()),
        depth_write: d.depth_write.as_ref().is_none_or(|b| *b.get_ref()),
        shading: crate::atlas::shading::convert(
            d.shading.as_ref(),
            d.atlas.as_ref(),
            d.blend
                .as_ref()
                .is_some_and(|b| *b.get_ref() == BlendDef::Over),
            field,
        )?,
    })
}
