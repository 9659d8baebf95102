//! The report's generated text: `docs/accuracy.md`, the README summary, the console summary.

use std::fmt::Write as _;
use std::path::Path;

use super::codesize::CodeSize;
use super::device_jobs::Knob;
use super::{cost, plot, Report, RowReport, BASELINE_TEXT};

const M4F: &str = "thumbv7em-none-eabihf";
/// "Within one 8-bit step" in the summary: on at least this fraction of the pixels.
const WITHIN: f64 = 0.99;
const RV: &str = "riscv32imc-unknown-none-elf";

/// README markers around the generated summary.
pub const BEGIN: &str = "<!-- accuracy:begin -->";
/// End marker.
pub const END: &str = "<!-- accuracy:end -->";

fn dev(r: &RowReport, t: &str) -> String {
    r.device_instructions_per_pixel
        .get(t)
        .map_or("-".into(), |v| format!("{v:.0}"))
}

fn matched(r: &RowReport) -> &'static str {
    r.device_match_cell()
}

fn pct(v: f64) -> String {
    format!("{:.2}%", 100.0 * v)
}

fn opt_psnr(e: Option<super::ErrorSummary>) -> String {
    e.map_or("-".into(), |e| format!("{:.2}", e.psnr))
}

fn opt_within(e: Option<super::ErrorSummary>) -> String {
    e.map_or("-".into(), |e| pct(e.within_one_step))
}

fn host(r: &RowReport) -> String {
    format!(
        "{:.1} ({:.1}-{:.1})",
        r.host_ns_per_pixel, r.host_ns_min, r.host_ns_max
    )
}

fn code<'a>(r: &'a RowReport, t: &str) -> Option<&'a CodeSize> {
    r.code_size.as_ref()?.get(t)
}

/// The baseline row (the first; it appears under several knobs).
fn baseline(report: &Report) -> Option<&RowReport> {
    report.rows.iter().find(|r| r.baseline)
}

/// A signed difference: `+12`, `-12`, `0`.
fn delta(v: u64, base: u64) -> String {
    match v.cmp(&base) {
        std::cmp::Ordering::Greater => format!("+{}", v - base),
        std::cmp::Ordering::Less => format!("-{}", base - v),
        std::cmp::Ordering::Equal => "0".into(),
    }
}

/// `value (difference from the baseline)` of a code-size field on target `t`, or `-`.
fn code_cell(r: &RowReport, base: Option<&RowReport>, t: &str, f: fn(&CodeSize) -> u64) -> String {
    let Some(c) = code(r, t) else {
        return "-".into();
    };
    match base.and_then(|b| code(b, t)) {
        Some(b) => format!("{} ({})", f(c), delta(f(c), f(b))),
        None => f(c).to_string(),
    }
}

/// The instance RAM of a row: `M4F (difference)`, with rv32imc's after a slash where it differs.
fn ram_cell(r: &RowReport, base: Option<&RowReport>) -> String {
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
fn set_change(r: &RowReport, base: &RowReport) -> String {
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
fn code_summary(report: &Report) -> Option<String> {
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
        .filter(|r| !r.combination && r.knob != super::blend::KNOB)
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

/// A row's name in the summaries: `baseline` for the baseline, else `knob=setting`.
pub fn label(r: &RowReport) -> String {
    if r.baseline {
        "baseline".into()
    } else {
        r.id.trim_start_matches("acc:").to_string()
    }
}

fn knob_note(k: Knob) -> &'static str {
    match k {
        Knob::CoordinateBits => {
            "Lattice-coordinate fraction bits `F` (`docs/model.md` 3.2: `U0` and `DU` of every \
             span rounded to `F` bits). The check plane's coordinates are multiples of small powers \
             of two, so its column only shows what few bits do; the `marble` scene (perspective, \
             unaligned coordinates) is measured too. `docs/precision.png` shows the scene at each \
             setting."
        }
        Knob::ValueBits => {
            "Bits of the value-noise corner values `V` (`docs/model.md` 3.2). Scene column: the \
             `marble` scene."
        }
        Knob::Interpolation => {
            "The fade of every octave; each setting is a different texture, so errors are against \
             the f64 reference of the same fade."
        }
        Knob::Evaluation => {
            "Span evaluation mode (`direct`, `fd`, `auto` are bit-identical by construction; \
             `fd32` takes the exact merged path for non-turbulent trilinear terms, and \
             `reanchored` only changes non-trilinear terms, so on the trilinear baseline both \
             give the same image) and `auto` with culling off (`auto-nocull`, reference without \
             culling)."
        }
        Knob::Octaves => {
            "Octaves `2^-i n(2^i s)`, `i < count`; `base` compares with the 4-octave baseline \
             image."
        }
        Knob::TableSize => {
            "Colour-table entries (the reference uses the same table); `256-linear` is the linear \
             look-up, which the `csat` box filter does not use (its combination with no filter \
             is among the combinations)."
        }
        Knob::Antialiasing => {
            "Colour-table filter. `supersampled`: against 8x8 (quick: 2x2) stratified point \
             samples of the f64 model per pixel; `seascape`: the seascape's first frame against \
             its supersampled truth; flicker: mean absolute frame-to-frame difference of the \
             band of rows around the seascape's horizon (a quarter of the image height) over the \
             first frames of its animation (texcore / supersampled truth; the truth culls only \
             octaves past the Nyquist limit of its own samples), and the same for texcore with \
             octave culling off (the papers' unit culls nothing). `ramp` (feature `ramp`) \
             approximates `csat` with one read a pixel of RGB565 levels and shades straight to \
             RGB565 (the device jobs take `shade565`, its own path, and fold RGB565 words): its \
             colours are RGB565 expanded, so every error column includes the reduction to \
             RGB565, which an RGB565 display applies to every filter's colours (`csat` reduced \
             to RGB565 measures 42.0 dB against the baseline's reference on this plane, \
             `docs/performance.md`, twenty-ninth round), and `within 1 step` is out of its \
             reach."
        }
        Knob::GradientNorm => "Norm of the filter width's gradient.",
        Knob::Perspective => {
            "Perspective interpolation of every object of the seascape (160x120, still frame); \
             error against the f64 reference of the scene drawn with exact perspective; device \
             counts per frame pixel, the scene walk and rasterizer included."
        }
        Knob::Basis => {
            "Noise basis; each is a different texture, errors against the f64 reference of the \
             same basis."
        }
        Knob::Hash => "Lattice hash; errors against the f64 reference with the same hash.",
        Knob::FilterWidths => {
            "Where the filter widths come from: the analytic gradients of `f` (exact, the \
             baseline) or the differences of neighbouring values, as a GPU's `ddx`/`ddy` \
             (`differences`, `texcore::texture::DifferenceSpans`, `docs/model.md` 8.4: the noise \
             evaluated without its gradients, each pixel's width from its right neighbour and the \
             pixel above, the last pixel of a span from its left neighbour). Errors against the \
             f64 reference with the analytic gradients. `ramp+differences` is the cheapest \
             filtered configuration, shaded straight to RGB565 as `ramp`."
        }
        Knob::BandLimit => {
            "Band-limiting of the octaves past the Nyquist limit (`texcore::bandlimit::BandLimit`, \
             `docs/model.md` section 8), on the seascape (160x120, still frame, its own `every16` \
             perspective): `footprint` (the default) weighs a faded octave by one over the square \
             root of the cells the pixel's footprint covers, `reach` by one over its largest \
             reach; `floor` is the smallest weight (default 1/4), `share` the part of the faded \
             variance `1 - w^2` that widens the filter (default 3/4); `off` is no band-limiting \
             (every octave at full amplitude, its whole variance past Nyquist in the filter). \
             PSNR: against the f64 reference of the scene drawn with exact perspective and the \
             default band-limiting; `seascape supersampled`: the first frame against its \
             supersampled truth; flicker as for `antialiasing`. Device counts per frame pixel, \
             the scene walk and rasterizer included."
        }
    }
}

/// The code-size note of a knob's table.
fn code_note(rows: &[&RowReport], base: Option<&RowReport>) -> String {
    let Some(base) = base else {
        return String::new();
    };
    let mut sets: Vec<&str> = Vec::new();
    for r in rows {
        if !sets.contains(&r.code_features.as_str()) {
            sets.push(&r.code_features);
        }
    }
    let sizes = |r: &RowReport| match (code(r, M4F), code(r, RV)) {
        (Some(m), Some(v)) => format!(
            "texcore `.text` {} bytes on the Cortex-M4F, {} on rv32imc",
            m.texcore_text, v.texcore_text
        ),
        _ => "not measured in this run".into(),
    };
    let mut s = match sets.as_slice() {
        [one] if *one == base.code_features => format!(
            "**Code size**: unchanged; every setting is a run-time choice over the same code \
             (`{one}`: {}).",
            sizes(base)
        ),
        [one] => format!(
            "**Code size**: every setting is a run-time choice over the same code, `{one}` \
             ({} against the baseline's `{}`): {}.",
            set_change(rows[0], base),
            base.code_features,
            sizes(rows[0])
        ),
        _ => format!(
            "**Code size**: the settings need different code; the texcore `.text` columns give \
             each feature set's size and its difference from the baseline's (`{}`).",
            base.code_features
        ),
    };
    let rodata: Vec<String> = rows
        .iter()
        .filter_map(|r| {
            let (m, v) = (code(r, M4F)?, code(r, RV)?);
            let (bm, bv) = (code(base, M4F)?, code(base, RV)?);
            (m.rodata != bm.rodata || v.rodata != bv.rodata).then(|| {
                format!(
                    "`{}` {} / {}",
                    r.setting,
                    delta(m.rodata, bm.rodata),
                    delta(v.rodata, bv.rodata)
                )
            })
        })
        .collect();
    if !rodata.is_empty() {
        let _ = write!(
            s,
            " `.rodata` against the baseline (Cortex-M4F / rv32imc): {}.",
            rodata.join(", ")
        );
    }
    if ram_differs(rows, Some(base)) {
        s.push_str(
            " The settings change the RAM of a texture-unit instance (`unit RAM`): the colour \
             table with its filter's data (csat sums, MIP levels) depends on the table size and \
             the filter.",
        );
    }
    s
}

/// Whether some measured row's instance RAM differs from the baseline's.
fn ram_differs(rows: &[&RowReport], base: Option<&RowReport>) -> bool {
    rows.iter().any(|r| {
        r.code_size.is_some()
            && [M4F, RV].iter().any(|t| {
                code(r, t).map(|c| c.instance_ram)
                    != base.and_then(|b| code(b, t)).map(|c| c.instance_ram)
            })
    })
}

fn table_for(s: &mut String, rows: &[&RowReport], knob: Option<Knob>, base: Option<&RowReport>) {
    // The RAM column where some row's instance differs from the baseline's.
    let ram = ram_differs(rows, base);
    let scene = matches!(knob, Some(Knob::CoordinateBits | Knob::ValueBits));
    let aa = matches!(knob, Some(Knob::Antialiasing | Knob::BandLimit));
    let mut head = String::from(
        "| setting | PSNR dB | max err | within 1 step | base PSNR | base within | \
         supersampled PSNR |",
    );
    let mut sep = String::from("|---|---:|---:|---:|---:|---:|---:|");
    if scene {
        head.push_str(" scene PSNR | scene within |");
        sep.push_str("---:|---:|");
    }
    if aa {
        head.push_str(" seascape supersampled PSNR | flicker (truth) | flicker, no culling |");
        sep.push_str("---:|---:|---:|");
    }
    head.push_str(
        " host ns/px (range) | M4F instr/px | rv32imc instr/px | device = host | features | \
         M4F texcore .text (diff) | rv32imc texcore .text (diff) |",
    );
    sep.push_str("---:|---:|---:|:-:|---|---:|---:|");
    if ram {
        head.push_str(" unit RAM (diff) |");
        sep.push_str("---:|");
    }
    head.push_str(" front |");
    sep.push_str(":-:|");
    let _ = writeln!(s, "{head}\n{sep}");
    for r in rows {
        let mut line = format!(
            "| `{}` | {:.2} | {:.2} | {} | {} | {} | {} |",
            if knob.is_some() {
                r.setting.to_string()
            } else {
                label(r)
            },
            r.psnr,
            r.max_error,
            pct(r.within_one_step),
            opt_psnr(r.base),
            opt_within(r.base),
            opt_psnr(r.supersampled),
        );
        if scene {
            let _ = write!(line, " {} | {} |", opt_psnr(r.scene), opt_within(r.scene));
        }
        if aa {
            let fl = r.flicker.map_or("-".into(), |f| {
                format!("{:.2} ({:.2})", f.texcore, f.reference)
            });
            let fln = r
                .flicker_nocull
                .map_or("-".into(), |f| format!("{:.2}", f.texcore));
            let _ = write!(
                line,
                " {} | {} | {} |",
                opt_psnr(r.scene_supersampled),
                fl,
                fln
            );
        }
        let _ = write!(
            line,
            " {} | {} | {} | {} | `{}` | {} | {} |",
            host(r),
            dev(r, M4F),
            dev(r, RV),
            matched(r),
            r.code_features,
            code_cell(r, base, M4F, |c| c.texcore_text),
            code_cell(r, base, RV, |c| c.texcore_text),
        );
        if ram {
            let _ = write!(line, " {} |", ram_cell(r, base));
        }
        let _ = write!(line, " {} |", if r.pareto { "yes" } else { "" });
        let _ = writeln!(s, "{line}");
    }
    let _ = writeln!(s);
}

/// `docs/accuracy.md`.
pub fn markdown(report: &Report) -> String {
    let mut s = String::new();
    let st = &report.settings;
    let _ = writeln!(s, "# What accuracy costs\n");
    let _ = writeln!(
        s,
        "Generated by `texsim report accuracy`{} on {} rows in {:.0} s ({:.0} s of it building \
         and running the firmware under QEMU, {:.0} s building the code-size probes); do not \
         edit by hand. Reproduce with \
         `cargo run --release -p host-sim --bin texsim -- report accuracy --write-docs`, which \
         rewrites this file, `docs/accuracy.png`, `docs/precision.png` and the summary in `README.md`.\n",
        if report.quick { " --quick" } else { "" },
        report.rows.len(),
        report.seconds.0,
        report.seconds.1,
        report.code_seconds
    );
    let _ = writeln!(s, "**Baseline**: {BASELINE_TEXT}.\n");
    let _ = writeln!(s, "## Method\n");
    let _ = writeln!(
        s,
        "- Every knob is varied alone from the baseline; the combinations at the end are \
         Pareto-front candidates. The configurations are defined once, in \
         `workloads/src/accuracy.rs`, which the firmware and the host share.\n\
         - **PSNR / max err / within 1 step**: the first {ps}x{ps} pixels of the marble check \
         plane (1/128 per pixel, {seg}-pixel spans) against the f64 reference with the row's \
         table, filter, norm and culling, at ideal precision and exact evaluation (what `texsim \
         check` reports). Max err in 8-bit units; within 1 step: every channel within one step \
         of the rounded reference.\n\
         - **base**: the same image against the *baseline's* f64 reference (rows that render \
         the baseline's texture): the error axis of the Pareto front.\n\
         - **supersampled**: against {ss}x{ss} stratified point samples a pixel of the f64 model \
         of the baseline's texture through its 256-entry table (nearest) - what a filter \
         approximates.\n\
         - **host ns/px**: median (fastest-slowest) of {runs} timed runs of the device job's own \
         code over the {ps}x{ps} plane on the development machine (shared, so noisy).\n\
         - **M4F / rv32imc instr/px**: exact instruction counts under QEMU (`-icount \
         shift=0`) of the firmware job over the top-left 64x64 pixels, minus the set-up job \
         that builds the same texture, divided by 4096 (perspective rows: the {sw}x{sh} \
         seascape, divided by its pixels). **device = host**: the device's checksum equals the \
         same code run on the host, and the host's error image contains exactly those pixels.\n\
         - **features / texcore .text**: the features the configuration needs, and the bytes \
         of `.text` that the DWARF line tables attribute to texcore (inlined code included) on \
         each target, with the difference from the baseline's, measured as `texsim report size` \
         does: `texcore-probe` (`firmware/src/probe.rs`, profile `release-size`) built with \
         exactly those features{quick_sets}. The probe keeps every compiled-in path linked, so \
         a setting chosen at run time never changes it. Features: {features}; `minimal`: none \
         of them (value noise, integer hash, no filter).\n\
         - **unit RAM** (where a knob changes it): one texture-unit instance, i.e. the colour \
         table with its csat sums or MIP levels at the row's table size, `TextureModel<8>` and \
         the texture evaluator, in bytes on the Cortex-M4F (rv32imc after a slash where it \
         differs), with the difference from the baseline's.\n\
         - **front**: on the Pareto front of base PSNR against M4F instructions (host ns when \
         QEMU is missing).\n",
        ps = st.plane_size,
        seg = super::device_jobs::SEGMENT,
        ss = st.supersample,
        runs = st.host_runs,
        sw = super::device_jobs::SCENE_W,
        sh = super::device_jobs::SCENE_H,
        quick_sets = if report.quick {
            " (`--quick`: only the sets of the baseline and of `antialiasing=none`; `-` \
             elsewhere)"
        } else {
            ""
        },
        features = super::codesize::FEATURE_RULES
            .iter()
            .map(|f| format!("`{}` {}", f.name, f.what))
            .collect::<Vec<_>>()
            .join(", "),
    );
    if !report.device_skipped.is_empty() {
        let _ = writeln!(
            s,
            "Device counts missing: {}\n",
            report.device_skipped.join("; ")
        );
    }
    let _ = writeln!(s, "## Summary\n");
    let _ = writeln!(s, "{}", front_summary(report));
    let _ = writeln!(s, "![error against instructions](accuracy.png)\n");
    let _ = writeln!(s, "## Pareto front\n");
    let mut seen = std::collections::HashSet::new();
    let mut fr: Vec<&RowReport> = report
        .rows
        .iter()
        .filter(|r| r.pareto && seen.insert(format!("{}/{}", r.checksum, cost(r))))
        .collect();
    fr.sort_by(|a, b| cost(a).total_cmp(&cost(b)));
    let _ = writeln!(
        s,
        "One row per distinct image and cost (the baseline appears under several knobs). A \
         configuration is on the front when no other is cheaper (M4F instructions) at a base \
         PSNR at most 0.1 dB lower.\n"
    );
    let base = baseline(report);
    table_for(&mut s, &fr, None, base);
    for k in Knob::ALL {
        let rows: Vec<&RowReport> = report
            .rows
            .iter()
            .filter(|r| r.knob == k.name() && !r.combination)
            .collect();
        if rows.is_empty() {
            continue;
        }
        let _ = writeln!(s, "## `{}`\n\n{}\n", k.name(), knob_note(k));
        let note = code_note(&rows, base);
        if !note.is_empty() {
            let _ = writeln!(s, "{note}\n");
        }
        table_for(&mut s, &rows, Some(k), base);
        if k == Knob::CoordinateBits && !report.precision_images.is_empty() {
            let _ = writeln!(s, "![marble at each coordinate precision](precision.png)\n");
        }
    }
    let shading: Vec<&RowReport> = report.rows.iter().filter(|r| r.knob == "shading").collect();
    if !shading.is_empty() {
        let _ = writeln!(s, "{}", super::shading::markdown(&shading));
    }
    let blend: Vec<&RowReport> = report
        .rows
        .iter()
        .filter(|r| r.knob == super::blend::KNOB)
        .collect();
    if !blend.is_empty() {
        let _ = writeln!(s, "{}", super::blend::markdown(&blend));
    }
    let combos: Vec<&RowReport> = report.rows.iter().filter(|r| r.combination).collect();
    if !combos.is_empty() {
        let _ = writeln!(s, "## Combinations\n");
        table_for(&mut s, &combos, None, base);
    }
    s
}

/// Writes `accuracy.md`, `accuracy.png` and `precision.png` into `dir`.
pub fn write_docs(report: &Report, dir: &Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let md = markdown(report);
    crate::output::write_atomic(&dir.join("accuracy.md"), |w| {
        use std::io::Write;
        w.write_all(md.as_bytes())
            .map_err(|e| crate::output::OutputError::Io {
                path: dir.join("accuracy.md"),
                source: e,
            })
    })
    .map_err(|e| e.to_string())?;
    if let Some(f) = plot::front_plot(report) {
        crate::output::write_png(&dir.join("accuracy.png"), &f).map_err(|e| e.to_string())?;
    }
    if let Some(f) = plot::contact_sheet(report) {
        crate::output::write_png(&dir.join("precision.png"), &f).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// `text` with the part between the README markers replaced by `section` (appended with the
/// markers when they are missing).
pub fn replace_section(text: &str, section: &str) -> String {
    match (text.find(BEGIN), text.find(END)) {
        (Some(a), Some(b)) if a < b => {
            format!("{}{BEGIN}\n{section}{}", &text[..a], &text[b..])
        }
        _ => format!("{}\n{BEGIN}\n{section}{END}\n", text.trim_end()),
    }
}

/// Rewrites the README's generated accuracy summary.
pub fn update_readme(report: &Report, path: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let section = format!(
        "{}\nGenerated by `texsim report accuracy`; tables, plot and method in \
         [`docs/accuracy.md`](docs/accuracy.md).\n",
        front_summary(report)
    );
    let new = replace_section(&text, &section);
    crate::output::write_atomic(path, |w| {
        use std::io::Write;
        w.write_all(new.as_bytes())
            .map_err(|e| crate::output::OutputError::Io {
                path: path.to_path_buf(),
                source: e,
            })
    })
    .map_err(|e| e.to_string())
}

/// The console summary (without `--json`).
pub fn text_summary(report: &Report) -> String {
    let mut s = String::new();
    for r in &report.rows {
        let _ = writeln!(
            s,
            "{:<34} psnr {:>6.2} max {:>6.2} within {:>8} host {:>8.1} ns  m4f {:>7}  rv32 {:>7}  \
             code {:>6}{}",
            r.id,
            r.psnr,
            r.max_error,
            pct(r.within_one_step),
            r.host_ns_per_pixel,
            dev(r, M4F),
            dev(r, RV),
            code(r, M4F).map_or("-".into(), |c| c.texcore_text.to_string()),
            if r.pareto { "  front" } else { "" }
        );
    }
    let _ = writeln!(s, "\n{}", front_summary(report));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readme_section_is_replaced_or_appended() {
        let t = format!("# A\n\n{BEGIN}\nold\n{END}\n\n## B\n");
        let n = replace_section(&t, "new\n");
        assert_eq!(n, format!("# A\n\n{BEGIN}\nnew\n{END}\n\n## B\n"));
        assert_eq!(replace_section(&n, "new\n"), n);
        let m = replace_section("# A\n", "x\n");
        assert_eq!(m, format!("# A\n{BEGIN}\nx\n{END}\n"));
    }
}
