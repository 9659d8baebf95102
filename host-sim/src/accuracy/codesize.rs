//! Code size where a knob changes it: each row's configuration needs a set of texcore features
//! ([`FEATURE_RULES`]); the report builds `texcore-probe` (`firmware/src/probe.rs`, profile
//! `release-size`) once per distinct set and target, exactly as `texsim report size` does
//! ([`crate::report::size::probe_facts`]), and reads texcore's share of `.text` (DWARF line
//! attribution, inlined code included), the ELF's `.text` and `.rodata`.
//!
//! The probe hides its texture from the optimiser, so every path the compiled-in features allow
//! stays linked: a knob whose settings are run-time choices over the same code (precision,
//! octaves, table size and look-up, gradient norm, evaluation mode, culling) has one feature set
//! and so one code size for all its settings. What the table size changes is RAM: every row also
//! gets the RAM of one texture-unit instance with its configuration ([`table_ram`] plus the
//! model and the texture evaluator, `core::mem::size_of` on the target from the probe's
//! `TEXCORE_PROBE_SIZES`). The colour-stage part is computed on the host with
//! [`ColorStage::bytes_for`]; its layouts (arrays of `Rgba8888` and `u64`) are the same on the
//! host and both targets, which every measurement checks against the probe's own sizes of the
//! 256-entry colour table and csat.

use std::collections::BTreeMap;
use std::time::Instant;

use serde::Serialize;
use texcore::filter::{Antialias, ColorStage, Csat, WidthSource};
use texcore::hash::HashKind;
use texcore::span::EvalMode;
use texcore::table::ColorTable;

use super::device_jobs::{BasisSel, Config, FadeSel, Row, BASELINE};
use crate::device::{DeviceTarget, RunOptions};
use crate::report::size;

/// A feature of the probe that some configurations need.
#[derive(Clone, Copy, Debug)]
pub struct FeatureRule {
    /// Name in the report: the texcore feature, or `render` (the probe's banded renderer).
    pub name: &'static str,
    /// The probe's cargo feature: `texcore?/<name>` for texcore's own, on both targets (the
    /// firmware's own `csat`, `mip`, ... and `texcore/<name>` would also switch on its
    /// Cortex-M-only dependency on texcore with `perm-hash`).
    pub cargo: &'static str,
    /// Whether a configuration needs it.
    pub needs: fn(&Config) -> bool,
    /// Which settings need it, in words.
    pub what: &'static str,
}

/// Which features a configuration needs, in report order: the single place that maps knob
/// settings to code. Everything a configuration sets that is not named here (coordinate and
/// value bits, octaves, table size and look-up, gradient norm, the forward-differencing mode,
/// culling, perspective mode) is chosen at run time over the same compiled code.
pub const FEATURE_RULES: [FeatureRule; 11] = [
    FeatureRule {
        name: "fd",
        cargo: "texcore?/fd",
        needs: |c| c.mode != EvalMode::Direct,
        what: "forward differencing (every evaluation mode but `direct`)",
    },
    FeatureRule {
        name: "perm-hash",
        cargo: "texcore?/perm-hash",
        needs: |c| c.hash == HashKind::Permutation,
        what: "the permutation hash (`hash=perm`, a 256-byte table)",
    },
    FeatureRule {
        name: "smooth-fade",
        cargo: "texcore?/smooth-fade",
        needs: |c| matches!(c.fade, FadeSel::Smooth | FadeSel::Quintic),
        what: "the smooth and quintic fades",
    },
    FeatureRule {
        name: "gradient-noise",
        cargo: "texcore?/gradient-noise",
        needs: |c| c.basis == BasisSel::Gradient,
        what: "the gradient-noise basis",
    },
    FeatureRule {
        name: "mnoise",
        cargo: "texcore?/mnoise",
        needs: |c| c.basis == BasisSel::MNoise,
        what: "the mNoise basis",
    },
    FeatureRule {
        name: "csat",
        cargo: "texcore?/csat",
        needs: |c| matches!(c.aa, Antialias::Csat | Antialias::Csat3),
        what: "the `csat` and `csat3` filters",
    },
    FeatureRule {
        name: "mip",
        cargo: "texcore?/mip",
        needs: |c| c.aa == Antialias::Mip,
        what: "the MIP filter",
    },
    FeatureRule {
        name: "ramp",
        cargo: "texcore?/ramp",
        needs: |c| c.aa == Antialias::Ramp,
        what: "the pre-filtered RGB565 ramp (`antialiasing=ramp`)",
    },
    FeatureRule {
        name: "multipass",
        cargo: "texcore?/multipass",
        needs: |c| matches!(c.mode, EvalMode::Multipass(_)),
        what: "multipass corner-by-corner noise (`evaluation=multipass-*`)",
    },
    FeatureRule {
        name: "differences",
        cargo: "differences",
        needs: |c| c.widths == WidthSource::Differences,
        what: "the filter widths from differences (`filter_widths=differences`; a probe \
               feature, not texcore's: `texture::DifferenceSpans` is linked where it is called)",
    },
    FeatureRule {
        name: "render",
        cargo: "render",
        needs: |c| c.perspective.is_some(),
        what: "the banded renderer, for every perspective mode (a probe feature, not texcore's)",
    },
];

/// The features `cfg` needs, in [`FEATURE_RULES`] order.
pub fn rules_for(cfg: &Config) -> Vec<&'static FeatureRule> {
    FEATURE_RULES.iter().filter(|r| (r.needs)(cfg)).collect()
}

/// The name of the feature set `cfg` needs: the features joined by `,`, or `minimal`.
pub fn feature_set(cfg: &Config) -> String {
    let names: Vec<&str> = rules_for(cfg).iter().map(|r| r.name).collect();
    if names.is_empty() {
        "minimal".into()
    } else {
        names.join(",")
    }
}

/// The configurations whose feature sets `--quick` measures: the baseline and the baseline
/// without a filter (so the csat code is measured against none; every row with one of these
/// sets gets its code size, the others none).
pub const QUICK_CONFIGS: [Config; 2] = [
    BASELINE,
    Config {
        aa: Antialias::None,
        ..BASELINE
    },
];

/// The code size of a row's configuration on one target.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct CodeSize {
    /// The feature set built (`minimal` or texcore features and `render`, joined by `,`).
    pub features: String,
    /// `.text` bytes attributed to texcore by the DWARF line tables (inlined code included).
    pub texcore_text: u64,
    /// The probe's `.text` bytes (start-up, runtime and the probe's own code included).
    pub text: u64,
    /// The probe's `.rodata` bytes (the permutation hash's 256-byte table included).
    pub rodata: u64,
    /// Colour table with the data its filter needs (csat sums, MIP levels) at the row's table
    /// size and filter ([`table_ram`]).
    pub table_ram: u64,
    /// One texture-unit instance: `table_ram` + `TextureModel<8>` + `TextureEvaluator`.
    pub instance_ram: u64,
}

/// What one probe build gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Build {
    /// texcore's `.text` bytes.
    pub texcore_text: u64,
    /// `.text` bytes.
    pub text: u64,
    /// `.rodata` bytes.
    pub rodata: u64,
    /// `size_of::<TextureModel<8>>()` on the target.
    pub model: u64,
    /// `size_of::<TextureEvaluator<8, 256>>()` on the target (independent of the table size).
    pub evaluator: u64,
}

/// The builds of a run: `triple -> feature set -> build`.
#[derive(Clone, Debug, Default)]
pub struct CodeSizes {
    /// The measured builds.
    pub builds: BTreeMap<&'static str, BTreeMap<String, Build>>,
    /// Wall-clock seconds spent building.
    pub seconds: f64,
}

impl CodeSizes {
    /// The code size of `cfg` on every target, or `None` if its feature set was not measured on
    /// every target.
    pub fn of(&self, cfg: &Config) -> Option<BTreeMap<String, CodeSize>> {
        if self.builds.is_empty() {
            return None;
        }
        let set = feature_set(cfg);
        let table = table_ram(cfg)?;
        self.builds
            .iter()
            .map(|(triple, sets)| {
                let b = sets.get(&set)?;
                Some((
                    triple.to_string(),
                    CodeSize {
                        features: set.clone(),
                        texcore_text: b.texcore_text,
                        text: b.text,
                        rodata: b.rodata,
                        table_ram: table,
                        instance_ram: table + b.model + b.evaluator,
                    },
                ))
            })
            .collect()
    }
}

/// Bytes of the colour table and of the data its filter needs at `cfg`'s table size and filter
/// ([`ColorStage::bytes_for`]; the scenes of the perspective rows use 256-entry tables).
pub fn table_ram(cfg: &Config) -> Option<u64> {
    let aa = cfg.aa;
    let n = if cfg.perspective.is_some() {
        256
    } else {
        cfg.table_size
    };
    let b = match n {
        16 => ColorStage::<16>::bytes_for(aa),
        32 => ColorStage::<32>::bytes_for(aa),
        64 => ColorStage::<64>::bytes_for(aa),
        128 => ColorStage::<128>::bytes_for(aa),
        256 => ColorStage::<256>::bytes_for(aa),
        512 => ColorStage::<512>::bytes_for(aa),
        1024 => ColorStage::<1024>::bytes_for(aa),
        _ => return None,
    };
    u64::try_from(b).ok()
}

/// Checks that the host's colour-table and csat layouts are the target's (the probe's sizes of
/// the 256-entry table and, with `csat`, of its csat), so that [`table_ram`] holds there.
fn check_layout(target: DeviceTarget, set: &str, unit: &size::UnitSizes) -> Result<(), String> {
    let table = core::mem::size_of::<ColorTable<256>>() as u64;
    let csat = Csat::<256>::BYTES as u64;
    if unit.color_table != table || (unit.csat != 0 && unit.csat != csat) {
        return Err(format!(
            "code size of feature set `{set}` on {target}: the probe's colour table / csat \
             ({} / {} bytes) differ from the host's ({table} / {csat}); the instance RAM cannot \
             be computed on the host",
            unit.color_table, unit.csat
        ));
    }
    Ok(())
}

/// Builds the probe with the cargo features of feature set `set` for `target` and reads it; the
/// error names the set and the target.
pub fn build_set(
    run: &RunOptions,
    target: DeviceTarget,
    set: &str,
    cargo: &[&str],
) -> Result<Build, String> {
    let facts = size::probe_facts(run, target, cargo)
        .map_err(|e| format!("code size of feature set `{set}` on {target}: {e}"))?;
    let unit = facts.unit.as_ref().ok_or_else(|| {
        format!(
            "code size of feature set `{set}` on {target}: the probe has no TEXCORE_PROBE_SIZES \
             table"
        )
    })?;
    check_layout(target, set, unit)?;
    Ok(Build {
        texcore_text: facts.texcore_text(),
        text: facts.sections.text,
        rodata: facts.sections.rodata,
        model: unit.model,
        evaluator: unit.texture_evaluator,
    })
}

/// Builds the probe for every distinct feature set of `rows` on both targets (with `quick`, only
/// the sets of [`QUICK_CONFIGS`]), each set once per target. A failed build is an error naming
/// the set and the target.
pub fn measure(rows: &[&Row], quick: bool, log: &mut dyn FnMut(&str)) -> Result<CodeSizes, String> {
    let start = Instant::now();
    let quick_sets: Vec<String> = QUICK_CONFIGS.iter().map(feature_set).collect();
    // Distinct sets in row order, with the configuration that first needs each.
    let mut sets: Vec<(String, &Config)> = Vec::new();
    for row in rows {
        let set = feature_set(&row.cfg);
        if (quick && !quick_sets.contains(&set)) || sets.iter().any(|(s, _)| *s == set) {
            continue;
        }
        sets.push((set, &row.cfg));
    }
    let run = RunOptions::default();
    let mut out = CodeSizes::default();
    for target in DeviceTarget::ALL {
        let mut builds = BTreeMap::new();
        for (set, cfg) in &sets {
            log(&format!("accuracy: code size of `{set}` on {target}"));
            let cargo: Vec<&str> = rules_for(cfg).iter().map(|r| r.cargo).collect();
            builds.insert(set.clone(), build_set(&run, target, set, &cargo)?);
        }
        out.builds.insert(target.triple(), builds);
    }
    out.seconds = start.elapsed().as_secs_f64();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::device_jobs::ROWS;
    use super::*;
    use texcore::raster::Perspective;

    #[test]
    fn feature_sets_follow_the_knobs() {
        assert_eq!(feature_set(&BASELINE), "fd,perm-hash,csat");
        let none = Config {
            aa: Antialias::None,
            hash: HashKind::Integer,
            ..BASELINE
        };
        assert_eq!(feature_set(&none), "fd");
        let direct = Config {
            mode: EvalMode::Direct,
            ..none
        };
        assert_eq!(feature_set(&direct), "minimal");
        let smooth = Config {
            fade: FadeSel::Quintic,
            ..BASELINE
        };
        assert_eq!(feature_set(&smooth), "fd,perm-hash,smooth-fade,csat");
        let persp = Config {
            perspective: Some(Perspective::Affine),
            ..BASELINE
        };
        assert_eq!(feature_set(&persp), "fd,perm-hash,csat,render");
        // Run-time knobs keep the baseline's set (per-pixel evaluation alone needs no `fd`).
        for row in ROWS.iter().filter(|r| {
            matches!(
                r.knob.name(),
                "coordinate_bits"
                    | "value_bits"
                    | "octaves"
                    | "table_size"
                    | "gradient_norm"
                    | "evaluation"
            ) && !r.combination
        }) {
            let want = if row.cfg.mode == EvalMode::Direct {
                "perm-hash,csat".to_string()
            } else if matches!(row.cfg.mode, EvalMode::Multipass(_)) {
                "fd,perm-hash,csat,multipass".to_string()
            } else {
                feature_set(&BASELINE)
            };
            assert_eq!(feature_set(&row.cfg), want, "{}", row.id);
        }
    }

    /// A build that fails (here: a feature the firmware does not have) is an error naming the
    /// feature set and the target, with cargo's diagnostics.
    #[test]
    fn failed_build_names_the_set_and_the_target() {
        let e = build_set(
            &RunOptions::default(),
            DeviceTarget::Riscv32imc,
            "bogus",
            &["no-such-feature"],
        )
        .unwrap_err();
        assert!(
            e.starts_with("code size of feature set `bogus` on riscv32imc-unknown-none-elf: "),
            "{e}"
        );
        assert!(e.contains("no-such-feature"), "{e}");
    }

    #[test]
    fn table_ram_grows_with_the_table_and_the_filter() {
        let at = |n: u16, aa: Antialias| {
            table_ram(&Config {
                table_size: n,
                aa,
                ..BASELINE
            })
            .unwrap()
        };
        assert_eq!(at(256, Antialias::None), 1024);
        assert_eq!(at(256, Antialias::Mip), 2048);
        assert_eq!(at(256, Antialias::Csat), 1024 + 256 * 8 + 16);
        assert_eq!(at(256, Antialias::Csat3), 1024 + 3 * 256 * 8 + 16);
        assert_eq!(at(16, Antialias::Csat), 16 * 4 + 16 * 8 + 16);
        assert!(at(1024, Antialias::Csat) > at(512, Antialias::Csat));
    }
}
