//! Hardware stack guard of the Cortex-M4F firmware (feature `stack-guard`).
//!
//! `memory.x`'s guarded layout (selected by this feature's build) puts the stack of the 128 KiB
//! RAM at the bottom, growing down towards 0x2000_0000, below which nothing is mapped, and the
//! static data at the top. An overflow therefore touches unmapped memory first, whatever the size of the frame that
//! overflows, and raises a bus fault (escalated to HardFault) before any byte of the static data
//! changes. The HardFault handler below runs without the stack (it cannot be used any more): it
//! moves the stack pointer to the top of the stack region, then [`hard_fault`] reports
//! `TEXFW error what=stack-overflow` (or `what=hardfault` for a fault with the stack pointer in
//! range) and exits through semihosting with code 103 (104), so the run fails loudly.
//!
//! With the guard the firmware runs only [`SELECTED`], the deepest job of the suite (the largest
//! stack high-water mark of a full run, reported by the harness); with `stack-guard-canary` it
//! runs [`CANARY`] instead, a recursion without bound that must end in the guard.
#![allow(unsafe_code)]
// unsafe: the handler is a `global_asm!` symbol and `hard_fault` an exported, unmangled function
// it branches to; neither touches memory the program uses (see above).

use workloads::job::{Ctx, Job};

/// The jobs the guarded firmware runs: the deepest scene (three slot textures with csat on its
/// stack, 91 KiB on the Cortex-M4F when the guard was added) and its set-up.
pub const SELECTED: [&str; 2] = ["scene:overlay", "scene:overlay/setup"];

/// Whether the guarded firmware runs job `name`.
pub fn selected(name: &str) -> bool {
    !cfg!(feature = "stack-guard-canary") && SELECTED.contains(&name)
}

/// The canary (feature `stack-guard-canary`): recursion that never ends, each level keeping a
/// kilobyte of stack alive.
pub static CANARY: &[Job] = if cfg!(feature = "stack-guard-canary") {
    &[Job {
        name: "stack:overflow-canary",
        run: canary,
    }]
} else {
    &[]
};

fn canary(_: &mut Ctx) -> u32 {
    deeper(core::hint::black_box(1))
}

#[inline(never)]
fn deeper(n: u32) -> u32 {
    let mut frame = [0u32; 256];
    frame[(n as usize) & 255] = n;
    let frame = core::hint::black_box(frame);
    // Always true at run time, opaque to the optimiser: the recursion has no base case.
    if core::hint::black_box(n) != 0 {
        deeper(n.wrapping_add(1)).wrapping_add(frame[(n as usize / 3) & 255])
    } else {
        frame[0]
    }
}

extern "C" {
    /// Top of the stack region (from the memory map).
    static _stack_start: u32;
    /// Bottom of the stack region.
    static _stack_end: u32;
}

// The vector table enters `HardFault` directly (cortex-m-rt's default handler is replaced).
// Without touching the stack: r0 = the stack pointer after the (failed) exception stacking, then
// the stack pointer moves to the top of the stack region and the report runs there.
core::arch::global_asm!(
    ".section .text.HardFault.texfw, \"ax\"",
    ".global HardFault",
    ".type HardFault, %function",
    ".thumb_func",
    "HardFault:",
    "mrs r0, msp",
    "ldr r1, =_stack_start",
    "mov sp, r1",
    "b texfw_hard_fault",
);

/// Reports the fault and exits: `sp` is the stack pointer when it happened.
#[no_mangle]
extern "C" fn texfw_hard_fault(sp: u32) -> ! {
    let bottom = core::ptr::addr_of!(_stack_end) as u32;
    if sp < bottom.wrapping_add(64) {
        defmt::println!(
            "TEXFW error what=stack-overflow sp={=u32:#010x} bottom={=u32:#010x}",
            sp,
            bottom
        );
        semihosting::process::exit(103)
    }
    let top = core::ptr::addr_of!(_stack_start) as u32;
    defmt::println!(
        "TEXFW error what=hardfault sp={=u32:#010x} top={=u32:#010x}",
        sp,
        top
    );
    semihosting::process::exit(104)
}
