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

/// Section totals of an ELF.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sections {
    /// Code.
    pub text: u64,
    /// Read-only data.
    pub rodata: u64,
    /// Initialised data.
    pub data: u64,
    /// Zero-initialised data.
    pub bss: u64,
}

fn classify(name: &str) -> Option<usize> {
    let is = |p: &str| name == p || name.starts_with(&format!("{p}."));
    if is(".vector_table")
        || is(".init")
        || name.starts_with(".init.")
        || is(".text")
        || is(".trap")
        // esp-hal's code run from RAM (the ESP32-C3 board example).
        || is(".rwtext")
    {
        Some(0)
    } else if is(".rodata") || is(".srodata") || is(".eh_frame") || is(".eh_frame_hdr") {
        Some(1)
    } else if is(".data") || is(".sdata") {
        Some(2)
    } else if is(".bss") || is(".sbss") {
        Some(3)
    } else {
        None
    }
}

/// Section totals of `elf`.
pub fn sections(file: &object::File<'_>) -> Sections {
    let mut s = [0u64; 4];
    for sec in file.sections() {
        if let Some(i) = sec.name().ok().and_then(classify) {
            s[i] += sec.size();
        }
    }
    Sections {
        text: s[0],
        rodata: s[1],
        data: s[2],
        bss: s[3],
    }
}

/// Address ranges of the code sections.
fn code_ranges(file: &object::File<'_>) -> Vec<(u64, u64)> {
    file.sections()
        .filter(|s| s.kind() == SectionKind::Text || s.name().ok().and_then(classify) == Some(0))
        .filter(|s| s.size() > 0)
        .map(|s| (s.address(), s.address() + s.size()))
        .collect()
}

/// `.text` bytes per source file, from the DWARF line tables.
pub fn text_by_file(file: &object::File<'_>) -> Result<BTreeMap<String, u64>, String> {
    let mut out: BTreeMap<String, u64> = BTreeMap::new();
    for ((path, _), b) in text_by_line(file)? {
        *out.entry(path).or_default() += b;
    }
    Ok(out)
}

/// `.text` bytes per source line (file, line), from the DWARF line tables.
pub fn text_by_line(file: &object::File<'_>) -> Result<BTreeMap<(String, u64), u64>, String> {
    let code = code_ranges(file);
    let load = |id: gimli::SectionId| -> Result<Cow<'_, [u8]>, gimli::Error> {
        Ok(file
            .section_by_name(id.name())
            .and_then(|s| s.uncompressed_data().ok())
            .unwrap_or(Cow::Borrowed(&[])))
    };
    let owned = gimli::DwarfSections::load(load).map_err(|e| e.to_string())?;
    let dwarf = owned.borrow(|s| gimli::EndianSlice::new(s, gimli::LittleEndian));
    let mut out: BTreeMap<(String, u64), u64> = BTreeMap::new();
    let mut units = dwarf.units();
    while let Some(header) = units.next().map_err(|e| e.to_string())? {
        let unit = dwarf.unit(header).map_err(|e| e.to_string())?;
        let Some(program) = unit.line_program.clone() else {
            continue;
        };
        let mut rows = program.rows();
        let mut prev: Option<(u64, (String, u64))> = None;
        while let Some((header, row)) = rows.next_row().map_err(|e| e.to_string())? {
            let addr = row.address();
            if let Some((pa, name)) = prev.take() {
                if addr > pa {
                    let bytes: u64 = code
                        .iter()
                        .map(|&(lo, hi)| addr.min(hi).saturating_sub(pa.max(lo)))
                        .sum();
                    *out.entry(name).or_default() += bytes;
                }
            }
            if row.end_sequence() {
                continue;
            }
            let path = row
                .file(header)
                .map(|f| file_path(&dwarf, &unit, header, f))
                .unwrap_or_default();
            let line = row.line().map_or(0, |l| l.get());
            prev = Some((addr, (path, line)));
        }
    }
    Ok(out)
}

type Slice<'a> = gimli::EndianSlice<'a, gimli::LittleEndian>;

/// `directory/name` of a line-table file entry (as the line rows name their files).
fn file_path(
    dwarf: &gimli::Dwarf<Slice<'_>>,
    unit: &gimli::Unit<Slice<'_>>,
    header: &gimli::LineProgramHeader<Slice<'_>>,
    f: &gimli::FileEntry<Slice<'_>>,
) -> String {
    let mut path = String::new();
    if let Some(dir) = f.directory(header) {
        if let Ok(d) = dwarf.attr_string(unit, dir) {
            path.push_str(&d.to_string_lossy());
            path.push('/');
        }
    }
    if let Ok(n) = dwarf.attr_string(unit, f.path_name()) {
        path.push_str(&n.to_string_lossy());
    }
    path
}

/// Where the functions of each source file start: `(declaration line, name)` per file, sorted,
/// from the DWARF subprogram entries (closures are left out: their lines count to the function
/// that contains them).
pub fn functions_by_file(
    file: &object::File<'_>,
) -> Result<BTreeMap<String, Vec<(u64, String)>>, String> {
    let load = |id: gimli::SectionId| -> Result<Cow<'_, [u8]>, gimli::Error> {
        Ok(file
            .section_by_name(id.name())
            .and_then(|s| s.uncompressed_data().ok())
            .unwrap_or(Cow::Borrowed(&[])))
    };
    let owned = gimli::DwarfSections::load(load).map_err(|e| e.to_string())?;
    let dwarf = owned.borrow(|s| gimli::EndianSlice::new(s, gimli::LittleEndian));
    let mut out: BTreeMap<String, Vec<(u64, String)>> = BTreeMap::new();
    let mut units = dwarf.units();
    while let Some(header) = units.next().map_err(|e| e.to_string())? {
        let unit = dwarf.unit(header).map_err(|e| e.to_string())?;
        let Some(program) = unit.line_program.clone() else {
            continue;
        };
        let lh = program.header();
        let mut entries = unit.entries();
        while let Some((_, e)) = entries.next_dfs().map_err(|e| e.to_string())? {
            if e.tag() != gimli::DW_TAG_subprogram {
                continue;
            }
            let attr = |a| e.attr_value(a).ok().flatten();
            let (Some(name), Some(line), Some(gimli::AttributeValue::FileIndex(fi))) = (
                attr(gimli::DW_AT_name),
                attr(gimli::DW_AT_decl_line).and_then(|l| l.udata_value()),
                attr(gimli::DW_AT_decl_file),
            ) else {
                continue;
            };
            let Ok(name) = dwarf.attr_string(&unit, name) else {
                continue;
            };
            let name = name.to_string_lossy();
            if name.starts_with('{') {
                continue;
            }
            // One entry per function, whatever its instances.
            let name = name.split('<').next().unwrap_or_default();
            let Some(f) = lh.file(fi) else {
                continue;
            };
            out.entry(file_path(&dwarf, &unit, lh, f))
                .or_default()
                .push((line, name.to_string()));
        }
    }
    for v in out.values_mut() {
        v.sort();
        v.dedup();
    }
    Ok(out)
}

/// texcore's `.text` per function (`file::function`, file relative to `texcore/src/`): each
/// line's bytes go to the function declared last at or before it in its file (inlined code
/// counts where it was written).
pub fn texcore_text_by_function(
    by_line: &BTreeMap<(String, u64), u64>,
    functions: &BTreeMap<String, Vec<(u64, String)>>,
) -> BTreeMap<String, u64> {
    let mut out: BTreeMap<String, u64> = BTreeMap::new();
    for ((path, line), b) in by_line {
        if !is_texcore_path(path) {
            continue;
        }
        let short = path
            .rsplit_once("texcore/src/")
            .map_or(path.as_str(), |x| x.1);
        let f = if *line == 0 {
            // Code the compiler made without a source line (spills, merged tails).
            "(line 0)"
        } else {
            functions
                .get(path)
                .and_then(|v| v.iter().take_while(|(l, _)| l <= line).last())
                .map_or("(file scope)", |(_, n)| n.as_str())
        };
        *out.entry(format!("{short}::{f}")).or_default() += b;
    }
    out
}

/// Whether a source path is texcore's.
fn is_texcore_path(p: &str) -> bool {
    p.contains("texcore/src/")
}

/// Bytes of out-of-line texcore symbols in code sections.
pub fn texcore_symbol_bytes(file: &object::File<'_>) -> u64 {
    let code = code_ranges(file);
    file.symbols()
        .filter(|s| s.kind() == SymbolKind::Text)
        .filter(|s| {
            code.iter()
                .any(|&(lo, hi)| s.address() >= lo && s.address() < hi)
        })
        .filter(|s| {
            s.name()
                .map(|n| format!("{:#}", rustc_demangle::demangle(n)).contains("texcore::"))
                .unwrap_or(false)
        })
        .map(|s| s.size())
        .sum()
}

/// The probe's `TEXCORE_PROBE_SIZES` table.
pub fn probe_sizes(file: &object::File<'_>) -> Option<UnitSizes> {
    let sym = file
        .symbols()
        .find(|s| s.name() == Ok("TEXCORE_PROBE_SIZES"))?;
    let sec = file.section_by_index(sym.section_index()?).ok()?;
    let data = sec.data().ok()?;
    let off = usize::try_from(sym.address().checked_sub(sec.address())?).ok()?;
    let bytes = data.get(off..off + 44)?;
    let v: Vec<u64> = bytes
        .chunks_exact(4)
        .map(|c| u64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]])))
        .collect();
    let mut u = UnitSizes {
        color_table: v[0],
        csat: v[1],
        color_stage: v[2],
        model: v[3],
        noise_term: v[4],
        span_evaluator: v[5],
        texture_evaluator: v[6],
        texture: v[7],
        perturbed_material: v[8],
        span: v[9],
        other_filter: v[10],
        unit_ram: 0,
    };
    u.unit_ram = u.color_table + u.csat + u.other_filter + u.model + u.texture_evaluator;
    Some(u)
}

/// Everything the report reads from one ELF.
pub struct ElfFacts {
    /// Section totals.
    pub sections: Sections,
    /// `.text` per source file.
    pub by_file: BTreeMap<String, u64>,
    /// texcore's `.text` per function ([`texcore_text_by_function`]).
    pub texcore_by_function: BTreeMap<String, u64>,
    /// Out-of-line texcore symbol bytes.
    pub texcore_symbols: u64,
    /// The probe's size table, if present.
    pub unit: Option<UnitSizes>,
}

impl ElfFacts {
    /// texcore's `.text` bytes by line attribution.
    pub fn texcore_text(&self) -> u64 {
        self.by_file
            .iter()
            .filter(|(p, _)| is_texcore_path(p))
            .map(|(_, b)| b)
            .sum()
    }
}

/// Reads an ELF.
pub fn analyse(path: &Path) -> Result<ElfFacts, SizeError> {
    let err = |message: String| SizeError::Elf {
        path: path.to_path_buf(),
        message,
    };
    let bytes = std::fs::read(path).map_err(|e| err(e.to_string()))?;
    let file = object::File::parse(&*bytes).map_err(|e| err(e.to_string()))?;
    let by_line = text_by_line(&file).map_err(err)?;
    let functions = functions_by_file(&file).map_err(err)?;
    let mut by_file: BTreeMap<String, u64> = BTreeMap::new();
    for ((path, _), b) in &by_line {
        *by_file.entry(path.clone()).or_default() += b;
    }
    Ok(ElfFacts {
        sections: sections(&file),
        texcore_by_function: texcore_text_by_function(&by_line, &functions),
        by_file,
        texcore_symbols: texcore_symbol_bytes(&file),
        unit: probe_sizes(&file),
    })
}

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

/// A source path outside texcore, shortened to `crate/path` (`core/num/int_macros.rs`,
/// `fixed-1.31.0/src/...`, `firmware/src/probe.rs`); no line-table file is `(unknown)`.
fn short_library_path(p: &str) -> String {
    if p.is_empty() {
        return "(unknown)".to_string();
    }
    for anchor in ["/library/", "/registry/src/"] {
        if let Some((_, rest)) = p.split_once(anchor) {
            // Registry paths start with the index directory.
            let rest = if anchor == "/registry/src/" {
                rest.split_once('/').map_or(rest, |x| x.1)
            } else {
                rest
            };
            return rest.to_string();
        }
    }
    if let Some(rest) = p.strip_prefix("library/") {
        return rest.to_string();
    }
    p.rsplit_once("firmware/")
        .map_or(p.to_string(), |(_, r)| format!("firmware/{r}"))
}

/// The part of texcore a function of the `minimal` probe belongs to (`file::function` as in
/// [`texcore_text_by_function`]).
pub fn minimal_part(f: &str) -> &'static str {
    let (file, func) = f.rsplit_once("::").unwrap_or((f, ""));
    match file {
        "span.rs" => match func {
            "run_merged"
            | "pixel_loop"
            | "pixels"
            | "cubic_poly"
            | "fd_start"
            | "fd_at"
            | "add"
            | "sub"
            | "pixels_in_cell"
            | "pixels_in_cell_axis"
            | "fits"
            | "wide"
            | "wmul"
            | "wadd"
            | "wsub" => "span evaluator: merged forward-difference path",
            "run" | "eval_term" | "amp_and_sign" | "combine" | "sat_i64" | "compiled_mode" => {
                "span evaluator: general (per-pixel) loop"
            }
            "(line 0)" => "span evaluator: code without a source line",
            _ => "span evaluator: per-span set-up and sample hand-over",
        },
        _ if file.starts_with("noise/") || file == "hash.rs" => "noise basis and lattice hash",
        "table.rs" | "texture.rs" | "color.rs" | "sink.rs" => "colour table and shading",
        _ if file.starts_with("filter/") => "colour table and shading",
        "presets.rs" | "transform.rs" | "model.rs" | "quadric.rs" => {
            "building the model (presets, transforms)"
        }
        _ => "other (formats, accessors)",
    }
}

fn kb(b: u64) -> String {
    format!("{:.1} KB", b as f64 / 1024.0)
}

/// The markdown of the report.
pub fn markdown(r: &SizeReport, quick: bool) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Device firmware sizes");
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "<!-- Generated by `texsim report size{}`; do not edit. -->",
        if quick { " --quick" } else { "" }
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "`texcore-probe` (`firmware/src/probe.rs`, profile `release-size`: `release` with \
         `opt-level = \"z\"`) links texcore's pixel path as a product would, with the texture hidden from the optimiser so that every path \
         the feature set compiles in stays linked: it shades a check plane (and renders a \
         blended, depth-tested perspective scene with `render`). `firmware` is the job-suite \
         firmware (profile `release`, every job and the counter self-test) for reference; \
         `board:<name>` rows are the board examples of `examples/boards/` (HAL, mipidsi display \
         driver and texcore: flash = text + rodata + data, RAM = data + bss). At \
         `opt-level = \"z\"` texcore compiles its size-lean code shape (crate documentation, \
         \"Code size\": no forced inlining, one merged pixel loop instead of its specialisations; \
         the same samples); `full-fast` is the `full` probe at `opt-level = 3`, the fast shape \
         that the job-suite firmware and `docs/cycles.md` measure. Sizes \
         in bytes from the ELF sections. `texcore .text` attributes each code byte to its source \
         file through the DWARF line tables (texcore code inlined into callers counts as \
         texcore); `texcore symbols` counts only out-of-line texcore functions. Budgets (Cortex-M4F): \
         texcore `.text` <= 4 KB for `minimal`, <= 24 KB for `full`; a texture-unit instance \
         <= 4 KB of RAM."
    );
    let _ = writeln!(s);
    let _ = writeln!(s, "Feature sets:");
    let _ = writeln!(s);
    for f in FEATURE_SETS {
        let _ = writeln!(
            s,
            "- `{}` (`--no-default-features --features {}`, profile `{}`): {}",
            f.name,
            if f.features.is_empty() {
                "\"\"".to_string()
            } else {
                f.features.join(",")
            },
            f.profile,
            f.what
        );
    }
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "| target | features | text | rodata | data | bss | texcore .text | texcore symbols | budget |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---|");
    for row in &r.rows {
        let budget = match (row.texcore_text_budget, row.within_budget) {
            (Some(b), Some(true)) => format!(
                "<= {}: within ({} to spare)",
                kb(b),
                kb(b - row.texcore_text)
            ),
            (Some(b), Some(false)) => {
                format!("<= {}: **OVER** by {}", kb(b), kb(row.texcore_text - b))
            }
            _ => String::new(),
        };
        let _ = writeln!(
            s,
            "| {} | `{}` | {} | {} | {} | {} | {} ({}) | {} | {} |",
            row.target,
            row.features,
            row.text,
            row.rodata,
            row.data,
            row.bss,
            row.texcore_text,
            kb(row.texcore_text),
            row.texcore_symbols,
            budget
        );
    }
    let _ = writeln!(s);
    let _ = writeln!(s, "## RAM of a texture-unit instance");
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "`core::mem::size_of` on each target (from the probe's `TEXCORE_PROBE_SIZES`). Instance = \
         256-entry colour table + its csat (without `csat`: the ramp's samples, or else the MIP \
         levels above the table, column `other`) + `TextureModel<8>` (quadric and up to 8 noise terms) \
         + `TextureEvaluator<8, 256>` (span-evaluator state); the span evaluator's per-span \
         working state is on the stack during `shade`. `ColorStage<256>` and `Texture<8, 256>` \
         are sized for the largest filter compiled in (with `csat`, the three-times-long table), \
         so an instance held in them is larger than the sum."
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "| target | features | table | csat | other | model | evaluator | **instance** | budget | ColorStage | Texture |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---|---:|---:|");
    for row in &r.rows {
        if let Some(u) = &row.unit {
            let _ = writeln!(
                s,
                "| {} | `{}` | {} | {} | {} | {} | {} | **{}** | {} | {} | {} |",
                row.target,
                row.features,
                u.color_table,
                u.csat,
                u.other_filter,
                u.model,
                u.texture_evaluator,
                u.unit_ram,
                if u.unit_ram <= BUDGET_UNIT_RAM {
                    "<= 4 KB: within"
                } else {
                    "<= 4 KB: **OVER**"
                },
                u.color_stage,
                u.texture
            );
        }
    }
    for (target, fns) in &r.minimal_functions {
        let total: u64 = fns.iter().map(|f| f.1).sum();
        let _ = writeln!(s);
        let _ = writeln!(s, "## What `minimal` contains ({target})");
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "`minimal` is texcore without features: trilinear value noise with the table-free \
             integer hash, a `mod`/`clamp` colour table (nearest or linear lookup), no \
             antialiasing and so no filter-width gradients (feature `gradients`, which `csat` \
             and `mip` enable), the quadric, and the span evaluator's per-pixel loop: without \
             feature `fd` every evaluation mode evaluates per pixel (the same samples; the `fd` \
             row prices forward differencing's code, `docs/cycles.md` its speed as the \
             `EvalMode::Direct` rows against the `Fd` ones). The {} of texcore `.text` by \
             function (the function whose source lines produced the bytes; inlined code counts \
             where it was written; closures count to their function), by part:",
            kb(total)
        );
        let mut parts: BTreeMap<&str, u64> = BTreeMap::new();
        for (f, b) in fns {
            *parts.entry(minimal_part(f)).or_default() += b;
        }
        let mut parts: Vec<(&str, u64)> = parts.into_iter().collect();
        parts.sort_by_key(|p| std::cmp::Reverse(p.1));
        let _ = writeln!(s);
        let _ = writeln!(s, "| part | .text bytes |");
        let _ = writeln!(s, "|---|---:|");
        for (p, b) in &parts {
            let _ = writeln!(s, "| {p} | {b} ({}) |", kb(*b));
        }
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "The budget is {}: {}.",
            kb(BUDGET_TEXT_MINIMAL),
            if total <= BUDGET_TEXT_MINIMAL {
                format!("within, {} to spare", kb(BUDGET_TEXT_MINIMAL - total))
            } else {
                format!("**over** by {}", kb(total - BUDGET_TEXT_MINIMAL))
            }
        );
        let _ = writeln!(s);
        let _ = writeln!(s, "By function:");
        let _ = writeln!(s);
        let _ = writeln!(s, "| function | .text bytes |");
        let _ = writeln!(s, "|---|---:|");
        let shown = 24;
        for (f, b) in fns.iter().take(shown) {
            let _ = writeln!(s, "| `{f}` | {b} |");
        }
        if fns.len() > shown {
            let rest: u64 = fns.iter().skip(shown).map(|f| f.1).sum();
            let _ = writeln!(s, "| {} other functions | {rest} |", fns.len() - shown);
        }
        if let Some(other) = r.minimal_other.get(target) {
            let _ = writeln!(s);
            let _ = writeln!(
                s,
                "The rest of the probe's `.text` (not counted as texcore): library code, including \
                 `core` methods inlined into texcore functions (integer arithmetic is attributed to \
                 `core/src/num/*`), the start-up code and the probe itself:"
            );
            let _ = writeln!(s);
            let _ = writeln!(s, "| source | .text bytes |");
            let _ = writeln!(s, "|---|---:|");
            let shown = 10;
            for (f, b) in other.iter().take(shown) {
                let _ = writeln!(s, "| `{f}` | {b} |");
            }
            if other.len() > shown {
                let rest: u64 = other.iter().skip(shown).map(|f| f.1).sum();
                let _ = writeln!(s, "| {} other sources | {rest} |", other.len() - shown);
            }
        }
    }
    for (target, files) in &r.top_files {
        let _ = writeln!(s);
        let _ = writeln!(s, "## Largest texcore sources in `full`, {target}");
        let _ = writeln!(s);
        let _ = writeln!(s, "| file | .text bytes |");
        let _ = writeln!(s, "|---|---:|");
        for (f, b) in files {
            let _ = writeln!(s, "| `{f}` | {b} |");
        }
    }
    s
}
