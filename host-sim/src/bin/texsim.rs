//! `texsim`: render, check and report on texcore scenes from the host.
use clap::Parser;

fn main() -> std::process::ExitCode {
    host_sim::cli::run(host_sim::cli::Cli::parse())
}
