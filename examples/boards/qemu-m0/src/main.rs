//! texcore on a Cortex-M0 (thumbv6m: no FPU, no hardware divide) under QEMU's `microbit` machine
//! (nRF51, 16 KB of RAM): builds the marble texture in one call (64-entry table, csat, the
//! table-free integer hash) and shades
//! a 64 x 64 plane of it, counting instructions with `-icount shift=0` (one instruction = 1 ns of
//! virtual time) through the nRF51's TIMER0 at 16 MHz (one tick = 62.5 instructions).
//!
//! Prints over semihosting:
//! `TEXM0 pixels=<n> checksum=<0x..> setup_ticks=<t> work_ticks=<t> instr_per_pixel=<x.y>`.
//! The pixel count is large enough (4096) that the tick's granularity is below 0.1 instruction
//! per pixel. Run: `cargo run --release` here (the runner is QEMU).
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use texcore::draw::PlaneMapping;
use texcore::filter::Antialias;
use texcore::hash::HashKind;
use texcore::ready::{Material, PresetName};

/// Side of the shaded square, pixels.
const SIDE: u16 = 64;
/// nRF51 TIMER0 base address.
const TIMER0: usize = 0x4000_8000;

/// TIMER0 register at `offset`.
fn reg(offset: usize) -> *mut u32 {
    (TIMER0 + offset) as *mut u32
}

/// Starts TIMER0 as a free-running 32-bit timer at 16 MHz.
fn timer_start() {
    // SAFETY: TIMER0's documented registers (MODE, BITMODE, PRESCALER, TASKS_CLEAR, TASKS_START)
    // on the nRF51; nothing else in this program uses the timer.
    unsafe {
        reg(0x504).write_volatile(0); // MODE = timer
        reg(0x508).write_volatile(3); // BITMODE = 32 bit
        reg(0x510).write_volatile(0); // PRESCALER = 16 MHz
        reg(0x00C).write_volatile(1); // TASKS_CLEAR
        reg(0x000).write_volatile(1); // TASKS_START
    }
}

/// The timer's count now (TASKS_CAPTURE[0], then CC[0]).
fn ticks() -> u32 {
    // SAFETY: as in `timer_start`.
    unsafe {
        reg(0x040).write_volatile(1);
        reg(0x540).read_volatile()
    }
}

/// Shades `rows` rows of the plane; returns the FNV-1a checksum of the colours.
#[inline(never)]
fn shade<const T: usize, const N: usize>(tex: &texcore::texture::Texture<T, N>, rows: u16) -> u32 {
    let mapping = PlaneMapping::scaled(32);
    let mut ev = tex.evaluator();
    let mut acc = 0x811C_9DC5u32;
    for y in 0..rows {
        let span = mapping.span(0, i32::from(y), SIDE);
        ev.shade(&span, |c| {
            acc = (acc ^ c.to_u32()).wrapping_mul(0x0100_0193)
        });
    }
    acc
}

#[entry]
fn main() -> ! {
    timer_start();
    let t0 = ticks();
    let Ok(marble) = Material::preset_with_hash(PresetName::Marble, HashKind::Integer)
        .texture::<64>(Antialias::Csat)
    else {
        semihosting::println!("TEXM0 error=material");
        semihosting::process::exit(1)
    };
    let marble = core::hint::black_box(marble);
    let t1 = ticks();
    let empty = shade(&marble, core::hint::black_box(0));
    let t2 = ticks();
    let checksum = shade(&marble, core::hint::black_box(SIDE));
    let t3 = ticks();
    let pixels = u32::from(SIDE) * u32::from(SIDE);
    let work = (t3 - t2).wrapping_sub(t2 - t1);
    // ticks * 62.5 instructions / pixels, in tenths.
    let tenths = (u64::from(work) * 625 / u64::from(pixels)) as u32;
    semihosting::println!(
        "TEXM0 pixels={} checksum={:#010x} setup_ticks={} work_ticks={} instr_per_pixel={}.{}",
        pixels,
        checksum,
        t1 - t0,
        work,
        tenths / 10,
        tenths % 10
    );
    let _ = empty;
    semihosting::process::exit(0)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    semihosting::process::exit(101)
}
