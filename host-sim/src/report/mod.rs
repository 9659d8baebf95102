//! Device reports: instruction counts per pixel under QEMU ([`cycles`]) and firmware sizes
//! ([`size`]), for the Cortex-M4F and rv32imc firmware, written as JSON rows and as generated
//! markdown (`docs/cycles.md`, `docs/size.md`).
//!
//! The device workloads are defined once, in `firmware/src/{planes,stages,scenes}.rs`, which use
//! nothing but `texcore`; this module includes those files verbatim ([`planes`], [`stages`],
//! [`scenes`]) so the host knows the job list, the work units of every job, and can recompute
//! the set-up, stage and scene checksums with the very same code. The preset check planes are
//! recomputed independently, through [`crate::unit::render_plane`] (the host's own pixel path).

pub mod cli;
pub mod cycles;
pub mod size;

#[path = "../../../firmware/src/planes.rs"]
pub mod planes;
#[path = "../../../firmware/src/scenes.rs"]
pub mod scenes;
#[path = "../../../firmware/src/stages.rs"]
pub mod stages;

use std::path::Path;

use texcore::color::Rgba8888;
use texcore::hash::HashKind;
use texcore::sink::ChecksumSink;

use crate::device::DeviceTarget;
use crate::unit::{self, UnitConfig};

/// What a device job measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum JobKind {
    /// A material's check plane through the whole texture pipeline.
    Plane,
    /// One stage of the pixel path.
    Stage,
    /// A scene through the banded renderer.
    Scene,
}

/// A device job of the texture-unit suite and its amount of work.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SuiteJob {
    /// Job name as the firmware reports it (`plane:marble`, `stage:csat`, `scene:floor`).
    pub name: String,
    /// Kind.
    pub kind: JobKind,
    /// Units of work (pixels, look-ups or triangles).
    pub units: u64,
    /// What a unit is.
    pub unit: &'static str,
}

/// Every job of the suite on `target`, in firmware order (each also has a `<name>/setup` job).
/// The Cortex-M4F runs the scenes whose frame fits its counter's window
/// ([`scenes::SceneJob::m4f`]); rv32imc runs them all.
pub fn suite_for(target: DeviceTarget) -> Vec<SuiteJob> {
    let mut jobs = suite();
    jobs.retain(|j| {
        target != DeviceTarget::CortexM4F
            || j.kind != JobKind::Scene
            || j.name.strip_prefix("scene:").is_some_and(|w| {
                scenes::builtin_band(w).is_some() || scenes::scene(w).is_some_and(|s| s.m4f)
            })
    });
    jobs
}

/// Every job of the suite on any target, in firmware order (each also has a `<name>/setup` job).
pub fn suite() -> Vec<SuiteJob> {
    let mut jobs = Vec::new();
    for m in planes::MATERIALS {
        jobs.push(SuiteJob {
            name: format!("plane:{m}"),
            kind: JobKind::Plane,
            units: u64::from(planes::SIZE * planes::SIZE),
            unit: "pixel",
        });
    }
    for s in stages::STAGES {
        jobs.push(SuiteJob {
            name: format!("stage:{}", s.name),
            kind: JobKind::Stage,
            units: u64::from(s.units),
            unit: s.unit,
        });
    }
    for s in scenes::SCENES {
        jobs.push(SuiteJob {
            name: format!("scene:{}", s.name),
            kind: JobKind::Scene,
            units: u64::from(s.size.0) * u64::from(s.size.1),
            unit: "pixel",
        });
    }
    for name in scenes::BUILTIN_SCENES {
        for (y0, y1) in scenes::BUILTIN_BANDS {
            jobs.push(SuiteJob {
                name: format!("scene:{name}@{y0}..{y1}"),
                kind: JobKind::Scene,
                units: u64::from(texcore::scene::builtin::WIDTH) * u64::from(y1 - y0),
                unit: "pixel",
            });
        }
    }
    jobs
}

/// The lattice hash the firmware of `target` shades with (its `config:hash` job reports it; this
/// is the default build's choice): permutation table on the Cortex-M4F, integer hash on rv32imc.
pub fn default_hash(target: DeviceTarget) -> HashKind {
    match target {
        DeviceTarget::CortexM4F => HashKind::Permutation,
        DeviceTarget::Riscv32imc => HashKind::Integer,
    }
}

/// The hash a device reported through its `config:hash` checksum (1 permutation, 2 integer).
pub fn hash_from_config(checksum: u32) -> Option<HashKind> {
    match checksum {
        1 => Some(HashKind::Permutation),
        2 => Some(HashKind::Integer),
        _ => None,
    }
}

/// The host's checksum of the preset check plane of `name` (64 x 64, csat), through
/// [`crate::unit`]: the host's texture-unit configuration and plane renderer.
pub fn host_plane_checksum(name: &str, hash: HashKind) -> Option<u32> {
    let m = unit::preset_material(name, hash).ok()?;
    let (img, _) = unit::render_plane(&m, &UnitConfig::default(), planes::SIZE).ok()?;
    let mut sink = ChecksumSink::new();
    for p in &img.pixels {
        sink.add_rgb565(Rgba8888::from_array(*p).to_rgb565().to_bits());
    }
    Some(sink.checksum())
}

/// The host's checksum of frame 0 of built-in scene `name` (csat, 256 entries), through
/// [`crate::scenes::render_frame`]: the host's own scene textures and renderer, whole frame.
pub fn host_builtin_scene_checksum(name: &str, hash: HashKind) -> Option<u32> {
    let scene = texcore::scene::builtin::by_name(name)?;
    let r = crate::scenes::render_frame(
        &scene,
        0,
        &UnitConfig::default(),
        hash,
        texcore::render::Output::Color,
    )
    .ok()?;
    Some(crate::scenes::checksum(&r.frame))
}

/// The host's checksum of rows `y0..y1` of frame 0 of built-in scene `name`: the rows of
/// [`host_builtin_scene_checksum`]'s whole frame (rendered once per scene and hash, then kept),
/// folded like the device's strip job (`ChecksumSink` over those rows, top to bottom).
pub fn host_builtin_band_checksum(name: &str, y0: u16, y1: u16, hash: HashKind) -> Option<u32> {
    use std::collections::HashMap;
    use texcore::sink::PixelSink as _;
    use std::sync::Mutex;
    static FRAMES: Mutex<Option<HashMap<(String, bool), crate::output::Frame>>> = Mutex::new(None);
    let key = (name.to_string(), hash == HashKind::Permutation);
    let mut frames = FRAMES.lock().unwrap_or_else(|e| e.into_inner());
    let frames = frames.get_or_insert_with(HashMap::new);
    if !frames.contains_key(&key) {
        let scene = texcore::scene::builtin::by_name(name)?;
        let r = crate::scenes::render_frame(
            &scene,
            0,
            &UnitConfig::default(),
            hash,
            texcore::render::Output::Color,
        )
        .ok()?;
        frames.insert(key.clone(), r.frame);
    }
    let frame = frames.get(&key)?;
    let w = frame.width as usize;
    let rows = frame.pixels.get(usize::from(y0) * w..usize::from(y1) * w)?;
    let mut c = ChecksumSink::new();
    for (y, row) in (y0..).zip(rows.chunks(w.max(1))) {
        let colors: Vec<Rgba8888> = row.iter().map(|p| Rgba8888::from_array(*p)).collect();
        c.write_span(0, y, &colors);
    }
    Some(c.checksum())
}

/// The set-up checksum of a built-in scene strip job (textures and scene built, nothing
/// rendered), through the device's own code.
fn host_builtin_band_setup(name: &str, y0: u16, y1: u16, hash: HashKind) -> u32 {
    let mut textures = Box::new(scenes::SlotTextures::new());
    let mut band = vec![Rgba8888::TRANSPARENT; scenes::BAND_PIXELS];
    let mut depth = vec![0u16; scenes::BAND_PIXELS];
    scenes::builtin_rows(
        name,
        hash,
        false,
        y0..y1,
        &mut textures,
        &mut band,
        &mut depth,
    )
}

/// Runs a scene workload on the host with heap band buffers.
fn host_scene(
    f: fn(HashKind, bool, &mut [Rgba8888], &mut [u16]) -> u32,
    hash: HashKind,
    work: bool,
) -> u32 {
    let mut band = vec![Rgba8888::TRANSPARENT; scenes::BAND_PIXELS];
    let mut depth = vec![0u16; scenes::BAND_PIXELS];
    f(hash, work, &mut band, &mut depth)
}

/// The host's checksum of suite job `name` (with or without the `/setup` suffix) for a device
/// shading with `hash`; `None` for a name outside the suite.
pub fn host_checksum(name: &str, hash: HashKind) -> Option<u32> {
    let (base, work) = match name.strip_suffix("/setup") {
        Some(b) => (b, false),
        None => (name, true),
    };
    if name == "config:hash" {
        return Some(match hash {
            HashKind::Permutation => 1,
            HashKind::Integer => 2,
        });
    }
    let (kind, what) = base.split_once(':')?;
    match kind {
        "plane" if work => host_plane_checksum(what, hash),
        "plane" => Some(planes::setup_checksum(what, hash)),
        "stage" => Some((stages::stage(what)?.run)(hash, work)),
        "scene" if scenes::builtin_band(what).is_some() => {
            let (n, y0, y1) = scenes::builtin_band(what)?;
            if work {
                host_builtin_band_checksum(n, y0, y1, hash)
            } else {
                Some(host_builtin_band_setup(n, y0, y1, hash))
            }
        }
        "scene" if work && texcore::scene::builtin::by_name(what).is_some() => {
            host_builtin_scene_checksum(what, hash)
        }
        "scene" => Some(host_scene(scenes::scene(what)?.run, hash, work)),
        _ => None,
    }
}

/// Writes `text` to `path` atomically (a temporary file next to it, then a rename), creating the
/// directory if needed.
pub fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path)
}

/// Formats a number with a thin grouping of thousands (`12 345`), for the markdown tables.
pub fn group(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(' ');
        }
        out.push(c);
    }
    out
}
