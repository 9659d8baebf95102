//! The board examples (`examples/boards/<board>/`): which boards there are, their targets, and
//! how one is built (`cargo build --release --locked` in its directory, each board its own
//! workspace, ELFs under `target/boards/`). Used by `texsim report size` (a row per board),
//! `.ci/boards.sh` does the same from the shell and `tests/tests/boards.rs` checks the builds.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A board example.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Board {
    /// Directory name under `examples/boards/` (the binary is `texcore-board-<name>`).
    pub name: &'static str,
    /// Target triple (the one its `.cargo/config.toml` names).
    pub target: &'static str,
    /// The chip and what the example draws.
    pub what: &'static str,
}

/// Every board example.
pub const BOARDS: [Board; 3] = [
    Board {
        name: "pico",
        target: "thumbv6m-none-eabi",
        what: "Raspberry Pi Pico (RP2040, Cortex-M0+): marble on an ST7789 through mipidsi",
    },
    Board {
        name: "esp32c3",
        target: "riscv32imc-unknown-none-elf",
        what: "ESP32-C3 (rv32imc): a fire panel on an ST7789 through mipidsi",
    },
    Board {
        name: "qemu-m0",
        target: "thumbv6m-none-eabi",
        what: "Cortex-M0 under QEMU's `microbit` machine (nRF51, 16 KB RAM): instructions per \
               pixel of a 64 x 64 marble plane with csat",
    },
];

impl Board {
    /// The example's directory.
    pub fn dir(&self, workspace: &Path) -> PathBuf {
        workspace.join("examples/boards").join(self.name)
    }

    /// Where its release ELF lands.
    pub fn elf(&self, workspace: &Path) -> PathBuf {
        workspace
            .join("target/boards")
            .join(self.target)
            .join("release")
            .join(format!("texcore-board-{}", self.name))
    }

    /// Builds the example (release, `--locked`); returns its ELF, or cargo's diagnostics.
    pub fn build(&self, cargo: &Path, workspace: &Path) -> Result<PathBuf, String> {
        let mut cmd = Command::new(cargo);
        cmd.current_dir(self.dir(workspace))
            .args(["build", "--release", "--locked", "--target-dir"])
            .arg(workspace.join("target/boards"));
        // The board's own configuration decides the build, not the calling cargo's environment.
        for (k, _) in std::env::vars_os() {
            let k = k.to_string_lossy().into_owned();
            if k == "RUSTFLAGS"
                || k == "CARGO_ENCODED_RUSTFLAGS"
                || k == "CARGO_BUILD_RUSTFLAGS"
                || k == "CARGO_BUILD_TARGET"
                || k == "CARGO_TARGET_DIR"
                || k.starts_with("CARGO_PKG_")
                || k.starts_with("CARGO_CRATE_")
                || k.starts_with("CARGO_BIN_")
                || k == "CARGO_MANIFEST_DIR"
                || k == "CARGO_MANIFEST_PATH"
                || k == "CARGO_PRIMARY_PACKAGE"
            {
                cmd.env_remove(&k);
            }
        }
        let out = cmd
            .output()
            .map_err(|e| format!("running {}: {e}", cargo.display()))?;
        if !out.status.success() {
            return Err(format!(
                "cargo build of examples/boards/{} for {} failed (is the target installed? \
                 `rustup target add {}`):\n{}",
                self.name,
                self.target,
                self.target,
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        let elf = self.elf(workspace);
        if elf.is_file() {
            Ok(elf)
        } else {
            Err(format!("the build left no ELF at {}", elf.display()))
        }
    }
}
