//! Reading a linked ELF: section totals, the code bytes attributed to source files, lines and
//! functions through the DWARF line tables, texcore's out-of-line symbols and the probe's
//! recorded type sizes. Errors name the file and what could not be read.

use super::*;

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

pub(super) fn classify(name: &str) -> Option<usize> {
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
pub(super) fn code_ranges(file: &object::File<'_>) -> Vec<(u64, u64)> {
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
pub(super) fn file_path(
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
pub(super) fn is_texcore_path(p: &str) -> bool {
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
