//! Linker setup for the device targets.
//!
//! - Cortex-M (`thumbv7em-none-eabihf`): cortex-m-rt's `link.x` does `INCLUDE memory.x`; the
//!   device memory map is `memory.x` at the repository root, copied to `OUT_DIR` and put on the
//!   linker search path (the linker reads the root file itself first: it resolves `INCLUDE` in its
//!   working directory, the workspace root). With feature `stack-guard`, the link also gets
//!   `--defsym=_texcore_stack_guard=1`, which selects `memory.x`'s second layout: the same RAM
//!   with the stack below the static data, above unmapped memory.
//! - RISC-V (`riscv32imc-unknown-none-elf`): riscv-rt's `link.x` expects the `REGION_*` aliases
//!   to be defined by an earlier script; `memory-riscv.x` (next to this file) is passed first.
//! - Both: `defmt.x` for the defmt string table.
//!
//! On the host nothing is linked specially (the firmware is an empty program there).
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR"));
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let os = env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();

    let cortex_m = manifest.join("../memory.x");
    // With `stack-guard` the Cortex-M stack sits below the static data, above unmapped memory
    // (memory.x's second layout).
    let stack_guard = env::var_os("CARGO_FEATURE_STACK_GUARD").is_some();
    // The accuracy firmware's scene part needs more rv32imc program memory (see that file).
    let riscv = if env::var_os("CARGO_FEATURE_ACCURACY").is_some() {
        manifest.join("memory-riscv-accuracy.x")
    } else {
        manifest.join("memory-riscv.x")
    };
    println!("cargo:rerun-if-changed={}", cortex_m.display());
    println!("cargo:rerun-if-changed={}", riscv.display());
    println!("cargo:rerun-if-changed=build.rs");

    println!(
        "cargo:rustc-env=FIRMWARE_TARGET={}",
        env::var("TARGET").unwrap_or_default()
    );
    if os != "none" {
        return;
    }
    match arch.as_str() {
        "arm" => {
            fs::copy(&cortex_m, out.join("memory.x")).expect("copy memory.x");
            println!("cargo:rustc-link-search={}", out.display());
            if stack_guard {
                println!("cargo:rustc-link-arg-bins=--defsym=_texcore_stack_guard=1");
            }
            println!("cargo:rustc-link-arg-bins=-Tlink.x");
        }
        "riscv32" => {
            fs::copy(&riscv, out.join("memory-riscv.x")).expect("copy memory-riscv.x");
            println!("cargo:rustc-link-search={}", out.display());
            println!("cargo:rustc-link-arg-bins=-Tmemory-riscv.x");
            println!("cargo:rustc-link-arg-bins=-Tlink.x");
        }
        other => panic!("firmware: unsupported device architecture {other}"),
    }
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    // Keep a map file for size/budget reviews.
    println!(
        "cargo:rustc-link-arg-bins=-Map={}",
        out.join("firmware.map").display()
    );
}
