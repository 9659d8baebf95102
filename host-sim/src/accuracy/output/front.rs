//! The summary's front: the baseline, the cheapest exact configuration, the cheapest within
//! one step and the cheapest of all.

use super::*;

/// The configurations the README calls "exact", "within one step" and "cheapest".
struct Front<'a> {
    /// The baseline row.
    baseline: &'a RowReport,
    /// The cheapest configuration with exactly the baseline's image.
    best: &'a RowReport,
    /// Per-pixel evaluation (the definition), if measured.
    direct: Option<&'a RowReport>,
    within: Option<&'a RowReport>,
    cheapest: &'a RowReport,
}

fn front(report: &Report) -> Option<Front<'_>> {
    let cands: Vec<&RowReport> = report.rows.iter().filter(|r| r.base.is_some()).collect();
    let psnr = |r: &RowReport| r.base.map_or(0.0, |b| b.psnr);
    let baseline = cands.iter().copied().find(|r| r.baseline)?;
    // Bit-identical to the baseline (same checksum of the device window and same errors).
    let best = cands
        .iter()
        .copied()
        .filter(|r| r.checksum == baseline.checksum && r.base == baseline.base)
        .min_by(|a, b| cost(a).total_cmp(&cost(b)))?;
    let direct = cands
        .iter()
        .copied()
        .find(|r| r.id == "acc:evaluation=direct");
    let within = cands
        .iter()
        .copied()
        .filter(|r| r.base.is_some_and(|b| b.within_one_step >= WITHIN))
        .min_by(|a, b| {
            cost(a)
                .total_cmp(&cost(b))
                .then(psnr(b).total_cmp(&psnr(a)))
        });
    let cheapest = cands
        .iter()
        .copied()
        .filter(|r| r.pareto)
        .min_by(|a, b| cost(a).total_cmp(&cost(b)))?;
    Some(Front {
        baseline,
        best,
        direct,
        within,
        cheapest,
    })
}

fn costs(r: &RowReport) -> String {
    match (
        r.device_instructions_per_pixel.get(M4F),
        r.device_instructions_per_pixel.get(RV),
    ) {
        (Some(m), Some(v)) => format!("{m:.0} instructions a pixel ({v:.0} on rv32imc)"),
        _ => format!(
            "{:.1} host ns a pixel (no device counts)",
            r.host_ns_per_pixel
        ),
    }
}

/// The generated summary of the front (README and the head of `docs/accuracy.md`).
pub fn front_summary(report: &Report) -> String {
    let mut s = String::new();
    let Some(f) = front(report) else {
        return "No configuration was measured.\n".into();
    };
    let name = |r: &RowReport| label(r);
    let _ = writeln!(
        s,
        "For the `marble` preset's check plane on a Cortex-M4F (errors against the exact f64 \
         image of the baseline, {}x{} pixels; device counts over its top-left 64x64):",
        report.settings.plane_size, report.settings.plane_size
    );
    let _ = writeln!(s);
    let b = f.best.base.unwrap_or_default();
    let also = if f.best.id == f.baseline.id || cost(f.best) == cost(f.baseline) {
        String::new()
    } else {
        format!(
            "; the baseline itself (`auto`, `csat`) costs {}",
            costs(f.baseline)
        )
    };
    let direct = f
        .direct
        .map(|d| {
            format!(
                "; per-pixel `direct` evaluation of the same image costs {}",
                costs(d)
            )
        })
        .unwrap_or_default();
    let _ = writeln!(
        s,
        "- exact, i.e. the baseline's image bit for bit (PSNR {:.2} dB, {} of the pixels within \
         one 8-bit step of the f64 reference), costs {} with `{}`{also}{direct};",
        b.psnr,
        pct(b.within_one_step),
        costs(f.best),
        name(f.best),
    );
    match f.within {
        Some(w) => {
            let wb = w.base.unwrap_or_default();
            let _ = writeln!(
                s,
                "- within one 8-bit step of the f64 reference on {} of the pixels costs {} with \
                 `{}` (PSNR {:.2} dB, {} within);",
                pct(WITHIN),
                costs(w),
                name(w),
                wb.psnr,
                pct(wb.within_one_step)
            );
        }
        None => {
            let _ = writeln!(
                s,
                "- no configuration stays within one 8-bit step on {} of the pixels;",
                pct(WITHIN)
            );
        }
    }
    let cb = f.cheapest.base.unwrap_or_default();
    let _ = writeln!(
        s,
        "- the cheapest point of the Pareto front, `{}`, costs {} at PSNR {:.2} dB ({} within \
         one step).",
        name(f.cheapest),
        costs(f.cheapest),
        cb.psnr,
        pct(cb.within_one_step)
    );
    let prec: Vec<&RowReport> = report
        .rows
        .iter()
        .filter(|r| r.knob == "coordinate_bits" && r.scene.is_some())
        .collect();
    if let (Some(lo), Some(hi)) = (prec.first(), prec.last()) {
        let (ls, hs) = (lo.scene.unwrap_or_default(), hi.scene.unwrap_or_default());
        let (cl, ch) = (cost(lo), cost(hi));
        let unit = if lo.device_instructions_per_pixel.contains_key(M4F) {
            "M4F instructions"
        } else {
            "host ns"
        };
        let time = if cl >= ch {
            format!(
                "fewer bits save no time on a 32-bit core ({cl:.0} against {ch:.0} {unit} a \
                 pixel on the check plane)"
            )
        } else {
            format!(
                "fewer bits save {:.0} {unit} a pixel on the check plane ({cl:.0} against {ch:.0})",
                ch - cl
            )
        };
        let _ = writeln!(
            s,
            "\nCoordinate precision (the paper's Fig. 10): on the `marble` scene {} fraction bits \
             give {:.2} dB against {:.2} dB at {} bits; {time}.",
            lo.setting, ls.psnr, hs.psnr, hi.setting
        );
    }
    if let Some(c) = code_summary(report) {
        let _ = writeln!(s, "\n{c}");
    }
    s
}
