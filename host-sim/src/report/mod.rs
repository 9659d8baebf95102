//! Device reports: instruction counts per pixel under QEMU ([`cycles`]) and firmware sizes
//! ([`size`]), for the Cortex-M4F and rv32imc firmware, written as JSON rows and as generated
//! markdown (`docs/cycles.md`, `docs/size.md`).
//!
//! The device workloads are defined once, in the `workloads` crate, which uses nothing but
//! `texcore`; this module re-exports its modules ([`planes`], [`stages`], [`scenes`]) so the host
//! knows the job list, the work units of every job, and can recompute
//! the set-up, stage and scene checksums with the very same code. The preset check planes are
//! recomputed independently, through [`crate::unit::render_plane`] (the host's own pixel path).

pub mod boards;
pub mod cli;
pub mod cycles;
pub mod peers;
pub mod size;

pub use workloads::{atlas, band, peers_workload, planes, scenes, stages};

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
    /// A workload of the peers' plane (noise alone, [`peers_workload`]).
    Peers,
    /// A built-in scene baked into a texture atlas or drawn from it (`workloads::atlas`).
    Atlas,
    /// An evaluation mode over a 320 x 8 band of value noise ([`band`]).
    Band,
}

/// A row of the texture-unit suite: a workload, its amount of work and the device jobs that
/// measure it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SuiteJob {
    /// Row name: the job name as the firmware reports it (`plane:marble`, `stage:csat`,
    /// `scene:floor`), or a built-in scene's (`scene:wood`) whose frame is several jobs.
    pub name: String,
    /// Kind.
    pub kind: JobKind,
    /// Units of work (pixels, look-ups or triangles).
    pub units: u64,
    /// What a unit is.
    pub unit: &'static str,
    /// The device jobs whose counts add up to the row, in firmware order, each with its
    /// `<job>/setup` job: `[name]`, or a built-in scene's strips `name@0 ..`
    /// ([`scenes::STRIPS`] of them, see [`scenes::builtin_strip`]).
    pub device_jobs: Vec<String>,
}

/// Every row of the suite on `target`, in firmware order. The Cortex-M4F runs the scenes of
/// [`scenes::SCENES`] whose frame fits its counter's window ([`scenes::SceneJob::m4f`]) and every
/// built-in scene (in strips, each within the window); rv32imc runs them all.
pub fn suite_for(target: DeviceTarget) -> Vec<SuiteJob> {
    let mut jobs = suite();
    jobs.retain(|j| {
        target != DeviceTarget::CortexM4F
            || j.kind != JobKind::Scene
            || j.name.strip_prefix("scene:").is_some_and(|w| {
                texcore::scene::builtin::by_name(w).is_some()
                    || scenes::LIT_SCENES.contains(&w)
                    || scenes::scene(w).is_some_and(|s| s.m4f)
            })
    });
    jobs
}

/// Every row of the suite on any target, in firmware order.
pub fn suite() -> Vec<SuiteJob> {
    let one = |name: String, kind: JobKind, units: u64, unit: &'static str| SuiteJob {
        device_jobs: vec![name.clone()],
        name,
        kind,
        units,
        unit,
    };
    let mut jobs = Vec::new();
    for m in planes::MATERIALS {
        jobs.push(one(
            format!("plane:{m}"),
            JobKind::Plane,
            u64::from(planes::SIZE * planes::SIZE),
            "pixel",
        ));
    }
    for s in stages::STAGES {
        jobs.push(one(
            format!("stage:{}", s.name),
            JobKind::Stage,
            u64::from(s.units),
            s.unit,
        ));
    }
    for w in peers_workload::WORKLOADS {
        jobs.push(one(
            format!("peers:{}", w.name),
            JobKind::Peers,
            u64::from(w.samples()),
            "sample",
        ));
    }
    for b in band::BANDS {
        jobs.push(one(
            format!("band:{}", b.name),
            JobKind::Band,
            u64::from(b.pixels()),
            "pixel",
        ));
    }
    for s in scenes::SCENES {
        jobs.push(one(
            format!("scene:{}", s.name),
            JobKind::Scene,
            u64::from(s.size.0) * u64::from(s.size.1),
            "pixel",
        ));
    }
    if let Some(s) = scenes::builtin_frame(atlas::SCENE) {
        let (w, h) = s.size();
        jobs.push(one(
            format!("atlas:{}-bake", atlas::SCENE),
            JobKind::Atlas,
            u64::from(atlas::owned_texels(&s)),
            "texel",
        ));
        jobs.push(one(
            format!("atlas:{}", atlas::SCENE),
            JobKind::Atlas,
            u64::from(w) * u64::from(h),
            "pixel",
        ));
    }
    for name in scenes::LIT_SCENES {
        let (w, h) = scenes::lit_frame(name).map_or((0, 0), |s| s.size());
        jobs.push(one(
            format!("scene:{name}"),
            JobKind::Scene,
            u64::from(w) * u64::from(h),
            "pixel",
        ));
    }
    for name in scenes::BUILTIN_SCENES {
        let (w, h) = scenes::builtin_frame(name).map_or((0, 0), |s| s.size());
        let name = format!("scene:{name}");
        jobs.push(SuiteJob {
            device_jobs: (0..scenes::STRIPS).map(|k| format!("{name}@{k}")).collect(),
            name,
            kind: JobKind::Scene,
            units: u64::from(w) * u64::from(h),
            unit: "pixel",
        });
    }
    jobs
}

/// The rows of the firmware's `approximate-scenes` build ([`scenes::APPROXIMATE_SCENES`] in
/// each of [`scenes::APPROXIMATE_MODES`], `scene:<name>~ramp` and `scene:<name>~ramp-diff`, whole
/// frames on both devices), which `texsim report cycles` runs beside the default build
/// ([`APPROXIMATE_FEATURE`]).
pub fn approximate_suite() -> Vec<SuiteJob> {
    let mut jobs = Vec::new();
    for name in scenes::APPROXIMATE_SCENES {
        let (w, h) = scenes::builtin_frame(name).map_or((0, 0), |s| s.size());
        for (_, suffix) in scenes::APPROXIMATE_MODES {
            let name = format!("scene:{name}{suffix}");
            jobs.push(SuiteJob {
                device_jobs: vec![name.clone()],
                name,
                kind: JobKind::Scene,
                units: u64::from(w) * u64::from(h),
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

/// The frame of built-in scene `name` that `texsim render <name>` renders by default (its still
/// frame, default knobs, `hash`), through the host's own scene textures and renderer
/// ([`crate::scenes::render_frame`]).
fn host_builtin_frame(name: &str, hash: HashKind) -> Option<crate::output::Frame> {
    host_still_frame(
        &texcore::scene::builtin::by_name(name)?,
        hash,
        &UnitConfig::default(),
    )
}

/// The still frame of `scene` with the knobs `cfg` and `hash`, through the host's own scene
/// textures and renderer ([`crate::scenes::render_frame`]).
fn host_still_frame(
    scene: &texcore::scene::Scene,
    hash: HashKind,
    cfg: &UnitConfig,
) -> Option<crate::output::Frame> {
    let r = crate::scenes::render_frame(
        scene,
        scene.still(),
        cfg,
        hash,
        texcore::render::Output::Color,
    )
    .ok()?;
    Some(r.frame)
}

/// The host's checksum of built-in scene `name` as `texsim render <name> --checksum` prints it
/// (with `--hash int` for [`HashKind::Integer`]): its still frame with the default knobs, FNV-1a
/// over the RGB565 pixels, row-major ([`crate::scenes::checksum`]).
pub fn host_builtin_scene_checksum(name: &str, hash: HashKind) -> Option<u32> {
    host_frame_rows(name, hash).and_then(|rows| rows.last().copied())
}

/// The host's expected checksum of the device job for strip `k` of built-in scene `name`: the
/// checksum of the rows of [`host_builtin_scene_checksum`]'s frame from the top to the end of
/// the strip ([`scenes::strip_rows`]), so the last strip's is the whole frame's.
pub fn host_builtin_strip_checksum(name: &str, k: usize, hash: HashKind) -> Option<u32> {
    let rows = host_frame_rows(name, hash)?;
    let h = u16::try_from(rows.len().checked_sub(1)?).ok()?;
    rows.get(usize::from(scenes::strip_rows(h, k).end)).copied()
}

/// Entry `y`: the checksum of rows `0..y` of the host frame of built-in scene `name` (entry 0:
/// no rows; the last: the whole frame). Rendered once per scene and hash, then kept.
fn host_frame_rows(name: &str, hash: HashKind) -> Option<std::sync::Arc<Vec<u32>>> {
    use std::collections::HashMap;
    use std::sync::{Arc, Mutex};
    type Cache = Mutex<HashMap<(String, bool), Arc<Vec<u32>>>>;
    static ROWS: std::sync::OnceLock<Cache> = std::sync::OnceLock::new();
    let key = (name.to_string(), hash == HashKind::Permutation);
    let cache = ROWS.get_or_init(Cache::default);
    if let Some(r) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return Some(r.clone());
    }
    let frame = host_builtin_frame(name, hash)?;
    let mut rows = vec![ChecksumSink::new().checksum()];
    let mut c = ChecksumSink::new();
    for row in frame.pixels.chunks(frame.width.max(1) as usize) {
        for p in row {
            c.add_rgb565(Rgba8888::from_array(*p).to_rgb565().to_bits());
        }
        rows.push(c.checksum());
    }
    debug_assert_eq!(rows.last().copied(), Some(crate::scenes::checksum(&frame)));
    let rows = Arc::new(rows);
    cache
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(key, rows.clone());
    Some(rows)
}

/// The host's checksum of lit scene `name` ([`scenes::LIT_SCENES`]): its still frame through
/// the host's own scene textures and renderer ([`crate::scenes::render_frame`], default knobs),
/// FNV-1a over the RGB565 pixels as `texsim render` prints it.
pub fn host_lit_scene_checksum(name: &str, hash: HashKind) -> Option<u32> {
    let frame = host_still_frame(&scenes::lit_scene(name)?, hash, &UnitConfig::default())?;
    Some(crate::scenes::checksum(&frame))
}

/// The firmware feature of the build that runs [`approximate_suite`].
pub const APPROXIMATE_FEATURE: &str = "approximate-scenes";

/// The built-in scene and approximate mode of a job's scene part (`fire~ramp-diff`: `fire` with
/// the ramp and the widths from differences).
pub fn approximate_scene(what: &str) -> Option<(&'static str, scenes::FrameMode)> {
    scenes::APPROXIMATE_SCENES.iter().find_map(|name| {
        let suffix = what.strip_prefix(name)?;
        scenes::APPROXIMATE_MODES
            .iter()
            .find(|(_, s)| *s == suffix)
            .map(|&(mode, _)| (*name, mode))
    })
}

/// The host's checksum of built-in scene `name` in approximate mode `mode`, as `texsim render
/// <name> --aa ramp [--widths differences] --checksum` prints it: its still frame through the
/// host's own scene textures and renderer.
pub fn host_approximate_scene_checksum(
    name: &str,
    mode: scenes::FrameMode,
    hash: HashKind,
) -> Option<u32> {
    let scene = texcore::scene::builtin::by_name(name)?;
    let widths = match mode {
        scenes::FrameMode::RampDifferences => texcore::filter::WidthSource::Differences,
        _ => texcore::filter::WidthSource::Gradients,
    };
    let cfg = UnitConfig {
        aa: texcore::filter::Antialias::Ramp,
        widths,
        ..UnitConfig::default()
    };
    let frame = host_still_frame(&scene, hash, &cfg)?;
    Some(crate::scenes::checksum(&frame))
}

/// The set-up checksum of a built-in scene strip job (scene and textures built, nothing
/// rendered), through the device's own code.
fn host_builtin_strip_setup(name: &str, k: usize, hash: HashKind) -> u32 {
    let mut band = vec![Rgba8888::TRANSPARENT; scenes::BAND_PIXELS];
    let mut depth = vec![0u16; scenes::BAND_PIXELS];
    let mut bins = vec![texcore::render::GroupRows::EMPTY; scenes::SCENE_GROUPS];
    scenes::builtin_strip(
        name,
        hash,
        false,
        k,
        scenes::FRAME_START,
        &mut band,
        &mut depth,
        &mut bins,
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

/// The atlas jobs (`atlas:<scene>-bake`, `atlas:<scene>`) on the host, through the device's own
/// code (`workloads::atlas`) with heap buffers.
fn host_atlas(what: &str, hash: HashKind, work: bool) -> Option<u32> {
    if what == format!("{}-bake", atlas::SCENE) {
        return Some(atlas::bake_job(hash, work));
    }
    if what != atlas::SCENE {
        return None;
    }
    let mut bins = vec![texcore::render::GroupRows::EMPTY; scenes::SCENE_GROUPS];
    let mut band = vec![0u16; atlas::DRAW_PIXELS];
    Some(atlas::draw_job(hash, work, &mut bins, &mut band))
}

/// The host's checksum of device job `name` (with or without the `/setup` suffix) for a device
/// shading with `hash`, or of a built-in scene's whole frame (`scene:<name>`, what the checksum
/// of its last strip must be); `None` for a name outside the suite.
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
        "peers" => Some(peers_workload::workload(what)?.run(hash, work)),
        "band" => Some(band::band(what)?.run(hash, work)),
        "scene" if scenes::builtin_strip_job(what).is_some() => {
            let (n, k) = scenes::builtin_strip_job(what)?;
            if work {
                host_builtin_strip_checksum(n, k, hash)
            } else {
                Some(host_builtin_strip_setup(n, k, hash))
            }
        }
        "scene" if texcore::scene::builtin::by_name(what).is_some() => {
            work.then(|| host_builtin_scene_checksum(what, hash))?
        }
        "scene" if approximate_scene(what).is_some() => {
            let (name, mode) = approximate_scene(what)?;
            if work {
                host_approximate_scene_checksum(name, mode, hash)
            } else {
                let mut band = vec![Rgba8888::TRANSPARENT; scenes::BAND_PIXELS];
                let mut depth = vec![0u16; scenes::BAND_PIXELS];
                let mut bins = vec![texcore::render::GroupRows::EMPTY; scenes::SCENE_GROUPS];
                Some(scenes::approximate_frame_job(
                    name, mode, hash, false, &mut band, &mut depth, &mut bins,
                ))
            }
        }
        "scene" if scenes::LIT_SCENES.contains(&what) => {
            if work {
                host_lit_scene_checksum(what, hash)
            } else {
                let mut band = vec![Rgba8888::TRANSPARENT; scenes::BAND_PIXELS];
                let mut depth = vec![0u16; scenes::BAND_PIXELS];
                let mut bins = vec![texcore::render::GroupRows::EMPTY; scenes::SCENE_GROUPS];
                Some(scenes::lit_frame_job(
                    what, hash, false, &mut band, &mut depth, &mut bins,
                ))
            }
        }
        "scene" => Some(host_scene(scenes::scene(what)?.run, hash, work)),
        "atlas" => host_atlas(what, hash, work),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_scene_fits_the_device() {
        for name in scenes::BUILTIN_SCENES {
            let s = scenes::builtin_frame(name).expect("a built-in scene");
            assert!(
                s.slots.len() <= scenes::SCENE_SLOTS,
                "{name}: {} texture slots, the device jobs hold {}",
                s.slots.len(),
                scenes::SCENE_SLOTS
            );
            let (w, _) = s.size();
            assert!(usize::from(w) * usize::from(scenes::BAND_ROWS) <= scenes::BAND_PIXELS);
            assert!(
                s.quad_count() <= scenes::SCENE_GROUPS,
                "{name}: {} quads, the device jobs bin {}",
                s.quad_count(),
                scenes::SCENE_GROUPS
            );
        }
        assert_eq!(scenes::BUILTIN_SCENES, texcore::scene::BUILTIN);
    }

    /// The approximate frames hold `APPROXIMATE_SLOTS` slot textures (a scene with more would
    /// render nothing on the device), and their widest RGB565 band fits the device's buffers.
    #[test]
    fn approximate_scenes_fit_their_slots() {
        for name in scenes::APPROXIMATE_SCENES {
            let s = scenes::builtin_frame(name).expect("a built-in scene");
            assert!(
                s.slots.len() <= scenes::APPROXIMATE_SLOTS,
                "{name}: {} texture slots, the approximate frames hold {}",
                s.slots.len(),
                scenes::APPROXIMATE_SLOTS
            );
            let (w, _) = s.size();
            let band = usize::from(w) * usize::from(scenes::RGB565_BAND_ROWS);
            assert!(band <= scenes::RGB565_BAND_PIXELS, "{name}");
        }
    }

    /// The band jobs: native multipass gives the direct samples (the same checksum), the
    /// reduced precisions differ, on both hashes; set-up is the same model for every mode.
    #[test]
    fn band_multipass_native_is_direct() {
        let names: Vec<_> = band::BANDS.iter().map(|b| b.name).collect();
        assert_eq!(
            names,
            [
                "direct",
                "fd",
                "multipass-native",
                "multipass-16.8",
                "multipass-8",
                "direct-1oct",
                "fd-1oct",
                "multipass-native-1oct"
            ]
        );
        for hash in [HashKind::Permutation, HashKind::Integer] {
            let c = |n: &str| host_checksum(&format!("band:{n}"), hash).expect(n);
            assert_eq!(c("multipass-native"), c("direct"), "{hash:?}");
            assert_ne!(c("multipass-16.8"), c("direct"), "{hash:?}");
            assert_ne!(c("multipass-8"), c("direct"), "{hash:?}");
            assert_ne!(c("fd"), c("multipass-8"), "{hash:?}");
            assert_eq!(c("multipass-native-1oct"), c("direct-1oct"), "{hash:?}");
            assert_eq!(c("fd-1oct"), c("direct-1oct"), "{hash:?}");
            assert_ne!(c("direct-1oct"), c("direct"), "{hash:?}");
            let setup = host_checksum("band:direct/setup", hash);
            assert_eq!(setup, host_checksum("band:multipass-8/setup", hash));
            assert_ne!(setup, host_checksum("band:direct", hash));
        }
        assert_eq!(band::band("fd").map(|b| b.pixels()), Some(2560));
    }

    /// The lit scene job (`scene:marble-lit`), run on the host with the device's code, gives the
    /// host renderer's frame; its light changes the unlit marble frame; its set-up builds the
    /// scene and textures only; the row is in the suite of both targets.
    #[test]
    fn lit_scene_job_is_the_host_frame() {
        let mut band = vec![Rgba8888::TRANSPARENT; scenes::BAND_PIXELS];
        let mut depth = vec![0u16; scenes::BAND_PIXELS];
        let mut bins = vec![texcore::render::GroupRows::EMPTY; scenes::SCENE_GROUPS];
        let hash = HashKind::Integer;
        let device =
            scenes::lit_frame_job("marble-lit", hash, true, &mut band, &mut depth, &mut bins);
        assert_eq!(host_checksum("scene:marble-lit", hash), Some(device));
        assert_ne!(host_builtin_scene_checksum("marble", hash), Some(device));
        let setup = host_checksum("scene:marble-lit/setup", hash);
        assert_eq!(setup, Some(host_builtin_strip_setup("marble", 0, hash)));
        assert!(scenes::lit_scene("marble").is_none() && scenes::lit_scene("nope-lit").is_none());
        assert!(scenes::lit_frame("marble-lit").is_some_and(|s| s.is_lit()));
        for target in [DeviceTarget::CortexM4F, DeviceTarget::Riscv32imc] {
            let row = suite_for(target)
                .into_iter()
                .find(|j| j.name == "scene:marble-lit")
                .expect("lit row");
            assert_eq!((row.units, row.device_jobs.len()), (320 * 240, 1));
        }
    }

    #[test]
    fn strips_cover_the_frame() {
        for h in [1u16, 3, 4, 31, 32, 240, 256, 257] {
            let mut y = 0;
            for k in 0..scenes::STRIPS {
                let r = scenes::strip_rows(h, k);
                assert_eq!(r.start, y, "{h} {k}");
                assert!(r.start <= r.end, "{h} {k}");
                assert_eq!(
                    r.start % scenes::BAND_ROWS,
                    0,
                    "{h} {k}: not on a band boundary"
                );
                y = r.end;
            }
            assert_eq!(y, h);
        }
        let rows: Vec<_> = (0..scenes::STRIPS)
            .map(|k| scenes::strip_rows(240, k))
            .collect();
        assert_eq!(rows, [0..56, 56..120, 120..176, 176..240]);
        assert_eq!(scenes::builtin_strip_job("wood@3"), Some(("wood", 3)));
        assert_eq!(scenes::builtin_strip_job("wood@4"), None);
        assert_eq!(scenes::builtin_strip_job("floor@0"), None);
        assert_eq!(scenes::FRAME_START, ChecksumSink::new().checksum());
    }

    /// The device's strip jobs, run here one after the other, give the host's frame checksum
    /// (what `texsim render <scene> --checksum` prints), and each strip the host's prefix.
    #[test]
    fn device_strips_give_the_host_frame_checksum() {
        let mut band = vec![Rgba8888::TRANSPARENT; scenes::BAND_PIXELS];
        let mut depth = vec![0u16; scenes::BAND_PIXELS];
        let mut bins = vec![texcore::render::GroupRows::EMPTY; scenes::SCENE_GROUPS];
        for hash in [HashKind::Permutation, HashKind::Integer] {
            for name in scenes::BUILTIN_SCENES {
                let mut c = scenes::FRAME_START;
                for k in 0..scenes::STRIPS {
                    c = scenes::builtin_strip(
                        name, hash, true, k, c, &mut band, &mut depth, &mut bins,
                    );
                    assert_eq!(
                        Some(c),
                        host_builtin_strip_checksum(name, k, hash),
                        "{name} strip {k} {hash:?}"
                    );
                }
                assert_eq!(
                    Some(c),
                    host_builtin_scene_checksum(name, hash),
                    "{name} {hash:?}"
                );
            }
        }
    }
}
