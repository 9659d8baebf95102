//! Exact instruction counting around one call of a job.
//!
//! [`Counter::measure`] returns the *raw* count of one window: from a counter read just before
//! the call to a counter read just after it. The window always contains the same glue (counter
//! read sequence, indirect call, return), so the harness measures an empty job once and
//! subtracts that *overhead*; see the crate docs for the measured constants.
//!
//! Three implementations, picked at compile time:
//!
//! - **RISC-V** (`minstret`): the retired-instruction counter, read as `minstreth, minstret,
//!   minstreth` (always three instructions). The 64-bit value is assembled branch-free afterwards:
//!   if the low word is `>= 2^31` no carry can have happened between the first high read and the
//!   low read, so the first high word belongs to it; otherwise no carry can happen between the low
//!   read and the second high read. So a wrap of the low word is handled without a data-dependent
//!   loop or branch inside the window. Under QEMU with `-icount`, `minstret` is the icount
//!   instruction counter, exact.
//!
//! - **Cortex-M under QEMU** (`systick-vernier`, default): QEMU does not implement DWT CYCCNT
//!   (it reads 0). SysTick runs from the MPS2 25 MHz system clock, and with `-icount shift=0`
//!   every instruction advances QEMU's virtual clock by exactly 1 ns, so one SysTick tick is
//!   exactly [`TICK`] = 40 instructions, not 1. We recover single-instruction resolution with a
//!   vernier: a loop whose iterations are exactly `TICK + 1` instructions and that reads the
//!   counter once per iteration. Relative to the tick grid, successive reads slip by one
//!   instruction, so `VAL + i` stays constant until the read lands exactly on a tick edge; that
//!   read's time is then known exactly in units of instructions. Doing it once before the call
//!   (the window starts at the aligned read) and once after it (the window ends at the first read,
//!   whose time is the aligned read's minus `(TICK + 1) * iterations`) gives the exact count:
//!
//!   `raw = TICK * (VAL_start - VAL_end) - (TICK + 1) * i_end`
//!
//!   SysTick is reloaded (24-bit, `0xFF_FFFF`) before each measurement and its COUNTFLAG checked
//!   after it, so a single window may be up to `2^24 * 40 = 671 088 640` instructions; a longer
//!   one is reported as an overflow rather than a wrong number. The tick length is a property of
//!   the QEMU machine and icount shift; the harness's self-test (nop sleds of known length) fails
//!   the run if it is ever different.
//!
//! - **Cortex-M hardware** (feature `dwt`): DWT CYCCNT, in core clock *cycles* (not
//!   instructions), 32-bit with wrapping subtraction (windows up to 2^32 cycles).

use workloads::job::{Ctx, JobFn};

/// One measured call.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Sample {
    /// What the job returned.
    pub checksum: u32,
    /// Instructions (or cycles with `dwt`) in the window, overhead included.
    pub raw: u64,
}

/// The window was too long for the counter (Cortex-M SysTick vernier only).
#[derive(Clone, Copy)]
pub struct Overflow;

/// Calls `f(ctx)` through an opaque function pointer so every job (and the empty calibration
/// job) goes through the same, non-inlined, non-specialised call sequence.
#[inline(always)]
fn call(f: JobFn, ctx: &mut Ctx) -> u32 {
    let f = core::hint::black_box(f);
    f(ctx)
}

// ---------------------------------------------------------------------------------------------
// RISC-V: minstret
// ---------------------------------------------------------------------------------------------
#[cfg(target_arch = "riscv32")]
mod imp {
    use super::{call, Ctx, JobFn, Overflow, Sample};

    /// What is counted.
    pub const NAME: &str = "minstret";
    /// Unit of the counts.
    pub const UNIT: &str = "instructions";

    pub struct Counter;

    impl Counter {
        pub fn init() -> Self {
            Counter
        }

        #[inline(never)]
        pub fn measure(&mut self, f: JobFn, ctx: &mut Ctx) -> Result<Sample, Overflow> {
            let start = read();
            let checksum = call(f, ctx);
            let end = read();
            Ok(Sample {
                checksum,
                raw: combine(end).wrapping_sub(combine(start)),
            })
        }
    }

    /// `(minstreth, minstret, minstreth)`, three consecutive instructions.
    #[inline(always)]
    #[allow(unsafe_code)]
    fn read() -> (u32, u32, u32) {
        let (h1, lo, h2): (u32, u32, u32);
        // SAFETY: reads three machine counter CSRs (we run in M-mode, where they are always
        // accessible); no memory, stack or flags are touched. Not `pure`/`nomem` so it is never
        // moved across the job call.
        unsafe {
            core::arch::asm!(
                "csrr {h1}, minstreth",
                "csrr {lo}, minstret",
                "csrr {h2}, minstreth",
                h1 = out(reg) h1,
                lo = out(reg) lo,
                h2 = out(reg) h2,
                options(nostack),
            );
        }
        (h1, lo, h2)
    }

    /// Branch-free 64-bit assembly of a `read()` triple (see the module docs).
    #[inline(always)]
    fn combine((h1, lo, h2): (u32, u32, u32)) -> u64 {
        let first = (lo >> 31).wrapping_neg(); // all ones when lo >= 2^31
        let hi = (h1 & first) | (h2 & !first);
        (u64::from(hi) << 32) | u64::from(lo)
    }
}

// ---------------------------------------------------------------------------------------------
// Cortex-M under QEMU: SysTick vernier
// ---------------------------------------------------------------------------------------------
#[cfg(all(target_arch = "arm", not(feature = "dwt")))]
mod imp {
    use super::{call, Ctx, JobFn, Overflow, Sample};
    use cortex_m::peripheral::{syst::SystClkSource, SYST};

    /// What is counted.
    pub const NAME: &str = "systick-vernier";
    /// Unit of the counts.
    pub const UNIT: &str = "instructions";

    /// Instructions per SysTick tick: 25 MHz MPS2 system clock, 1 ns per instruction
    /// (`-icount shift=0`). The vernier loop below is `TICK + 1` instructions long.
    pub const TICK: u32 = 40;
    const RELOAD: u32 = 0x00FF_FFFF;
    /// SysTick current value register.
    const SYST_CVR: u32 = 0xE000_E018;

    pub struct Counter {
        syst: SYST,
    }

    impl Counter {
        pub fn init() -> Self {
            // The harness is the only user of the core peripherals and takes them once.
            let mut syst = match cortex_m::Peripherals::take() {
                Some(p) => p.SYST,
                None => crate::fail_early(),
            };
            syst.disable_interrupt();
            syst.set_clock_source(SystClkSource::Core);
            syst.set_reload(RELOAD);
            syst.clear_current();
            syst.enable_counter();
            Counter { syst }
        }

        #[inline(never)]
        pub fn measure(&mut self, f: JobFn, ctx: &mut Ctx) -> Result<Sample, Overflow> {
            self.restart();
            let (i_start, s_start) = vernier();
            let checksum = call(f, ctx);
            let (i_end, s_end) = vernier();
            // Outside the window from here on.
            if self.syst.has_wrapped() {
                return Err(Overflow);
            }
            // vernier() returns (i* + 1, VAL(i*) + i*) for the aligned read i*.
            let val_start = s_start.wrapping_sub(i_start.wrapping_sub(1));
            let i_end_star = i_end.wrapping_sub(1);
            let val_end = s_end.wrapping_sub(i_end_star);
            let ticks = u64::from(val_start.wrapping_sub(val_end) & RELOAD);
            let raw = ticks * u64::from(TICK) - u64::from(TICK + 1) * u64::from(i_end_star);
            Ok(Sample { checksum, raw })
        }

        /// Reloads SysTick and waits until it has counted at least once from the reload value,
        /// so the vernier only ever sees single-tick decrements; clears COUNTFLAG.
        fn restart(&mut self) {
            self.syst.clear_current();
            loop {
                let v = SYST::get_current();
                if v != 0 && v < RELOAD {
                    break;
                }
            }
            let _ = self.syst.has_wrapped();
        }
    }

    /// The vernier: returns `(i* + 1, VAL_i* + i*)` where read `i*` (counted from 0) is the first
    /// whose `VAL + i` differs from the previous read's. Reads are exactly `TICK + 1` = 41
    /// instructions apart, including read 0 -> read 1 (the first iteration is unrolled with nops
    /// standing in for the compare and branch).
    #[inline(always)]
    #[allow(unsafe_code)]
    fn vernier() -> (u32, u32) {
        let (i, s): (u32, u32);
        // SAFETY: only reads the SysTick current-value register (a side-effect-free read of a
        // memory-mapped core register that always exists on ARMv7-M) and uses the declared
        // scratch registers; no stack use. Flags are clobbered (no `preserves_flags`).
        unsafe {
            core::arch::asm!(
                "movs {i}, #0",
                // read 0 (unrolled): ldr, add, add + 38 nops = 41
                "ldr {v}, [{cvr}]",
                "add {prev}, {v}, {i}",
                "add {i}, {i}, #1",
                ".rept 38",
                "nop",
                ".endr",
                // reads 1..: ldr, add, add, 35 nops, cmp, mov, beq = 41
                "2:",
                "ldr {v}, [{cvr}]",
                "add {s}, {v}, {i}",
                "add {i}, {i}, #1",
                ".rept 35",
                "nop",
                ".endr",
                "cmp {s}, {prev}",
                "mov {prev}, {s}",
                "beq 2b",
                cvr = in(reg) SYST_CVR,
                i = out(reg) i,
                s = out(reg) s,
                v = out(reg) _,
                prev = out(reg) _,
                options(nostack, readonly),
            );
        }
        (i, s)
    }
}

// ---------------------------------------------------------------------------------------------
// Cortex-M hardware: DWT CYCCNT
// ---------------------------------------------------------------------------------------------
#[cfg(all(target_arch = "arm", feature = "dwt"))]
mod imp {
    use super::{call, Ctx, JobFn, Overflow, Sample};
    use cortex_m::peripheral::DWT;

    /// What is counted.
    pub const NAME: &str = "dwt-cyccnt";
    /// Unit of the counts.
    pub const UNIT: &str = "cycles";

    pub struct Counter;

    impl Counter {
        pub fn init() -> Self {
            let mut p = match cortex_m::Peripherals::take() {
                Some(p) => p,
                None => crate::fail_early(),
            };
            p.DCB.enable_trace();
            p.DWT.enable_cycle_counter();
            Counter
        }

        #[inline(never)]
        pub fn measure(&mut self, f: JobFn, ctx: &mut Ctx) -> Result<Sample, Overflow> {
            let start = DWT::cycle_count();
            let checksum = call(f, ctx);
            let end = DWT::cycle_count();
            Ok(Sample {
                checksum,
                raw: u64::from(end.wrapping_sub(start)),
            })
        }
    }
}

pub use imp::{Counter, NAME, UNIT};
