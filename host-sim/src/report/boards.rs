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
               pixel of a 64 x 64 marble plane (64-entry table, csat)",
    },
];

impl Board {
    /// The example's directory.
    pub fn dir(&self, workspace: &Path) -> PathBuf {
        workspace.join("examples/boards").join(self.name)
    }

    /// Where its release ELF lands.
    pub fn elf(&self, workspace: &Path) -> PathBuf {
        self.elf_in(&workspace.join("target/boards"))
    }

    /// Where its release ELF lands when built into `target_dir`.
    pub fn elf_in(&self, target_dir: &Path) -> PathBuf {
        target_dir
            .join(self.target)
            .join("release")
            .join(format!("texcore-board-{}", self.name))
    }

    /// Builds the example (release, `--locked`) into `target/boards`; returns its ELF, or
    /// cargo's diagnostics.
    pub fn build(&self, cargo: &Path, workspace: &Path) -> Result<PathBuf, String> {
        self.build_in(cargo, workspace, &workspace.join("target/boards"))
    }

    /// [`Board::build`] into the target directory `target_dir`.
    pub fn build_in(
        &self,
        cargo: &Path,
        workspace: &Path,
        target_dir: &Path,
    ) -> Result<PathBuf, String> {
        let mut cmd = Command::new(cargo);
        cmd.current_dir(self.dir(workspace))
            .args(["build", "--release", "--locked", "--target-dir"])
            .arg(target_dir);
        // The board's own configuration decides the build, not the calling cargo's environment
        // (its target and target directory included).
        crate::device::isolate_cargo_env(&mut cmd, &["CARGO_BUILD_TARGET", "CARGO_TARGET_DIR"]);
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
        let elf = self.elf_in(target_dir);
        if elf.is_file() {
            Ok(elf)
        } else {
            Err(format!("the build left no ELF at {}", elf.display()))
        }
    }
}

/// What the Cortex-M0 example (`qemu-m0`) measured: its `TEXM0` line.
#[derive(Clone, Debug, PartialEq)]
pub struct M0Count {
    /// Pixels shaded (64 x 64).
    pub pixels: u64,
    /// FNV-1a checksum of the pixels' colours.
    pub checksum: u32,
    /// Instructions of the texture's set-up (TIMER0 ticks x 62.5).
    pub setup_instructions: u64,
    /// Instructions of the shading alone (ticks x 62.5, minus an empty shading call).
    pub instructions: u64,
}

/// Side of the `qemu-m0` example's plane.
pub const M0_SIDE: u16 = 64;

/// Runs the `qemu-m0` example's ELF under `qemu-system-arm -machine microbit -icount shift=0`
/// and parses its report.
pub fn run_qemu_m0(elf: &Path) -> Result<M0Count, String> {
    let out = Command::new("qemu-system-arm")
        .args([
            "-machine",
            "microbit",
            "-cpu",
            "cortex-m0",
            "-icount",
            "shift=0,align=off,sleep=off",
            "-display",
            "none",
            "-monitor",
            "none",
            "-serial",
            "none",
            "-semihosting-config",
            "enable=on,target=native",
            "-kernel",
        ])
        .arg(elf)
        .stdin(std::process::Stdio::null())
        .output()
        .map_err(|e| {
            format!("starting qemu-system-arm: {e} (install QEMU: .ci/install-qemu.sh)")
        })?;
    let text = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        return Err(format!(
            "the Cortex-M0 example {}: {text}{}",
            match out.status.code() {
                Some(c) => format!("exited with code {c}"),
                None => "was stopped by a signal".to_string(),
            },
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let line = text
        .lines()
        .find(|l| l.starts_with("TEXM0 "))
        .ok_or_else(|| {
            format!(
                "no TEXM0 line in the Cortex-M0 example's output: \"{}\"",
                text.escape_debug()
            )
        })?;
    let field = |k: &str| -> Result<&str, String> {
        line.split_whitespace()
            .find_map(|w| w.strip_prefix(k).and_then(|v| v.strip_prefix('=')))
            .ok_or_else(|| format!("no {k} in \"{}\"", line.escape_debug()))
    };
    let num = |k: &str| -> Result<u64, String> {
        field(k)?
            .parse()
            .map_err(|_| format!("{k} is not a number in \"{}\"", line.escape_debug()))
    };
    let checksum = field("checksum")?;
    let checksum = u32::from_str_radix(checksum.trim_start_matches("0x"), 16)
        .map_err(|_| format!("checksum is not hex in \"{}\"", line.escape_debug()))?;
    // One TIMER0 tick at 16 MHz is 62.5 ns = 62.5 instructions at -icount shift=0.
    Ok(M0Count {
        pixels: num("pixels")?,
        checksum,
        setup_instructions: num("setup_ticks")? * 125 / 2,
        instructions: num("work_ticks")? * 125 / 2,
    })
}

/// The `qemu-m0` example's checksum recomputed on the host with the same calls (marble, integer
/// hash, 64-entry table, csat, `PlaneMapping::scaled(32)`, 64 rows of 64 pixels).
pub fn host_m0_checksum() -> Option<u32> {
    use texcore::draw::PlaneMapping;
    use texcore::filter::Antialias;
    use texcore::hash::HashKind;
    use texcore::ready::{Material, PresetName};
    let tex = Material::preset_with_hash(PresetName::Marble, HashKind::Integer)
        .texture::<64>(Antialias::Csat)
        .ok()?;
    let mapping = PlaneMapping::scaled(32);
    let mut ev = tex.evaluator();
    let mut acc = 0x811C_9DC5u32;
    for y in 0..i32::from(M0_SIDE) {
        ev.shade(&mapping.span(0, y, M0_SIDE), |c| {
            acc = (acc ^ c.to_u32()).wrapping_mul(0x0100_0193)
        });
    }
    Some(acc)
}
