//! Stack high-water mark by painting: the free stack is filled with a pattern at start-up and
//! the lowest word that no longer holds it tells how deep the stack has ever been.
//!
//! The stack runs from the top of RAM (`_stack_start`) down to the end of the static data
//! (`__sheap`, the end of `.bss`/`.uninit`, defined by both `cortex-m-rt` and `riscv-rt`); with
//! no heap, everything between is stack. [`paint`] fills that range below the caller's frame;
//! [`used`] scans it from the bottom. Nothing checks for an overflow while it happens (the stack
//! would run into `.bss`), so the harness reports the mark after every job and the host test
//! asserts a margin (`tests/tests/firmware_qemu.rs`).
#![allow(unsafe_code)]
// unsafe is needed to read and write the free stack through raw pointers. Soundness: only the
// words between the end of the static data and an address well below the current stack
// pointer are touched; nothing lives there (no heap, single core, no interrupt handlers).

/// The pattern of an unused stack word.
const PAINT: u32 = 0xC0FF_EE5A;
/// Bytes below the caller's frame that [`paint`] leaves alone (its own frame and call).
const MARGIN: usize = 512;

extern "C" {
    /// Top of the stack (one past the highest word), from the runtime's linker script.
    static _stack_start: u32;
    /// End of the static data: the lowest address the stack may reach.
    #[cfg(not(target_arch = "arm"))]
    static __sheap: u32;
    /// The lowest address the stack may reach: the end of the static data (cortex-m-rt's
    /// default), or the bottom of RAM with the `stack-guard` memory map.
    #[cfg(target_arch = "arm")]
    static _stack_end: u32;
}

fn top() -> usize {
    core::ptr::addr_of!(_stack_start) as usize
}

fn bottom() -> usize {
    #[cfg(not(target_arch = "arm"))]
    let b = core::ptr::addr_of!(__sheap) as usize;
    #[cfg(target_arch = "arm")]
    let b = core::ptr::addr_of!(_stack_end) as usize;
    (b + 3) & !3
}

/// Bytes of stack between the end of the static data and the top of RAM.
pub fn size() -> usize {
    top().saturating_sub(bottom())
}

/// Paints the free stack below the caller's frame (less [`MARGIN`] bytes).
#[inline(never)]
pub fn paint() {
    let here = 0u32;
    let sp = core::hint::black_box(core::ptr::addr_of!(here) as usize);
    let end = sp.saturating_sub(MARGIN) & !3;
    let mut p = bottom();
    while p < end {
        // SAFETY: `p` is a word-aligned address between the end of the static data and
        // `MARGIN` bytes below this function's frame: unused stack (see the module comment).
        unsafe { core::ptr::write_volatile(p as *mut u32, PAINT) };
        p += 4;
    }
}

/// The stack's high-water mark since [`paint`], in bytes from the top.
#[inline(never)]
pub fn used() -> usize {
    let mut p = bottom();
    let top = top();
    while p < top {
        // SAFETY: as in `paint`, a word-aligned address inside the stack region; reading it has
        // no effect on the program.
        if unsafe { core::ptr::read_volatile(p as *const u32) } != PAINT {
            break;
        }
        p += 4;
    }
    top - p
}
