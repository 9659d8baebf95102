//! The texcore rows of `texsim report peers` on both devices under QEMU stay within [`BOUNDS`]:
//! the peers firmware (feature `peers-band`: one 8-row band of the 256 x 256 peer plane, 2048
//! samples a job, so the test stays short; the report runs the whole plane) is built and run, and
//! every texcore row must
//! - give the host's checksum (the same kernel recomputed here, `workloads/src/peers.rs`), and
//! - cost at most its bound in exact instructions per sample (net of the set-up and the checksum
//!   fold, as the report counts them).
//!
//! The bounds are about 10% above the figures measured when they were set (in the comments), so
//! a regression fails; lower them when the kernels get faster. texcore's band figures equal the
//! whole plane's (docs/peers.md) to within 0.1%. The fastnoise-lite rows are checked for their
//! checksums only.
//!
//! When QEMU is not installed the test fails if `CI` is set, and otherwise prints a skip message
//! and returns.

use host_sim::device::{self, DeviceTarget, RunOptions};
use host_sim::report::peers;

/// `(workload, implementation, Cortex-M4F, rv32imc)`: the most instructions per sample each
/// texcore row may cost on one 8-row band of the peer plane.
const BOUNDS: &[(&str, &str, f64, f64)] = &[
    ("value-1oct", "texcore-fd", 16.0, 23.0),     // 13.8 / 20.8
    ("value-1oct", "texcore-auto", 16.0, 23.0),   // 13.9 / 20.9
    ("value-1oct", "texcore-direct", 43.0, 53.0), // 38.8 / 47.8
    ("value-4oct", "texcore-fd", 169.0, 212.0),   // 153.1 / 192.1
    ("value-4oct", "texcore-auto", 170.0, 212.0), // 153.8 / 192.6
    ("value-4oct", "texcore-direct", 267.0, 342.0), // 242.6 / 310.1
    ("value-4oct-grad", "texcore-fd", 318.0, 390.0), // 289.0 / 354.5
    ("value-4oct-grad", "texcore-auto", 319.0, 391.0), // 289.6 / 355.0
    ("value-4oct-grad", "texcore-direct", 1297.0, 1904.0), // 1193.7 / 1735.3
    ("value-4oct-span16", "texcore-fd", 357.0, 416.0), // 324.3 / 377.8
    ("value-4oct-span16", "texcore-auto", 368.0, 425.0), // 334.3 / 385.8
    ("value-4oct-span16", "texcore-direct", 433.0, 533.0), // 393.0 / 484.4
    ("marble-csat-rgb565", "texcore-fd", 928.0, 1146.0), // 843.0 / 1041.6
    ("marble-csat-rgb565", "texcore-auto", 928.0, 1147.0), // 843.5 / 1042.1
    ("marble-csat-rgb565", "texcore-direct", 1493.0, 2104.0), // 1356.8 / 1912.6
    ("marble-csat-rgb565-span16", "texcore-fd", 1074.0, 1396.0), // 975.7 / 1268.2
    ("marble-csat-rgb565-span16", "texcore-auto", 1083.0, 1403.0), // 983.6 / 1275.4
    (
        "marble-csat-rgb565-span16",
        "texcore-direct",
        1782.0,
        2507.0,
    ), // 1619.8 / 2278.3
    ("smooth-1oct", "texcore-fd", 406.0, 512.0),  // 368.9 / 464.6
    ("smooth-1oct", "texcore-auto", 407.0, 512.0), // 369.1 / 464.7
    ("smooth-1oct", "texcore-direct", 628.0, 817.0), // 570.2 / 741.9
    ("perlin-1oct", "texcore-fd", 686.0, 1094.0), // 623.2 / 994.3
    ("perlin-1oct", "texcore-auto", 686.0, 1094.0), // 623.4 / 994.4
    ("perlin-1oct", "texcore-direct", 1055.0, 1456.0), // 958.2 / 1323.2
    ("perlin-4oct", "texcore-fd", 2584.0, 4256.0), // 2349.0 / 3869.0
    ("perlin-4oct", "texcore-auto", 2585.0, 4257.0), // 2349.8 / 3869.6
    ("perlin-4oct", "texcore-direct", 3853.0, 5497.0), // 3502.6 / 4996.5
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
