//! Host side of the device firmware: build it, run it under QEMU with exact instruction
//! counting, decode its defmt report, and return structured per-job results.
//!
//! ```no_run
//! use host_sim::device::{run_firmware, DeviceTarget, RunOptions};
//! let run = run_firmware(DeviceTarget::Riscv32imc, &RunOptions::default())?;
//! for job in &run.jobs {
//!     println!("{} {:#010x} {} instructions", job.name, job.checksum, job.instructions);
//! }
//! # Ok::<(), host_sim::device::DeviceError>(())
//! ```
//!
//! Steps, each with its own error variant (nothing here panics on bad input or a failed run):
//! 1. [`build_firmware`]: `cargo build --release -p firmware --target T` in the workspace root
//!    (so `.cargo/config.toml` and `memory.x` apply); the ELF path comes from cargo's JSON
//!    messages.
//! 2. [`run_elf`]: `qemu-system-arm -machine mps2-an386 -cpu cortex-m4` or
//!    `qemu-system-riscv32 -machine virt -bios none`, always with
//!    `-icount shift=0,align=off,sleep=off` (one instruction per virtual ns: deterministic),
//!    semihosting output on a stdio chardev, no display, killed after a timeout.
//! 3. [`decode_defmt`]: the semihosting byte stream is decoded with `defmt-decoder` and the
//!    ELF's `.defmt` table into one text line per frame.
//! 4. [`parse_report`]: the `TEXFW ...` lines (protocol in the firmware's `harness` module) become
//!    a [`DeviceRun`].
//!
//! [`DeviceError::QemuMissing`] is returned when the QEMU binary is not installed, so callers
//! (tests) can decide whether that is a skip or a failure.
//!
//! Counts: `instructions` is net of the measurement overhead (the raw count of measuring an
//! empty job, reported as [`DeviceRun::overhead`]). On RISC-V they come from `minstret`, on the
//! Cortex-M from a SysTick vernier (see the firmware's `counter` module); both are exact under
//! icount and identical from run to run.

use std::fmt;
use std::io::{self, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::thread;
use std::time::{Duration, Instant};

/// A device target the firmware is built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DeviceTarget {
    /// Cortex-M4F, `thumbv7em-none-eabihf`, QEMU `mps2-an386`.
    CortexM4F,
    /// RISC-V soft-core class, `riscv32imc-unknown-none-elf`, QEMU `virt`.
    Riscv32imc,
}

impl DeviceTarget {
    /// Both targets.
    pub const ALL: [DeviceTarget; 2] = [DeviceTarget::CortexM4F, DeviceTarget::Riscv32imc];

    /// The Rust target triple.
    pub fn triple(self) -> &'static str {
        match self {
            DeviceTarget::CortexM4F => "thumbv7em-none-eabihf",
            DeviceTarget::Riscv32imc => "riscv32imc-unknown-none-elf",
        }
    }

    /// The QEMU system emulator binary.
    pub fn qemu_binary(self) -> &'static str {
        match self {
            DeviceTarget::CortexM4F => "qemu-system-arm",
            DeviceTarget::Riscv32imc => "qemu-system-riscv32",
        }
    }

    /// Machine selection arguments.
    pub fn qemu_machine_args(self) -> &'static [&'static str] {
        match self {
            DeviceTarget::CortexM4F => &["-machine", "mps2-an386", "-cpu", "cortex-m4"],
            DeviceTarget::Riscv32imc => &["-machine", "virt", "-bios", "none"],
        }
    }

    /// The full QEMU argument list for running `elf` (used by [`run_elf`]; the cargo runner
    /// `firmware/qemu-run.sh` uses the same).
    pub fn qemu_args(self, elf: &Path) -> Vec<String> {
        let mut args: Vec<String> = self
            .qemu_machine_args()
            .iter()
            .map(|s| s.to_string())
            .collect();
        for a in [
            "-icount",
            "shift=0,align=off,sleep=off",
            "-display",
            "none",
            "-monitor",
            "none",
            "-serial",
            "none",
            "-chardev",
            "stdio,id=texfw-semihosting",
            "-semihosting-config",
            "enable=on,target=native,chardev=texfw-semihosting",
            "-kernel",
        ] {
            args.push(a.to_string());
        }
        args.push(elf.display().to_string());
        args
    }
}

impl fmt::Display for DeviceTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.triple())
    }
}

/// How to build and run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Workspace root (contains `.cargo/config.toml`, `memory.x`, `firmware/`).
    pub workspace: PathBuf,
    /// Extra cargo features of the firmware crate.
    pub features: Vec<String>,
    /// Kill QEMU after this long.
    pub timeout: Duration,
    /// Cargo binary (default: `$CARGO`, else `cargo`).
    pub cargo: PathBuf,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            workspace: workspace_root(),
            features: Vec::new(),
            timeout: Duration::from_secs(600),
            cargo: std::env::var_os("CARGO")
                .map(PathBuf::from)
                .unwrap_or_else(|| PathBuf::from("cargo")),
        }
    }
}

/// The workspace root this crate was built in (`host-sim/..`).
pub fn workspace_root() -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.parent().unwrap_or(here).to_path_buf()
}

/// One job's result, as reported by the firmware.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JobResult {
    /// Job name.
    pub name: String,
    /// Checksum the job returned on the device.
    pub checksum: u32,
    /// Net instruction count (cycles with the firmware's `dwt` feature) of the first run.
    pub instructions: u64,
    /// Net count of the second run of the same job in the same boot.
    pub repeat: u64,
    /// The firmware's verdict for this job (both runs agreed on checksum and count).
    pub pass: bool,
}

/// One counter self-test: a nop sled of `nops` instructions must measure exactly `nops`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SelfTest {
    /// Sled length.
    pub nops: u32,
    /// What the counter measured (net).
    pub measured: u64,
    /// `measured == nops`.
    pub pass: bool,
}

/// The firmware's stack high-water mark (the free stack is painted before the first job).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StackUse {
    /// Bytes of stack ever used, from the top of RAM.
    pub used: u64,
    /// Bytes between the end of the static data and the top of RAM.
    pub size: u64,
    /// The first job that reached `used`.
    pub job: String,
}

/// A complete, decoded firmware run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceRun {
    /// Target the firmware ran on.
    pub target: DeviceTarget,
    /// Target triple as reported by the firmware.
    pub reported_target: String,
    /// Counter implementation (`minstret`, `systick-vernier`, `dwt-cyccnt`).
    pub counter: String,
    /// Unit of the counts (`instructions` or `cycles`).
    pub unit: String,
    /// Raw count of measuring an empty job; subtracted from every reported count.
    pub overhead: u64,
    /// Second measurement of the overhead (must equal `overhead`).
    pub overhead_repeat: u64,
    /// Counter self-tests.
    pub selftests: Vec<SelfTest>,
    /// Per-job results, in firmware order.
    pub jobs: Vec<JobResult>,
    /// The deepest the stack has been during the jobs (`TEXFW stack ..`; `None` if the
    /// firmware did not report it).
    pub stack: Option<StackUse>,
    /// The firmware's overall verdict (`TEXFW end pass=..`).
    pub firmware_pass: bool,
    /// QEMU's exit code (the firmware's semihosting exit code).
    pub exit_code: i32,
    /// Every decoded defmt line, in order.
    pub log: Vec<String>,
}

impl DeviceRun {
    /// Everything passed: firmware verdict, exit code 0, every self-test and job.
    pub fn pass(&self) -> bool {
        self.firmware_pass
            && self.exit_code == 0
            && self.overhead == self.overhead_repeat
            && self.selftests.iter().all(|s| s.pass)
            && self.jobs.iter().all(|j| j.pass)
    }

    /// The job with this name.
    pub fn job(&self, name: &str) -> Option<&JobResult> {
        self.jobs.iter().find(|j| j.name == name)
    }
}

/// Why building, running or decoding failed.
#[derive(Debug)]
pub enum DeviceError {
    /// The QEMU binary is not installed (or not runnable).
    QemuMissing {
        /// Binary name looked for.
        binary: &'static str,
        /// The error from trying to run it.
        source: io::Error,
    },
    /// `cargo build` of the firmware failed.
    Build {
        /// Target being built.
        target: DeviceTarget,
        /// What went wrong (cargo's diagnostics when it ran).
        message: String,
    },
    /// QEMU could not be started or waited for.
    Io {
        /// What was being done.
        context: String,
        /// The error.
        source: io::Error,
    },
    /// QEMU ran longer than the timeout and was killed.
    Timeout {
        /// Target.
        target: DeviceTarget,
        /// The timeout.
        after: Duration,
        /// Whatever was decoded before the kill.
        log: Vec<String>,
    },
    /// The semihosting stream could not be decoded.
    Decode(String),
    /// QEMU exited without a complete report (crash, panic, early exit).
    Run {
        /// Target.
        target: DeviceTarget,
        /// Exit code (`None`: killed by a signal).
        exit_code: Option<i32>,
        /// Decoded log lines.
        log: Vec<String>,
        /// QEMU's stderr.
        stderr: String,
    },
    /// The firmware completed but reported a failed check (self-test, repeatability).
    Failed(Box<DeviceRun>),
}

impl fmt::Display for DeviceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DeviceError::QemuMissing { binary, source } => write!(
                f,
                "{binary} is not available ({source}); install QEMU with .ci/install-qemu.sh"
            ),
            DeviceError::Build { target, message } => {
                write!(f, "building the firmware for {target} failed: {message}")
            }
            DeviceError::Io { context, source } => write!(f, "{context}: {source}"),
            DeviceError::Timeout { target, after, log } => write!(
                f,
                "firmware on {target} did not finish within {} s; log so far:\n{}",
                after.as_secs(),
                log.join("\n")
            ),
            DeviceError::Decode(m) => write!(f, "decoding the defmt stream failed: {m}"),
            DeviceError::Run {
                target,
                exit_code,
                log,
                stderr,
            } => write!(
                f,
                "firmware run on {target} failed ({}) without a complete report\nlog:\n{}\n\
                 qemu stderr:\n{stderr}",
                match exit_code {
                    Some(c) => format!("exit {c}"),
                    None => "killed by a signal".to_string(),
                },
                log.join("\n")
            ),
            DeviceError::Failed(run) => write!(
                f,
                "firmware on {} reported a failed check (exit {})\nlog:\n{}",
                run.target,
                run.exit_code,
                run.log.join("\n")
            ),
        }
    }
}

impl std::error::Error for DeviceError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            DeviceError::QemuMissing { source, .. } | DeviceError::Io { source, .. } => {
                Some(source)
            }
            _ => None,
        }
    }
}

/// Checks that the QEMU binary for `target` runs; returns its version line.
pub fn check_qemu(target: DeviceTarget) -> Result<String, DeviceError> {
    let binary = target.qemu_binary();
    let out = Command::new(binary)
        .arg("--version")
        .stdin(Stdio::null())
        .output()
        .map_err(|source| DeviceError::QemuMissing { binary, source })?;
    if !out.status.success() {
        return Err(DeviceError::QemuMissing {
            binary,
            source: io::Error::other(format!("`{binary} --version` exited {}", out.status)),
        });
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .lines()
        .next()
        .unwrap_or_default()
        .to_string())
}

/// Builds the firmware (release) for `target`; returns the ELF path.
///
/// Runs `cargo build --release -p firmware --target <triple> [--features ..]` in
/// `opts.workspace`, without the caller's `RUSTFLAGS` (the device build is defined by the
/// repository's config alone).
pub fn build_firmware(target: DeviceTarget, opts: &RunOptions) -> Result<PathBuf, DeviceError> {
    let mut cmd = Command::new(&opts.cargo);
    cmd.current_dir(&opts.workspace).args([
        "build",
        "--release",
        "-p",
        "firmware",
        "--target",
        target.triple(),
        "--message-format=json-render-diagnostics",
    ]);
    if !opts.features.is_empty() {
        cmd.arg("--features").arg(opts.features.join(","));
    }
    isolate_cargo_env(&mut cmd, &[]);
    cargo_artifact(&mut cmd, &opts.cargo, "firmware")
        .map_err(|message| DeviceError::Build { target, message })
}

/// Removes from `cmd` the environment a device build must not inherit, and the variables named
/// in `also`: the outer cargo's per-crate settings (when called from a test or a build script)
/// and ambient host `RUSTFLAGS`, so that the device build (hence its sizes and instruction
/// counts) depends on the repository's configuration alone (a `-C target-cpu=native` would not
/// even build for the device).
pub(crate) fn isolate_cargo_env(cmd: &mut Command, also: &[&str]) {
    for (k, _) in std::env::vars_os() {
        let k = k.to_string_lossy().into_owned();
        if k == "RUSTFLAGS"
            || k == "CARGO_ENCODED_RUSTFLAGS"
            || k == "CARGO_BUILD_RUSTFLAGS"
            || k.starts_with("CARGO_PKG_")
            || k.starts_with("CARGO_CRATE_")
            || k.starts_with("CARGO_BIN_")
            || k == "CARGO_MANIFEST_DIR"
            || k == "CARGO_MANIFEST_PATH"
            || k == "CARGO_PRIMARY_PACKAGE"
            || also.contains(&k.as_str())
        {
            cmd.env_remove(&k);
        }
    }
}

/// Runs a `cargo build --message-format=json` command and returns the executable it built for
/// binary `bin`; on failure, a message with cargo's diagnostics.
pub(crate) fn cargo_artifact(
    cmd: &mut Command,
    cargo: &Path,
    bin: &str,
) -> Result<PathBuf, String> {
    let out = cmd
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("could not run {}: {e}", cargo.display()))?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(format!("cargo exited {}\n{stderr}", out.status));
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    for line in stdout.lines() {
        let Ok(msg) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        if msg["reason"] == "compiler-artifact" && msg["target"]["name"] == bin {
            if let Some(exe) = msg["executable"].as_str() {
                return Ok(PathBuf::from(exe));
            }
        }
    }
    Err(format!(
        "cargo reported no executable for `{bin}`\n{stderr}"
    ))
}

/// Runs an already built firmware ELF under QEMU and parses its report.
pub fn run_elf(
    target: DeviceTarget,
    elf: &Path,
    timeout: Duration,
) -> Result<DeviceRun, DeviceError> {
    check_qemu(target)?;
    let elf_bytes = std::fs::read(elf).map_err(|source| DeviceError::Io {
        context: format!("reading {}", elf.display()),
        source,
    })?;
    let mut child = Command::new(target.qemu_binary())
        .args(target.qemu_args(elf))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|source| DeviceError::Io {
            context: format!("starting {}", target.qemu_binary()),
            source,
        })?;
    let stdout = drain(child.stdout.take());
    let stderr = drain(child.stderr.take());
    let status = wait_timeout(&mut child, timeout);
    let stream = stdout.join().unwrap_or_default();
    let stderr = String::from_utf8_lossy(&stderr.join().unwrap_or_default()).into_owned();
    let status = status.map_err(|source| DeviceError::Io {
        context: format!("waiting for {}", target.qemu_binary()),
        source,
    })?;
    let log = decode_defmt(&elf_bytes, &stream)?;
    let Some(status) = status else {
        return Err(DeviceError::Timeout {
            target,
            after: timeout,
            log,
        });
    };
    let exit_code = status.code();
    match parse_report(target, &log, exit_code.unwrap_or(-1)) {
        Some(run) if run.pass() => Ok(run),
        Some(run) if exit_code.is_some() => Err(DeviceError::Failed(Box::new(run))),
        _ => Err(DeviceError::Run {
            target,
            exit_code,
            log,
            stderr,
        }),
    }
}

/// Builds and runs the firmware for `target`: [`build_firmware`] then [`run_elf`].
///
/// `Ok` only when the run passed ([`DeviceRun::pass`]); a completed run with a failed check is
/// [`DeviceError::Failed`] carrying the full results.
pub fn run_firmware(target: DeviceTarget, opts: &RunOptions) -> Result<DeviceRun, DeviceError> {
    // Fail fast, before a build, when QEMU is missing.
    check_qemu(target)?;
    let elf = build_firmware(target, opts)?;
    run_elf(target, &elf, opts.timeout)
}

/// Decodes a defmt byte stream (as written by the firmware's semihosting logger) with the
/// string table of `elf`; one line per frame. A truncated final frame is ignored.
pub fn decode_defmt(elf: &[u8], stream: &[u8]) -> Result<Vec<String>, DeviceError> {
    let table = defmt_decoder::Table::parse(elf)
        .map_err(|e| DeviceError::Decode(format!("reading the ELF's defmt table: {e:#}")))?
        .ok_or_else(|| DeviceError::Decode("the ELF has no .defmt section".into()))?;
    let mut decoder = table.new_stream_decoder();
    decoder.received(stream);
    let mut lines = Vec::new();
    loop {
        match decoder.decode() {
            Ok(frame) => lines.push(frame.display_message().to_string()),
            Err(defmt_decoder::DecodeError::UnexpectedEof) => break,
            Err(defmt_decoder::DecodeError::Malformed) => {
                if table.encoding().can_recover() {
                    lines.push("<malformed defmt frame skipped>".into());
                } else {
                    return Err(DeviceError::Decode("malformed defmt frame".into()));
                }
            }
        }
    }
    Ok(lines)
}

/// Parses the `TEXFW` report lines. `None` if the report is incomplete (no `begin`, `overhead`
/// or `end` line) or a line does not parse.
pub fn parse_report(target: DeviceTarget, log: &[String], exit_code: i32) -> Option<DeviceRun> {
    let mut run = DeviceRun {
        target,
        reported_target: String::new(),
        counter: String::new(),
        unit: String::new(),
        overhead: 0,
        overhead_repeat: 0,
        selftests: Vec::new(),
        jobs: Vec::new(),
        stack: None,
        firmware_pass: false,
        exit_code,
        log: log.to_vec(),
    };
    let (mut begin, mut overhead, mut end) = (false, false, false);
    for line in log {
        let mut words = line.split_whitespace();
        if words.next() != Some("TEXFW") {
            continue;
        }
        let kind = words.next()?;
        let kv: Vec<(&str, &str)> = words.filter_map(|w| w.split_once('=')).collect();
        let get = |k: &str| kv.iter().find(|(key, _)| *key == k).map(|(_, v)| *v);
        match kind {
            "begin" => {
                run.reported_target = get("target")?.to_string();
                run.counter = get("counter")?.to_string();
                run.unit = get("unit")?.to_string();
                begin = true;
            }
            "overhead" => {
                run.overhead = get("raw")?.parse().ok()?;
                run.overhead_repeat = get("repeat")?.parse().ok()?;
                overhead = true;
            }
            "selftest" => run.selftests.push(SelfTest {
                nops: get("nops")?.parse().ok()?,
                measured: get("measured")?.parse().ok()?,
                pass: get("ok")? == "true",
            }),
            "job" => run.jobs.push(JobResult {
                name: get("name")?.to_string(),
                checksum: parse_u32(get("checksum")?)?,
                instructions: get("count")?.parse().ok()?,
                repeat: get("repeat")?.parse().ok()?,
                pass: get("ok")? == "true",
            }),
            "stack" => {
                run.stack = Some(StackUse {
                    used: get("used")?.parse().ok()?,
                    size: get("size")?.parse().ok()?,
                    job: get("job")?.to_string(),
                })
            }
            "end" => {
                run.firmware_pass = get("pass")? == "true";
                end = true;
            }
            _ => {}
        }
    }
    (begin && overhead && end).then_some(run)
}

fn parse_u32(s: &str) -> Option<u32> {
    match s.strip_prefix("0x") {
        Some(hex) => u32::from_str_radix(hex, 16).ok(),
        None => s.parse().ok(),
    }
}

fn drain<R: Read + Send + 'static>(pipe: Option<R>) -> thread::JoinHandle<Vec<u8>> {
    thread::spawn(move || {
        let mut buf = Vec::new();
        if let Some(mut p) = pipe {
            let _ = p.read_to_end(&mut buf);
        }
        buf
    })
}

/// Waits for `child` up to `timeout`; on timeout kills it and returns `Ok(None)`.
fn wait_timeout(child: &mut Child, timeout: Duration) -> io::Result<Option<ExitStatus>> {
    let deadline = Instant::now() + timeout;
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok(Some(status));
        }
        if Instant::now() >= deadline {
            let _ = child.kill();
            let _ = child.wait();
            return Ok(None);
        }
        thread::sleep(Duration::from_millis(10));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(s: &str) -> Vec<String> {
        s.lines().map(str::to_string).collect()
    }

    #[test]
    fn parses_a_report() {
        let log = lines(
            "TEXFW begin target=riscv32imc-unknown-none-elf counter=minstret unit=instructions protocol=1\n\
             TEXFW overhead raw=11 repeat=11\n\
             TEXFW selftest nops=40 measured=40 ok=true\n\
             TEXFW job name=a checksum=0x0000002a count=100 repeat=100 ok=true\n\
             TEXFW stack used=9000 size=115564 job=a\n\
             TEXFW end pass=true jobs=1",
        );
        let run = parse_report(DeviceTarget::Riscv32imc, &log, 0).expect("complete report");
        assert!(run.pass());
        assert_eq!(
            run.stack,
            Some(StackUse {
                used: 9000,
                size: 115_564,
                job: "a".into()
            })
        );
        assert_eq!(run.overhead, 11);
        assert_eq!(
            run.job("a").map(|j| (j.checksum, j.instructions)),
            Some((42, 100))
        );
        assert_eq!(run.selftests.len(), 1);
    }

    #[test]
    fn incomplete_or_failed_reports() {
        let log = lines("TEXFW begin target=t counter=c unit=instructions protocol=1");
        assert!(parse_report(DeviceTarget::CortexM4F, &log, 0).is_none());
        let log = lines(
            "TEXFW begin target=t counter=c unit=instructions protocol=1\n\
             TEXFW overhead raw=5 repeat=5\n\
             TEXFW job name=a checksum=0x1 count=1 repeat=2 ok=false\n\
             TEXFW end pass=false jobs=1",
        );
        let run = parse_report(DeviceTarget::CortexM4F, &log, 1).expect("complete");
        assert!(!run.pass());
    }

    #[test]
    fn qemu_args_have_icount_and_semihosting() {
        let args = DeviceTarget::CortexM4F.qemu_args(Path::new("fw.elf"));
        let s = args.join(" ");
        assert!(s.contains("-icount shift=0,align=off,sleep=off"));
        assert!(s.contains("mps2-an386"));
        assert!(s.ends_with("-kernel fw.elf"));
    }
}
