//! texcore device firmware: runs texcore workloads ("jobs") on the device targets under exact
//! instruction counting and reports checksums and counts over `defmt`.
//!
//! Targets:
//! - `thumbv7em-none-eabihf`: Cortex-M4F, QEMU machine `mps2-an386`, `cortex-m-rt`, memory map
//!   `memory.x` at the repository root (512 KiB flash at 0, 128 KiB RAM at 0x2000_0000).
//! - `riscv32imc-unknown-none-elf`: RISC-V soft-core class (no FPU, table-free code only), QEMU
//!   `virt -bios none`, `riscv-rt`, memory map `firmware/memory-riscv.x` (640 KiB + 128 KiB in
//!   the DRAM window at 0x8000_0000).
//!
//! On the host this crate's program only delegates: `cargo run -p firmware` builds the firmware
//! for the device (`TEXFW_TARGET`, default `thumbv7em-none-eabihf`) and runs it under QEMU
//! through the runner below, printing the decoded log lines.
//!
//! # Running
//!
//! `cargo run --release -p firmware --target thumbv7em-none-eabihf` (or the RISC-V triple): the
//! runner in `.cargo/config.toml` is `firmware/qemu-run.sh`, which starts QEMU with
//! `-icount shift=0,align=off,sleep=off`, semihosting on a stdio chardev and no display, decodes
//! the defmt stream with `defmt-print` when it is installed, otherwise with `texsim defmt-decode`
//! (host-sim's decoder), and exits with the firmware's exit code. From Rust,
//! `host_sim::device::run_firmware` builds, runs and decodes into structured results; the test
//! `tests/tests/firmware_qemu.rs` checks them against the host.
//!
//! Exit codes (semihosting `SYS_EXIT_EXTENDED`): 0 every check passed, 1 a check failed, 101 a
//! panic (with `TEXFW panic file=.. line=..` logged first), 102 start-up failure.
//!
//! # What is measured
//!
//! See [`counter`] for how each target counts (RISC-V `minstret`; Cortex-M under QEMU a SysTick
//! vernier giving single-instruction resolution from the 40-instruction tick; Cortex-M hardware
//! DWT CYCCNT cycles with feature `dwt`) and [`harness`] for the report protocol. Every count is
//! net of the measurement overhead, the raw count of measuring an empty job, which the firmware
//! measures at start-up and reports. Measured with the toolchain of this commit (release
//! profile, QEMU 10.0, `-icount shift=0`):
//!
//! | target | counter | overhead | what it is |
//! |---|---|---|---|
//! | riscv32imc | `minstret` | 11 instructions | the start `csrr minstret`, 1 high-word read, 5 call-setup instructions, `jalr`, the empty job's `li a0, 0; ret`, the end's first high-word read |
//! | thumbv7em | `systick-vernier` | 51 instructions | from the aligned start-vernier read: the rest of that 41-instruction loop iteration, call setup and `blx` (5), the empty job's `movs r0, #0; bx lr`, the end vernier's set-up and first read |
//!
//! They depend on code generation, so the firmware re-measures them on every run instead of
//! hard-coding them; the self-test (nop sleds of 1, 2, 39, 40, 41, 1000, 4099 instructions must
//! measure exactly that) checks that the subtraction is exact on every phase of the SysTick
//! tick. A reported count is therefore "instructions executed by the job beyond an empty job".
//!
//! # What runs
//!
//! The jobs of the `workloads` crate (`workloads::jobs::JOBS`): the hash and span benchmarks, then the texture-unit suite: preset
//! check planes, single stages of the pixel path, two scenes of its own, and every built-in scene
//! of `texcore::scene::builtin` at display size (320 x 240, the zone plate 256 x 256) with no frame
//! buffer: each frame as `workloads::scenes::STRIPS` jobs, one per horizontal strip, rendered in 8-row
//! bands into a checksum sink that continues the previous strip's checksum, so that the last
//! strip reports the checksum of the whole frame (equal to `texsim render <scene> --checksum`).
//!
//! # Memory
//!
//! 128 KiB of RAM on both targets: the static data (the scene renderer's RGBA and depth bands,
//! 15 KiB, and the logger) at the bottom and the stack above it, no heap. Textures are built on
//! the stack of the job that uses them (about 8 KiB each with csat; a built-in scene has up to
//! `workloads::scenes::SCENE_SLOTS`). The harness paints the free stack before the first job and reports
//! its high-water mark ([`stack`]).
//!
//! # Features
//!
//! - `rtt`: log over RTT (`defmt-rtt`, real hardware with probe-rs) instead of semihosting.
//! - `dwt`: Cortex-M hardware cycle counter (DWT CYCCNT) instead of the QEMU SysTick vernier.
//! - `approximate-scenes`: run the built-in scenes in the approximate modes (the ramp, with and
//!   without the filter widths from differences: `workloads::jobs::APPROXIMATE_JOBS`, `texsim
//!   report cycles`) instead of the default jobs.
//! - `peers`: run the peer-comparison jobs (`workloads::peer_jobs`, `texsim report peers`) instead of the
//!   default jobs: texcore next to `fastnoise-lite`; `peers-band` shortens them to one band.
//! - `panic-never`: the panic handler calls an undefined symbol, so the release link fails if
//!   any panicking path survives optimisation; `firmware/check-panic-never.sh` builds it for both
//!   targets (and builds a deliberately panicking canary, feature `panic-never-canary`, which
//!   must fail to link, so the check is known to bite).
#![cfg_attr(target_os = "none", no_std, no_main)]
#![deny(unsafe_code)]

/// On the host, `cargo run -p firmware` builds the device firmware and runs it under QEMU with
/// readable logs: it runs `cargo run --release -p firmware --target $TEXFW_TARGET` (default
/// `thumbv7em-none-eabihf`; `riscv32imc-unknown-none-elf` for the other target), whose runner
/// (`firmware/qemu-run.sh`) decodes the defmt stream. Extra arguments are passed to cargo.
#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let target =
        std::env::var("TEXFW_TARGET").unwrap_or_else(|_| "thumbv7em-none-eabihf".to_string());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    eprintln!("firmware: running the device firmware for {target} under QEMU (TEXFW_TARGET selects the target)");
    let status = std::process::Command::new(cargo)
        .current_dir(root)
        .args(["run", "--release", "-p", "firmware", "--target", &target])
        .args(std::env::args_os().skip(1))
        .status();
    match status {
        Ok(s) => std::process::ExitCode::from(s.code().unwrap_or(1).clamp(0, 255) as u8),
        Err(e) => {
            eprintln!("firmware: starting cargo failed: {e}");
            std::process::ExitCode::from(2)
        }
    }
}

#[cfg(target_os = "none")]
pub mod counter;
#[cfg(all(target_os = "none", target_arch = "arm", feature = "stack-guard"))]
pub mod guard;
#[cfg(target_os = "none")]
pub mod harness;
#[cfg(all(target_os = "none", not(feature = "rtt")))]
mod logger;
#[cfg(target_os = "none")]
pub mod stack;

#[cfg(all(target_os = "none", feature = "rtt"))]
use defmt_rtt as _;

/// Runs the harness and exits through semihosting with 0 (pass) or 1 (fail).
#[cfg(target_os = "none")]
fn app() -> ! {
    let pass = harness::run();
    semihosting::process::exit(if pass { 0 } else { 1 })
}

/// Start-up failure (e.g. core peripherals already taken): exit code 102.
#[cfg(target_os = "none")]
pub fn fail_early() -> ! {
    defmt::println!("TEXFW error what=startup");
    semihosting::process::exit(102)
}

#[cfg(all(target_os = "none", target_arch = "arm"))]
mod entry {
    // cortex-m-rt's `#[entry]` expands to an `#[export_name = "main"]` trampoline, which the
    // `unsafe_code` lint flags; it is the runtime's documented entry point.
    #![allow(unsafe_code)]
    #[cortex_m_rt::entry]
    fn main() -> ! {
        super::app()
    }
}

#[cfg(all(target_os = "none", target_arch = "riscv32"))]
mod entry {
    // riscv-rt's `#[entry]` expands to an `#[export_name = "main"]` function, which the
    // `unsafe_code` lint flags; it is the runtime's documented entry point.
    #![allow(unsafe_code)]
    #[riscv_rt::entry]
    fn main() -> ! {
        super::app()
    }
}

/// Normal panic handler: log the location, exit with 101.
#[cfg(all(target_os = "none", not(feature = "panic-never")))]
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    match info.location() {
        Some(l) => defmt::println!("TEXFW panic file={=str} line={=u32}", l.file(), l.line()),
        None => defmt::println!("TEXFW panic file=? line=0"),
    }
    semihosting::process::exit(101)
}

/// `panic-never` panic handler: references a symbol that exists nowhere, so the link fails
/// (`undefined symbol: texcore_firmware_panic_is_reachable`) iff some panic path is still
/// reachable after optimisation. Never meant to run.
#[cfg(all(target_os = "none", feature = "panic-never"))]
#[panic_handler]
#[allow(unsafe_code)]
fn panic(_: &core::panic::PanicInfo) -> ! {
    extern "Rust" {
        fn texcore_firmware_panic_is_reachable() -> !;
    }
    // SAFETY: never executes: this build only exists to fail linking when it is reachable.
    unsafe { texcore_firmware_panic_is_reachable() }
}
