//! Multipass noise on the devices: the accuracy report's `evaluation=multipass-*` rows (and the
//! `direct`, `fd`, `auto` rows they are compared with) under QEMU on both targets, each device
//! checksum equal to the host's, and the exact instructions per pixel printed (`docs/multipass.md`).
//! Skipped (with a message) where QEMU is missing, unless `CI` is set.

use host_sim::accuracy::device::{measure, pixels, DevicePolicy};
use host_sim::accuracy::device_jobs::ROWS;
use host_sim::accuracy::measure::plane_device_checksum;

const IDS: &[&str] = &[
    "acc:evaluation=direct",
    "acc:evaluation=fd",
    "acc:evaluation=auto",
    "acc:evaluation=multipass-native",
    "acc:evaluation=multipass-16.8",
    "acc:evaluation=multipass-8",
];

#[test]
fn multipass_rows_run_on_both_devices_with_the_host_checksum() {
    let rows: Vec<_> = ROWS.iter().filter(|r| IDS.contains(&r.id)).collect();
    assert_eq!(rows.len(), IDS.len());
    let policy = if std::env::var_os("CI").is_some() {
        DevicePolicy::Required
    } else {
        DevicePolicy::IfAvailable
    };
    let res = measure(&rows, policy).unwrap();
    for s in &res.skipped {
        eprintln!("SKIPPED: {s}");
    }
    for (target, map) in &res.rows {
        for row in &rows {
            let m = map
                .get(row.id)
                .unwrap_or_else(|| panic!("{target}: no {}", row.id));
            let host = plane_device_checksum(&row.cfg).unwrap();
            assert_eq!(
                m.checksum, host,
                "{target} {}: device and host checksums differ",
                row.id
            );
            eprintln!(
                "{target} {}: {:.1} instructions/pixel ({} setup)",
                row.id,
                m.render() as f64 / pixels(row),
                m.setup
            );
        }
        // Native multipass is the direct samples the long way round: never fewer instructions.
        let ipp = |id: &str| map[id].render();
        assert!(ipp("acc:evaluation=multipass-native") > ipp("acc:evaluation=fd"));
    }
}
