//! The texcore rows of `texsim report peers` on both devices under QEMU stay within [`BOUNDS`]:
//! the peers firmware (feature `peers-band`: one 8-row band of the 256 x 256 peer plane, 2048
//! samples a job, so the test stays short; the report runs the whole plane) is built and run, and
//! every texcore row must
//! - give the host's checksum (the same kernel recomputed here, `workloads/src/peers.rs`), and
//! - cost at most its bound in exact instructions per sample (net of the set-up and the checksum
//!   fold, as the report counts them).
//!
//! The bounds are about 10% above the figures measured when they were set (in the comments), so
//! a regression fails; lower them when the kernels get faster. texcore's band figures are the
//! whole plane's (docs/peers.md) where every row is evaluated alike; the whole-row workloads
//! keep their row schedule across rows (`texcore::span::PlaneRows`), whose cells along the rows
//! are made once per cell band, so in a band of 8 rows they cost more a sample than over the
//! plane (`value-4oct` 83.5 against 71.6 on the M4F). The fastnoise-lite rows are checked for
//! their checksums only.
//!
//! When QEMU is not installed the test fails if `CI` is set, and otherwise prints a skip message
//! and returns.

use host_sim::device::{self, DeviceTarget, RunOptions};
use host_sim::report::peers;

/// `(workload, implementation, Cortex-M4F, rv32imc)`: the most instructions per sample each
/// texcore row may cost on one 8-row band of the peer plane (the 16-pixel-span rows through the
/// plane set-up, `span::PlaneSetup`: `docs/performance.md`, twenty-fifth round; walked from the
/// rows' cell schedule, `span::PlaneSpans` and `texture::TextureSpans`, twenty-seventh round).
const BOUNDS: &[(&str, &str, f64, f64)] = &[
    ("value-1oct", "texcore-fd", 15.0, 21.0),     // 12.8 / 18.8
    ("value-1oct", "texcore-auto", 15.0, 21.0),   // 13.0 / 18.9
    ("value-1oct", "texcore-direct", 43.0, 54.0), // 39.0 / 48.2
    ("value-4oct", "texcore-fd", 93.0, 98.0),     // 83.8 / 88.3
    ("value-4oct", "texcore-auto", 93.0, 98.0),   // 84.4 / 88.8
    ("value-4oct", "texcore-direct", 268.0, 342.0), // 242.9 / 310.5
    ("value-4oct-grad", "texcore-fd", 164.0, 188.0), // 148.5 / 170.9
    ("value-4oct-grad", "texcore-auto", 164.0, 189.0), // 149.0 / 171.4
    ("value-4oct-grad", "texcore-direct", 1314.0, 1910.0), // 1194.2 / 1736.0
    ("value-4oct-span16", "texcore-fd", 102.0, 115.0), // 92.9 / 104.0
    ("value-4oct-span16", "texcore-auto", 103.0, 115.0), // 93.4 / 104.5
    ("value-4oct-span16", "texcore-direct", 386.0, 484.0), // 350.8 / 439.8
    ("marble-csat-rgb565", "texcore-fd", 396.0, 434.0), // 359.7 / 394.2
    ("marble-csat-rgb565", "texcore-auto", 397.0, 435.0), // 360.2 / 394.6
    ("marble-csat-rgb565", "texcore-direct", 1520.0, 2111.0), // 1381.6 / 1918.2
    ("marble-csat-rgb565-span16", "texcore-fd", 453.0, 484.0), // 411.6 / 439.8
    ("marble-csat-rgb565-span16", "texcore-auto", 454.0, 485.0), // 412.1 / 440.2
    (
        "marble-csat-rgb565-span16",
        "texcore-direct",
        1731.0,
        2393.0,
    ), // 1573.4 / 2174.9
    ("smooth-1oct", "texcore-fd", 24.0, 31.0),    // 21.4 / 27.3
    ("smooth-1oct", "texcore-auto", 24.0, 31.0),  // 21.5 / 27.3
    ("smooth-1oct", "texcore-direct", 625.0, 815.0), // 567.9 / 740.4
    ("perlin-1oct", "texcore-fd", 32.0, 45.0),    // 28.4 / 40.7
    ("perlin-1oct", "texcore-auto", 32.0, 45.0),  // 28.5 / 40.8
    ("perlin-1oct", "texcore-direct", 969.0, 1147.0), // 880.1 / 1042.7
    ("perlin-4oct", "texcore-fd", 394.0, 521.0),  // 358.1 / 473.3
    ("perlin-4oct", "texcore-auto", 394.0, 521.0), // 358.5 / 473.5
    ("perlin-4oct", "texcore-direct", 3521.0, 4274.0), // 3200.5 / 3885.4
    ("perlin-1oct", "texcore-fused", 32.0, 45.0), // 28.3 / 40.6
    ("perlin-4oct", "texcore-fused", 298.0, 365.0), // 271.1 / 331.0
    ("marble-csat-rgb565", "texcore-ramp", 250.0, 297.0), // 226.8 / 270.0
    ("marble-csat-rgb565-span16", "texcore-ramp", 306.0, 351.0), // 278.4 / 318.9
    ("marble-csat-rgb565", "texcore-ramp-diff", 200.0, 237.0), // 182.0 / 215.4
    (
        "marble-csat-rgb565-span16",
        "texcore-ramp-diff",
        262.0,
        306.0,
    ), // 237.8 / 278.5
];

fn bound(workload: &str, implementation: &str, target: DeviceTarget) -> Option<f64> {
    BOUNDS
        .iter()
        .find(|b| b.0 == workload && b.1 == implementation)
        .map(|b| match target {
            DeviceTarget::CortexM4F => b.2,
            DeviceTarget::Riscv32imc => b.3,
        })
}

fn check(target: DeviceTarget) {
    if let Err(e) = device::check_qemu(target) {
        if std::env::var_os("CI").is_some() {
            panic!("CI is set and QEMU is required: {e}");
        }
        eprintln!("\nSKIPPED peers_qemu for {target}: {e} (with CI set this is an error)\n");
        return;
    }
    let rows =
        peers::run_device(target, true, &RunOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let mut failures = Vec::new();
    let mut texcore_rows = 0;
    for r in &rows {
        assert_eq!(r.samples, 8 * 256);
        if r.checksum_match != Some(true) {
            failures.push(format!(
                "{} {}: device checksum differs from the host's",
                r.workload, r.implementation
            ));
        }
        if !r.implementation.starts_with("texcore") {
            continue;
        }
        texcore_rows += 1;
        let Some(b) = bound(&r.workload, &r.implementation, target) else {
            failures.push(format!("{} {}: no bound", r.workload, r.implementation));
            continue;
        };
        let v = r.instructions_per_sample.unwrap_or(f64::INFINITY);
        // The figures, for setting the bounds (`--nocapture`).
        eprintln!(
            "{target} {} {}: {v:.1} (bound {b})",
            r.workload, r.implementation
        );
        if v > b {
            failures.push(format!(
                "{} {}: {v:.1} instructions per sample > bound {b}",
                r.workload, r.implementation
            ));
        }
    }
    assert_eq!(
        texcore_rows,
        BOUNDS.len(),
        "{target}: a texcore row is missing"
    );
    assert!(failures.is_empty(), "{target}:\n{}", failures.join("\n"));
}

#[test]
fn peers_within_bounds_on_cortex_m4f() {
    check(DeviceTarget::CortexM4F);
}

#[test]
fn peers_within_bounds_on_rv32imc() {
    check(DeviceTarget::Riscv32imc);
}
