//! `texsim report cycles`: instructions per pixel of every device job on both targets.
//!
//! Builds the firmware (release) for the Cortex-M4F and rv32imc, runs it under QEMU with
//! `-icount shift=0` (exact instruction counts, see `host_sim::device`), and for every row of the
//! texture-unit suite ([`super::suite`]) reports
//!
//! - `instructions`: the job's count minus its `/setup` job's count (textures, tables and inputs
//!   built, nothing shaded), i.e. the instructions of the work itself; a built-in scene's frame
//!   is rendered as several jobs (horizontal strips, so that each fits the Cortex-M4F counter's
//!   window, [`M4F_WINDOW`]) and its row adds them up;
//! - `instructions_per_pixel`: that divided by the row's units (pixels; look-ups or triangles
//!   for the stages whose `unit` says so);
//! - `checksum_match`: the device's checksum equals the host's checksum of the same job with the
//!   same lattice hash (the one the device reports in its `config:hash` job), and the set-up
//!   checksums match too; for a built-in scene every strip matches and the last strip's
//!   checksum, the whole frame's, equals what `texsim render <scene> --checksum` prints.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Duration;

use serde::Serialize;
use texcore::hash::HashKind;

use super::{
    approximate_suite, hash_from_config, host_checksum, suite_for, write_atomic, JobKind, SuiteJob,
    APPROXIMATE_FEATURE,
};
use crate::device::{self, DeviceError, DeviceRun, DeviceTarget, RunOptions};

/// One row of the report.
#[derive(Clone, Debug, Serialize)]
pub struct CycleRow {
    /// Target triple.
    pub target: String,
    /// Job name: `plane:<material>`, `stage:<stage>` or `scene:<scene>`.
    pub scene: String,
    /// What the job is.
    pub kind: JobKind,
    /// The stage marker: `true` for the per-stage rows (`stage:*`).
    pub stage: bool,
    /// What one unit of work is (`pixel`, `lookup`, `triangle`).
    pub unit: String,
    /// Units of work.
    pub units: u64,
    /// Net instructions per unit (`instructions / units`).
    pub instructions_per_pixel: f64,
    /// Net instructions: the job minus its set-up job (summed over a built-in scene's strips).
    pub instructions: u64,
    /// Instructions of the set-up job alone (summed over a built-in scene's strips: each strip
    /// builds the scene and its textures again).
    pub setup_instructions: u64,
    /// Device jobs the row adds up: 1, or a built-in scene's strips.
    pub device_jobs: usize,
    /// The largest count of one of those jobs (set-up included): what the Cortex-M4F counter
    /// must measure in one window ([`M4F_WINDOW`]).
    pub max_job_instructions: u64,
    /// Lattice hash the device shaded with.
    pub hash: String,
    /// Device checksum (hex): a built-in scene's is its last strip's, the whole frame's.
    pub device_checksum: String,
    /// Host checksum of the same job (hex): a built-in scene's is what
    /// `texsim render <scene> --checksum` prints (`--hash int` for the integer hash).
    pub host_checksum: String,
    /// Device and host agree on the job and on its set-up (on every strip of a built-in scene
    /// and its set-up, and on the whole frame).
    pub checksum_match: bool,
}

/// The most instructions the Cortex-M4F counter (the SysTick vernier under QEMU) measures in
/// one job: 2^24 ticks of 40 instructions.
pub const M4F_WINDOW: u64 = (1 << 24) * 40;

/// Options of the report.
#[derive(Clone, Debug)]
pub struct CyclesOptions {
    /// Only the reference subset of jobs ([`QUICK_JOBS`]).
    pub quick: bool,
    /// Targets to run.
    pub targets: Vec<DeviceTarget>,
    /// Where to write the markdown table (`None`: do not write).
    pub markdown: Option<PathBuf>,
    /// Build and run options.
    pub run: RunOptions,
}

impl Default for CyclesOptions {
    fn default() -> Self {
        CyclesOptions {
            quick: false,
            targets: DeviceTarget::ALL.to_vec(),
            markdown: Some(device::workspace_root().join("docs/cycles.md")),
            run: RunOptions {
                timeout: Duration::from_secs(900),
                ..RunOptions::default()
            },
        }
    }
}

/// The rows of `--quick`: the fast-path reference (marble check plane with csat), one octave of
/// noise, the csat filter, one suite scene and one built-in scene.
pub const QUICK_JOBS: [&str; 5] = [
    "plane:marble",
    "stage:noise-octave",
    "stage:csat",
    "scene:floor",
    "scene:fire",
];

/// Why the report could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CyclesError {
    /// Building or running the firmware failed.
    #[error("{0}")]
    Device(#[from] DeviceError),
    /// A job of the suite is missing from the device's report.
    #[error("{target}: the firmware did not report job `{job}`")]
    MissingJob {
        /// Target.
        target: DeviceTarget,
        /// Job.
        job: String,
    },
    /// The host has no computation for a job.
    #[error("no host computation for job `{0}`")]
    NoHost(String),
    /// Building or running the Cortex-M0 example (`examples/boards/qemu-m0`) failed.
    #[error("Cortex-M0 example: {0}")]
    M0(String),
    /// Writing the markdown failed.
    #[error("writing {path}: {source}")]
    Write {
        /// File.
        path: PathBuf,
        /// Error.
        source: std::io::Error,
    },
}

fn hash_name(h: HashKind) -> &'static str {
    match h {
        HashKind::Permutation => "permutation",
        HashKind::Integer => "integer",
    }
}

/// The rows of one target's run.
pub fn rows_for_run(
    target: DeviceTarget,
    run: &DeviceRun,
    jobs: &[SuiteJob],
) -> Result<Vec<CycleRow>, CyclesError> {
    let missing = |job: &str| CyclesError::MissingJob {
        target,
        job: job.to_string(),
    };
    let hash = run
        .job("config:hash")
        .and_then(|j| hash_from_config(j.checksum))
        .ok_or_else(|| missing("config:hash"))?;
    let mut rows = Vec::new();
    for job in jobs {
        let (mut net, mut setup_sum, mut max_job) = (0u64, 0u64, 0u64);
        let (mut parts_match, mut last, mut last_host) = (true, 0u32, None);
        for name in &job.device_jobs {
            let setup_name = format!("{name}/setup");
            let main = run.job(name).ok_or_else(|| missing(name))?;
            let setup = run.job(&setup_name).ok_or_else(|| missing(&setup_name))?;
            let host =
                host_checksum(name, hash).ok_or_else(|| CyclesError::NoHost(name.clone()))?;
            let host_setup = host_checksum(&setup_name, hash)
                .ok_or_else(|| CyclesError::NoHost(setup_name.clone()))?;
            net += main.instructions.saturating_sub(setup.instructions);
            setup_sum += setup.instructions;
            max_job = max_job.max(main.instructions).max(setup.instructions);
            parts_match &= main.checksum == host && setup.checksum == host_setup;
            (last, last_host) = (main.checksum, Some(host));
        }
        // A row of several jobs (a built-in scene's strips) is also checked as a whole: the last
        // strip's checksum is the frame's, which the host computes from its own whole frame.
        let host = match job.device_jobs.as_slice() {
            [one] if *one == job.name => last_host,
            _ => host_checksum(&job.name, hash),
        }
        .ok_or_else(|| CyclesError::NoHost(job.name.clone()))?;
        rows.push(CycleRow {
            target: target.triple().to_string(),
            scene: job.name.clone(),
            kind: job.kind,
            stage: job.kind == JobKind::Stage,
            unit: job.unit.to_string(),
            units: job.units,
            instructions_per_pixel: net as f64 / job.units.max(1) as f64,
            instructions: net,
            setup_instructions: setup_sum,
            device_jobs: job.device_jobs.len(),
            max_job_instructions: max_job,
            hash: hash_name(hash).to_string(),
            device_checksum: format!("{last:#010x}"),
            host_checksum: format!("{host:#010x}"),
            checksum_match: parts_match && !job.device_jobs.is_empty() && last == host,
        });
    }
    Ok(rows)
}

/// Builds, runs and compares on every target of `opts`; writes the markdown when asked.
pub fn report(opts: &CyclesOptions) -> Result<Vec<CycleRow>, CyclesError> {
    let mut rows = Vec::new();
    for &target in &opts.targets {
        let mut jobs = suite_for(target);
        if opts.quick {
            jobs.retain(|j| QUICK_JOBS.contains(&j.name.as_str()));
        }
        let run = match device::run_firmware(target, &opts.run) {
            Ok(run) => run,
            // A completed run whose own checks failed still has counts and checksums to report.
            Err(DeviceError::Failed(run)) => *run,
            Err(e) => return Err(e.into()),
        };
        rows.extend(rows_for_run(target, &run, &jobs)?);
        if !opts.quick {
            rows.extend(approximate_rows(target, &opts.run)?);
        }
    }
    if !opts.quick {
        rows.push(m0_row(&opts.run)?);
    }
    if let Some(path) = &opts.markdown {
        write_atomic(path, &markdown(&rows, opts.quick)).map_err(|source| CyclesError::Write {
            path: path.clone(),
            source,
        })?;
    }
    Ok(rows)
}

/// The rows of the built-in scenes in the approximate modes ([`approximate_suite`]), from the
/// firmware's own build for them ([`APPROXIMATE_FEATURE`]: they do not fit the default build's
/// flash).
pub fn approximate_rows(
    target: DeviceTarget,
    run: &RunOptions,
) -> Result<Vec<CycleRow>, CyclesError> {
    let mut opts = run.clone();
    opts.features.push(APPROXIMATE_FEATURE.to_string());
    let run = match device::run_firmware(target, &opts) {
        Ok(run) => run,
        Err(DeviceError::Failed(run)) => *run,
        Err(e) => return Err(e.into()),
    };
    rows_for_run(target, &run, &approximate_suite())
}

/// The Cortex-M0 row: the `qemu-m0` board example (QEMU `microbit`, 16 KB RAM) shading a
/// 64 x 64 marble plane with a 64-entry csat table, counted through the nRF51's TIMER0.
fn m0_row(run: &RunOptions) -> Result<CycleRow, CyclesError> {
    let board = super::boards::BOARDS
        .iter()
        .find(|b| b.name == "qemu-m0")
        .ok_or_else(|| CyclesError::M0("no qemu-m0 board".into()))?;
    let elf = board
        .build(&run.cargo, &run.workspace)
        .map_err(CyclesError::M0)?;
    let m0 = super::boards::run_qemu_m0(&elf).map_err(CyclesError::M0)?;
    let host = super::boards::host_m0_checksum();
    Ok(CycleRow {
        target: format!("{} (QEMU microbit, Cortex-M0)", board.target),
        scene: "plane:marble (64-entry table)".to_string(),
        kind: JobKind::Plane,
        stage: false,
        unit: "pixel".to_string(),
        units: m0.pixels,
        instructions_per_pixel: m0.instructions as f64 / m0.pixels.max(1) as f64,
        instructions: m0.instructions,
        setup_instructions: m0.setup_instructions,
        device_jobs: 1,
        max_job_instructions: m0.instructions + m0.setup_instructions,
        hash: hash_name(HashKind::Integer).to_string(),
        device_checksum: format!("{:#010x}", m0.checksum),
        host_checksum: host.map_or_else(|| "-".to_string(), |h| format!("{h:#010x}")),
        checksum_match: host == Some(m0.checksum),
    })
}

/// The markdown table of the rows.
pub fn markdown(rows: &[CycleRow], quick: bool) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Device instruction counts");
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "<!-- Generated by `texsim report cycles{}`; do not edit. -->",
        if quick { " --quick" } else { "" }
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "Exact instruction counts under QEMU (`-icount shift=0`: RISC-V `minstret`, Cortex-M \
         SysTick vernier; see `firmware/src/counter.rs`), release build. `instr/unit` is the \
         job's count minus its `/setup` job's count (textures, tables and inputs built, nothing \
         shaded), divided by its units. Check planes are 64 x 64 pixels in spans of 16 with a \
         256-entry colour table and csat; `band:<mode>` rows are one renderer band (8 rows of \
         320 pixels) of 4-octave trilinear value noise with gradients, one span per row, in each \
         evaluation mode (multipass corner-by-corner noise against `Direct` and `Fd`: \
         `docs/multipass.md`), every sample folded into the checksum; scenes are rendered at display size (320 x 240; the \
         zone plate 256 x 256) through `Renderer::render_banded` with 8-row bands into a \
         `ChecksumSink` (FNV-1a over RGB565), no frame buffer. The built-in scenes (`scene:wood` \
         to `scene:torus`, their still frame) are rendered in {} horizontal strips \
         (`Renderer::render_banded_rows_binned` with the frame's `FrameBins`: the first strip's \
         first band bins the mesh quads into the rows they can cover, in a 4 KB table, so every \
         other band only generates the quads that touch it; each later strip fills the same bins \
         with `Renderer::bin` in both its job and its set-up job, so a frame counts one walk over \
         the scene, as one whole-frame call does), one device job each (their counts are summed here), \
         each strip's checksum continuing the previous one's: \
         the last strip's is the checksum of the whole frame, which must equal \
         `texsim render <scene> --checksum` (with `--hash int` on rv32imc). The approximate rows \
         (`scene:<name>~ramp`, `scene:<name>~ramp-diff`) are whole frames of the firmware's \
         `approximate-scenes` build, rendered into an RGB565 band \
         (`Renderer::render_banded_rows_binned_rgb565`: the RGBA band's rows reduced, the same \
         checksum). `match`: the device's \
         checksum equals the host's for the same job, its set-up and (built-in scenes) every \
         strip, with the same lattice hash (Cortex-M4F: permutation table, rv32imc: integer \
         hash). The Cortex-M4F counter (SysTick vernier) measures at most {} instructions per \
         job; `largest job` is the largest single count (set-up included) of a row's jobs.",
        super::scenes::STRIPS,
        super::group(M4F_WINDOW),
    );
    if rows.iter().any(|r| r.target.contains("Cortex-M0")) {
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "The Cortex-M0 row (no FPU, no hardware divide, no 32 x 32 -> 64 multiply) is the \
             `examples/boards/qemu-m0` program under QEMU's `microbit` machine (nRF51, 16 KB of \
             RAM: the job-suite firmware does not fit), release build at `opt-level = 3`: a \
             64 x 64 marble plane with a 64-entry csat table (a 256-entry texture overflows the \
             stack), integer hash. Counted through the nRF51's TIMER0 at 16 MHz under \
             `-icount shift=0` (one tick = 62.5 instructions, so the total is exact to 63 \
             instructions); `set-up` is the texture's construction, and an empty shading call is \
             subtracted from the work."
        );
    }
    let mut targets: Vec<&str> = rows.iter().map(|r| r.target.as_str()).collect();
    targets.dedup();
    for t in targets {
        let _ = writeln!(s);
        let _ = writeln!(s, "## {t}");
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "| job | unit | units | instr/unit | instructions | set-up | largest job | hash | checksum | match |"
        );
        let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---|---|---|");
        for r in rows.iter().filter(|r| r.target == t) {
            let _ = writeln!(
                s,
                "| `{}` | {} | {} | {:.1} | {} | {} | {} | {} | `{}` | {} |",
                r.scene,
                r.unit,
                super::group(r.units),
                r.instructions_per_pixel,
                super::group(r.instructions),
                super::group(r.setup_instructions),
                super::group(r.max_job_instructions),
                r.hash,
                r.device_checksum,
                if r.checksum_match { "yes" } else { "**NO**" }
            );
        }
    }
    s
}
