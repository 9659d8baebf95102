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
    ("value-1oct", "texcore-fd", 87.0, 105.0),   // 78.4 / 94.9
    ("value-1oct", "texcore-auto", 87.0, 105.0), // 78.5 / 95.0
    ("value-1oct", "texcore-direct", 289.0, 356.0), // 262.1 / 323.0
    ("value-4oct", "texcore-fd", 543.0, 720.0),  // 493.0 / 653.7
    ("value-4oct", "texcore-auto", 543.0, 720.0), // 493.5 / 654.1
    ("value-4oct", "texcore-direct", 829.0, 969.0), // 752.9 / 880.1
    ("value-4oct-grad", "texcore-fd", 732.0, 946.0), // 665.2 / 859.5
    ("value-4oct-grad", "texcore-auto", 733.0, 946.0), // 665.7 / 860.0
    ("value-4oct-grad", "texcore-direct", 1297.0, 1904.0), // 1179.1 / 1730.5
    ("value-4oct-span16", "texcore-fd", 652.0, 879.0), // 592.1 / 798.6
    ("value-4oct-span16", "texcore-auto", 661.0, 887.0), // 600.0 / 805.9
    ("value-4oct-span16", "texcore-direct", 1067.0, 1265.0), // 969.7 / 1149.2
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
    ("smooth-1oct", "texcore-fd", 413.0, 538.0), // 375.4 / 488.7
    ("smooth-1oct", "texcore-auto", 414.0, 538.0), // 375.5 / 488.8
    ("smooth-1oct", "texcore-direct", 639.0, 850.0), // 580.2 / 772.7
    ("perlin-1oct", "texcore-fd", 693.0, 1121.0), // 629.7 / 1018.3
    ("perlin-1oct", "texcore-auto", 693.0, 1121.0), // 629.8 / 1018.4
    ("perlin-1oct", "texcore-direct", 1065.0, 1490.0), // 968.2 / 1353.9
    ("perlin-4oct", "texcore-fd", 2585.0, 4298.0), // 2349.3 / 3906.4
    ("perlin-4oct", "texcore-auto", 2585.0, 4298.0), // 2349.7 / 3906.7
    ("perlin-4oct", "texcore-direct", 3875.0, 5562.0), // 3522.0 / 5055.8
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
