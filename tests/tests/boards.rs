//! Builds each board example (`examples/boards/<board>/`, its own workspace) for its target, as
//! `.ci/boards.sh` does (`host_sim::report::boards`), and checks that the result is a device ELF
//! for that architecture with texcore's pixel path linked in:
//!
//! - `pico`: Raspberry Pi Pico, RP2040 Cortex-M0+, `thumbv6m-none-eabi` (ARM ELF);
//! - `esp32c3`: ESP32-C3, `riscv32imc-unknown-none-elf` (RISC-V ELF).
//!
//! No hardware is needed. The targets must be installed (`rustup target add ..`, done by
//! `.ci/run`); a missing target fails the test with the command to run.

use std::path::{Path, PathBuf};

use host_sim::device::workspace_root;
use host_sim::report::boards::{Board, BOARDS};

fn board(name: &str) -> Board {
    *BOARDS.iter().find(|b| b.name == name).expect("board")
}

/// Builds the board into `target_dir`; checks the ELF's machine (`e_machine`, offset 18) and that
/// texcore's span evaluator is in it (named in the debug info even where LTO inlined it:
/// `debug = 2`). Returns the ELF.
fn build_and_check(name: &str, machine: u16, target_dir: &Path) -> PathBuf {
    let b = board(name);
    let cargo = PathBuf::from(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    let elf = b
        .build_in(&cargo, &workspace_root(), target_dir)
        .unwrap_or_else(|e| panic!("{e}"));
    let bytes = std::fs::read(&elf).expect("reading the ELF");
    assert_eq!(&bytes[..4], b"\x7fELF", "{}", elf.display());
    assert_eq!(
        u16::from_le_bytes([bytes[18], bytes[19]]),
        machine,
        "{}",
        elf.display()
    );
    let name = b"SpanEvaluator";
    assert!(
        bytes.windows(name.len()).any(|w| w == name),
        "{}: texcore's span evaluator is not in the ELF",
        elf.display()
    );
    elf
}

/// Every board, one after another: each builds for its target with texcore's pixel path in it,
/// and the Cortex-M0 example, run under QEMU (`microbit`, `-icount shift=0`), shades the host's
/// checksum and counts its instructions.
///
/// The boards build into `target/boards` (as `.ci/boards.sh` and `texsim report size` do), where
/// the next run finds them. With `TEXCORE_CI_FREE_DISK=1` (set by `.ci/run`: a CI machine may
/// have only a few GB of disk) each board builds into a directory of its own instead, removed as
/// soon as its checks pass, so that at most one board's build (up to about 0.9 GB) is on disk.
#[test]
fn boards_build_and_the_m0_example_runs() {
    let free = std::env::var_os("TEXCORE_CI_FREE_DISK").is_some_and(|v| v == "1");
    for (name, target, machine) in [
        ("pico", "thumbv6m-none-eabi", 0x28),
        ("esp32c3", "riscv32imc-unknown-none-elf", 0xf3),
        ("qemu-m0", "thumbv6m-none-eabi", 0x28),
    ] {
        assert_eq!(board(name).target, target);
        let dir = workspace_root().join(if free {
            format!("target/boards-{name}")
        } else {
            "target/boards".to_string()
        });
        let elf = build_and_check(name, machine, &dir);
        if name == "qemu-m0" {
            m0_shades_the_host_checksum_and_counts_instructions(&elf);
        }
        if free {
            std::fs::remove_dir_all(&dir)
                .unwrap_or_else(|e| panic!("removing {}: {e}", dir.display()));
        }
    }
}

/// The Cortex-M0 example's run: it must shade the host's checksum and count its instructions.
fn m0_shades_the_host_checksum_and_counts_instructions(elf: &Path) {
    let m0 = host_sim::report::boards::run_qemu_m0(elf).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m0.pixels, 64 * 64);
    assert_eq!(
        Some(m0.checksum),
        host_sim::report::boards::host_m0_checksum(),
        "{m0:?}"
    );
    assert!(m0.instructions > 10 * m0.pixels, "{m0:?}");
    assert!(m0.setup_instructions > 0, "{m0:?}");
}
