//! The report's `shading` knob: the built-in `marble` scene drawn from meshed texture atlases
//! (Carr & Hart 2002, [`crate::atlas`]) against the same frame shaded procedurally, so a user
//! sees what drawing from a baked atlas costs in accuracy and what it saves in time.
//!
//! Rows (each a [`RowReport`] with knob `shading`):
//!
//! - `procedural`: the frame as `texsim render marble` shades it (the reference of the others);
//! - `atlas-<N>-<look-up>`: every object from its own `N x N` uniform atlas (gutter 1) sampled
//!   nearest, bilinear or MIP (`texsim render marble --via-atlas N --atlas-sampling ...`);
//! - `atlas-128-device` (full run only: the device scene is the built-in 320 x 240 frame): the
//!   device's own atlas jobs (`workloads::atlas`: one 128 x 128 RGB565 atlas for the whole
//!   scene, gutter 0, nearest), computed here with the device's code.
//!
//! Errors: `psnr`, `max_error`, `within_one_step` against the procedural frame (both in RGB565
//! for the device row, as the device draws); `scene` against the f64 reference of the scene
//! (what the precision rows report for the same scene). Cost: host ns per frame pixel of the
//! draw alone (the bake is `host_bake_ms`, paid once while the texture does not change) and,
//! for `procedural` and `atlas-128-device`, exact device instructions per frame pixel of the
//! firmware jobs `scene:marble` and `atlas:marble` (`device_setup_instructions`: the device
//! bake, `atlas:marble-bake`), with their checksums compared against the host's.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use texcore::color::{Rgb565, Rgba8888};
use texcore::hash::HashKind;
use texcore::render::{GroupRows, Output};
use texcore::scene::Scene;

use super::device::DevicePolicy;
use super::device_jobs::BASELINE;
use super::{codesize, measure, set_primary, ErrorSummary, RowReport, Settings};
use crate::atlas::scene::render_via_atlas;
use crate::atlas::view::Sampling;
use crate::atlas::AtlasKind;
use crate::device::{self, DeviceError, DeviceTarget, RunOptions};
use crate::metrics::compare_rgba8;
use crate::report::{self, atlas as dev_atlas, cycles};
use crate::scenes::{self, HostScene};

/// The scene every row draws.
pub const SCENE: &str = "marble";

/// One host atlas setting: name, atlas side, look-up.
type Setting = (&'static str, u32, Sampling);

/// The atlas settings of the full run.
pub const FULL: [Setting; 9] = [
    ("atlas-256-nearest", 256, Sampling::Nearest),
    ("atlas-256-bilinear", 256, Sampling::Bilinear),
    ("atlas-256-mip", 256, Sampling::Mip),
    ("atlas-512-nearest", 512, Sampling::Nearest),
    ("atlas-512-bilinear", 512, Sampling::Bilinear),
    ("atlas-512-mip", 512, Sampling::Mip),
    ("atlas-1024-nearest", 1024, Sampling::Nearest),
    ("atlas-1024-bilinear", 1024, Sampling::Bilinear),
    ("atlas-1024-mip", 1024, Sampling::Mip),
];

/// The atlas settings of `--quick`.
pub const QUICK: [Setting; 2] = [
    ("atlas-256-nearest", 256, Sampling::Nearest),
    ("atlas-256-bilinear", 256, Sampling::Bilinear),
];

/// The device row's name.
pub const DEVICE_ROW: &str = "atlas-128-device";

/// The firmware jobs the rows' device figures come from.
pub const DEVICE_JOBS: [&str; 3] = ["scene:marble", "atlas:marble", "atlas:marble-bake"];

/// The probe features of the procedural rows (the baseline's texture and the renderer) and of
/// the atlas rows (the same and `atlas`), as [`codesize::build_set`] takes them.
const PROCEDURAL_SET: (&str, &[&str]) = (
    "fd,perm-hash,csat,render",
    &[
        "texcore?/fd",
        "texcore?/perm-hash",
        "texcore?/csat",
        "render",
    ],
);
const ATLAS_SET: (&str, &[&str]) = (
    "fd,perm-hash,csat,render,atlas",
    &[
        "texcore?/fd",
        "texcore?/perm-hash",
        "texcore?/csat",
        "render",
        "atlas",
    ],
);

fn row(setting: &'static str, id: &'static str, config: String, features: &str) -> RowReport {
    let mut r = RowReport::unmeasured("shading", setting, id, config, features.to_string());
    r.reference = "the same frame of the marble scene shaded procedurally";
    r
}

/// Median, fastest and slowest of `t`.
fn spread(mut t: Vec<f64>) -> (f64, f64, f64) {
    t.sort_by(f64::total_cmp);
    let n = t.len();
    if n == 0 {
        return (0.0, 0.0, 0.0);
    }
    let median = if n % 2 == 1 {
        t[n / 2]
    } else {
        (t[n / 2 - 1] + t[n / 2]) / 2.0
    };
    (median, t[0], t[n - 1])
}

/// The host rows: `procedural` and every atlas setting of the run, on the marble scene at the
/// precision scene's size, against `reference` (the scene's f64 reference at that size).
pub fn host_rows(
    settings: &Settings,
    quick: bool,
    reference: &[[f64; 4]],
) -> Result<Vec<RowReport>, String> {
    let (w, h) = settings.precision_scene;
    let scene = texcore::scene::by_name(SCENE).ok_or("no marble scene")?;
    let scene = measure::resized(&scene, w, h);
    let frame = scene.still();
    let cfg = measure::unit_config(&BASELINE);
    let hash = BASELINE.hash;
    let px = f64::from(w) * f64::from(h);
    let runs = settings.host_runs.max(1);
    let procedural = || {
        scenes::render_frame(&scene, frame, &cfg, hash, Output::Color)
            .map(|r| r.frame.pixels)
            .map_err(|e| e.to_string())
    };
    let proc_img = procedural()?;
    let mut out = Vec::new();

    let mut r = row(
        "procedural",
        "shading:procedural",
        format!("marble scene {w}x{h}, every pixel shaded by the texture unit"),
        PROCEDURAL_SET.0,
    );
    r.reference = "the procedural frame itself";
    set_primary(
        &mut r,
        &compare_rgba8(&proc_img, &proc_img).map_err(|e| e.to_string())?,
    );
    r.scene = Some((&measure::errors(&proc_img, reference).map_err(|e| e.to_string())?).into());
    let t = measure::Timing::measure(runs, px, || {
        std::hint::black_box(procedural().ok());
    });
    (
        r.host_ns_per_pixel,
        r.host_ns_min,
        r.host_ns_max,
        r.host_runs,
    ) = (t.median, t.min, t.max, t.runs);
    out.push(r);

    let host = HostScene::builtin(scene.clone());
    let list: &[Setting] = if quick { &QUICK } else { &FULL };
    for &(setting, size, sampling) in list {
        let draw = || {
            render_via_atlas(
                &host,
                frame,
                (size, AtlasKind::Uniform),
                sampling,
                &cfg,
                hash,
            )
        };
        let first = draw()?;
        let mut r = row(
            setting,
            setting,
            format!(
                "marble scene {w}x{h}, each object from its own {size}x{size} uniform atlas \
                 (gutter 1), {} look-ups",
                format!("{sampling:?}").to_lowercase()
            ),
            ATLAS_SET.0,
        );
        set_primary(
            &mut r,
            &compare_rgba8(&first.frame.pixels, &proc_img).map_err(|e| e.to_string())?,
        );
        r.scene = Some(
            (&measure::errors(&first.frame.pixels, reference).map_err(|e| e.to_string())?).into(),
        );
        r.atlas_texels_baked = Some(first.baked_texels);
        // Each timed call bakes and draws; the draw is the call minus its bake.
        let (mut draws, mut bakes) = (Vec::new(), Vec::new());
        for _ in 0..runs {
            let start = Instant::now();
            let done = draw()?;
            let total = start.elapsed().as_secs_f64();
            draws.push((total - done.bake_seconds).max(0.0) * 1e9 / px);
            bakes.push(done.bake_seconds * 1e3);
        }
        (r.host_ns_per_pixel, r.host_ns_min, r.host_ns_max) = spread(draws);
        r.host_runs = runs;
        r.host_bake_ms = Some(spread(bakes).0);
        out.push(r);
    }

    if !quick && (w, h) == dev_frame_size()? {
        out.push(device_row(&proc_img, reference, hash, runs)?);
    }
    Ok(out)
}

fn dev_frame_size() -> Result<(u16, u16), String> {
    Ok(report::scenes::builtin_frame(dev_atlas::SCENE)
        .ok_or("no marble scene")?
        .size())
}

/// The device's atlas (computed here with the device's code): its frame in RGBA, the number of
/// texels it bakes, and its checksum.
fn device_frame(scene: &Scene, hash: HashKind) -> Result<(Vec<[u8; 4]>, u32, u32), String> {
    let mut texels = Box::new([0u16; dev_atlas::TEXELS]);
    let baked = dev_atlas::bake_scene(scene, hash, &mut texels, true);
    let mut bins = vec![GroupRows::EMPTY; report::scenes::SCENE_GROUPS];
    let mut px = Vec::new();
    let ok = dev_atlas::draw_scene_rows(scene, &texels, &mut bins, |row| {
        px.extend(row.iter().map(|p| Rgb565(*p).to_rgba8888().to_array()))
    });
    if !ok {
        return Err("the marble scene does not fit the device atlas".into());
    }
    let checksum = dev_atlas::draw_scene(scene, &texels, &mut bins);
    Ok((px, baked, checksum))
}

fn device_row(
    proc_img: &[[u8; 4]],
    reference: &[[f64; 4]],
    hash: HashKind,
    runs: usize,
) -> Result<RowReport, String> {
    let scene = report::scenes::builtin_frame(dev_atlas::SCENE).ok_or("no marble scene")?;
    let (img, baked, _) = device_frame(&scene, hash)?;
    let q = |p: &[u8; 4]| {
        Rgba8888::from_array(*p)
            .to_rgb565()
            .to_rgba8888()
            .to_array()
    };
    let proc565: Vec<[u8; 4]> = proc_img.iter().map(q).collect();
    let (w, h) = scene.size();
    let mut r = row(
        DEVICE_ROW,
        "atlas:marble",
        format!(
            "marble scene {w}x{h} drawn as the devices draw it: one {side}x{side} RGB565 atlas \
             for the whole scene (gutter 0), nearest look-ups",
            side = dev_atlas::SIDE
        ),
        ATLAS_SET.0,
    );
    r.reference = "the same frame shaded procedurally, both in RGB565";
    set_primary(
        &mut r,
        &compare_rgba8(&img, &proc565).map_err(|e| e.to_string())?,
    );
    r.scene = Some((&measure::errors(&img, reference).map_err(|e| e.to_string())?).into());
    r.atlas_texels_baked = Some(u64::from(baked));
    let px = f64::from(w) * f64::from(h);
    let mut bins = vec![GroupRows::EMPTY; report::scenes::SCENE_GROUPS];
    let mut texels = Box::new([0u16; dev_atlas::TEXELS]);
    let mut bakes = Vec::new();
    for _ in 0..runs {
        let start = Instant::now();
        std::hint::black_box(dev_atlas::bake_scene(&scene, hash, &mut texels, true));
        bakes.push(start.elapsed().as_secs_f64() * 1e3);
    }
    r.host_bake_ms = Some(spread(bakes).0);
    let t = measure::Timing::measure(runs, px, || {
        std::hint::black_box(dev_atlas::draw_scene(&scene, &texels, &mut bins));
    });
    (
        r.host_ns_per_pixel,
        r.host_ns_min,
        r.host_ns_max,
        r.host_runs,
    ) = (t.median, t.min, t.max, t.runs);
    Ok(r)
}

/// The device figures of the rows: the default firmware built and run on both targets, its
/// `scene:marble`, `atlas:marble` and `atlas:marble-bake` rows ([`cycles::rows_for_run`], net of
/// their set-up jobs, checksums compared with the host's) put on the `procedural` and
/// `atlas-128-device` rows. Returns the targets skipped and why.
pub fn apply_device(rows: &mut [RowReport], policy: DevicePolicy) -> Result<Vec<String>, String> {
    if !rows.iter().any(|r| r.setting == DEVICE_ROW) {
        return Ok(Vec::new());
    }
    let (targets, skipped) = super::device::runnable_targets(policy)?;
    for target in targets {
        let opts = RunOptions {
            timeout: Duration::from_secs(900),
            ..RunOptions::default()
        };
        let run = match device::run_firmware(target, &opts) {
            Ok(run) => run,
            Err(DeviceError::Failed(run)) => *run,
            Err(e) => return Err(format!("{target}: {e}")),
        };
        let mut jobs = report::suite_for(target);
        jobs.retain(|j| DEVICE_JOBS.contains(&j.name.as_str()));
        let measured = cycles::rows_for_run(target, &run, &jobs).map_err(|e| e.to_string())?;
        let get = |name: &str| measured.iter().find(|c| c.scene == name);
        let triple = target.triple().to_string();
        for r in rows.iter_mut() {
            let (draw, bake) = match r.setting {
                "procedural" => (get("scene:marble"), None),
                DEVICE_ROW => (get("atlas:marble"), get("atlas:marble-bake")),
                _ => continue,
            };
            let Some(draw) = draw else {
                return Err(format!("{target}: no device row for {}", r.setting));
            };
            r.device_instructions_per_pixel
                .insert(triple.clone(), draw.instructions_per_pixel);
            let mut ok = draw.checksum_match;
            if let Some(b) = bake {
                r.device_setup_instructions
                    .insert(triple.clone(), b.instructions);
                ok &= b.checksum_match;
            }
            r.device_checksum_match.insert(triple.clone(), ok);
            r.checksum = draw.device_checksum.trim_start_matches("0x").to_string();
        }
    }
    Ok(skipped)
}

/// The code size of the procedural and atlas feature sets on both targets, put on the rows.
pub fn apply_code_size(rows: &mut [RowReport], log: &mut dyn FnMut(&str)) -> Result<(), String> {
    let run = RunOptions::default();
    let mut sizes: BTreeMap<&str, BTreeMap<String, codesize::CodeSize>> = BTreeMap::new();
    for (set, cargo) in [PROCEDURAL_SET, ATLAS_SET] {
        let mut per = BTreeMap::new();
        for target in DeviceTarget::ALL {
            log(&format!("accuracy: code size of `{set}` on {target}"));
            let b = codesize::build_set(&run, target, set, cargo)?;
            let table = codesize::table_ram(&BASELINE).unwrap_or(0);
            per.insert(
                target.triple().to_string(),
                codesize::CodeSize {
                    features: set.to_string(),
                    texcore_text: b.texcore_text,
                    text: b.text,
                    rodata: b.rodata,
                    table_ram: table,
                    instance_ram: table + b.model + b.evaluator,
                },
            );
        }
        sizes.insert(set, per);
    }
    for r in rows {
        r.code_size = sizes.get(r.code_features.as_str()).cloned();
    }
    Ok(())
}

/// The markdown section of the knob.
pub fn markdown(rows: &[&RowReport]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## `shading`\n\nThe built-in `marble` scene drawn from meshed texture atlases against \
         the same frame shaded procedurally (`texsim render marble --via-atlas N \
         --atlas-sampling S`, `shading = \"atlas\"` in scene files; docs/atlas.md). PSNR, max err \
         and within 1 step against the procedural frame; **scene PSNR** against the scene's f64 \
         reference. **draw ns/px**: host time of drawing a frame from atlases already baked \
         (median of the timed runs), **bake**: host milliseconds to lay out and bake them, paid \
         again only when the texture or the mesh changes. Device: exact instructions per frame \
         pixel of the firmware jobs `scene:marble` (procedural) and `atlas:marble` (the \
         device's 128 x 128 atlas), and the device bake (`atlas:marble-bake`) in instructions \
         per baked texel.\n"
    );
    let _ = writeln!(
        s,
        "| setting | PSNR | max err | within 1 step | scene PSNR | texels baked | bake (ms) | \
         draw ns/px | M4F instr/px | rv32imc instr/px | M4F bake instr/texel | device = host | \
         texcore .text (M4F) |"
    );
    let _ = writeln!(
        s,
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|"
    );
    let m4f = DeviceTarget::CortexM4F.triple();
    let rv = DeviceTarget::Riscv32imc.triple();
    for r in rows {
        let dev = |t: &str| r.device_cell(t);
        let bake_texel = match (r.device_setup_instructions.get(m4f), r.atlas_texels_baked) {
            (Some(i), Some(n)) if n > 0 => format!("{:.1}", *i as f64 / n as f64),
            _ => "-".to_string(),
        };
        let matched = r.device_match_cell();
        let _ = writeln!(
            s,
            "| `{}` | {:.2} | {:.0} | {:.1}% | {} | {} | {} | {:.1} | {} | {} | {} | {} | {} |",
            r.setting,
            r.psnr,
            r.max_error,
            100.0 * r.within_one_step,
            r.scene
                .map_or("-".to_string(), |e: ErrorSummary| format!("{:.2}", e.psnr)),
            r.atlas_texels_baked
                .map_or("-".to_string(), |n| n.to_string()),
            r.host_bake_ms
                .map_or("-".to_string(), |v| format!("{v:.1}")),
            r.host_ns_per_pixel,
            dev(m4f),
            dev(rv),
            bake_texel,
            matched,
            r.code_size
                .as_ref()
                .and_then(|c| c.get(m4f))
                .map_or("-".to_string(), |c| c.texcore_text.to_string()),
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quick rows: the procedural row is its own reference, the atlases come close to it
    /// and finer look-ups do not do worse than nearest; the draw is timed apart from the bake.
    #[test]
    fn quick_rows_compare_atlases_with_the_procedural_frame() {
        let settings = Settings::QUICK;
        let (w, h) = settings.precision_scene;
        let scene = measure::resized(&texcore::scene::by_name(SCENE).unwrap(), w, h);
        let reference = measure::scene_reference(&scene, scene.still(), &BASELINE).unwrap();
        let rows = host_rows(&settings, true, &reference).unwrap();
        assert_eq!(rows.len(), 1 + QUICK.len());
        assert_eq!(rows[0].setting, "procedural");
        assert_eq!(rows[0].psnr, 100.0);
        assert_eq!(rows[0].within_one_step, 1.0);
        for r in &rows[1..] {
            assert!(r.psnr > 20.0 && r.psnr < 100.0, "{}: {}", r.setting, r.psnr);
            assert!(r.atlas_texels_baked.unwrap() > 0);
            assert!(r.host_bake_ms.unwrap() > 0.0 && r.host_ns_per_pixel > 0.0);
            assert!(r.scene.is_some());
        }
        assert!(
            rows[2].psnr >= rows[1].psnr - 0.5,
            "bilinear against nearest"
        );
        let md = markdown(&rows.iter().collect::<Vec<_>>());
        assert!(md.contains("| `atlas-256-bilinear` |"), "{md}");
    }

    /// The device row's frame is the device's (its checksum is the one the firmware test
    /// compares with the devices) and resembles the procedural frame.
    #[test]
    fn device_row_draws_the_device_atlas() {
        let scene = report::scenes::builtin_frame(dev_atlas::SCENE).unwrap();
        let hash = HashKind::Integer;
        let (img, baked, checksum) = device_frame(&scene, hash).unwrap();
        assert_eq!(
            Some(checksum),
            report::host_checksum("atlas:marble", hash),
            "the device job's checksum"
        );
        assert_eq!(baked, dev_atlas::owned_texels(&scene));
        let (w, h) = scene.size();
        assert_eq!(img.len(), usize::from(w) * usize::from(h));
    }
}
