//! The table cells: device counts, code sizes and RAM against the baseline, settings.

use super::*;

pub(super) fn dev(r: &RowReport, t: &str) -> String {
    r.device_instructions_per_pixel
        .get(t)
        .map_or("-".into(), |v| format!("{v:.0}"))
}

pub(super) fn matched(r: &RowReport) -> &'static str {
    r.device_match_cell()
}

pub(super) fn pct(v: f64) -> String {
    format!("{:.2}%", 100.0 * v)
}

pub(super) fn opt_psnr(e: Option<crate::accuracy::ErrorSummary>) -> String {
    e.map_or("-".into(), |e| format!("{:.2}", e.psnr))
}

pub(super) fn opt_within(e: Option<crate::accuracy::ErrorSummary>) -> String {
    e.map_or("-".into(), |e| pct(e.within_one_step))
}

pub(super) fn host(r: &RowReport) -> String {
    format!(
        "{:.1} ({:.1}-{:.1})",
        r.host_ns_per_pixel, r.host_ns_min, r.host_ns_max
    )
}

pub(super) fn code<'a>(r: &'a RowReport, t: &str) -> Option<&'a CodeSize> {
    r.code_size.as_ref()?.get(t)
}

/// The baseline row (the first; it appears under several knobs).
pub(super) fn baseline(report: &Report) -> Option<&RowReport> {
    report.rows.iter().find(|r| r.baseline)
}

/// A signed difference: `+12`, `-12`, `0`.
pub(super) fn delta(v: u64, base: u64) -> String {
    match v.cmp(&base) {
        std::cmp::Ordering::Greater => format!("+{}", v - base),
        std::cmp::Ordering::Less => format!("-{}", base - v),
        std::cmp::Ordering::Equal => "0".into(),
    }
}

/// `value (difference from the baseline)` of a code-size field on target `t`, or `-`.
pub(super) fn code_cell(
    r: &RowReport,
    base: Option<&RowReport>,
    t: &str,
    f: fn(&CodeSize) -> u64,
) -> String {
    let Some(c) = code(r, t) else {
        return "-".into();
    };
    match base.and_then(|b| code(b, t)) {
        Some(b) => format!("{} ({})", f(c), delta(f(c), f(b))),
        None => f(c).to_string(),
    }
}

/// The instance RAM of a row: `M4F (difference)`, with rv32imc's after a slash where it differs.
pub(super) fn ram_cell(r: &RowReport, base: Option<&RowReport>) -> String {
    let m = code_cell(r, base, M4F, |c| c.instance_ram);
    match (code(r, M4F), code(r, RV)) {
        (Some(a), Some(b)) if a.instance_ram != b.instance_ram => {
            format!("{m} / {}", code_cell(r, base, RV, |c| c.instance_ram))
        }
        _ => m,
    }
}

/// The feature set of `r` as a difference from the baseline's: `+smooth-fade`, `-csat`, or
/// `same` (the baseline's).
pub(super) fn set_change(r: &RowReport, base: &RowReport) -> String {
    let of = |x: &RowReport| -> Vec<String> {
        x.code_features
            .split(',')
            .filter(|f| *f != "minimal")
            .map(str::to_string)
            .collect()
    };
    let (a, b) = (of(r), of(base));
    let mut parts: Vec<String> = a
        .iter()
        .filter(|f| !b.contains(f))
        .map(|f| format!("+{f}"))
        .collect();
    parts.extend(b.iter().filter(|f| !a.contains(f)).map(|f| format!("-{f}")));
    if parts.is_empty() {
        "same".into()
    } else {
        parts.join(" ")
    }
}

/// The code-size paragraph of the summary: the baseline's texcore code and every feature set of
/// a single-knob row that differs from it.
pub(super) fn code_summary(report: &Report) -> Option<String> {
    let base = baseline(report)?;
    let (bm, br) = (code(base, M4F)?, code(base, RV)?);
    let mut s = format!(
        "Code size (texcore `.text` on the Cortex-M4F / rv32imc, for the features a \
         configuration needs; not an axis of the front): the baseline (`{}`) is {} / {} bytes",
        base.code_features, bm.texcore_text, br.texcore_text
    );
    // Distinct sets of single-knob rows other than the baseline's, in row order (not the
    // `gradient_blend` rows: another plane and model, whose code is in the fast shape's row
    // schedule, which no size-lean probe has).
    let mut sets: Vec<(&str, Vec<&RowReport>)> = Vec::new();
    for r in report
        .rows
        .iter()
        .filter(|r| !r.combination && r.knob != crate::accuracy::blend::KNOB)
    {
        if r.code_features == base.code_features {
            continue;
        }
        match sets.iter_mut().find(|(f, _)| *f == r.code_features) {
            Some((_, v)) => v.push(r),
            None => sets.push((&r.code_features, vec![r])),
        }
    }
    let mut parts = Vec::new();
    let mut unmeasured = Vec::new();
    for (_, rows) in &sets {
        // "every `perspective` setting" when the set is that of all of a knob's settings.
        let knob = rows[0].knob;
        let of_knob = report
            .rows
            .iter()
            .filter(|r| r.knob == knob && !r.combination)
            .count();
        let names =
            if rows.len() > 1 && rows.iter().all(|r| r.knob == knob) && rows.len() == of_knob {
                format!("every `{knob}` setting")
            } else {
                let names: Vec<String> = rows.iter().map(|r| format!("`{}`", label(r))).collect();
                names.join(", ")
            };
        let (Some(m), Some(v)) = (code(rows[0], M4F), code(rows[0], RV)) else {
            unmeasured.push(names);
            continue;
        };
        let mut p = format!(
            "{names} ({}): {} / {}",
            set_change(rows[0], base),
            delta(m.texcore_text, bm.texcore_text),
            delta(v.texcore_text, br.texcore_text)
        );
        if m.rodata != bm.rodata || v.rodata != br.rodata {
            let _ = write!(
                p,
                ", `.rodata` {} / {}",
                delta(m.rodata, bm.rodata),
                delta(v.rodata, br.rodata)
            );
        }
        parts.push(p);
    }
    if parts.is_empty() {
        s.push('.');
    } else {
        let _ = write!(s, "; the settings that change it: {}.", parts.join("; "));
    }
    if !unmeasured.is_empty() {
        let _ = write!(s, " Not measured in this run: {}.", unmeasured.join(", "));
    }
    s.push_str(
        " Every other setting is a run-time choice over the baseline's code; what the table size \
         and the filter change is the RAM of a texture-unit instance (see their tables).",
    );
    Some(s)
}
