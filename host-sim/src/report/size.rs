//! `texsim report size`: firmware section sizes per target and feature set, texcore's share of
//! `.text`, and the RAM of a texture-unit instance.
//!
//! Two kinds of builds, both for the Cortex-M4F and rv32imc:
//! - `texcore-probe` (`firmware/src/probe.rs`, profile `release-size` (opt-level "z"),
//!   `--no-default-features` plus each [`FEATURE_SETS`] entry): texcore's pixel path linked as a
//!   product would, with every compiled-in path reachable. `minimal` is texcore without features
//!   (value noise, integer hash, mod/clamp table, no antialiasing, the span evaluator's exact
//!   strategies only); `full` is every basis, csat, MIP, perturbed materials, every evaluation
//!   strategy, and the banded renderer with perspective, depth and blending. These are the rows
//!   the budgets apply to.
//! - the job-suite `firmware` (profile `release`, default features, feature set `firmware`): for
//!   reference; it links every job and the counter self-test sleds.
//! - the board examples (`board:pico` on `thumbv6m-none-eabi`, `board:esp32c3` on
//!   `riscv32imc-unknown-none-elf`; [`super::boards`]): a whole product's flash and RAM (HAL,
//!   display driver, texcore), each with its own release profile.
//!
//! Per ELF: `text` (`.vector_table`, `.init*`, `.text*`, `.trap*`), `rodata` (`.rodata*`,
//! `.srodata*`, `.eh_frame*`), `data` (`.data*`, `.sdata*`), `bss` (`.bss*`, `.sbss*`), in bytes;
//! RAM regions that are only reserved (`.stack`, `.heap`, `.uninit`) are not counted.
//!
//! texcore's share of `.text` is measured two ways: `texcore_text` attributes every byte of
//! `.text` to the source file of its DWARF line-table row (so texcore code inlined into the
//! caller counts as texcore), and `texcore_symbols` sums the sizes of the symbols whose demangled
//! name names a texcore item (out-of-line texcore functions only). For `minimal` the report also
//! breaks texcore's share down by function (each line's bytes to the function declared last
//! before it in its file, from the DWARF subprogram entries) and lists the rest of the probe's
//! `.text` by source.
//!
//! The RAM of a texture-unit instance comes from the probe's `TEXCORE_PROBE_SIZES` table
//! (`core::mem::size_of` on the target itself): a 256-entry colour table, its csat (summed-area
//! table), the model with its noise terms (capacity 8) and the texture evaluator (span evaluator
//! state). The evaluator's per-span working state lives on the stack during `shade` and is not
//! included.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use object::{Object, ObjectSection, ObjectSymbol, SectionKind, SymbolKind};
use serde::Serialize;

use super::write_atomic;
use crate::device::{self, DeviceTarget, RunOptions};

/// A feature set of the probe: report name, firmware features and build profile.
#[derive(Clone, Copy, Debug)]
pub struct FeatureSet {
    /// Name in the report.
    pub name: &'static str,
    /// `firmware` crate features (with `--no-default-features`).
    pub features: &'static [&'static str],
    /// Cargo profile: `release-size` (`opt-level = "z"`, texcore's size-lean code shape) or
    /// `release` (`opt-level = 3`, its fast shape).
    pub profile: &'static str,
    /// What it adds.
    pub what: &'static str,
}

/// The probe's feature sets, from `minimal` to `full`, and `full` in the fast code shape.
/// `perm-hash` only takes effect on the Cortex-M4F (the rv32imc build is table-free in every set).
pub const FEATURE_SETS: [FeatureSet; 16] = [
    FeatureSet {
        name: "minimal",
        features: &[],
        profile: "release-size",
        what: "value noise, integer hash, mod/clamp table, no antialiasing (so no gradients), \
               per-pixel evaluation (no forward differencing): the reduced model",
    },
    FeatureSet {
        name: "fd",
        features: &["fd"],
        profile: "release-size",
        what: "minimal + forward differencing (`EvalMode::Fd` and `Auto`: the merged exact path)",
    },
    FeatureSet {
        name: "csat",
        features: &["csat"],
        profile: "release-size",
        what: "minimal + summed-area colour-table filters (with the filter-width gradients)",
    },
    FeatureSet {
        name: "mip",
        features: &["mip"],
        profile: "release-size",
        what: "minimal + colour-table MIP map (with the filter-width gradients)",
    },
    FeatureSet {
        name: "ramp",
        features: &["ramp"],
        profile: "release-size",
        what: "minimal + the pre-filtered RGB565 ramp (`Antialias::Ramp`, with the filter-width \
               gradients), shaded straight to RGB565 (`shade565`; a system of its own, not part \
               of `full`; compare with `csat`)",
    },
    FeatureSet {
        name: "ramp-diff",
        features: &["ramp", "differences"],
        profile: "release-size",
        what: "ramp + the filter widths from the differences of neighbouring values \
               (`texture::DifferenceSpans`: the values without gradients, two rows of them in the \
               caller's `DifferenceMemory`, 8 bytes a pixel of width; a probe feature, not \
               texcore's: the code is linked where it is called; compare with `ramp`)",
    },
    FeatureSet {
        name: "bases",
        features: &["smooth-fade", "gradient-noise", "mnoise", "perm-hash"],
        profile: "release-size",
        what: "minimal + smooth fades, gradient noise, mNoise, permutation hash (M4F)",
    },
    FeatureSet {
        name: "eval",
        features: &["turbulence-fd", "fd32", "reanchor"],
        profile: "release-size",
        what: "minimal + forward differencing with the span evaluator's optional strategies: \
               forward differencing of turbulent terms, `EvalMode::Fd32` (`reanchor` takes \
               effect only with a basis that is not a cubic, as in `full`)",
    },
    FeatureSet {
        name: "perturb",
        features: &["perturb"],
        profile: "release-size",
        what: "minimal + Miné & Neyret perturbed materials",
    },
    FeatureSet {
        name: "render",
        features: &["render"],
        profile: "release-size",
        what: "minimal + banded renderer (rasterizer, perspective, depth, blending)",
    },
    FeatureSet {
        name: "multipass",
        features: &["fd", "multipass"],
        profile: "release-size",
        what: "minimal + forward differencing + multipass corner-by-corner noise \
               (`EvalMode::Multipass`; a system of its own, not part of `full`)",
    },
    FeatureSet {
        name: "atlas",
        features: &["atlas"],
        profile: "release-size",
        what: "minimal + meshed texture atlases: packed-mesh validation, the atlas bake, nearest, \
               bilinear and MIP atlas look-ups (a system of its own, not part of `full`)",
    },
    FeatureSet {
        name: "render-diff",
        features: &["render", "ramp", "render-differences"],
        profile: "release-size",
        what: "render + ramp + the renderer's filter widths from differences \
               (`Renderer::with_differences`, texcore `differences`: segment values without \
               gradients, the row above in the caller's `DifferenceMemory`, a face cache; \
               compare with `render` and `ramp`)",
    },
    FeatureSet {
        name: "lighting",
        features: &["render", "lighting"],
        profile: "release-size",
        what: "render + per-vertex lighting: the lights of a lit scene's vertices \
               (`Lighting::shade`: ambient, diffuse, specular) and the renderer's lighting stage \
               (a system of its own, not part of `full`; compare with `render`)",
    },
    FeatureSet {
        name: "full",
        features: &["full", "perm-hash"],
        profile: "release-size",
        what: "every basis, csat, MIP, perturbed materials, forward differencing with every \
               evaluation strategy, renderer with perspective and blending",
    },
    FeatureSet {
        name: "full-fast",
        features: &["full", "perm-hash"],
        profile: "release",
        what: "`full` at `opt-level = 3`: texcore's fast code shape (the merged loop's \
               specialisations, forced inlining), as the job-suite firmware and the cycles \
               report run it",
    },
];

/// The sets of `--quick`.
pub const QUICK_SETS: [&str; 2] = ["minimal", "full"];

/// Budgets on the Cortex-M4F: texcore `.text` of `minimal` and of `full`, and the RAM of one
/// texture-unit instance.
pub const BUDGET_TEXT_MINIMAL: u64 = 4 * 1024;
/// See [`BUDGET_TEXT_MINIMAL`].
pub const BUDGET_TEXT_FULL: u64 = 24 * 1024;
/// See [`BUDGET_TEXT_MINIMAL`].
pub const BUDGET_UNIT_RAM: u64 = 4 * 1024;

/// `core::mem::size_of` of the parts of a texture unit on the target (probe table order).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct UnitSizes {
    /// `ColorTable<256>`.
    pub color_table: u64,
    /// `Csat<256>` (0 without `csat`).
    pub csat: u64,
    /// `ColorStage<256>` (sized for the largest filter compiled in).
    pub color_stage: u64,
    /// `TextureModel<8>`: quadric and up to 8 noise terms.
    pub model: u64,
    /// One `NoiseTerm`.
    pub noise_term: u64,
    /// `SpanEvaluator<8>`.
    pub span_evaluator: u64,
    /// `TextureEvaluator<8, 256>` (contains the span evaluator).
    pub texture_evaluator: u64,
    /// `Texture<8, 256>` as typed (model, `ColorStage`, options).
    pub texture: u64,
    /// `PerturbedMaterial<8>` (0 without `perturb`).
    pub perturbed_material: u64,
    /// `Span`.
    pub span: u64,
    /// The filter data beyond the table of an instance without `csat`: the ramp's samples
    /// (`Ramp565<256>`, feature `ramp`), else the MIP levels above level 0 (feature `mip`),
    /// else 0.
    pub other_filter: u64,
    /// One texture-unit instance: colour table + csat or other filter data + model + texture
    /// evaluator.
    pub unit_ram: u64,
}

/// One row of the report.
#[derive(Clone, Debug, Serialize)]
pub struct SizeRow {
    /// Target triple.
    pub target: String,
    /// Feature set (`minimal` .. `full`, or `firmware` for the job-suite firmware).
    pub features: String,
    /// The firmware features built.
    pub cargo_features: Vec<String>,
    /// Binary and profile.
    pub binary: String,
    /// Code bytes.
    pub text: u64,
    /// Read-only data bytes.
    pub rodata: u64,
    /// Initialised data bytes (flash and RAM).
    pub data: u64,
    /// Zero-initialised RAM bytes.
    pub bss: u64,
    /// `.text` bytes attributed to texcore by the DWARF line tables (inlined code included).
    pub texcore_text: u64,
    /// `.text` bytes of out-of-line texcore symbols.
    pub texcore_symbols: u64,
    /// texcore's `.text` budget for this set on this target, if one applies.
    pub texcore_text_budget: Option<u64>,
    /// `texcore_text <= texcore_text_budget` (`None` without a budget).
    pub within_budget: Option<bool>,
    /// Texture-unit sizes (probe builds only).
    pub unit: Option<UnitSizes>,
    /// `unit.unit_ram <= 4 KB` (probe builds only).
    pub unit_ram_within_budget: Option<bool>,
}

/// The report: rows plus the largest texcore contributors of the `full` probe on each target.
#[derive(Clone, Debug, Serialize)]
pub struct SizeReport {
    /// One row per target and feature set.
    pub rows: Vec<SizeRow>,
    /// Per target: the texcore source files with the most `.text` in the `full` probe.
    pub top_files: BTreeMap<String, Vec<(String, u64)>>,
    /// texcore's `.text` of the `minimal` probe per function, largest first (Cortex-M4F, the
    /// budget's target).
    pub minimal_functions: BTreeMap<String, Vec<(String, u64)>>,
    /// The `minimal` probe's `.text` per source file outside texcore (library code, the probe
    /// itself), largest first (Cortex-M4F).
    pub minimal_other: BTreeMap<String, Vec<(String, u64)>>,
}

/// Options of the report.
#[derive(Clone, Debug)]
pub struct SizeOptions {
    /// Only `minimal` and `full`, and no job-suite firmware.
    pub quick: bool,
    /// Targets.
    pub targets: Vec<DeviceTarget>,
    /// Where to write the markdown (`None`: nowhere).
    pub markdown: Option<PathBuf>,
    /// Workspace root and cargo.
    pub run: RunOptions,
}

impl Default for SizeOptions {
    fn default() -> Self {
        SizeOptions {
            quick: false,
            targets: DeviceTarget::ALL.to_vec(),
            markdown: Some(device::workspace_root().join("docs/size.md")),
            run: RunOptions::default(),
        }
    }
}

/// Why the report failed.
#[derive(Debug, thiserror::Error)]
pub enum SizeError {
    /// A build failed.
    #[error("building {what} for {target}: {message}")]
    Build {
        /// Target.
        target: DeviceTarget,
        /// What was built.
        what: String,
        /// Cargo's diagnostics.
        message: String,
    },
    /// The ELF could not be read.
    #[error("reading {path}: {message}")]
    Elf {
        /// File.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A board example failed to build.
    #[error("building the {board} board example: {message}")]
    Board {
        /// Board name.
        board: &'static str,
        /// Cargo's diagnostics.
        message: String,
    },
    /// Writing the markdown failed.
    #[error("writing {path}: {source}")]
    Write {
        /// File.
        path: PathBuf,
        /// Error.
        source: std::io::Error,
    },
}

/// Builds `bin` of the firmware crate; returns the ELF.
fn build(
    opts: &RunOptions,
    target: DeviceTarget,
    bin: &str,
    profile: &str,
    features: Option<&[&str]>,
) -> Result<PathBuf, SizeError> {
    let mut cmd = Command::new(&opts.cargo);
    cmd.current_dir(&opts.workspace).args([
        "build",
        "--profile",
        profile,
        "-p",
        "firmware",
        "--bin",
        bin,
        "--target",
        target.triple(),
        "--message-format=json-render-diagnostics",
    ]);
    if let Some(f) = features {
        cmd.arg("--no-default-features");
        if !f.is_empty() {
            cmd.arg("--features").arg(f.join(","));
        }
    }
    // As host_sim::device::build_firmware: the device build depends on the repository alone.
    crate::device::isolate_cargo_env(&mut cmd, &[]);
    let what = match features {
        None => format!("{bin} ({profile}, default features)"),
        Some([]) => format!("{bin} ({profile}, no features)"),
        Some(f) => format!("{bin} ({profile}, features {})", f.join(",")),
    };
    crate::device::cargo_artifact(&mut cmd, &opts.cargo, bin).map_err(|message| SizeError::Build {
        target,
        what,
        message,
    })
}

mod elf;
mod markdown;

pub use elf::*;
pub use markdown::*;

fn row(
    target: DeviceTarget,
    set: &str,
    cargo_features: &[&str],
    binary: &str,
    facts: &ElfFacts,
) -> SizeRow {
    let budget = match (target, set) {
        (DeviceTarget::CortexM4F, "minimal") => Some(BUDGET_TEXT_MINIMAL),
        (DeviceTarget::CortexM4F, "full") => Some(BUDGET_TEXT_FULL),
        _ => None,
    };
    let texcore_text = facts.texcore_text();
    SizeRow {
        target: target.triple().to_string(),
        features: set.to_string(),
        cargo_features: cargo_features.iter().map(|s| s.to_string()).collect(),
        binary: binary.to_string(),
        text: facts.sections.text,
        rodata: facts.sections.rodata,
        data: facts.sections.data,
        bss: facts.sections.bss,
        texcore_text,
        texcore_symbols: facts.texcore_symbols,
        texcore_text_budget: budget,
        within_budget: budget.map(|b| texcore_text <= b),
        unit_ram_within_budget: facts.unit.as_ref().map(|u| u.unit_ram <= BUDGET_UNIT_RAM),
        unit: facts.unit.clone(),
    }
}

/// The row of a board example (`examples/boards/<board>`, its own release profile: `opt-level =
/// "s"`, fat LTO): flash is `text + rodata + data`, RAM `data + bss`; no budget applies.
fn board_row(board: &super::boards::Board, facts: &ElfFacts) -> SizeRow {
    SizeRow {
        target: board.target.to_string(),
        features: format!("board:{}", board.name),
        cargo_features: vec!["default".to_string()],
        binary: format!("texcore-board-{} (release)", board.name),
        text: facts.sections.text,
        rodata: facts.sections.rodata,
        data: facts.sections.data,
        bss: facts.sections.bss,
        texcore_text: facts.texcore_text(),
        texcore_symbols: facts.texcore_symbols,
        texcore_text_budget: None,
        within_budget: None,
        unit: None,
        unit_ram_within_budget: None,
    }
}

/// Builds `texcore-probe` (profile `release-size`, `--no-default-features --features
/// <features>`: `firmware` features, or texcore's as `texcore/<name>`) for `target` and reads
/// its ELF. Every build of a feature set overwrites the same ELF, so it is read at once.
pub(crate) fn probe_facts(
    run: &RunOptions,
    target: DeviceTarget,
    features: &[&str],
) -> Result<ElfFacts, SizeError> {
    probe_facts_in(run, target, features, "release-size")
}

/// [`probe_facts`] with another cargo profile.
fn probe_facts_in(
    run: &RunOptions,
    target: DeviceTarget,
    features: &[&str],
    profile: &str,
) -> Result<ElfFacts, SizeError> {
    let elf = build(run, target, "texcore-probe", profile, Some(features))?;
    analyse(&elf)
}

/// Builds and measures everything; writes the markdown when asked.
pub fn report(opts: &SizeOptions) -> Result<SizeReport, SizeError> {
    let mut rows = Vec::new();
    let mut top_files = BTreeMap::new();
    let mut minimal_functions = BTreeMap::new();
    let mut minimal_other = BTreeMap::new();
    for &target in &opts.targets {
        for set in FEATURE_SETS
            .iter()
            .filter(|s| !opts.quick || QUICK_SETS.contains(&s.name))
        {
            let facts = probe_facts_in(&opts.run, target, set.features, set.profile)?;
            if set.name == "full" {
                let mut files: Vec<(String, u64)> = facts
                    .by_file
                    .iter()
                    .filter(|(p, _)| is_texcore_path(p))
                    .map(|(p, b)| {
                        let short = p.rsplit_once("texcore/src/").map_or(p.as_str(), |x| x.1);
                        (short.to_string(), *b)
                    })
                    .collect();
                files.sort_by_key(|f| std::cmp::Reverse(f.1));
                files.truncate(12);
                top_files.insert(target.triple().to_string(), files);
            }
            if set.name == "minimal" && target == DeviceTarget::CortexM4F {
                let mut fns: Vec<(String, u64)> = facts
                    .texcore_by_function
                    .iter()
                    .map(|(f, b)| (f.clone(), *b))
                    .collect();
                fns.sort_by_key(|f| std::cmp::Reverse(f.1));
                minimal_functions.insert(target.triple().to_string(), fns);
                let mut other: BTreeMap<String, u64> = BTreeMap::new();
                for (p, b) in facts.by_file.iter().filter(|(p, _)| !is_texcore_path(p)) {
                    *other.entry(short_library_path(p)).or_default() += b;
                }
                let mut other: Vec<(String, u64)> = other.into_iter().collect();
                other.sort_by_key(|f| std::cmp::Reverse(f.1));
                minimal_other.insert(target.triple().to_string(), other);
            }
            rows.push(row(
                target,
                set.name,
                set.features,
                &format!("texcore-probe ({})", set.profile),
                &facts,
            ));
        }
        if !opts.quick {
            let elf = build(&opts.run, target, "firmware", "release", None)?;
            let facts = analyse(&elf)?;
            rows.push(row(
                target,
                "firmware",
                &["default"],
                "firmware job suite (release)",
                &facts,
            ));
        }
    }
    if !opts.quick {
        for board in super::boards::BOARDS {
            let elf = board
                .build(&opts.run.cargo, &opts.run.workspace)
                .map_err(|message| SizeError::Board {
                    board: board.name,
                    message,
                })?;
            let facts = analyse(&elf)?;
            rows.push(board_row(&board, &facts));
        }
    }
    let report = SizeReport {
        rows,
        top_files,
        minimal_functions,
        minimal_other,
    };
    if let Some(path) = &opts.markdown {
        write_atomic(path, &markdown(&report, opts.quick)).map_err(|source| SizeError::Write {
            path: path.clone(),
            source,
        })?;
    }
    Ok(report)
}
