//! The accuracy report's device measurements: each firmware part built for both targets and
//! run under QEMU ([`crate::device`]), job counts turned into instructions per pixel.

use std::collections::BTreeMap;
use std::time::Duration;

use super::device_jobs::{self as fw, Part, Row};
use crate::device::{self, DeviceError, DeviceTarget, RunOptions};

/// What to do about QEMU.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DevicePolicy {
    /// Measure; a missing QEMU (or any failure) is an error.
    Required,
    /// Measure when QEMU is installed; without it, report no device counts.
    IfAvailable,
    /// Do not measure.
    Off,
}

/// One measured row on one target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Measured {
    /// The set-up job's count (building the texture only).
    pub setup: u64,
    /// The measured job's count (building and rendering).
    pub run: u64,
    /// The measured job's checksum.
    pub checksum: u32,
}

impl Measured {
    /// Instructions of the rendering alone (the difference of the two jobs).
    pub fn render(&self) -> u64 {
        self.run.saturating_sub(self.setup)
    }
}

/// Device results by target triple and row id.
#[derive(Clone, Debug, Default)]
pub struct DeviceResults {
    /// `triple -> row id -> counts`.
    pub rows: BTreeMap<&'static str, BTreeMap<String, Measured>>,
    /// Why a target was not measured (QEMU missing).
    pub skipped: Vec<String>,
    /// Wall-clock seconds spent building and running.
    pub seconds: f64,
}

/// Pixels a row's job renders.
pub fn pixels(row: &Row) -> f64 {
    if row.cfg.perspective.is_some() {
        f64::from(fw::SCENE_W) * f64::from(fw::SCENE_H)
    } else {
        f64::from(fw::SIDE) * f64::from(fw::SIDE)
    }
}

/// The targets to measure under `policy` (both, unless `Off`), and those skipped and why: with
/// `IfAvailable` a target whose QEMU is missing is skipped, with `Required` it is an error.
pub fn runnable_targets(policy: DevicePolicy) -> Result<(Vec<DeviceTarget>, Vec<String>), String> {
    let (mut run, mut skipped) = (Vec::new(), Vec::new());
    if policy == DevicePolicy::Off {
        return Ok((run, skipped));
    }
    for target in DeviceTarget::ALL {
        match device::check_qemu(target) {
            Ok(_) => run.push(target),
            Err(e) if policy == DevicePolicy::IfAvailable => {
                skipped.push(format!("{target}: {e}"));
            }
            Err(e) => return Err(e.to_string()),
        }
    }
    Ok((run, skipped))
}

/// Builds and runs the firmware parts the rows need, on both targets.
pub fn measure(rows: &[&Row], policy: DevicePolicy) -> Result<DeviceResults, String> {
    let start = std::time::Instant::now();
    let mut out = DeviceResults::default();
    if policy == DevicePolicy::Off {
        return Ok(out);
    }
    let mut parts: Vec<Part> = rows.iter().map(|r| Part::of(&r.cfg)).collect();
    parts.sort();
    parts.dedup();
    let (targets, skipped) = runnable_targets(policy)?;
    out.skipped = skipped;
    for target in targets {
        let mut map = BTreeMap::new();
        for part in &parts {
            let opts = RunOptions {
                features: vec![part.feature().to_string()],
                timeout: Duration::from_secs(600),
                ..RunOptions::default()
            };
            let run = device::run_firmware(target, &opts).map_err(|e| match e {
                DeviceError::QemuMissing { .. } => e.to_string(),
                other => format!("{target} part `{}`: {other}", part.feature()),
            })?;
            for row in rows.iter().filter(|r| Part::of(&r.cfg) == *part) {
                let (Some(s), Some(r)) = (run.job(row.setup), run.job(row.id)) else {
                    return Err(format!(
                        "{target}: the firmware part `{}` did not report job {}",
                        part.feature(),
                        row.id
                    ));
                };
                map.insert(
                    row.id.to_string(),
                    Measured {
                        setup: s.instructions,
                        run: r.instructions,
                        checksum: r.checksum,
                    },
                );
            }
        }
        out.rows.insert(target.triple(), map);
    }
    out.seconds = start.elapsed().as_secs_f64();
    Ok(out)
}
