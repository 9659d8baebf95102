//! Runs the calibration, the counter self-test and every job, and reports over defmt.
//!
//! Report protocol (one `defmt::println!` frame per line, always enabled, parsed by
//! `host_sim::device`; every line starts with `TEXFW` and continues with `key=value` words):
//!
//! ```text
//! TEXFW begin target=<triple> counter=<name> unit=<instructions|cycles> protocol=1
//! TEXFW overhead raw=<u64> repeat=<u64>
//! TEXFW selftest nops=<u32> measured=<u64> ok=<bool>
//! TEXFW job name=<str> checksum=<0x........> count=<u64> repeat=<u64> ok=<bool>
//! TEXFW error what=<str> ...            (what=counter-overflow job=<str>: a job too long to count)
//! TEXFW stack used=<bytes> size=<bytes> job=<str>
//! TEXFW end pass=<bool> jobs=<u32>
//! ```
//!
//! `overhead` is the raw count of measuring the empty job (`fn(&mut Ctx) -> u32 { 0 }`); every
//! other count is net: raw minus overhead, i.e. the instructions a job executes beyond an empty
//! job. `repeat` is a second measurement of the same thing, which must be identical. The self
//! test measures nop sleds of known length (which compile to the empty job plus `n` nops) and
//! checks the counter returns exactly `n`.
//!
//! `stack`: the deepest the stack has been during the jobs (`crate::stack`: the free stack is
//! painted before the first job and checked after each), out of `size` bytes between the static
//! data and the top of RAM, and the first job that reached that depth. The run does not fail on
//! it (an overflow would already have corrupted the static data); the host test asserts a
//! margin. With feature `stack-guard` (Cortex-M4F, `crate::guard`) the stack lies above unmapped
//! memory instead, and an overflow ends the run with `TEXFW error what=stack-overflow`.

use crate::counter::{Counter, Sample, NAME, UNIT};
use crate::stack;
use defmt::println;
use workloads::job::{Ctx, JobFn};
#[cfg(all(feature = "approximate-scenes", not(feature = "peers")))]
use workloads::jobs::APPROXIMATE_JOBS as JOBS;
#[cfg(not(any(feature = "peers", feature = "approximate-scenes")))]
use workloads::jobs::{JOBS, SCENE_JOBS};
#[cfg(feature = "peers-band")]
use workloads::peer_jobs::BAND as JOBS;
#[cfg(all(feature = "peers", not(feature = "peers-band")))]
use workloads::peer_jobs::PLANE as JOBS;

/// The peer-comparison firmware and the approximate-scenes firmware run no strip jobs.
#[cfg(any(feature = "peers", feature = "approximate-scenes"))]
static SCENE_JOBS: &[workloads::job::Job] = &[];

const TARGET: &str = env!("FIRMWARE_TARGET");

/// Jobs whose name contains `TEXFW_ONLY` (set at build time; unset: every job). For profiling one
/// job (`firmware/profile.sh`).
fn selected(name: &str) -> bool {
    #[cfg(all(target_arch = "arm", feature = "stack-guard"))]
    if !crate::guard::selected(name) {
        return false;
    }
    match option_env!("TEXFW_ONLY") {
        Some(only) if !only.is_empty() => contains(name, only),
        _ => true,
    }
}

fn contains(hay: &str, needle: &str) -> bool {
    let (h, n) = (hay.as_bytes(), needle.as_bytes());
    n.len() <= h.len() && (0..=h.len() - n.len()).any(|i| h.get(i..i + n.len()) == Some(n))
}

fn empty(_: &mut Ctx) -> u32 {
    0
}

/// `N` nops, then what [`empty`] does.
#[allow(unsafe_code)]
fn sled<const N: u32>(_: &mut Ctx) -> u32 {
    // SAFETY: executes `N` nops; touches no registers, memory or flags.
    unsafe {
        core::arch::asm!(".rept {n}", "nop", ".endr", n = const N, options(nomem, nostack, preserves_flags));
    }
    0
}

/// Sled lengths chosen to land on every kind of tick phase of the Cortex-M vernier (below, at and
/// above one tick of 40 instructions, and many ticks).
static SLEDS: &[(u32, JobFn)] = &[
    (1, sled::<1>),
    (2, sled::<2>),
    (39, sled::<39>),
    (40, sled::<40>),
    (41, sled::<41>),
    (1000, sled::<1000>),
    (4099, sled::<4099>),
];

fn measure(c: &mut Counter, f: JobFn, ctx: &mut Ctx, name: &str) -> Option<Sample> {
    match c.measure(f, ctx) {
        Ok(s) => Some(s),
        Err(_) => {
            println!("TEXFW error what=counter-overflow job={=str}", name);
            None
        }
    }
}

/// Runs everything; `true` when every check passed.
pub fn run() -> bool {
    let mut counter = Counter::init();
    let mut ctx = Ctx::new();
    let mut pass = true;
    println!(
        "TEXFW begin target={=str} counter={=str} unit={=str} protocol=1",
        TARGET, NAME, UNIT
    );

    let (Some(o1), Some(o2)) = (
        measure(&mut counter, empty, &mut ctx, "overhead"),
        measure(&mut counter, empty, &mut ctx, "overhead"),
    ) else {
        println!("TEXFW end pass=false jobs=0");
        return false;
    };
    println!("TEXFW overhead raw={=u64} repeat={=u64}", o1.raw, o2.raw);
    pass &= o1.raw == o2.raw;
    let overhead = o1.raw;

    for &(n, f) in SLEDS {
        let measured = match measure(&mut counter, f, &mut ctx, "selftest") {
            Some(s) => s.raw.wrapping_sub(overhead),
            None => u64::MAX,
        };
        let ok = measured == u64::from(n);
        pass &= ok;
        println!(
            "TEXFW selftest nops={=u32} measured={=u64} ok={=bool}",
            n, measured, ok
        );
    }

    stack::paint();
    let mut peak = (stack::used(), "harness");
    let mut count = 0u32;
    #[cfg(all(target_arch = "arm", feature = "stack-guard"))]
    let canary = crate::guard::CANARY;
    #[cfg(not(all(target_arch = "arm", feature = "stack-guard")))]
    let canary: &[workloads::job::Job] = &[];
    let jobs = JOBS.iter().chain(SCENE_JOBS).filter(|j| selected(j.name));
    for job in jobs.chain(canary) {
        let (Some(a), Some(b)) = (
            measure(&mut counter, job.run, &mut ctx, job.name),
            measure(&mut counter, job.run, &mut ctx, job.name),
        ) else {
            pass = false;
            continue;
        };
        let ok = a == b;
        pass &= ok;
        count += 1;
        println!(
            "TEXFW job name={=str} checksum={=u32:#010x} count={=u64} repeat={=u64} ok={=bool}",
            job.name,
            a.checksum,
            a.raw.wrapping_sub(overhead),
            b.raw.wrapping_sub(overhead),
            ok
        );
        let used = stack::used();
        if used > peak.0 {
            peak = (used, job.name);
        }
    }
    println!(
        "TEXFW stack used={=usize} size={=usize} job={=str}",
        peak.0,
        stack::size(),
        peak.1
    );
    println!("TEXFW end pass={=bool} jobs={=u32}", pass, count);
    pass
}
