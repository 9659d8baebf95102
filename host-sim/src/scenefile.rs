//! Scene files (TOML): cameras, objects, materials (presets or any texture model) and
//! animations, loaded into a [`HostScene`] whose per-frame hook supplies each frame's texcore
//! [`Scene`] and slot materials. The format is documented in `docs/scenes.md`.
//!
//! Loading validates everything before anything is rendered: syntax, unknown fields, types,
//! ranges, references between objects, materials and animation tracks, and every animation frame
//! (the camera is not degenerate, the amplitudes fit texcore's budget). Reals are converted to
//! fixed point once, here; animations interpolate the fixed-point values. A problem is reported
//! as a [`SceneFileError`] naming the file, line, column and field:
//!
//! ```text
//! scene.toml:12:7: camera.fov: 0 is out of range (0 < fov < 180 degrees)
//! ```

mod build;
pub(crate) mod convert;
mod lights;
mod limits;
pub(crate) mod schema;

use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use texcore::hash::HashKind;
use texcore::scene::Scene;

use crate::scenes::{FrameHook, HostScene};
use crate::unit::{MaterialSpec, UnitError};
use convert::{Fail, SceneDef, Target};

pub use convert::{AMPLITUDE_MAX, COORD_MAX, DEGREES_MAX, FRAMES_MAX, SIZE_MAX, TERMS_MAX};
pub use limits::{FILE_MAX, NAME_MAX, STRING_MAX};

/// A scene file problem: where it is and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneFileError {
    /// The file as given.
    pub file: String,
    /// Line, from 1 (0: not about a place in the file, e.g. it cannot be read).
    pub line: usize,
    /// Column in characters, from 1 (0 with `line`).
    pub column: usize,
    /// The field, as a dotted path with array indices (`objects[1].mesh.level`); empty for
    /// syntax errors.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for SceneFileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file)?;
        if self.line > 0 {
            write!(f, ":{}:{}", self.line, self.column)?;
        }
        if !self.field.is_empty() {
            write!(f, ": {}", self.field)?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for SceneFileError {}

/// Line and column (from 1, columns in characters) of byte offset `pos`.
fn line_col(src: &str, pos: usize) -> (usize, usize) {
    let pos = pos.min(src.len());
    let pos = (0..=pos)
        .rev()
        .find(|p| src.is_char_boundary(*p))
        .unwrap_or(0);
    let before = &src[..pos];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |k| k + 1);
    (line, before[start..].chars().count() + 1)
}

/// The dotted path of the deepest key or value at byte `pos` of a TOML document.
fn path_at(src: &str, pos: usize) -> String {
    use toml::de::{DeTable, DeValue};
    fn walk(v: &DeValue<'_>, pos: usize, path: &str, best: &mut Option<(usize, String)>) {
        match v {
            DeValue::Table(t) => {
                for (k, val) in t.iter() {
                    let p = if path.is_empty() {
                        k.get_ref().to_string()
                    } else {
                        format!("{path}.{}", k.get_ref())
                    };
                    let hit = |r: Range<usize>| r.start <= pos && pos < r.end.max(r.start + 1);
                    if hit(k.span()) || hit(val.span()) {
                        let depth = p.len();
                        if best.as_ref().is_none_or(|(d, _)| depth >= *d) {
                            *best = Some((depth, p.clone()));
                        }
                    }
                    walk(val.get_ref(), pos, &p, best);
                }
            }
            DeValue::Array(a) => {
                for (i, val) in a.iter().enumerate() {
                    let p = format!("{path}[{i}]");
                    let r = val.span();
                    if r.start <= pos && pos < r.end.max(r.start + 1) {
                        let depth = p.len();
                        if best.as_ref().is_none_or(|(d, _)| depth >= *d) {
                            *best = Some((depth, p.clone()));
                        }
                    }
                    walk(val.get_ref(), pos, &p, best);
                }
            }
            _ => {}
        }
    }
    let Ok(doc) = DeTable::parse(src) else {
        return String::new();
    };
    let mut best = None;
    walk(&DeValue::Table(doc.into_inner()), pos, "", &mut best);
    best.map(|(_, p)| p).unwrap_or_default()
}

/// The host hook of a loaded scene file.
struct FileScene {
    def: SceneDef,
}

impl FrameHook for FileScene {
    fn frame(&self, frame: u32, hash: HashKind) -> Result<(Scene, Vec<MaterialSpec>), UnitError> {
        let d = self.def.at(frame);
        let materials = d.materials(hash).map_err(|(_, e)| e)?;
        Ok((d.scene(), materials))
    }
    fn atlas_shading(&self) -> Vec<Option<crate::atlas::shading::AtlasShading>> {
        self.def.objects.iter().map(|o| o.shading).collect()
    }
}

/// Checks every frame: the camera is not degenerate and every material builds. Errors point at
/// the animation track responsible (with the frame), or at the camera or material.
fn validate_frames(def: &SceneDef) -> Result<(), Fail> {
    let frames = if def.tracks.is_empty() { 1 } else { def.frames };
    for f in 0..frames {
        let d = def.at(f);
        let at = |pred: &dyn Fn(Target) -> bool| def.tracks.iter().find(|t| pred(t.target));
        if d.camera().view().is_none() {
            let msg = "the camera is degenerate (the eye is on the target, or up is parallel to the view direction)";
            return Err(match at(&|t| matches!(t, Target::Eye | Target::LookAt)) {
                Some(t) => Fail {
                    span: t.span.clone(),
                    field: t.field.clone(),
                    message: format!("at frame {f}: {msg}"),
                },
                None => Fail {
                    span: def.camera_span.clone(),
                    field: "camera".into(),
                    message: msg.into(),
                },
            });
        }
        if let Err((k, e)) = d.materials(HashKind::default()) {
            let m = &def.materials[k];
            return Err(match at(&|t| t == Target::Amplitude(k)) {
                Some(t) => Fail {
                    span: t.span.clone(),
                    field: t.field.clone(),
                    message: format!("at frame {f}: material `{}`: {e}", m.name),
                },
                None => Fail {
                    span: m.amplitude_span.clone().unwrap_or(m.span.clone()),
                    field: if m.amplitude_span.is_some() {
                        format!("materials.{}.amplitude", m.name)
                    } else {
                        format!("materials.{}", m.name)
                    },
                    message: e.to_string(),
                },
            });
        }
    }
    Ok(())
}

/// Parses and validates scene file text. `file` names it in errors; the scene's name defaults to
/// `file`'s stem.
pub fn parse(source: &str, file: &str) -> Result<HostScene, SceneFileError> {
    let err = |span: Option<Range<usize>>, field: String, message: String| {
        let (line, column) = match &span {
            Some(r) => line_col(source, r.start),
            None => (0, 0),
        };
        SceneFileError {
            file: file.to_string(),
            line,
            column,
            field,
            message,
        }
    };
    if let Some((span, field, message)) = limits::long_string(source) {
        return Err(err(Some(span), field, message));
    }
    let parsed: schema::FileDef = match toml::from_str(source) {
        Ok(p) => p,
        Err(e) => {
            let field = e
                .span()
                .map(|r| path_at(source, r.start))
                .unwrap_or_default();
            let span = e.span().or(Some(0..0));
            return Err(err(span, field, limits::toml_words(e.message().trim_end())));
        }
    };
    let stem = Path::new(file)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let base = Path::new(file).parent().unwrap_or(Path::new(""));
    let def = convert::convert(&parsed, &stem, base)
        .and_then(|d| validate_frames(&d).map(|()| d))
        .map_err(|f| err(Some(f.span), f.field, f.message))?;
    let scene = def.scene();
    Ok(HostScene {
        scene,
        hook: Some(Arc::new(FileScene { def })),
    })
}

/// Loads and validates a scene file. A file larger than [`FILE_MAX`] is refused after reading
/// `FILE_MAX + 1` bytes, whatever it is (a regular file, `/dev/zero`, a FIFO).
pub fn load(path: &Path) -> Result<HostScene, SceneFileError> {
    let file = path.display().to_string();
    let fail = |message: String| SceneFileError {
        file: file.clone(),
        line: 0,
        column: 0,
        field: String::new(),
        message,
    };
    let source = limits::read_limited(path, FILE_MAX).map_err(fail)?;
    parse(&source, &file)
}
