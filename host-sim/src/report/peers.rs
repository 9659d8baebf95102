//! `texsim report peers`: texcore next to the peer noise libraries on the same plane and
//! workloads (`texcore::texture::workload::peers`).
//!
//! - Devices (Cortex-M4F, rv32imc): the firmware built with feature `peers` (whole plane) or
//!   `peers-band` (`--quick`: one 8-row band) runs texcore's three exact modes, the
//!   approximate `Fused` on the gradient-noise workloads (`texcore-fused`), the approximate
//!   pre-filtered RGB565 ramp on the marble workloads (`texcore-ramp`, and `texcore-ramp-diff`
//!   with the filter widths from the differences of neighbouring values) and `fastnoise-lite`
//!   under QEMU with exact instruction counting (`host_sim::device`). Instructions per sample are
//!   `(job - setup - fold) / samples`: the set-up job builds the model, texture or generator and
//!   evaluates nothing, and `peers:fold` is the cost of the checksum fold that follows every row
//!   (so the figure is the evaluation and the store into the line buffer). Every device checksum
//!   is recomputed on the host with the same code (`workloads::peers`, the `workloads` crate's
//!   feature `peers`, as [`kernels`]).
//! - Host (`x86_64`): the same kernels plus `noise` (noise-rs, f64). Instructions per sample from
//!   `valgrind --tool=callgrind` runs of this executable (`--kernel`, one kernel per process; the
//!   difference of a run with 64 rows and one without, less the fold's own), nanoseconds per
//!   sample as the median of 21 timed runs of the whole plane in this process (less the medians
//!   of the set-up and of the fold). Both depend on how this executable was
//!   built: run the report from a release build (`cargo run --release -p host-sim -- report
//!   peers`); the report says which profile it ran in.
//!
//! Markdown: one table per workload, each row's figure and its ratio to `texcore-fd` on the
//! same target. `docs/peers.md` is written only with `--write-docs`.

pub use workloads::peers as kernels;

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Instant;

use noise::{Fbm, MultiFractal, NoiseFn, Perlin, Value};
use texcore::hash::HashKind;
use texcore::texture::workload::peers::{self as wl, Workload};

use self::kernels::Implementation;
use crate::device::{self, DeviceTarget, RunOptions};

/// The host target triple in the rows.
pub const HOST_TRIPLE: &str = "x86_64-unknown-linux-gnu";
/// The lattice hash of the host rows (texcore's full build; as the Cortex-M4F).
pub const HOST_HASH: HashKind = HashKind::Permutation;

/// One row of the report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PeerRow {
    /// Workload name (`value-1oct`, ...).
    pub workload: String,
    /// Implementation (`texcore-fd`, `texcore-auto`, `texcore-direct`, `texcore-fused` (the
    /// Perlin workloads only), `texcore-ramp` and `texcore-ramp-diff` (the marble workloads
    /// only), `fastnoise-lite`,
    /// `noise`).
    pub implementation: String,
    /// Target triple.
    pub target: String,
    /// Instructions per sample (device: exact QEMU count; host: callgrind), `None` when not
    /// measured (valgrind missing).
    pub instructions_per_sample: Option<f64>,
    /// Median host nanoseconds per sample (host rows only).
    pub ns_per_sample: Option<f64>,
    /// Device rows: whether the device checksum equals the host's recomputation.
    pub checksum_match: Option<bool>,
    /// Samples measured (rows x 256).
    pub samples: u64,
}

/// What to run.
#[derive(Clone, Debug)]
pub struct PeersOptions {
    /// One 8-row band on the devices, 16 rows under callgrind, 3 timed runs.
    pub quick: bool,
    /// Device targets.
    pub targets: Vec<DeviceTarget>,
    /// Measure the host rows.
    pub host: bool,
    /// Firmware build and run options (features are set per run).
    pub run: RunOptions,
}

impl Default for PeersOptions {
    fn default() -> Self {
        PeersOptions {
            quick: false,
            targets: DeviceTarget::ALL.to_vec(),
            host: true,
            run: RunOptions::default(),
        }
    }
}

/// An implementation on the host: a device one or `noise`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HostImpl {
    /// texcore or fastnoise-lite (the device kernels).
    Device(Implementation),
    /// noise-rs.
    NoiseRs,
}

impl HostImpl {
    /// Name in reports.
    pub fn name(self) -> &'static str {
        match self {
            HostImpl::Device(i) => i.name(),
            HostImpl::NoiseRs => "noise",
        }
    }

    /// The implementation called `name`.
    pub fn by_name(name: &str) -> Option<HostImpl> {
        if name == "noise" {
            return Some(HostImpl::NoiseRs);
        }
        Implementation::ALL
            .into_iter()
            .find(|i| i.name() == name)
            .map(HostImpl::Device)
    }
}

/// noise-rs's equivalent of workload `w` (seed 0, frequency 1, lacunarity 2, persistence 1/2):
/// `Value` (quintic fade) for the value and smooth workloads, `Perlin` for the Perlin ones, `Fbm`
/// of them for 4 octaves. `None` when it has none.
fn noise_rs(w: Workload) -> Option<Box<dyn NoiseFn<f64, 3>>> {
    let fbm = |f: Box<dyn NoiseFn<f64, 3>>| Some(f);
    match w {
        Workload::Value1 | Workload::Smooth1 => fbm(Box::new(Value::new(0))),
        Workload::Perlin1 => fbm(Box::new(Perlin::new(0))),
        Workload::Value4 | Workload::Value4Span16 => fbm(Box::new(
            Fbm::<Value>::new(0)
                .set_octaves(4)
                .set_frequency(1.0)
                .set_lacunarity(2.0)
                .set_persistence(0.5),
        )),
        Workload::Perlin4 => fbm(Box::new(
            Fbm::<Perlin>::new(0)
                .set_octaves(4)
                .set_frequency(1.0)
                .set_lacunarity(2.0)
                .set_persistence(0.5),
        )),
        _ => None,
    }
}

/// Whether `imp` has an equivalent of `w` on the host.
fn host_has(w: Workload, imp: HostImpl) -> bool {
    match imp {
        HostImpl::Device(i) => kernels::has(w, i),
        HostImpl::NoiseRs => noise_rs(w).is_some(),
    }
}

/// Every host implementation, in report order.
fn host_impls() -> Vec<HostImpl> {
    let mut v: Vec<HostImpl> = Implementation::ALL.map(HostImpl::Device).to_vec();
    v.push(HostImpl::NoiseRs);
    v
}

/// Runs one host kernel over `rows` rows into `line`, folding each row like the device jobs
/// ([`kernels::run`]; noise-rs stores the low word of each `f64`); `rows = 0` only builds it.
pub fn host_kernel(w: Workload, imp: HostImpl, rows: u16, line: &mut [u32]) -> u32 {
    match imp {
        HostImpl::Device(i) => kernels::run(w, i, HOST_HASH, rows, line),
        HostImpl::NoiseRs => {
            let Some(n) = noise_rs(w) else {
                return 0;
            };
            let n = std::hint::black_box(n);
            let r = f64::from(kernels::R);
            let mut acc = kernels::FNV_OFFSET;
            for y in 0..rows {
                let t = f64::from(y) / 32.0;
                for (x, p) in (0u16..).zip(line[..usize::from(wl::SIZE)].iter_mut()) {
                    *p = n.get([f64::from(x) / 32.0, t, r]).to_bits() as u32;
                }
                for &v in &line[..usize::from(wl::SIZE)] {
                    acc = kernels::fold(acc, v);
                }
            }
            acc
        }
    }
}

/// `--kernel` spec: `<workload>:<implementation>:<rows>` or `fold:<rows>`.
pub fn run_kernel_spec(spec: &str) -> Result<u32, String> {
    let mut line = vec![0u32; usize::from(wl::SIZE)];
    let parts: Vec<&str> = spec.split(':').collect();
    let rows = |s: &str| {
        s.parse::<u16>()
            .ok()
            .filter(|&r| r <= wl::SIZE)
            .ok_or_else(|| format!("bad row count `{s}` in --kernel `{spec}` (0..=256)"))
    };
    match parts.as_slice() {
        ["fold", r] => Ok(kernels::fold_only(rows(r)?, &mut line)),
        [w, i, r] => {
            let w = Workload::by_name(w)
                .ok_or_else(|| format!("unknown workload `{w}` in --kernel `{spec}`"))?;
            let i = HostImpl::by_name(i)
                .ok_or_else(|| format!("unknown implementation `{i}` in --kernel `{spec}`"))?;
            Ok(host_kernel(w, i, rows(r)?, &mut line))
        }
        _ => Err(format!(
            "bad --kernel `{spec}`: expected <workload>:<implementation>:<rows> or fold:<rows>"
        )),
    }
}

/// The callgrind instruction count (`Collected`) of this executable running `--kernel spec`.
fn callgrind(spec: &str) -> Result<u64, String> {
    let exe = std::env::current_exe().map_err(|e| format!("locating texsim: {e}"))?;
    let out = Command::new("valgrind")
        .args([
            "--tool=callgrind",
            "--callgrind-out-file=/dev/null",
            "--cache-sim=no",
        ])
        .arg(&exe)
        .args(["report", "peers", "--kernel", spec])
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("running valgrind: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "valgrind on `--kernel {spec}` exited {}: {}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let err = String::from_utf8_lossy(&out.stderr);
    err.lines()
        .find_map(|l| {
            let (_, rest) = l.split_once("Collected :")?;
            rest.trim().replace(',', "").parse::<u64>().ok()
        })
        .ok_or_else(|| format!("no `Collected :` line in callgrind's output:\n{err}"))
}

/// Median of `runs` timed runs of `f` in nanoseconds.
fn median_ns(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..runs.max(1))
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_nanos() as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    let n = t.len();
    if n % 2 == 1 {
        t[n / 2]
    } else {
        (t[n / 2 - 1] + t[n / 2]) / 2.0
    }
}

/// The host rows: callgrind counts (when valgrind runs) and median ns.
fn host_rows(quick: bool, log: &mut dyn FnMut(&str)) -> Vec<PeerRow> {
    // Callgrind runs 16 or 64 rows (two octave-0 cells high): the same per-sample cost as the
    // whole plane to a fraction of an instruction, at a quarter of the time under valgrind.
    let cg_rows: u16 = if quick { 16 } else { 64 };
    let runs = if quick { 3 } else { 21 };
    let valgrind = Command::new("valgrind")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !valgrind {
        log("valgrind is not installed: host rows without instruction counts");
    }
    let fold = if valgrind {
        match (callgrind(&format!("fold:{cg_rows}")), callgrind("fold:0")) {
            (Ok(a), Ok(b)) => Some(a.saturating_sub(b)),
            (Err(e), _) | (_, Err(e)) => {
                log(&e);
                None
            }
        }
    } else {
        None
    };
    let mut line = vec![0u32; usize::from(wl::SIZE)];
    let mut out = Vec::new();
    for w in Workload::ALL {
        for imp in host_impls() {
            if !host_has(w, imp) {
                continue;
            }
            let spec = |r: u16| format!("{}:{}:{r}", w.name(), imp.name());
            let instructions = fold.and_then(|fold| {
                let a = callgrind(&spec(cg_rows));
                let b = callgrind(&spec(0));
                match (a, b) {
                    (Ok(a), Ok(b)) => Some(
                        a.saturating_sub(b).saturating_sub(fold) as f64
                            / (f64::from(cg_rows) * f64::from(wl::SIZE)),
                    ),
                    (Err(e), _) | (_, Err(e)) => {
                        log(&e);
                        None
                    }
                }
            });
            let samples = f64::from(wl::SIZE) * f64::from(wl::SIZE);
            let work = median_ns(runs, || {
                std::hint::black_box(host_kernel(w, imp, wl::SIZE, &mut line));
            });
            let setup = median_ns(runs, || {
                std::hint::black_box(host_kernel(w, imp, 0, &mut line));
            });
            let fold_ns = median_ns(runs, || {
                std::hint::black_box(kernels::fold_only(wl::SIZE, &mut line));
            });
            log(&format!("host {} {}", w.name(), imp.name()));
            out.push(PeerRow {
                workload: w.name().into(),
                implementation: imp.name().into(),
                target: HOST_TRIPLE.into(),
                instructions_per_sample: instructions,
                ns_per_sample: Some((work - setup - fold_ns).max(0.0) / samples),
                checksum_match: None,
                samples: u64::from(wl::SIZE) * u64::from(wl::SIZE),
            });
        }
    }
    out
}

/// Net count of device job `name` (job minus its `/setup`), `None` if either is missing.
fn net(run: &device::DeviceRun, name: &str) -> Option<(u64, u32)> {
    let a = run.job(name)?;
    let b = run.job(&format!("{name}/setup"))?;
    Some((a.instructions.saturating_sub(b.instructions), a.checksum))
}

/// The texcore lattice hash of a device's peers firmware (`crate::report::default_hash`).
fn device_hash(t: DeviceTarget) -> HashKind {
    super::default_hash(t)
}

/// Rows each device job evaluates in a build with (`band`) or without feature `peers-band`.
pub fn device_rows(band: bool) -> u16 {
    if band {
        wl::BAND
    } else {
        wl::SIZE
    }
}

/// The device job of a row: `peers:<workload>:<implementation>` (its set-up job adds `/setup`).
pub fn job_name(w: Workload, imp: Implementation) -> String {
    format!("peers:{}:{}", w.name(), imp.name())
}

/// Measures the device rows of `run` (the peers firmware of `run.target`, `rows` rows a job).
pub fn device_rows_of(run: &device::DeviceRun, rows: u16) -> Result<Vec<PeerRow>, String> {
    let target = run.target;
    let (fold, _) = net(run, "peers:fold")
        .ok_or_else(|| format!("{target}: the firmware reported no peers:fold job"))?;
    let samples = u64::from(rows) * u64::from(wl::SIZE);
    let mut line = vec![0u32; usize::from(wl::SIZE)];
    let mut out = Vec::new();
    for (w, i) in kernels::rows() {
        let name = job_name(w, i);
        let (count, checksum) =
            net(run, &name).ok_or_else(|| format!("{target}: no job {name} in the report"))?;
        let host = kernels::run(w, i, device_hash(target), rows, &mut line);
        out.push(PeerRow {
            workload: w.name().into(),
            implementation: i.name().into(),
            target: target.triple().into(),
            instructions_per_sample: Some(count.saturating_sub(fold) as f64 / samples as f64),
            ns_per_sample: None,
            checksum_match: Some(host == checksum),
            samples,
        });
    }
    Ok(out)
}

/// Builds and runs the peers firmware on `target`.
pub fn run_device(
    target: DeviceTarget,
    band: bool,
    run: &RunOptions,
) -> Result<Vec<PeerRow>, String> {
    let mut opts = run.clone();
    opts.features = vec![if band { "peers-band" } else { "peers" }.to_string()];
    let r = device::run_firmware(target, &opts).map_err(|e| e.to_string())?;
    if !r.pass() {
        return Err(format!(
            "{target}: the peers firmware reported a failed check"
        ));
    }
    device_rows_of(&r, device_rows(band))
}

/// Runs the report.
pub fn report(opts: &PeersOptions, log: &mut dyn FnMut(&str)) -> Result<Vec<PeerRow>, String> {
    let mut rows = Vec::new();
    for &t in &opts.targets {
        log(&format!("building and running the peers firmware on {t}"));
        rows.extend(run_device(t, opts.quick, &opts.run)?);
    }
    if opts.host {
        rows.extend(host_rows(opts.quick, log));
    }
    Ok(rows)
}

fn short(target: &str) -> &str {
    match target {
        "thumbv7em-none-eabihf" => "Cortex-M4F",
        "riscv32imc-unknown-none-elf" => "rv32imc",
        _ => "host",
    }
}

/// The markdown of the rows: one table per workload.
pub fn markdown(rows: &[PeerRow], quick: bool) -> String {
    let mut targets: Vec<&str> = Vec::new();
    for r in rows {
        if !targets.contains(&r.target.as_str()) {
            targets.push(&r.target);
        }
    }
    let key = |r: &PeerRow| {
        (
            r.workload.clone(),
            r.implementation.clone(),
            r.target.clone(),
        )
    };
    let by: HashMap<_, &PeerRow> = rows.iter().map(|r| (key(r), r)).collect();
    let get = |w: &str, i: &str, t: &str| by.get(&(w.to_string(), i.to_string(), t.to_string()));
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# texcore next to the peer noise libraries\n\n\
         Generated by `texsim report peers{}` ({} build of texsim on the host); do not edit.\n\n\
         The plane: 256 x 256 pixels, pixel `(x, y)` at `s = x/32`, `t = y/32`, `r = 0.37` \
         (`24248 / 65536`), whole-row spans (16-pixel spans for `-span16`: each row's spans \
         left to right through the plane's set-up, `span::PlaneSetup`, and walked from the \
         rows' cell schedule, `span::PlaneSpans` for values and `texture::TextureSpans` for \
         colours, each row's walk kept from span to span), every sample \
         stored into a line buffer (`texcore::texture::workload::peers`, \
         `workloads/src/peers.rs`).\n\n\
         Device figures are exact QEMU instruction counts per sample ({}), net of the set-up and \
         of the checksum fold; host figures are callgrind instructions and the median ns per \
         sample (x86_64). `ratio` is the row's figure over `texcore-fd`'s on the same target \
         (below 1: fewer instructions than `texcore-fd`). The instruction counts are exact and \
         repeatable; the host nanoseconds are wall-clock medians on the machine that ran the \
         report and vary with its load.\n\n\
         Equivalents: `fastnoise-lite` (f32) `Value` has the smooth fade `3u^2 - 2u^3` (the \
         equivalent of `smooth-1oct`, the nearest one of the trilinear workloads) and `Perlin` \
         the quintic fade, `FBm` for 4 octaves; `noise` (noise-rs, f64, host only) `Value` has the \
         quintic fade, `Fbm` for 4 octaves. No peer has the gradients or the colour stage.\n\n\
         `texcore-ramp` (the marble workloads) colours the same samples through the \
         pre-filtered RGB565 ramp (`Antialias::Ramp`, approximate: the width rounded to a power \
         of two, one read a pixel; its error in `docs/accuracy.md`, `antialiasing=ramp`) instead \
         of the summed-area table; `texcore-ramp-diff` also takes each pixel's filter width \
         from the differences of neighbouring values instead of the gradients \
         (`texcore::texture::DifferenceRows` and `DifferenceSpans`, approximate: the noise \
         evaluated without its gradients, the values of the row above kept in a \
         `DifferenceMemory`; its error in `docs/accuracy.md`, `combo=ramp+differences`). \
         `texcore-fused` (the Perlin workloads) is `EvalMode::Fused`, \
         the one approximate evaluation mode here: on this plane (rows along the lattice's x axis) one octave is the exact \
         modes' row, and rows of several octaves add each octave's floored product term after \
         term, within one unit of `2^-16` a term of the exact value (its error in \
         `docs/accuracy.md`, knob `gradient_blend`); the other rows are exact. The exact modes \
         interpolate gradient noise in one blend (`docs/model.md` 4.3): along a row of the \
         lattice's x axis two stepped 64-bit sums and one product a pixel.\n",
        if quick { " --quick" } else { "" },
        if cfg!(debug_assertions) {
            "debug"
        } else {
            "optimised"
        },
        if quick {
            "one 8-row band of the plane"
        } else {
            "the whole plane"
        },
    );
    for w in Workload::ALL {
        let impls: Vec<&str> = host_impls()
            .into_iter()
            .map(HostImpl::name)
            .filter(|i| targets.iter().any(|t| get(w.name(), i, t).is_some()))
            .collect();
        if impls.is_empty() {
            continue;
        }
        let _ = writeln!(s, "## `{}`\n", w.name());
        let mut head = String::from("| implementation |");
        let mut rule = String::from("|---|");
        for t in &targets {
            let t = short(t);
            if t == "host" {
                head.push_str(" host instr | ratio | host ns | ratio |");
                rule.push_str("---:|---:|---:|---:|");
            } else {
                let _ = write!(head, " {t} | ratio |");
                rule.push_str("---:|---:|");
            }
        }
        let _ = writeln!(s, "{head}\n{rule}");
        for i in impls {
            let mut line = format!("| `{i}` |");
            for t in &targets {
                let base = get(w.name(), "texcore-fd", t);
                let row = get(w.name(), i, t);
                let cell = |v: Option<f64>, b: Option<f64>, digits: usize| match v {
                    Some(v) => {
                        let ratio = b
                            .filter(|&b| b > 0.0)
                            .map_or("".to_string(), |b| format!("{:.2}", v / b));
                        format!(" {v:.digits$} | {ratio} |")
                    }
                    None => " - | |".to_string(),
                };
                let ins = cell(
                    row.and_then(|r| r.instructions_per_sample),
                    base.and_then(|r| r.instructions_per_sample),
                    1,
                );
                line.push_str(&ins);
                if short(t) == "host" {
                    line.push_str(&cell(
                        row.and_then(|r| r.ns_per_sample),
                        base.and_then(|r| r.ns_per_sample),
                        2,
                    ));
                }
            }
            let _ = writeln!(s, "{line}");
        }
        s.push('\n');
    }
    let bad: Vec<String> = rows
        .iter()
        .filter(|r| r.checksum_match == Some(false))
        .map(|r| format!("`{}` `{}` on {}", r.workload, r.implementation, r.target))
        .collect();
    if bad.is_empty() {
        let _ = writeln!(
            s,
            "Every device checksum equals the host's recomputation of the same kernel."
        );
    } else {
        let _ = writeln!(
            s,
            "Device checksums that differ from the host's: {}.",
            bad.join(", ")
        );
    }
    s
}

/// Where `--write-docs` writes: `docs/peers.md` of the workspace.
pub fn docs_path() -> PathBuf {
    device::workspace_root().join("docs").join("peers.md")
}

/// `texsim report peers`: exit 0, 1 when a run fails or a texcore device checksum differs from
/// the host's, 2 for a bad `--kernel`.
pub fn cli(a: &super::cli::PeersArgs) -> std::process::ExitCode {
    use std::io::Write;
    use std::process::ExitCode;
    if let Some(spec) = &a.kernel {
        return match run_kernel_spec(spec) {
            Ok(c) => {
                println!("{c:#010x}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("texsim: {e}");
                ExitCode::from(2)
            }
        };
    }
    let opts = PeersOptions {
        quick: a.quick,
        targets: if a.no_device {
            Vec::new()
        } else if a.targets.is_empty() {
            DeviceTarget::ALL.to_vec()
        } else {
            a.targets.iter().map(|&t| t.into()).collect()
        },
        host: !a.no_host,
        ..PeersOptions::default()
    };
    if cfg!(debug_assertions) {
        eprintln!(
            "texsim: warning: this texsim is a debug build; the host figures are not representative \
             (cargo run --release -p host-sim -- report peers)"
        );
    }
    let rows = match report(&opts, &mut |m| eprintln!("texsim: {m}")) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("texsim: report peers failed: {e}");
            return ExitCode::from(1);
        }
    };
    let md = markdown(&rows, a.quick);
    if a.json {
        let mut out = std::io::stdout().lock();
        let _ = serde_json::to_writer_pretty(&mut out, &rows);
        let _ = writeln!(out);
    } else {
        print!("{md}");
    }
    if a.write_docs {
        let path = docs_path();
        if let Err(e) = super::write_atomic(&path, &md) {
            eprintln!("texsim: writing {}: {e}", path.display());
            return ExitCode::from(1);
        }
        eprintln!("texsim: wrote {}", path.display());
    }
    let bad: Vec<String> = rows
        .iter()
        .filter(|r| r.checksum_match == Some(false) && r.implementation.starts_with("texcore"))
        .map(|r| format!("{} {} {}", r.target, r.workload, r.implementation))
        .collect();
    if !bad.is_empty() {
        eprintln!(
            "texsim: device and host checksums differ: {}",
            bad.join(", ")
        );
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::device::{DeviceRun, JobResult};

    #[test]
    fn kernel_specs_are_checked() {
        assert_eq!(run_kernel_spec("fold:0"), Ok(kernels::FNV_OFFSET));
        assert_eq!(
            run_kernel_spec("value-1oct:texcore-fd:0"),
            Ok(kernels::FNV_OFFSET)
        );
        for bad in [
            "",
            "fold",
            "fold:257",
            "fold:-1",
            "nope:texcore-fd:1",
            "value-1oct:nope:1",
            "value-1oct:texcore-fd:x",
            "a:b:c:d",
        ] {
            assert!(run_kernel_spec(bad).is_err(), "{bad}");
        }
        // A row that does not exist folds nothing.
        let mut line = vec![0u32; 256];
        assert_eq!(
            host_kernel(Workload::Value4Grad, HostImpl::NoiseRs, 1, &mut line),
            0
        );
    }

    fn job(name: &str, checksum: u32, instructions: u64) -> JobResult {
        JobResult {
            name: name.into(),
            checksum,
            instructions,
            repeat: instructions,
            pass: true,
        }
    }

    /// Per-sample counts are `(job - setup - fold) / samples`, and a checksum the host does not
    /// reproduce is flagged.
    #[test]
    fn device_rows_subtract_setup_and_fold() {
        let rows = 2u16;
        let samples = u64::from(rows) * 256;
        let mut jobs = vec![
            job("peers:fold", 1, 1000 + 5 * samples),
            job("peers:fold/setup", 1, 1000),
        ];
        let mut line = vec![0u32; 256];
        let hash = default_hash_of(DeviceTarget::Riscv32imc);
        for (k, (w, i)) in kernels::rows().enumerate() {
            let name = job_name(w, i);
            let good = kernels::run(w, i, hash, rows, &mut line);
            // Row 0's checksum is wrong.
            let c = if k == 0 { good ^ 1 } else { good };
            jobs.push(job(&name, c, 500 + (5 + 100) * samples));
            jobs.push(job(&format!("{name}/setup"), 0, 500));
        }
        let run = DeviceRun {
            target: DeviceTarget::Riscv32imc,
            reported_target: "riscv32imc-unknown-none-elf".into(),
            counter: "minstret".into(),
            unit: "instructions".into(),
            overhead: 11,
            overhead_repeat: 11,
            selftests: Vec::new(),
            jobs,
            stack: None,
            firmware_pass: true,
            exit_code: 0,
            log: Vec::new(),
        };
        let out = device_rows_of(&run, rows).expect("rows");
        assert_eq!(out.len(), kernels::rows().count());
        for (k, r) in out.iter().enumerate() {
            assert_eq!(r.instructions_per_sample, Some(100.0), "{r:?}");
            assert_eq!(r.checksum_match, Some(k != 0), "{r:?}");
            assert_eq!(r.samples, samples);
        }
        let md = markdown(&out, true);
        for w in Workload::ALL {
            assert!(md.contains(&format!("## `{}`", w.name())), "{w:?}");
        }
        assert!(md.contains("| `texcore-fd` | 100.0 | 1.00 |"), "{md}");
        assert!(md.contains("differ from the host's: `value-1oct` `texcore-fd`"));
        // A missing job is an error, not a row.
        let mut short = run.clone();
        short.jobs.retain(|j| j.name != "peers:fold");
        assert!(device_rows_of(&short, rows).is_err());
    }

    /// The firmware's job lists (`workloads::peer_jobs`, whole plane and band) name every row
    /// of the report and its set-up, after `peers:fold` and its set-up, and nothing else.
    #[test]
    fn job_lists_name_every_row() {
        let mut want = vec!["peers:fold".to_string(), "peers:fold/setup".to_string()];
        for (w, i) in kernels::rows() {
            want.push(job_name(w, i));
            want.push(format!("{}/setup", job_name(w, i)));
        }
        for list in [workloads::peer_jobs::PLANE, workloads::peer_jobs::BAND] {
            let mut got: Vec<String> = list.iter().map(|j| j.name.to_string()).collect();
            let mut want = want.clone();
            got.sort();
            want.sort();
            assert_eq!(got, want);
        }
        assert_eq!(workloads::peer_jobs::PLANE_ROWS, device_rows(false));
        assert_eq!(workloads::peer_jobs::BAND_ROWS, device_rows(true));
    }

    fn default_hash_of(t: DeviceTarget) -> HashKind {
        device_hash(t)
    }
}
