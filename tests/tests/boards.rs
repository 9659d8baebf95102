//! Builds each board example (`examples/boards/<board>/`, its own workspace) for its target, as
//! `.ci/boards.sh` does (`host_sim::report::boards`), and checks that the result is a device ELF
//! for that architecture with texcore's pixel path linked in:
//!
//! - `pico`: Raspberry Pi Pico, RP2040 Cortex-M0+, `thumbv6m-none-eabi` (ARM ELF);
//! - `esp32c3`: ESP32-C3, `riscv32imc-unknown-none-elf` (RISC-V ELF).
//!
//! No hardware is needed. The targets must be installed (`rustup target add ..`, done by
//! `.ci/run`); a missing target fails the test with the command to run.

use std::path::PathBuf;

use host_sim::device::workspace_root;
use host_sim::report::boards::{Board, BOARDS};

fn board(name: &str) -> Board {
    *BOARDS.iter().find(|b| b.name == name).expect("board")
}

/// Builds the board; checks the ELF's machine (`e_machine`, offset 18) and that texcore's span
/// evaluator is in it (named in the debug info even where LTO inlined it: `debug = 2`).
fn build_and_check(name: &str, machine: u16) {
    let b = board(name);
    let cargo = PathBuf::from(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    let elf = b
        .build(&cargo, &workspace_root())
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
}

#[test]
fn pico_builds_for_thumbv6m() {
    assert_eq!(board("pico").target, "thumbv6m-none-eabi");
    build_and_check("pico", 0x28);
}

#[test]
fn esp32c3_builds_for_riscv32imc() {
    assert_eq!(board("esp32c3").target, "riscv32imc-unknown-none-elf");
    build_and_check("esp32c3", 0xf3);
}

#[test]
fn qemu_m0_builds_for_thumbv6m() {
    assert_eq!(board("qemu-m0").target, "thumbv6m-none-eabi");
    build_and_check("qemu-m0", 0x28);
}

/// The checksum of the Cortex-M0 example's plane, recomputed on the host with the same calls.
fn host_m0_checksum() -> u32 {
    use texcore::draw::PlaneMapping;
    use texcore::filter::Antialias;
    use texcore::hash::HashKind;
    use texcore::ready::{Material, PresetName};
    let tex = Material::preset_with_hash(PresetName::Marble, HashKind::Integer)
        .texture::<256>(Antialias::Csat)
        .expect("marble");
    let mapping = PlaneMapping::scaled(32);
    let mut ev = tex.evaluator();
    let mut acc = 0x811C_9DC5u32;
    for y in 0..64 {
        ev.shade(&mapping.span(0, y, 64), |c| {
            acc = (acc ^ c.to_u32()).wrapping_mul(0x0100_0193)
        });
    }
    acc
}

/// Runs the Cortex-M0 example under QEMU (`microbit`, `-icount shift=0`): it must print the
/// host's checksum and an instruction count per pixel.
#[test]
fn qemu_m0_shades_the_host_checksum_and_counts_instructions() {
    let elf = board("qemu-m0").build(
        &PathBuf::from(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into())),
        &workspace_root(),
    );
    let elf = elf.unwrap_or_else(|e| panic!("{e}"));
    let out = std::process::Command::new("qemu-system-arm")
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
        .arg(&elf)
        .stdin(std::process::Stdio::null())
        .output()
        .expect("qemu-system-arm (install it with .ci/install-qemu.sh)");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "exit {:?}: {text}", out.status.code());
    let line = text
        .lines()
        .find(|l| l.starts_with("TEXM0 "))
        .unwrap_or_else(|| panic!("no report line in {text:?}"));
    let field = |k: &str| {
        line.split_whitespace()
            .find_map(|w| w.strip_prefix(k).and_then(|v| v.strip_prefix('=')))
            .unwrap_or_else(|| panic!("no {k} in {line}"))
            .to_string()
    };
    assert_eq!(
        field("checksum"),
        format!("{:#010x}", host_m0_checksum()),
        "{line}"
    );
    let ipp: f64 = field("instr_per_pixel").parse().expect("a number");
    assert!(ipp > 10.0 && ipp < 100_000.0, "{line}");
    eprintln!("{line}");
}
