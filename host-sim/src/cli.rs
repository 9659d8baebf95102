//! The `texsim` command line.
//!
//! Every subcommand returns an exit status: 0 on success, 1 when a check fails its bounds, 2 for
//! bad input (unknown names, malformed files, out-of-range parameters) with a message on stderr
//! naming the problem. Nothing panics on bad input, and no output file is left half written.

use std::io::Write;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};
use texcore::filter::{Antialias, GradientNorm};
use texcore::hash::HashKind;
use texcore::span::EvalMode;
use texcore::table::TableLookup;

use crate::unit::{self, UnitConfig};

/// texsim: render, check and report on texcore textures from the host.
#[derive(Debug, Parser)]
#[command(name = "texsim", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Compare texcore against the f64 reference on a preset's check plane.
    Check(CheckArgs),
    /// List the presets.
    Presets,
    /// Device reports: instruction counts (`cycles`) and firmware sizes (`size`).
    #[command(subcommand)]
    Report(crate::report::cli::ReportCommand),
}

/// Span evaluation mode (`--eval`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EvalArg {
    /// Per-pixel evaluation.
    Direct,
    /// Exact forward differencing (bit-identical to direct).
    Fd,
    /// Forward differencing where cells are long, direct where short (bit-identical).
    Auto,
    /// 32-bit forward differencing (bounded drift).
    Fd32,
    /// Piecewise re-anchored forward differencing of smooth-fade noise (approximate).
    Reanchored,
}

/// Colour-table antialiasing (`--aa`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AaArg {
    /// No filtering.
    None,
    /// Colour-table MIP map.
    Mip,
    /// Summed-area colour table.
    Csat,
    /// Three-times-long summed-area table.
    Csat3,
}

/// Gradient norm (`--norm`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum NormArg {
    /// Euclidean (integer square root).
    L2,
    /// Sum of absolute values.
    L1,
    /// Largest absolute value.
    Max,
}

/// Colour-table look-up (`--lookup`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LookupArg {
    /// Nearest entry.
    Nearest,
    /// Linear between entries.
    Linear,
}

/// Lattice hash (`--hash`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum HashArg {
    /// 256-entry permutation table.
    Perm,
    /// Table-free integer hash.
    Int,
}

/// The accuracy knobs shared by every rendering command.
#[derive(Clone, Debug, Args)]
pub struct KnobArgs {
    /// Span evaluation.
    #[arg(long = "eval", value_enum, default_value_t = EvalArg::Auto)]
    pub eval: EvalArg,
    /// Antialiasing filter of the colour table.
    #[arg(long, value_enum, default_value_t = AaArg::Csat)]
    pub aa: AaArg,
    /// Gradient norm of the filter width.
    #[arg(long, value_enum, default_value_t = NormArg::L2)]
    pub norm: NormArg,
    /// Colour-table look-up.
    #[arg(long, value_enum, default_value_t = LookupArg::Nearest)]
    pub lookup: LookupArg,
    /// Colour-table entries (a power of two, 2..=1024).
    #[arg(long, default_value_t = 256)]
    pub table_size: usize,
    /// Keep octaves past the Nyquist limit (they alias; their width still widens the filter).
    #[arg(long)]
    pub no_cull: bool,
    /// Lattice hash.
    #[arg(long, value_enum, default_value_t = HashArg::Perm)]
    pub hash: HashArg,
}

impl KnobArgs {
    /// The texture-unit configuration.
    pub fn config(&self) -> UnitConfig {
        UnitConfig {
            table_size: self.table_size,
            lookup: match self.lookup {
                LookupArg::Nearest => TableLookup::Nearest,
                LookupArg::Linear => TableLookup::Linear,
            },
            aa: match self.aa {
                AaArg::None => Antialias::None,
                AaArg::Mip => Antialias::Mip,
                AaArg::Csat => Antialias::Csat,
                AaArg::Csat3 => Antialias::Csat3,
            },
            norm: match self.norm {
                NormArg::L2 => GradientNorm::L2,
                NormArg::L1 => GradientNorm::L1,
                NormArg::Max => GradientNorm::Max,
            },
            mode: match self.eval {
                EvalArg::Direct => EvalMode::Direct,
                EvalArg::Fd => EvalMode::Fd,
                EvalArg::Auto => EvalMode::Auto,
                EvalArg::Fd32 => EvalMode::Fd32,
                EvalArg::Reanchored => EvalMode::Reanchored,
            },
            cull: !self.no_cull,
        }
    }

    /// The lattice hash.
    pub fn hash(&self) -> HashKind {
        match self.hash {
            HashArg::Perm => HashKind::Permutation,
            HashArg::Int => HashKind::Integer,
        }
    }
}

/// `texsim check`.
#[derive(Clone, Debug, Args)]
pub struct CheckArgs {
    /// Preset name (see `texsim presets`).
    pub name: String,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Image size in pixels (square).
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub size: u32,
    /// Fail (exit 1) unless at least this fraction of pixels is within one 8-bit step.
    #[arg(long)]
    pub min_within: Option<f64>,
    /// Accuracy knobs.
    #[command(flatten)]
    pub knobs: KnobArgs,
}

/// Runs the command line; returns the process exit status.
pub fn run(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Check(a) => check(&a),
        Command::Report(r) => crate::report::cli::run(&r),
        Command::Presets => {
            let mut out = std::io::stdout().lock();
            for name in texcore::presets::NAMES {
                let _ = writeln!(out, "{name}");
            }
            ExitCode::SUCCESS
        }
    }
}

/// Prints an error and returns exit status 2.
pub fn bad_input(msg: impl std::fmt::Display) -> ExitCode {
    eprintln!("texsim: error: {msg}");
    ExitCode::from(2)
}

fn check(a: &CheckArgs) -> ExitCode {
    let material = match unit::preset_material(&a.name, a.knobs.hash()) {
        Ok(m) => m,
        Err(e) => return bad_input(e),
    };
    let cfg = a.knobs.config();
    let report = match unit::check_material(&material, &cfg, a.size) {
        Ok(r) => r,
        Err(e) => return bad_input(e),
    };
    let mut out = std::io::stdout().lock();
    if a.json {
        let _ = serde_json::to_writer(&mut out, &report);
        let _ = writeln!(out);
    } else {
        let m = &report.metrics;
        let _ = writeln!(
            out,
            "{}: {}x{} pixels, max error {:.3}, mean error {:.4}, PSNR {:.2} dB, within one step {:.4}%",
            report.name,
            report.width,
            report.height,
            m.max_error,
            m.mean_error,
            m.psnr,
            100.0 * m.within_one_step
        );
    }
    if let Some(min) = a.min_within {
        if report.metrics.within_one_step < min {
            eprintln!(
                "texsim: check failed: within_one_step {} < {min}",
                report.metrics.within_one_step
            );
            return ExitCode::from(1);
        }
    }
    ExitCode::SUCCESS
}
