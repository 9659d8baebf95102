//! `texsim` run as a separate process, for the command-line tests.
//!
//! A test binary re-executes itself with the command line in an environment variable; its
//! `texsim_child` test (declared with [`texsim_child_test!`](crate::texsim_child_test)) runs
//! `host_sim::cli::run` on it and exits with its status. So the parent sees the real exit
//! status, standard output, standard error and output files, with no `cargo run` and no stale
//! binary under `target/`.
//!
//! Guarantees: the child's exit status is the command's (0, 1, 2 or 130; anything else, a
//! panic included, is 101); its standard output is everything the command wrote after the
//! harness's marker line, byte for byte.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Output};

use clap::Parser;
use host_sim::cli::Cli;

/// The environment variable that carries the child's command line (a JSON array of strings).
pub const CHILD_ARGS: &str = "TEXSIM_TEST_CHILD_ARGS";

/// Written by the child before the command runs: the test harness's own output comes before it.
const MARKER: &[u8] = b"--- texsim output ---\n";

/// Declares the `#[test] fn texsim_child()` that serves [`command`]'s re-executions (in a normal
/// test run it does nothing).
#[macro_export]
macro_rules! texsim_child_test {
    () => {
        /// In the child process: run the command line given in the environment and exit with
        /// its status. In the normal test run this does nothing.
        #[test]
        fn texsim_child() {
            $crate::child::serve();
        }
    };
}

/// In the child process: runs the command line given in [`CHILD_ARGS`] and exits with its
/// status. Returns at once when the variable is not set (the normal test run).
pub fn serve() {
    let Ok(args) = std::env::var(CHILD_ARGS) else {
        return;
    };
    let args: Vec<String> = serde_json::from_str(&args).expect("a JSON array of arguments");
    {
        let mut out = std::io::stdout().lock();
        let _ = out.write_all(MARKER);
        let _ = out.flush();
    }
    let code = match Cli::try_parse_from(std::iter::once("texsim".to_string()).chain(args)) {
        Ok(cli) => host_sim::cli::run(cli),
        Err(e) => {
            let _ = e.print();
            if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            }
        }
    };
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    let status = [0u8, 1, 2, 130]
        .into_iter()
        .find(|&k| code == ExitCode::from(k))
        .map_or(101, i32::from);
    std::process::exit(status);
}

/// What a `texsim` run did.
#[derive(Debug)]
pub struct Run {
    /// The exit status (-1 when killed by a signal).
    pub status: i32,
    /// Standard output, decoded lossily as UTF-8.
    pub stdout: String,
    /// Standard output, byte for byte (binary outputs such as `-o -`).
    pub bytes: Vec<u8>,
    /// Standard error.
    pub stderr: String,
}

/// The command that runs `texsim ARGS` in a child of this test binary; spawn it, or run it
/// with [`finish`].
pub fn command(args: &[&str]) -> Command {
    let mut cmd = Command::new(std::env::current_exe().expect("the test binary's path"));
    cmd.args([
        "texsim_child",
        "--exact",
        "--nocapture",
        "--test-threads=1",
        "-q",
    ])
    .env(
        CHILD_ARGS,
        serde_json::to_string(args).expect("arguments as JSON"),
    );
    cmd
}

/// Runs `cmd` (from [`command`]) to its end and splits its output at the marker. Panics, naming
/// the command, when the child printed no marker (it did not reach the command).
pub fn finish(mut cmd: Command) -> Run {
    let out: Output = cmd.output().expect("the test binary runs");
    let at = out
        .stdout
        .windows(MARKER.len())
        .position(|w| w == MARKER)
        .unwrap_or_else(|| {
            panic!(
                "no child output for {:?}: {}{}",
                cmd.get_envs()
                    .find(|(k, _)| *k == CHILD_ARGS)
                    .and_then(|(_, v)| v),
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            )
        });
    let bytes = out.stdout[at + MARKER.len()..].to_vec();
    Run {
        status: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&bytes).into_owned(),
        bytes,
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Runs `texsim ARGS` in a child process.
pub fn texsim(args: &[&str]) -> Run {
    finish(command(args))
}

/// A fresh, empty temporary directory for one test: `PREFIX-PID-NAME` in the system's
/// temporary directory (earlier contents removed).
pub fn tmp_dir(prefix: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("{prefix}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("a temporary directory");
    d
}

/// A path as `&str` for a command line (the tests' paths are UTF-8).
pub fn s(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}
