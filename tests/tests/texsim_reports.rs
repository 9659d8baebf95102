//! Runs `texsim report size --json --quick` and `texsim report cycles --json --quick` (the real
//! command, through `cargo run`) and checks the row schema of both.
//!
//! `report cycles` needs QEMU: without it the cycles test fails when `CI` is set and is skipped
//! (with a message) otherwise. `report size` needs only the device toolchains.

use std::process::{Command, Stdio};

use serde_json::Value;

const TARGETS: [&str; 2] = ["thumbv7em-none-eabihf", "riscv32imc-unknown-none-elf"];

/// `cargo run -q -p host-sim --bin texsim -- report <args>`; returns the parsed stdout.
/// The reports build the firmware with different features into the same ELF path (the cycles
/// report the default job suite, the peers report the `peers` build): one report at a time.
static FIRMWARE_BUILDS: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn texsim_report(args: &[&str]) -> Value {
    let _serial = FIRMWARE_BUILDS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let root = host_sim::device::workspace_root();
    let mut cmd = Command::new(cargo);
    cmd.current_dir(&root)
        .args([
            "run", "-q", "-p", "host-sim", "--bin", "texsim", "--", "report",
        ])
        .args(args)
        .stdin(Stdio::null());
    // Like host_sim::device: the nested builds must not inherit this test's per-crate cargo
    // variables or host RUSTFLAGS.
    for (k, _) in std::env::vars_os() {
        let k = k.to_string_lossy().into_owned();
        if k == "RUSTFLAGS"
            || k == "CARGO_ENCODED_RUSTFLAGS"
            || k.starts_with("CARGO_PKG_")
            || k.starts_with("CARGO_CRATE_")
            || k.starts_with("CARGO_BIN_")
            || k == "CARGO_MANIFEST_DIR"
            || k == "CARGO_MANIFEST_PATH"
            || k == "CARGO_PRIMARY_PACKAGE"
        {
            cmd.env_remove(&k);
        }
    }
    let out = cmd.output().expect("running cargo");
    assert!(
        out.status.success(),
        "texsim report {args:?} failed ({}):\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "texsim report {args:?}: stdout is not JSON ({e}):\n{}",
            String::from_utf8_lossy(&out.stdout)
        )
    })
}

fn uint(row: &Value, key: &str) -> u64 {
    row[key]
        .as_u64()
        .unwrap_or_else(|| panic!("{key} is not an unsigned integer in {row}"))
}

#[test]
fn size_report_schema() {
    let rows = texsim_report(&["size", "--json", "--quick", "--no-write"]);
    let rows = rows.as_array().expect("an array of rows");
    for t in TARGETS {
        for f in ["minimal", "full"] {
            let row = rows
                .iter()
                .find(|r| r["target"] == t && r["features"] == f)
                .unwrap_or_else(|| panic!("no row for {t} {f}"));
            let text = uint(row, "text");
            let texcore = uint(row, "texcore_text");
            uint(row, "rodata");
            uint(row, "data");
            uint(row, "bss");
            uint(row, "texcore_symbols");
            assert!(text > 0, "{t} {f}: empty .text");
            assert!(
                texcore > 0 && texcore <= text,
                "{t} {f}: texcore share {texcore} of {text}"
            );
            let unit = &row["unit"];
            let ram = uint(unit, "unit_ram");
            assert!(
                uint(unit, "color_table") >= 1024,
                "{t} {f}: 256 RGBA entries"
            );
            assert!(ram >= uint(unit, "color_table") + uint(unit, "model"));
            assert!(row["unit_ram_within_budget"].is_boolean());
        }
        // full adds code: csat, MIP, every basis, the renderer.
        let text_of = |f: &str| {
            rows.iter()
                .find(|r| r["target"] == t && r["features"] == f)
                .map(|r| uint(r, "texcore_text"))
                .unwrap_or(0)
        };
        assert!(text_of("full") > text_of("minimal"), "{t}: full <= minimal");
        // csat is in full's instance, not minimal's.
        let csat_of = |f: &str| {
            rows.iter()
                .find(|r| r["target"] == t && r["features"] == f)
                .map(|r| uint(&r["unit"], "csat"))
                .unwrap_or(0)
        };
        assert_eq!(csat_of("minimal"), 0);
        assert!(csat_of("full") > 0);
    }
    // The budgets are reported for the Cortex-M4F.
    let m4 = rows
        .iter()
        .find(|r| r["target"] == TARGETS[0] && r["features"] == "minimal")
        .expect("M4F minimal");
    assert_eq!(uint(m4, "texcore_text_budget"), 4096);
    assert!(m4["within_budget"].is_boolean());
}

#[test]
fn cycles_report_schema() {
    for t in host_sim::device::DeviceTarget::ALL {
        match host_sim::device::check_qemu(t) {
            Ok(_) => {}
            Err(e) if std::env::var_os("CI").is_some() => {
                panic!("CI is set and QEMU is required: {e}")
            }
            Err(e) => {
                let msg =
                    format!("\nSKIPPED cycles_report_schema: {e} (with CI set this is an error)\n");
                let _ = std::io::Write::write_all(&mut std::io::stderr(), msg.as_bytes());
                return;
            }
        }
    }
    let rows = texsim_report(&["cycles", "--json", "--quick"]);
    let rows = rows.as_array().expect("an array of rows");
    for t in TARGETS {
        let of_target: Vec<&Value> = rows.iter().filter(|r| r["target"] == t).collect();
        assert!(!of_target.is_empty(), "no rows for {t}");
        for r in &of_target {
            assert!(r["scene"].is_string(), "{r}");
            let ipp = r["instructions_per_pixel"]
                .as_f64()
                .unwrap_or_else(|| panic!("instructions_per_pixel is not a number in {r}"));
            assert!(ipp > 0.0, "{r}");
            assert_eq!(r["checksum_match"], Value::Bool(true), "{r}");
            assert!(r["stage"].is_boolean(), "{r}");
        }
        assert!(
            of_target.iter().any(|r| r["scene"] == "plane:marble"),
            "{t}: the reference job"
        );
        assert!(
            of_target.iter().any(|r| r["stage"] == Value::Bool(true)
                && r["scene"].as_str().is_some_and(|s| s.starts_with("stage:"))),
            "{t}: a per-stage row"
        );
        assert!(
            of_target
                .iter()
                .any(|r| r["scene"].as_str().is_some_and(|s| s.starts_with("scene:"))),
            "{t}: a scene row"
        );
    }
}

/// `texsim report peers --json --quick --no-host` (one band on each device under QEMU): the
/// JSON schema: every workload with texcore's three modes, and fastnoise-lite.
#[test]
fn peers_report_schema() {
    for t in host_sim::device::DeviceTarget::ALL {
        match host_sim::device::check_qemu(t) {
            Ok(_) => {}
            Err(e) if std::env::var_os("CI").is_some() => {
                panic!("CI is set and QEMU is required: {e}")
            }
            Err(e) => {
                let msg =
                    format!("\nSKIPPED peers_report_schema: {e} (with CI set this is an error)\n");
                let _ = std::io::Write::write_all(&mut std::io::stderr(), msg.as_bytes());
                return;
            }
        }
    }
    let rows = texsim_report(&["peers", "--json", "--quick", "--no-host"]);
    let rows = rows.as_array().expect("an array of rows");
    for t in TARGETS {
        let of_target: Vec<&Value> = rows.iter().filter(|r| r["target"] == t).collect();
        for w in [
            "value-1oct",
            "value-4oct",
            "value-4oct-grad",
            "value-4oct-span16",
            "marble-csat-rgb565",
            "marble-csat-rgb565-span16",
            "smooth-1oct",
            "perlin-1oct",
        ] {
            for i in ["texcore-fd", "texcore-auto", "texcore-direct"] {
                let r = of_target
                    .iter()
                    .find(|r| r["workload"] == w && r["implementation"] == i)
                    .unwrap_or_else(|| panic!("{t}: no row {w} {i}"));
                let v = r["instructions_per_sample"]
                    .as_f64()
                    .unwrap_or_else(|| panic!("instructions_per_sample is not a number in {r}"));
                assert!(v > 0.0, "{r}");
                assert!(r["ns_per_sample"].is_null(), "{r}");
                assert_eq!(r["checksum_match"], Value::Bool(true), "{r}");
            }
        }
        assert!(
            of_target
                .iter()
                .any(|r| r["workload"] == "value-1oct" && r["implementation"] == "fastnoise-lite"),
            "{t}: fastnoise-lite"
        );
        for w in ["perlin-1oct", "perlin-4oct"] {
            assert!(
                of_target.iter().any(|r| r["workload"] == w
                    && r["implementation"] == "texcore-fused"
                    && r["checksum_match"] == Value::Bool(true)),
                "{t}: {w} texcore-fused"
            );
        }
    }
}
