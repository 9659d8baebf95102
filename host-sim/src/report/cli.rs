//! `texsim report ...` arguments and dispatch.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand, ValueEnum};

use super::{cycles, peers, size};
use crate::device::{self, DeviceTarget};

/// `texsim report` subcommands.
#[derive(Debug, Subcommand)]
pub enum ReportCommand {
    /// Instructions per pixel of every device job under QEMU, with device/host checksum checks;
    /// with --write-docs, writes docs/cycles.md.
    Cycles(CyclesArgs),
    /// Firmware section sizes per target and feature set, texcore's share of .text and the RAM
    /// of a texture-unit instance; with --write-docs, writes docs/size.md.
    Size(SizeArgs),
    /// Error and cost (host time, exact device instructions, code size) of every accuracy knob,
    /// the Pareto front; with --write-docs, writes docs/accuracy.md, docs/accuracy.png,
    /// docs/precision.png and the README summary.
    Accuracy(crate::accuracy::AccuracyArgs),
    /// texcore's modes next to fastnoise-lite (both devices under QEMU and the host) and noise-rs
    /// (host) on the same plane and workloads; writes docs/peers.md only with --write-docs.
    Peers(PeersArgs),
}

/// `texsim report peers`.
#[derive(Clone, Debug, Args)]
pub struct PeersArgs {
    /// Print the rows as one JSON array instead of markdown.
    #[arg(long)]
    pub json: bool,
    /// One 8-row band on the devices, 16 rows under callgrind, 3 timed runs (fast; for tests).
    #[arg(long)]
    pub quick: bool,
    /// Device targets (default: both).
    #[arg(long = "target", value_enum)]
    pub targets: Vec<TargetArg>,
    /// No device rows (host only).
    #[arg(long, conflicts_with = "targets")]
    pub no_device: bool,
    /// No host rows (devices only).
    #[arg(long)]
    pub no_host: bool,
    /// Write docs/peers.md.
    #[arg(long)]
    pub write_docs: bool,
    /// Internal: run one host kernel (`<workload>:<implementation>:<rows>` or `fold:<rows>`),
    /// print its checksum and exit (what the callgrind measurements run).
    #[arg(long, hide = true)]
    pub kernel: Option<String>,
}

/// A device target on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TargetArg {
    /// Cortex-M4F (`thumbv7em-none-eabihf`).
    #[value(name = "thumbv7em-none-eabihf", alias = "m4f")]
    Thumbv7em,
    /// RISC-V rv32imc (`riscv32imc-unknown-none-elf`).
    #[value(name = "riscv32imc-unknown-none-elf", alias = "rv32imc")]
    Riscv32imc,
}

impl From<TargetArg> for DeviceTarget {
    fn from(t: TargetArg) -> Self {
        match t {
            TargetArg::Thumbv7em => DeviceTarget::CortexM4F,
            TargetArg::Riscv32imc => DeviceTarget::Riscv32imc,
        }
    }
}

/// Options shared by both reports.
#[derive(Clone, Debug, Args)]
pub struct CommonArgs {
    /// Print the rows as one JSON array instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Only a subset (fast; for tests).
    #[arg(long)]
    pub quick: bool,
    /// Targets (default: both).
    #[arg(long = "target", value_enum)]
    pub targets: Vec<TargetArg>,
    /// Write the markdown to the workspace's docs/cycles.md or docs/size.md (without it, or
    /// --markdown, the report only prints).
    #[arg(long, conflicts_with = "markdown")]
    pub write_docs: bool,
    /// Write the markdown to this file instead.
    #[arg(long)]
    pub markdown: Option<PathBuf>,
    /// Write no markdown (the default; kept for older command lines).
    #[arg(long, hide = true, conflicts_with_all = ["markdown", "write_docs"])]
    pub no_write: bool,
}

impl CommonArgs {
    fn targets(&self) -> Vec<DeviceTarget> {
        if self.targets.is_empty() {
            DeviceTarget::ALL.to_vec()
        } else {
            self.targets.iter().map(|&t| t.into()).collect()
        }
    }

    fn markdown(&self, default_name: &str) -> Option<PathBuf> {
        if let Some(p) = &self.markdown {
            Some(p.clone())
        } else if self.write_docs {
            Some(device::workspace_root().join("docs").join(default_name))
        } else {
            None
        }
    }
}

/// `texsim report cycles`.
#[derive(Clone, Debug, Args)]
pub struct CyclesArgs {
    /// Common options.
    #[command(flatten)]
    pub common: CommonArgs,
}

/// `texsim report size`.
#[derive(Clone, Debug, Args)]
pub struct SizeArgs {
    /// Common options.
    #[command(flatten)]
    pub common: CommonArgs,
}

fn print_json<T: serde::Serialize>(rows: &T) {
    let mut out = std::io::stdout().lock();
    let _ = serde_json::to_writer_pretty(&mut out, rows);
    let _ = writeln!(out);
}

/// Runs a report subcommand. Exit status 0 on success, 1 when a device checksum differs from the
/// host's or a build or run fails, 2 for bad input.
pub fn run(cmd: &ReportCommand) -> ExitCode {
    match cmd {
        ReportCommand::Accuracy(a) => crate::accuracy::cli(a),
        ReportCommand::Peers(a) => peers::cli(a),
        ReportCommand::Cycles(a) => {
            let opts = cycles::CyclesOptions {
                quick: a.common.quick,
                targets: a.common.targets(),
                markdown: a.common.markdown("cycles.md"),
                ..cycles::CyclesOptions::default()
            };
            let rows = match cycles::report(&opts) {
                Ok(r) => r,
                Err(e) => {
                    eprintln!("texsim: report cycles failed: {e}");
                    return ExitCode::from(1);
                }
            };
            if a.common.json {
                print_json(&rows);
            } else {
                let mut out = std::io::stdout().lock();
                let _ = write!(out, "{}", cycles::markdown(&rows, opts.quick));
            }
            let bad: Vec<String> = rows
                .iter()
                .filter(|r| !r.checksum_match)
                .map(|r| format!("{} {}", r.target, r.scene))
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
        ReportCommand::Size(a) => {
            let opts = size::SizeOptions {
                quick: a.common.quick,
                targets: a.common.targets(),
                markdown: a.common.markdown("size.md"),
                ..size::SizeOptions::default()
            };
            let report = match size::report(&opts) {
                Ok(r) => r,
                Err(e) => {
                    eprintln!("texsim: report size failed: {e}");
                    return ExitCode::from(1);
                }
            };
            if a.common.json {
                print_json(&report.rows);
            } else {
                let mut out = std::io::stdout().lock();
                let _ = write!(out, "{}", size::markdown(&report, opts.quick));
            }
            ExitCode::SUCCESS
        }
    }
}
