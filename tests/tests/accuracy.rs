//! `texsim report accuracy` and the precision knobs.
//!
//! - The command itself (`report accuracy --quick --json`, in a child process of this test
//!   binary, writing its docs and README summary into a temporary directory): every knob present,
//!   every numeric field finite, and with QEMU both device targets in every row with matching
//!   checksums. Without QEMU the device checks are skipped with a message, unless `CI` is set:
//!   then the command (and so this test) fails. The code sizes (built without QEMU) are always
//!   checked: `--quick` measures the baseline's feature set and that of `antialiasing=none` on
//!   both targets; the csat filter adds code and RAM, and run-time knobs change neither.
//! - The precision knobs: 16/16 is exactly the default, and fewer bits never improve the error
//!   against the f64 reference by more than noise.

use std::io::Write;
use std::path::PathBuf;

use host_sim::metrics::compare_to_reference;
use host_sim::unit::{self, UnitConfig};
use texcore::hash::HashKind;
use texcore::model::Precision;

const KNOBS: [&str; 15] = [
    "coordinate_bits",
    "value_bits",
    "interpolation",
    "evaluation",
    "octaves",
    "table_size",
    "antialiasing",
    "gradient_norm",
    "perspective",
    "basis",
    "hash",
    "band_limit",
    "filter_widths",
    "shading",
    "gradient_blend",
];
const TARGETS: [&str; 2] = ["thumbv7em-none-eabihf", "riscv32imc-unknown-none-elf"];

texcore_tests::texsim_child_test!();

fn qemu_available() -> bool {
    host_sim::device::DeviceTarget::ALL
        .iter()
        .all(|&t| host_sim::device::check_qemu(t).is_ok())
}

fn finite(v: &serde_json::Value, path: &str) {
    match v {
        serde_json::Value::Number(n) => {
            let f = n.as_f64().unwrap_or(f64::NAN);
            assert!(f.is_finite(), "{path} = {n} is not finite");
        }
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                finite(x, &format!("{path}.{k}"));
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                finite(x, &format!("{path}[{i}]"));
            }
        }
        _ => {}
    }
}

#[test]
fn report_accuracy_quick_json_schema() {
    let dir = std::env::temp_dir().join(format!("texsim-accuracy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let readme: PathBuf = dir.join("README.md");
    std::fs::write(
        &readme,
        "# t\n\n<!-- accuracy:begin -->\nold\n<!-- accuracy:end -->\n\n## after\n",
    )
    .unwrap();
    let texcore_tests::child::Run {
        status,
        stdout,
        stderr,
        ..
    } = texcore_tests::child::texsim(&[
        "report",
        "accuracy",
        "--quick",
        "--json",
        "--out",
        dir.to_str().unwrap(),
        "--readme",
        readme.to_str().unwrap(),
    ]);
    assert_eq!(status, 0, "texsim report accuracy failed:\n{stderr}");
    let rows: Vec<serde_json::Value> = serde_json::from_str(&stdout)
        .unwrap_or_else(|e| panic!("not a JSON array ({e}):\n{stdout}"));
    assert!(!rows.is_empty());
    for knob in KNOBS {
        assert!(
            rows.iter().any(|r| r["knob"] == knob),
            "knob {knob} missing"
        );
    }
    let device = qemu_available();
    if !device {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set: QEMU must be installed"
        );
        let _ = writeln!(
            std::io::stderr(),
            "\nSKIPPED device checks of report_accuracy_quick_json_schema: QEMU is not installed\n"
        );
    }
    for r in &rows {
        let id = r["id"].as_str().unwrap_or("?").to_string();
        assert!(KNOBS.contains(&r["knob"].as_str().unwrap_or("")), "{id}");
        assert!(r["setting"].is_string(), "{id}");
        for k in ["psnr", "max_error", "within_one_step", "host_ns_per_pixel"] {
            assert!(r[k].is_number(), "{id}: {k} missing");
        }
        finite(r, &id);
        assert!(r["host_ns_per_pixel"].as_f64().unwrap() > 0.0, "{id}");
        let w = r["within_one_step"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&w), "{id}");
        let d = r["device_instructions_per_pixel"]
            .as_object()
            .unwrap_or_else(|| panic!("{id}: device object"));
        // The `shading` rows (the marble scene from atlases) and the `gradient_blend` rows have
        // device counts only in the full run (the default firmware's `scene:marble` and
        // `atlas:marble` jobs; the peers firmware).
        if device && r["knob"] != "shading" && r["knob"] != "gradient_blend" {
            for t in TARGETS {
                let v = d
                    .get(t)
                    .and_then(|v| v.as_f64())
                    .unwrap_or_else(|| panic!("{id}: no count for {t}"));
                assert!(v > 10.0, "{id} {t}: {v}");
                assert_eq!(r["device_checksum_match"][t], true, "{id} {t}");
            }
            assert_eq!(d.len(), 2, "{id}");
        }
        assert!(r["pareto"].is_boolean(), "{id}");
    }
    // The baseline is exact where it must be: direct, fd and auto give the same image.
    let psnr = |id: &str| {
        rows.iter()
            .find(|r| r["id"] == id)
            .map(|r| r["psnr"].as_f64().unwrap())
    };
    assert_eq!(psnr("acc:evaluation=direct"), psnr("acc:evaluation=auto"));
    // The band-limiting rows: the default rule is the seascape's own image (the `every16`
    // perspective row), the other rule another image; both measured against the supersampled
    // truth and for flicker.
    let by_id = |id: &str| {
        rows.iter()
            .find(|r| r["id"] == id)
            .unwrap_or_else(|| panic!("{id} missing"))
    };
    let (foot, reach) = (
        by_id("acc:band_limit=footprint"),
        by_id("acc:band_limit=reach"),
    );
    assert_eq!(
        foot["checksum"],
        by_id("acc:perspective=every16")["checksum"]
    );
    assert_ne!(foot["checksum"], reach["checksum"]);
    for r in [foot, reach] {
        assert!(r["scene_supersampled"]["psnr"].is_number(), "{}", r["id"]);
        assert!(r["flicker"]["texcore"].is_number(), "{}", r["id"]);
    }
    assert!(rows.iter().any(|r| r["pareto"] == true));
    // The `gradient_blend` rows: the exact samples are `Direct`'s; along x one octave's fused
    // samples are too, four octaves' within `EvalMode::Fused`'s bound (one unit a term for the
    // term-by-term floors; amplitudes summing to 1.875) and not everywhere the exact ones.
    for (setting, bound) in [
        ("exact-1oct", 0),
        ("fused-1oct", 0),
        ("exact-4oct", 0),
        ("fused-4oct", 4),
    ] {
        let r = by_id(setting);
        assert_eq!(r["knob"], "gradient_blend");
        let max = r["value_error"]["max_vs_exact"].as_i64().unwrap();
        assert!(max <= bound, "{setting}: {max}");
        assert_eq!(max == 0, bound == 0, "{setting}: {max}");
        assert!(
            r["value_error"]["max_vs_f64"].as_f64().unwrap() < 8.0,
            "{setting}"
        );
    }
    check_code_sizes(&rows);
    // Generated files.
    for f in ["accuracy.md", "accuracy.png", "precision.png"] {
        let p = dir.join(f);
        assert!(
            std::fs::metadata(&p)
                .map(|m| m.len() > 100)
                .unwrap_or(false),
            "{} not written",
            p.display()
        );
    }
    let md = std::fs::read_to_string(dir.join("accuracy.md")).unwrap();
    for knob in KNOBS {
        assert!(md.contains(&format!("## `{knob}`")), "accuracy.md: {knob}");
    }
    assert!(md.contains("## Pareto front"));
    assert!(md.contains("M4F texcore .text (diff)"));
    assert!(md.contains("**Code size**: unchanged"));
    assert!(md.contains("unit RAM (diff)"));
    let img = image::open(dir.join("accuracy.png")).unwrap().to_rgb8();
    // The front is drawn in red.
    assert!(img
        .pixels()
        .any(|p| p.0[0] > 200 && p.0[1] < 60 && p.0[2] < 60));
    let sheet = image::open(dir.join("precision.png")).unwrap().to_rgb8();
    assert_eq!(sheet.width() % 2, 0);
    let text = std::fs::read_to_string(&readme).unwrap();
    assert!(!text.contains("\nold\n"), "README section not replaced");
    assert!(text.contains("## after"));
    assert!(text.contains("Cortex-M4F"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The `code_size` fields of a `--quick` run.
fn check_code_sizes(rows: &[serde_json::Value]) {
    let row = |id: &str| {
        rows.iter()
            .find(|r| r["id"] == id)
            .unwrap_or_else(|| panic!("{id} missing"))
    };
    let base = rows
        .iter()
        .find(|r| r["baseline"] == true)
        .expect("baseline");
    let none = row("acc:antialiasing=none");
    let quick_sets = [&base["code_features"], &none["code_features"]];
    assert_ne!(quick_sets[0], quick_sets[1]);
    for r in rows {
        let id = r["id"].as_str().unwrap_or("?");
        let set = &r["code_features"];
        assert!(set.is_string(), "{id}: code_features");
        let Some(c) = r.get("code_size") else {
            panic!("{id}: code_size missing");
        };
        if !quick_sets.contains(&set) {
            assert!(c.is_null(), "{id}: {set} is not a --quick set: {c}");
            continue;
        }
        let c = c
            .as_object()
            .unwrap_or_else(|| panic!("{id}: code_size not measured"));
        assert_eq!(c.len(), 2, "{id}");
        for t in TARGETS {
            let x = &c[t];
            assert_eq!(&x["features"], set, "{id} {t}");
            let n = |k: &str| {
                x[k].as_u64()
                    .unwrap_or_else(|| panic!("{id} {t}: code_size.{k}"))
            };
            assert!(n("texcore_text") > 1000, "{id} {t}");
            assert!(n("text") > n("texcore_text"), "{id} {t}");
            assert!(n("rodata") >= 256, "{id} {t}: the permutation table");
            assert!(n("table_ram") >= 1024, "{id} {t}");
            assert!(n("instance_ram") > n("table_ram"), "{id} {t}");
        }
    }
    let at = |r: &serde_json::Value, t: &str, k: &str| r["code_size"][t][k].as_u64().unwrap();
    for t in TARGETS {
        // The csat filter adds code and RAM.
        assert!(
            at(base, t, "texcore_text") > at(none, t, "texcore_text"),
            "{t}: csat adds code"
        );
        assert!(at(base, t, "instance_ram") > at(none, t, "instance_ram"));
        // Run-time knobs: the baseline's code.
        for r in rows.iter().filter(|r| {
            r["combination"] == false
                && [
                    "coordinate_bits",
                    "value_bits",
                    "octaves",
                    "gradient_norm",
                    "evaluation",
                    "table_size",
                ]
                .contains(&r["knob"].as_str().unwrap_or(""))
        }) {
            if r["id"] == "acc:evaluation=direct" {
                // Per-pixel evaluation alone needs no forward differencing (texcore `fd`).
                assert_eq!(r["code_features"], "perm-hash,csat", "{t}");
                continue;
            }
            for k in ["texcore_text", "text", "rodata"] {
                assert_eq!(at(r, t, k), at(base, t, k), "{} {t} {k}", r["id"]);
            }
        }
    }
}

/// The marble preset's check plane at `bits` coordinate or value bits against the ideal f64
/// reference: PSNR.
fn plane_psnr(name: &str, cfg: &UnitConfig, size: u32) -> (f64, Vec<[u8; 4]>) {
    let m = unit::preset_material(name, HashKind::Permutation).unwrap();
    let (img, _) = unit::render_plane(&m, cfg, size).unwrap();
    let reference = unit::reference_plane(&m, cfg, size).unwrap();
    (
        compare_to_reference(&img.pixels, &reference).unwrap().psnr,
        img.pixels,
    )
}

/// 16/16 is the native format: setting it explicitly changes no pixel of any preset, and the
/// knob is applied to perturbed materials too.
#[test]
fn sixteen_sixteen_equals_the_default() {
    let native = UnitConfig {
        precision: Precision::new(16, 16).unwrap(),
        ..UnitConfig::default()
    };
    assert_eq!(native, UnitConfig::default());
    for name in texcore::presets::NAMES {
        let (a, ia) = plane_psnr(name, &UnitConfig::default(), 64);
        let (b, ib) = plane_psnr(name, &native, 64);
        assert_eq!(ia, ib, "{name}");
        assert_eq!(a, b, "{name}");
    }
    // Perturbed materials carry the precision on their channels.
    let coarse = UnitConfig {
        precision: Precision::new(4, 4).unwrap(),
        ..UnitConfig::default()
    };
    let (_, fine) = plane_psnr("mn-marble", &UnitConfig::default(), 64);
    let (_, rough) = plane_psnr("mn-marble", &coarse, 64);
    assert_ne!(fine, rough);
}

/// Fewer coordinate or value bits never improve the error against the f64 reference by more than
/// noise (0.25 dB) on the check planes of marble, clouds and wood.
#[test]
fn fewer_bits_never_help() {
    for name in ["marble", "clouds", "wood"] {
        for coord in [true, false] {
            let psnr: Vec<f64> = [4u32, 8, 12, 16]
                .iter()
                .map(|&b| {
                    let p = if coord {
                        Precision::new(b, 16)
                    } else {
                        Precision::new(16, b)
                    }
                    .unwrap();
                    let cfg = UnitConfig {
                        precision: p,
                        ..UnitConfig::default()
                    };
                    plane_psnr(name, &cfg, 128).0
                })
                .collect();
            for w in psnr.windows(2) {
                assert!(
                    w[0] <= w[1] + 0.25,
                    "{name} ({}): PSNR by bits 4, 8, 12, 16 = {psnr:?}",
                    if coord { "coordinates" } else { "values" }
                );
            }
            assert!(
                psnr[0] < psnr[3],
                "{name}: 4 bits should lose accuracy: {psnr:?}"
            );
        }
    }
}

/// What the ramp filter (`antialiasing=ramp`, an RGB565 filter) gives up on an RGB565 display:
/// on the marble check plane against the baseline's (csat) f64 reference, its PSNR is within
/// 1 dB of the summed-area filter's colours reduced to RGB565 (docs/performance.md, twenty-ninth
/// round: 41.5 against 42.0 dB at 256 x 256), and its colours are RGB565 already (reducing them
/// changes nothing).
#[test]
fn the_ramp_on_an_rgb565_display_is_near_csat() {
    use texcore::color::Rgba8888;
    use texcore::filter::Antialias;
    let size = 256;
    let m = unit::preset_material("marble", HashKind::Permutation).unwrap();
    let csat = UnitConfig {
        aa: Antialias::Csat,
        ..UnitConfig::default()
    };
    let ramp = UnitConfig {
        aa: Antialias::Ramp,
        ..csat
    };
    let reference = unit::reference_plane(&m, &csat, size).unwrap();
    let reduce = |px: &[[u8; 4]]| -> Vec<[u8; 4]> {
        px.iter()
            .map(|&p| Rgba8888::from_array(p).to_rgb565().to_rgba8888().to_array())
            .collect()
    };
    let c = unit::render_plane(&m, &csat, size).unwrap().0.pixels;
    let r = unit::render_plane(&m, &ramp, size).unwrap().0.pixels;
    assert_eq!(reduce(&r), r, "the ramp's colours are RGB565");
    let c565 = compare_to_reference(&reduce(&c), &reference).unwrap();
    let exact = compare_to_reference(&c, &reference).unwrap();
    let r565 = compare_to_reference(&r, &reference).unwrap();
    eprintln!(
        "csat {:.2} dB, csat reduced to RGB565 {:.2} dB, ramp {:.2} dB",
        exact.psnr, c565.psnr, r565.psnr
    );
    assert!(exact.psnr > c565.psnr + 10.0);
    assert!(
        r565.psnr > c565.psnr - 1.0,
        "{} vs {}",
        r565.psnr,
        c565.psnr
    );
}
