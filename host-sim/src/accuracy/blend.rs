//! The report's `gradient_blend` knob: Perlin gradient noise in the row schedule by the exact
//! modes' stepped sums (`exact`, `EvalMode::Fd`: `docs/model.md` 4.3's blend, bit for bit
//! `Direct`) or by `EvalMode::Fused`'s (`fused`: the last product along each row's own axis,
//! several terms' products floored term after term), so a user sees what the approximate mode
//! costs in accuracy and what it saves in time.
//!
//! Rows (each a [`RowReport`] with knob `gradient_blend`): `exact-1oct`, `fused-1oct`,
//! `exact-4oct`, `fused-4oct`, on the peers' plane (`texsim report peers`, 256 x 256 pixels at
//! `1/32` a pixel, whole rows along the lattice's x axis through `SpanEvaluator::rows`) with
//! one and four octaves of quintic gradient noise (`perlin-1oct`, `perlin-4oct`). Along x one
//! term's fused row is the exact one; four terms differ by their floors.
//!
//! Errors: the samples in units of `2^-16` against `Direct`'s (the exact modes', bit for bit)
//! and against the f64 reference of the same model ([`ValueError`]); `psnr`, `max_error`,
//! `within_one_step` of the samples as an 8-bit grey image (`[-1, 1]` to `[0, 255]`) against
//! the f64 reference's. Cost: host ns per sample (median of the timed runs of the whole plane)
//! and, in the full run, exact device instructions per sample of the peers firmware's one-band
//! jobs `peers:perlin-*:texcore-fd` and `peers:perlin-*:texcore-fused`, their checksums
//! compared with the host's.

use std::time::Duration;

use serde::Serialize;
use texcore::format::TexValue;
use texcore::hash::HashKind;
use texcore::span::{EvalMode, EvalOptions, SpanEvaluator};
use texcore::texture::workload::peers::{self as wl, Workload};

use super::device::DevicePolicy;
use super::{measure, set_primary, RowReport, Settings};
use crate::bridge::ref_model;
use crate::device::{DeviceTarget, RunOptions};
use crate::metrics::compare_to_reference;
use crate::report::peers as dev_peers;

/// The knob's name.
pub const KNOB: &str = "gradient_blend";

/// The rows: setting, workload, mode.
pub const SETTINGS: [(&str, Workload, EvalMode); 4] = [
    ("exact-1oct", Workload::Perlin1, EvalMode::Fd),
    ("fused-1oct", Workload::Perlin1, EvalMode::Fused),
    ("exact-4oct", Workload::Perlin4, EvalMode::Fd),
    ("fused-4oct", Workload::Perlin4, EvalMode::Fused),
];

/// The samples' error in units of `2^-16`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ValueError {
    /// Largest `|sample - Direct's|`.
    pub max_vs_exact: i64,
    /// Mean `|sample - Direct's|`.
    pub mean_vs_exact: f64,
    /// Share of the samples equal to `Direct`'s.
    pub equal_share: f64,
    /// Largest `|sample - f64 reference|`.
    pub max_vs_f64: f64,
    /// Mean `|sample - f64 reference|`.
    pub mean_vs_f64: f64,
}

/// The plane's samples of workload `w` in `mode` (integer hash), row-major.
pub fn plane(w: Workload, mode: EvalMode) -> Vec<i32> {
    let Some(m) = wl::model(w, HashKind::Integer) else {
        return Vec::new();
    };
    let opts = EvalOptions {
        mode,
        gradients: false,
        cull: true,
        ..Default::default()
    };
    let mut ev = SpanEvaluator::new(&m, opts);
    let mut line = [TexValue::ZERO; wl::SIZE as usize];
    let mut out = Vec::with_capacity(usize::from(wl::SIZE) * usize::from(wl::SIZE));
    wl::value_plane(&mut ev, w, wl::SIZE, &mut line, |_, row| {
        out.extend(row.iter().map(|v| v.to_bits()));
    });
    out
}

/// The f64 reference of workload `w`'s plane (units of `2^-16`), row-major.
fn reference(w: Workload) -> Vec<f64> {
    let Some(m) = wl::model(w, HashKind::Integer) else {
        return Vec::new();
    };
    let r = ref_model(&m);
    let step = f64::from(wl::STEP) / 65536.0;
    let z = f64::from(wl::R_BITS) / 65536.0;
    let n = wl::SIZE;
    (0..n)
        .flat_map(|y| (0..n).map(move |x| [f64::from(x) * step, f64::from(y) * step, z]))
        .map(|s| r.f(s) * 65536.0)
        .collect()
}

/// Grey 8-bit pixel of a value `v` (units of `2^-16`): `[-1, 1]` to `[0, 255]`.
fn grey(v: f64) -> f64 {
    ((v / 65536.0 + 1.0) * 127.5).clamp(0.0, 255.0)
}

/// The errors of `got` against `exact` (`Direct`'s) and `truth` (the f64 reference).
pub fn value_error(got: &[i32], exact: &[i32], truth: &[f64]) -> ValueError {
    let n = got.len().max(1) as f64;
    let (mut max, mut sum, mut equal, mut fmax, mut fsum) = (0i64, 0i64, 0usize, 0f64, 0f64);
    for ((g, e), t) in got.iter().zip(exact).zip(truth) {
        let d = (i64::from(*g) - i64::from(*e)).abs();
        max = max.max(d);
        sum += d;
        equal += usize::from(d == 0);
        let fd = (f64::from(*g) - t).abs();
        fmax = fmax.max(fd);
        fsum += fd;
    }
    ValueError {
        max_vs_exact: max,
        mean_vs_exact: sum as f64 / n,
        equal_share: equal as f64 / n,
        max_vs_f64: fmax,
        mean_vs_f64: fsum / n,
    }
}

/// The host rows: every setting's errors and host time.
pub fn host_rows(settings: &Settings) -> Result<Vec<RowReport>, String> {
    let runs = settings.host_runs.max(1);
    let px = f64::from(wl::SIZE) * f64::from(wl::SIZE);
    let mut out = Vec::new();
    for w in [Workload::Perlin1, Workload::Perlin4] {
        let exact = plane(w, EvalMode::Direct);
        let truth = reference(w);
        let truth_grey: Vec<[f64; 4]> = truth
            .iter()
            .map(|&t| {
                let g = grey(t);
                [g, g, g, 255.0]
            })
            .collect();
        for &(setting, _, mode) in SETTINGS.iter().filter(|s| s.1 == w) {
            let got = plane(w, mode);
            let features = if mode == EvalMode::Fused {
                "fd,smooth-fade,gradient-noise,fused"
            } else {
                "fd,smooth-fade,gradient-noise"
            };
            let mut r = RowReport::unmeasured(
                KNOB,
                setting,
                setting,
                format!(
                    "{} of quintic gradient noise on the peers' plane (256 x 256, 1/32 a pixel, \
                     whole rows through `SpanEvaluator::rows`), `{mode}` evaluation",
                    if w == Workload::Perlin1 {
                        "one octave"
                    } else {
                        "four octaves"
                    }
                ),
                features.to_string(),
            );
            r.reference = "the f64 reference of the same noise, as 8-bit grey";
            let img: Vec<[u8; 4]> = got
                .iter()
                .map(|&v| {
                    let g = grey(f64::from(v)).round() as u8;
                    [g, g, g, 255]
                })
                .collect();
            set_primary(
                &mut r,
                &compare_to_reference(&img, &truth_grey).map_err(|e| e.to_string())?,
            );
            r.value_error = Some(value_error(&got, &exact, &truth));
            let t = measure::Timing::measure(runs, px, || {
                std::hint::black_box(plane(w, mode));
            });
            (
                r.host_ns_per_pixel,
                r.host_ns_min,
                r.host_ns_max,
                r.host_runs,
            ) = (t.median, t.min, t.max, t.runs);
            out.push(r);
        }
    }
    Ok(out)
}

/// The device figures of the rows: the peers firmware's one-band build run on both targets, its
/// `perlin-1oct` and `perlin-4oct` rows of `texcore-fd` (the `exact` settings) and
/// `texcore-fused`. Returns the targets skipped and why.
pub fn apply_device(rows: &mut [RowReport], policy: DevicePolicy) -> Result<Vec<String>, String> {
    if rows.is_empty() {
        return Ok(Vec::new());
    }
    let (targets, skipped) = super::device::runnable_targets(policy)?;
    for target in targets {
        let opts = RunOptions {
            timeout: Duration::from_secs(900),
            ..RunOptions::default()
        };
        let measured = dev_peers::run_device(target, true, &opts)?;
        let triple = target.triple().to_string();
        for r in rows.iter_mut() {
            let Some(&(_, w, mode)) = SETTINGS.iter().find(|s| s.0 == r.setting) else {
                continue;
            };
            let imp = if mode == EvalMode::Fused {
                "texcore-fused"
            } else {
                "texcore-fd"
            };
            let Some(m) = measured
                .iter()
                .find(|m| m.workload == w.name() && m.implementation == imp)
            else {
                return Err(format!("{target}: no peers row {} {imp}", w.name()));
            };
            if let Some(v) = m.instructions_per_sample {
                r.device_instructions_per_pixel.insert(triple.clone(), v);
            }
            if let Some(ok) = m.checksum_match {
                r.device_checksum_match.insert(triple.clone(), ok);
            }
        }
    }
    Ok(skipped)
}

/// The knob's section of `docs/accuracy.md`.
pub fn markdown(rows: &[&RowReport]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## `{KNOB}`\n\nPerlin gradient noise (quintic fade) on the peers' plane of \
         `docs/peers.md` (256 x 256 pixels, whole rows along the lattice's x axis through \
         `SpanEvaluator::rows`): the exact modes' stepped sums (`exact`, `EvalMode::Fd`, the \
         blend of `docs/model.md` 4.3, bit for bit `Direct`) against `EvalMode::Fused`'s \
         (`fused`, crate feature `fused`: the last product along each row's own axis, which is \
         x here, and rows of several terms without quadric floored term after term). **vs \
         exact**: the samples against `Direct`'s, in units of `2^-16` (largest, mean, share \
         equal); **vs f64**: against the f64 reference of the same model, in units of `2^-16`; \
         PSNR, max err and within 1 step of the samples as an 8-bit grey image (`[-1, 1]` to \
         `[0, 255]`) against the reference's. Device: exact instructions per sample of the peers \
         firmware's one-band jobs (`peers:perlin-*:texcore-fd`, `peers:perlin-*:texcore-fused`; \
         the whole plane's figures are in `docs/peers.md`). Code: `fused` adds the term-by-term \
         rows and the rows along y and z to the fast code shape's row schedule \
         (`docs/performance.md`); the size-lean shape has no row \
         schedule, so there it adds nothing and `Fused` evaluates as `Fd`.\n"
    );
    let _ = writeln!(
        s,
        "| setting | max vs exact | mean vs exact | equal to exact | max vs f64 | mean vs f64 | \
         PSNR | within 1 step | host ns/sample | M4F instr/sample | rv32imc instr/sample | \
         device = host |"
    );
    let _ = writeln!(
        s,
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    let m4f = DeviceTarget::CortexM4F.triple();
    let rv = DeviceTarget::Riscv32imc.triple();
    for r in rows {
        let dev = |t: &str| r.device_cell(t);
        let matched = r.device_match_cell();
        let e = r.value_error.unwrap_or_default();
        let _ = writeln!(
            s,
            "| `{}` | {} | {:.3} | {:.2}% | {:.2} | {:.2} | {:.2} | {:.2}% | {:.2} | {} | {} | {} |",
            r.setting,
            e.max_vs_exact,
            e.mean_vs_exact,
            e.equal_share * 100.0,
            e.max_vs_f64,
            e.mean_vs_f64,
            r.psnr,
            r.within_one_step * 100.0,
            r.host_ns_per_pixel,
            dev(m4f),
            dev(rv),
            matched,
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact mode's samples are `Direct`'s; the fused ones too for one octave (rows along
    /// x), and within the mode's bound for four (one unit a term for the term-by-term floors),
    /// differing somewhere.
    #[test]
    fn fused_is_within_its_bound_and_exact_is_direct() {
        for (w, bound) in [(Workload::Perlin1, 0), (Workload::Perlin4, 4)] {
            let exact = plane(w, EvalMode::Direct);
            let truth = reference(w);
            let fd = value_error(&plane(w, EvalMode::Fd), &exact, &truth);
            assert_eq!(fd.max_vs_exact, 0, "{w:?}");
            assert_eq!(fd.equal_share, 1.0);
            let fused = value_error(&plane(w, EvalMode::Fused), &exact, &truth);
            assert!(fused.max_vs_exact <= bound, "{w:?} {fused:?}");
            assert_eq!(fused.max_vs_exact == 0, bound == 0, "{w:?} {fused:?}");
            // Both within a few units of the f64 noise (the quintic fade's rounding aside).
            assert!(
                fd.max_vs_f64 < 8.0 && fused.max_vs_f64 < 8.0,
                "{fd:?} {fused:?}"
            );
        }
    }
}
