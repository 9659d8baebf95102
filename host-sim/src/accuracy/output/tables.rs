//! The report's per-knob tables and their notes.

use super::*;

/// A row's name in the summaries: `baseline` for the baseline, else `knob=setting`.
pub fn label(r: &RowReport) -> String {
    if r.baseline {
        "baseline".into()
    } else {
        r.id.trim_start_matches("acc:").to_string()
    }
}

pub(super) fn knob_note(k: Knob) -> &'static str {
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
pub(super) fn code_note(rows: &[&RowReport], base: Option<&RowReport>) -> String {
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

pub(super) fn table_for(
    s: &mut String,
    rows: &[&RowReport],
    knob: Option<Knob>,
    base: Option<&RowReport>,
) {
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
