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

/// A semantic error: where, which field, what.
#[derive(Debug)]
pub(crate) struct Fail {
    pub span: Range<usize>,
    pub field: String,
    pub message: String,
}

pub(crate) type R<T> = Result<T, Fail>;

pub(crate) fn fail<T>(
    span: Range<usize>,
    field: impl Into<String>,
    message: impl Into<String>,
) -> R<T> {
    Err(Fail {
        span,
        field: field.into(),
        message: message.into(),
    })
}

/// Largest world coordinate, texture translation or matrix entry magnitude (`Q16.16` holds
/// `[-32768, 32768)`).
pub const COORD_MAX: f64 = 32767.0;
/// Largest image side in pixels.
pub const SIZE_MAX: i64 = 4096;
/// Most animation frames.
pub const FRAMES_MAX: i64 = 10_000;
/// Largest rotation magnitude in degrees (1000 turns).
pub const DEGREES_MAX: f64 = 360_000.0;
/// Largest noise amplitude or material amplitude factor magnitude (texcore's amplitude budget).
pub const AMPLITUDE_MAX: f64 = 512.0;
/// Capacity of a material's noise terms.
pub const TERMS_MAX: usize = texcore::presets::PRESET_TERMS;

/// `x` as raw `Q16.16`, rounded to nearest (the caller has checked the range).
pub(crate) fn q16(x: f64) -> i64 {
    (x * 65536.0).round() as i64
}

/// Degrees as raw angle units (`2^32` per turn), rounded to nearest.
pub(crate) fn angle_units(deg: f64) -> i64 {
    (deg * 4_294_967_296.0 / 360.0).round() as i64
}

/// A real as echoed in a message: shortened to scientific notation when long (`1e300`, not its
/// 301 digits).
fn number(v: f64) -> String {
    let s = format!("{v}");
    if s.len() <= 16 {
        return s;
    }
    let e = format!("{v:e}");
    if e.len() <= 16 {
        e
    } else {
        format!("{v:.6e}")
    }
}

/// A real in a range (`ok`), described by `range` in the message.
pub(super) fn real(v: &S<f64>, field: &str, ok: impl Fn(f64) -> bool, range: &str) -> R<f64> {
    let x = *v.get_ref();
    if !x.is_finite() || !ok(x) {
        return fail(
            v.span(),
            field,
            format!("{} is out of range ({range})", number(x)),
        );
    }
    Ok(x)
}

/// An integer in `lo..=hi`.
fn int(v: &S<i64>, field: &str, lo: i64, hi: i64, what: &str) -> R<i64> {
    let x = *v.get_ref();
    if x < lo || x > hi {
        return fail(
            v.span(),
            field,
            format!("{x} is out of range ({lo} <= {what} <= {hi})"),
        );
    }
    Ok(x)
}

fn coord_ok(x: f64) -> bool {
    x.abs() <= COORD_MAX
}

const COORD_RANGE: &str = "|v| <= 32767";

/// Three coordinates within `±32767`, as raw `Q16.16`.
pub(super) fn coord3(v: &S<[f64; 3]>, field: &str) -> R<[i64; 3]> {
    let mut out = [0i64; 3];
    for (k, x) in v.get_ref().iter().enumerate() {
        if !x.is_finite() || !coord_ok(*x) {
            return fail(
                v.span(),
                format!("{field}[{k}]"),
                format!("{} is out of range ({COORD_RANGE})", number(*x)),
            );
        }
        out[k] = q16(*x);
    }
    Ok(out)
}

/// A number or three numbers from a TOML value.
fn num_or_vec3(v: &S<Value>, field: &str) -> R<[f64; 3]> {
    let n = |x: &Value| match x {
        Value::Integer(i) => Some(*i as f64),
        Value::Float(f) => Some(*f),
        _ => None,
    };
    match v.get_ref() {
        Value::Array(a) if a.len() == 3 => {
            let mut out = [0.0; 3];
            for (k, x) in a.iter().enumerate() {
                match n(x) {
                    Some(f) => out[k] = f,
                    None => {
                        return fail(
                            v.span(),
                            format!("{field}[{k}]"),
                            format!("expected a number, found {}", x.type_str()),
                        )
                    }
                }
            }
            Ok(out)
        }
        x => match n(x) {
            Some(f) => Ok([f; 3]),
            None => fail(
                v.span(),
                field,
                format!(
                    "expected a number or an array of 3 numbers, found {}",
                    describe(x)
                ),
            ),
        },
    }
}

fn describe(v: &Value) -> String {
    match v {
        Value::Array(a) => format!("an array of {} values", a.len()),
        x => x.type_str().to_string(),
    }
}

/// Three reals each satisfying `ok`.
pub(super) fn reals3(
    v: &S<Value>,
    field: &str,
    ok: impl Fn(f64) -> bool,
    range: &str,
) -> R<[f64; 3]> {
    let a = num_or_vec3(v, field)?;
    for (k, x) in a.iter().enumerate() {
        if !x.is_finite() || !ok(*x) {
            let f = if matches!(v.get_ref(), Value::Array(_)) {
                format!("{field}[{k}]")
            } else {
                field.to_string()
            };
            return fail(
                v.span(),
                f,
                format!("{} is out of range ({range})", number(*x)),
            );
        }
    }
    Ok(a)
}

fn entry(x: i64) -> MatrixEntry {
    MatrixEntry::from_bits(x as i32)
}

/// A 3x3 or 3x4 matrix of `Q16.16` entries (rows); the fourth column is a translation.
/// A matrix (rows) and the translation of its fourth column, raw `Q16.16`.
type MatrixFx = ([[i64; 3]; 3], Option<[i64; 3]>);

fn matrix(v: &Rows, field: &str) -> R<MatrixFx> {
    let rows = v.get_ref();
    let cols = rows.first().map_or(0, Vec::len);
    if rows.len() != 3 || !(cols == 3 || cols == 4) || rows.iter().any(|r| r.len() != cols) {
        return fail(
            v.span(),
            field,
            "expected 3 rows of 3 numbers (or of 4: the last column is the translation)",
        );
    }
    let mut m = [[0i64; 3]; 3];
    let mut t = [0i64; 3];
    for (i, row) in rows.iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            if !x.is_finite() || !coord_ok(*x) {
                return fail(
                    v.span(),
                    format!("{field}[{i}][{j}]"),
                    format!("{} is out of range ({COORD_RANGE})", number(*x)),
                );
            }
            if j < 3 {
                m[i][j] = q16(*x);
            } else {
                t[i] = q16(*x);
            }
        }
    }
    Ok((m, (cols == 4).then_some(t)))
}

/// An affine map from `scale` (number or 3 numbers) or `matrix` (3x3 or 3x4) and `translate`.
fn affine(
    scale: Option<&S<Value>>,
    scale_name: &str,
    mat: Option<&S<Vec<Vec<f64>>>>,
    translate: Option<&S<[f64; 3]>>,
    field: &str,
) -> R<([[i64; 3]; 3], [i64; 3])> {
    let mut m = [[65536, 0, 0], [0, 65536, 0], [0, 0, 65536]];
    let mut t = [0i64; 3];
    match (scale, mat) {
        (Some(_), Some(mm)) => {
            return fail(
                mm.span(),
                format!("{field}.matrix"),
                format!("give either `{scale_name}` or `matrix`, not both"),
            )
        }
        (Some(s), None) => {
            let k = reals3(s, &format!("{field}.{scale_name}"), coord_ok, COORD_RANGE)?;
            for i in 0..3 {
                m[i][i] = q16(k[i]);
            }
        }
        (None, Some(mm)) => {
            let (mx, tx) = matrix(mm, &format!("{field}.matrix"))?;
            m = mx;
            if let Some(tx) = tx {
                if let Some(tr) = translate {
                    return fail(
                        tr.span(),
                        format!("{field}.translate"),
                        "the matrix has 4 columns: its last column is already the translation",
                    );
                }
                t = tx;
            }
        }
        (None, None) => {}
    }
    if let Some(tr) = translate {
        t = coord3(tr, &format!("{field}.translate"))?;
    }
    Ok((m, t))
}

pub(crate) fn to_affine(m: &[[i64; 3]; 3], t: &[i64; 3]) -> Affine3 {
    Affine3::new(
        [
            [entry(m[0][0]), entry(m[0][1]), entry(m[0][2])],
            [entry(m[1][0]), entry(m[1][1]), entry(m[1][2])],
            [entry(m[2][0]), entry(m[2][1]), entry(m[2][2])],
        ],
        [entry(t[0]), entry(t[1]), entry(t[2])],
    )
}

/// `#rrggbb` or `#rrggbbaa`.
fn colour(v: &S<String>, field: &str) -> R<[u8; 4]> {
    let s = v.get_ref();
    let hex = s.strip_prefix('#').unwrap_or("");
    let ok = (hex.len() == 6 || hex.len() == 8) && hex.chars().all(|c| c.is_ascii_hexdigit());
    if !ok {
        return fail(
            v.span(),
            field,
            format!("`{s}` is not a colour (\"#rrggbb\" or \"#rrggbbaa\", hexadecimal)"),
        );
    }
    let b = |k: usize| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16).unwrap_or(0);
    Ok([b(0), b(1), b(2), if hex.len() == 8 { b(3) } else { 255 }])
}

/// Names of materials and objects: used in animation parameters, so no dots or spaces.
fn check_name(name: &str, span: Range<usize>, field: &str) -> R<()> {
    if name.len() > NAME_MAX {
        return fail(
            span,
            field,
            format!(
                "a name of {} bytes is too long (names are at most {NAME_MAX} bytes)",
                name.len()
            ),
        );
    }
    let ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        && !name.chars().all(|c| c.is_ascii_digit());
    if !ok {
        return fail(
            span,
            field,
            format!("`{name}` is not a valid name (letters, digits, `_` and `-`, not only digits)"),
        );
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// The converted scene.

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

fn leak(s: &str) -> &'static str {
    Box::leak(s.to_string().into_boxed_str())
}

fn hash(h: HashDef) -> HashKind {
    match h {
        HashDef::Perm => HashKind::Permutation,
        HashDef::Int => HashKind::Integer,
    }
}

fn basis(b: Option<&S<BasisDef>>) -> BasisKind {
    match b.map(|b| *b.get_ref()) {
        None | Some(BasisDef::Value) => BasisKind::Value,
        Some(BasisDef::Gradient) => BasisKind::Gradient,
        Some(BasisDef::Mnoise) => BasisKind::Modified,
    }
}

fn fade(f: Option<&S<FadeDef>>) -> Fade {
    match f.map(|f| *f.get_ref()) {
        None | Some(FadeDef::Linear) => Fade::Linear,
        Some(FadeDef::Smooth) => Fade::Smooth,
        Some(FadeDef::Quintic) => Fade::Quintic,
    }
}

fn amplitude_value(v: Option<&S<f64>>, field: &str) -> R<Amplitude> {
    match v {
        None => Ok(Amplitude::ONE),
        Some(a) => {
            let x = real(a, field, |x| x.abs() <= AMPLITUDE_MAX, "|amplitude| <= 512")?;
            Ok(Amplitude::from_bits(q16(x) as i32))
        }
    }
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

fn keys(v: &S<Vec<KeyDef>>, field: &str) -> R<Vec<Key>> {
    let list = v.get_ref();
    if list.is_empty() {
        return fail(v.span(), field, "at least one colour key is needed");
    }
    if list.len() > texcore::ready::MAX_KEYS {
        return fail(
            v.span(),
            field,
            format!(
                "{} colour keys given, at most {} allowed",
                list.len(),
                texcore::ready::MAX_KEYS
            ),
        );
    }
    let mut out: Vec<Key> = Vec::with_capacity(list.len());
    for (i, k) in list.iter().enumerate() {
        let (p, c) = k.get_ref();
        let f = format!("{field}[{i}]");
        let x = real(p, &f, |x| (0.0..=1.0).contains(&x), "0 <= position <= 1")?;
        let pos = q16(x) as u32;
        if let Some(prev) = out.last() {
            if pos < prev.0 {
                return fail(
                    p.span(),
                    f,
                    format!(
                        "position {} is before the previous key's ({}): keys must be in order",
                        number(x),
                        number(f64::from(prev.0) / 65536.0)
                    ),
                );
            }
        }
        out.push((pos, colour(c, &f)?));
    }
    Ok(out)
}

fn material(name: &str, m: &S<MaterialDef>, field: &str) -> R<MaterialFx> {
    let d = m.get_ref();
    let preset = match &d.preset {
        Some(p) => {
            let known = texcore::presets::NAMES;
            match known.iter().find(|n| **n == p.get_ref().as_str()) {
                Some(n) => Some(*n),
                None => {
                    return fail(
                        p.span(),
                        format!("{field}.preset"),
                        format!(
                            "unknown preset `{}` (known: {})",
                            p.get_ref(),
                            known.join(", ")
                        ),
                    )
                }
            }
        }
        None => None,
    };
    let perturbed = preset.is_some_and(|p| p.starts_with("mn-"));
    if perturbed {
        let model_field = [
            ("quadric", d.quadric.as_ref().map(|v| v.span())),
            (
                "noise",
                d.noise.as_ref().and_then(|v| v.first()).map(|v| v.span()),
            ),
            (
                "octaves",
                d.octaves.as_ref().and_then(|v| v.first()).map(|v| v.span()),
            ),
            ("phase", d.phase.as_ref().map(|v| v.span())),
            (
                "phase_direction",
                d.phase_direction.as_ref().map(|v| v.span()),
            ),
        ];
        for (f, span) in model_field {
            if let Some(span) = span {
                return fail(
                    span,
                    format!("{field}.{f}"),
                    format!(
                        "preset `{}` is a perturbed material, not a quadric-plus-noise model: it has no {f}",
                        preset.unwrap_or("")
                    ),
                );
            }
        }
    }
    let amplitude = match &d.amplitude {
        Some(a) => q16(real(
            a,
            &format!("{field}.amplitude"),
            |x| x.abs() <= AMPLITUDE_MAX,
            "|amplitude| <= 512",
        )?),
        None => 65536,
    };
    let phase = match &d.phase {
        Some(p) => q16(real(p, &format!("{field}.phase"), coord_ok, COORD_RANGE)?),
        None => 0,
    };
    let phase_direction = match &d.phase_direction {
        Some(v) => {
            let dir = coord3(v, &format!("{field}.phase_direction"))?;
            dir.map(|x| x as i32)
        }
        None => [0, 65536, 0],
    };
    let keys = match &d.keys {
        Some(k) => Some(&*Box::leak(
            keys(k, &format!("{field}.keys"))?.into_boxed_slice(),
        )),
        None if preset.is_none() => {
            return fail(
                m.span(),
                format!("{field}.keys"),
                "missing: a material without a preset needs colour keys",
            )
        }
        None => None,
    };
    let quadric = match &d.quadric {
        Some(q) => {
            let c = q.get_ref();
            if c.len() != 10 {
                return fail(
                    q.span(),
                    format!("{field}.quadric"),
                    format!(
                        "expected 10 coefficients [A, B, C, D, E, F, G, H, I, J], found {}",
                        c.len()
                    ),
                );
            }
            let mut out = [QuadricCoeff::ZERO; 10];
            for (k, x) in c.iter().enumerate() {
                if !x.is_finite() || !coord_ok(*x) {
                    return fail(
                        q.span(),
                        format!("{field}.quadric[{k}]"),
                        format!("{} is out of range ({COORD_RANGE})", number(*x)),
                    );
                }
                out[k] = QuadricCoeff::from_bits(q16(*x) as i32);
            }
            Some(Quadric::from_coefficients(out))
        }
        None => None,
    };
    let mut terms: Option<Vec<TermFx>> = None;
    let mut count = 0usize;
    if let Some(list) = &d.noise {
        let t = terms.get_or_insert_with(Vec::new);
        for (i, n) in list.iter().enumerate() {
            let f = format!("{field}.noise[{i}]");
            let nd = n.get_ref();
            count += 1;
            if count > TERMS_MAX {
                return fail(
                    n.span(),
                    f,
                    format!("a material has at most {TERMS_MAX} noise terms (octaves included)"),
                );
            }
            let (mm, tt) = affine(
                nd.scale.as_ref(),
                "scale",
                nd.matrix.as_ref(),
                nd.translate.as_ref(),
                &f,
            )?;
            t.push(TermFx::Noise {
                amplitude: amplitude_value(nd.amplitude.as_ref(), &format!("{f}.amplitude"))?,
                transform: to_affine(&mm, &tt),
                kind: basis(nd.basis.as_ref()),
                fade: fade(nd.fade.as_ref()),
                hash: nd.hash.as_ref().map(|h| hash(*h.get_ref())),
                turbulence: nd.turbulence.as_ref().is_some_and(|b| *b.get_ref()),
            });
        }
    }
    if let Some(list) = &d.octaves {
        let t = terms.get_or_insert_with(Vec::new);
        for (i, o) in list.iter().enumerate() {
            let f = format!("{field}.octaves[{i}]");
            let od = o.get_ref();
            let n = int(
                &od.count,
                &format!("{f}.count"),
                1,
                TERMS_MAX as i64,
                "count",
            )? as usize;
            count += n;
            if count > TERMS_MAX {
                return fail(
                    od.count.span(),
                    format!("{f}.count"),
                    format!("a material has at most {TERMS_MAX} noise terms (octaves included); this makes {count}"),
                );
            }
            let (mm, tt) = affine(
                od.frequency.as_ref(),
                "frequency",
                od.matrix.as_ref(),
                od.translate.as_ref(),
                &f,
            )?;
            t.push(TermFx::Octaves {
                count: n as u8,
                amplitude: amplitude_value(od.amplitude.as_ref(), &format!("{f}.amplitude"))?,
                base: to_affine(&mm, &tt),
                rotate: od.rotate.as_ref().is_some_and(|b| *b.get_ref()),
                kind: basis(od.basis.as_ref()),
                fade: fade(od.fade.as_ref()),
                hash: od.hash.as_ref().map(|h| hash(*h.get_ref())),
                turbulence: od.turbulence.as_ref().is_some_and(|b| *b.get_ref()),
            });
        }
    }
    Ok(MaterialFx {
        name: leak(name),
        preset,
        keys,
        squared_keys: d
            .key_spacing
            .as_ref()
            .map(|s| *s.get_ref() == SpacingDef::Squared),
        wrap: d.wrap.as_ref().map(|w| match *w.get_ref() {
            WrapDef::Mod => TableWrap::Mod,
            WrapDef::Clamp => TableWrap::Clamp,
        }),
        quadric,
        terms,
        hash: d.hash.as_ref().map(|h| hash(*h.get_ref())),
        amplitude,
        phase,
        phase_direction,
        span: m.span(),
        amplitude_span: d.amplitude.as_ref().map(|a| a.span()),
    })
}

/// The fields each mesh kind takes.
const MESH_FIELDS: [(&str, &[&str]); 6] = [
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
fn mesh_file(m: &S<MeshDef>, f: &S<String>, field: &str, base: &std::path::Path) -> R<Mesh> {
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

fn mesh(m: &S<MeshDef>, field: &str, base: &std::path::Path) -> R<Mesh> {
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

fn object(o: &S<ObjectDef>, field: &str, slot: u8, base: &std::path::Path) -> R<ObjectFx> {
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

/// How a parameter's values are read: `(vector?, converter)`.
#[derive(Clone, Copy)]
enum Kind {
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

const PARAMS: &str = "camera.eye, camera.target, camera.fov, camera.half_height, \
objects.OBJECT.position, objects.OBJECT.rotation, objects.OBJECT.scale, \
objects.OBJECT.texture.translate, materials.MATERIAL.phase, materials.MATERIAL.amplitude";

fn track_value(v: &S<Value>, field: &str, kind: Kind) -> R<[i64; 3]> {
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

fn track(
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
