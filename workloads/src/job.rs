//! A job and the context it runs in: the unit of work the firmware measures.
//!
//! A job is a plain function `fn(&mut Ctx) -> u32` that does a fixed amount of work and returns a
//! checksum of everything it computed. The firmware's harness runs every entry of
//! [`crate::jobs::JOBS`] twice under the instruction counter and reports `name`, checksum and
//! instruction count; the host recomputes the checksum with the same texcore functions
//! (`tests/tests/firmware_qemu.rs`).
//!
//! To add a workload: write the function (in the module of its concept), fold what it produces
//! with [`fold`] / [`fold_line`] starting from [`FNV_OFFSET`], and append a [`job!`](crate::job!) to
//! [`crate::jobs::JOBS`]. Keep it panic-free: `firmware/check-panic-never.sh` links every job with
//! a panic handler that cannot link.
//!
//! Checksum: 32-bit FNV-1a over 32-bit words, `acc = (acc ^ word) * 0x0100_0193 (mod 2^32)` from
//! `acc = 0x811C_9DC5`. Each job documents which words it folds, in which order.

use texcore::hash::HashKind;
use texcore::model::TextureModel;
use texcore::span::EvalMode;
use texcore::texture::{workload, Texture};

/// Entries of the context's scanline buffer: one 256-pixel row.
pub const LINE: usize = 256;

/// FNV-1a 32-bit offset basis: the checksum of nothing.
pub const FNV_OFFSET: u32 = 0x811C_9DC5;
/// FNV-1a 32-bit prime.
pub const FNV_PRIME: u32 = 0x0100_0193;

/// Folds one 32-bit word into a checksum (FNV-1a over words).
#[inline(always)]
pub fn fold(acc: u32, word: u32) -> u32 {
    (acc ^ word).wrapping_mul(FNV_PRIME)
}

/// Folds a whole line, entry 0 first.
#[inline(always)]
pub fn fold_line(acc: u32, line: &[u32]) -> u32 {
    line.iter().fold(acc, |a, &w| fold(a, w))
}

/// What a job gets to work with. Lives on the stack of the harness for the whole run.
pub struct Ctx {
    /// Scratch scanline: jobs write one row of results here, then checksum it (the shape a
    /// renderer has: produce a span into a line buffer, hand the line on).
    pub line: [u32; LINE],
    /// The third lattice coordinate of the hash planes. Set at run time from an opaque value so
    /// the compiler cannot precompute a job. The harness uses [`Ctx::PLANE_Z`].
    pub z: u16,
    /// The value-noise workload models (1 and 4 octaves), built outside the measured window.
    pub fbm: [TextureModel<{ workload::TERMS }>; 2],
    /// The marble + csat texture (built outside the measured window); each marble job sets its
    /// evaluation mode (one texture, not three: the stack is shared with the scene jobs).
    pub marble: Option<Texture<{ workload::TERMS }, 256>>,
    /// Entry `k`: the built-in scene (index in `crate::scenes::BUILTIN_SCENES`) whose strip
    /// `k - 1` ran last, and the checksum of its rows up to the end of that strip, which strip
    /// `k` continues (`crate::suite::scene_strip`). Entry 0 is unused (strip 0 starts afresh).
    pub frame_checksums: [Option<(usize, u32)>; crate::scenes::STRIPS],
}

impl Ctx {
    /// The `z` coordinate every hash-plane job uses (the host test uses the same).
    pub const PLANE_Z: u16 = 7;

    /// A zeroed line and `z = PLANE_Z`, passed through `black_box`. Not inlined: building the
    /// textures takes stack that the harness's frame should not keep for the whole run.
    #[inline(never)]
    pub fn new() -> Self {
        Ctx {
            line: [0; LINE],
            z: core::hint::black_box(Self::PLANE_Z),
            fbm: [
                core::hint::black_box(workload::value_fbm(1, HASH)),
                core::hint::black_box(workload::value_fbm(4, HASH)),
            ],
            marble: core::hint::black_box(workload::marble_csat(HASH, EvalMode::Auto)),
            frame_checksums: [None; crate::scenes::STRIPS],
        }
    }
}

/// The signature of a job: does its work on the context, returns the checksum.
pub type JobFn = fn(&mut Ctx) -> u32;

impl Default for Ctx {
    fn default() -> Self {
        Self::new()
    }
}

/// One named workload.
#[derive(Clone, Copy)]
pub struct Job {
    /// Stable name, reported to the host (no spaces).
    pub name: &'static str,
    /// The work; returns its checksum.
    pub run: JobFn,
}

/// The lattice hash of the texture jobs: the permutation table on the Cortex-M, the table-free
/// integer hash on the RISC-V soft-core class.
#[cfg(all(target_arch = "arm", feature = "perm-hash"))]
pub const HASH: HashKind = HashKind::Permutation;
/// The lattice hash of the texture jobs: the permutation table on the Cortex-M, the table-free
/// integer hash on the RISC-V soft-core class.
#[cfg(not(all(target_arch = "arm", feature = "perm-hash")))]
pub const HASH: HashKind = HashKind::Integer;

/// Side of the square planes of the span and texture jobs, in pixels.
pub const PLANE: u16 = 128;

/// A [`Job`] named `$name` running `$f`; with `per_target` first, the name ends in the build's
/// hash and plane size (`<name>_perm_128` on the Cortex-M, `<name>_int_128` on the RISC-V).
#[macro_export]
macro_rules! job {
    (per_target $name:literal, $f:expr) => {
        $crate::job::Job {
            name: if cfg!(all(target_arch = "arm", feature = "perm-hash")) {
                concat!($name, "_perm_128")
            } else {
                concat!($name, "_int_128")
            },
            run: $f,
        }
    };
    ($name:expr, $f:expr) => {
        $crate::job::Job {
            name: $name,
            run: $f,
        }
    };
}
