//! Workloads ("jobs") the firmware measures, and the context they run in.
//!
//! A job is a plain function `fn(&mut Ctx) -> u32` that does a fixed amount of work and returns a
//! checksum of everything it computed. The harness runs every entry of [`JOBS`] twice under the
//! instruction counter and reports `name`, checksum and instruction count; the host recomputes
//! the checksum with the same texcore functions (`tests/tests/firmware_qemu.rs`).
//!
//! To add a workload (e.g. a texcore scanline render later): write the function, fold what it
//! produces with [`fold`] / [`fold_line`] starting from [`FNV_OFFSET`], and append a [`Job`] to
//! [`JOBS`]. Keep it panic-free: `check-panic-never.sh` links every job with a panic handler that
//! cannot link.
//!
//! Checksum: 32-bit FNV-1a over 32-bit words, `acc = (acc ^ word) * 0x0100_0193 (mod 2^32)` from
//! `acc = 0x811C_9DC5`. Each job documents which words it folds, in which order.
//!
//! Per target: the RISC-V soft-core class build runs only table-free code (no ROM tables); the
//! Cortex-M build additionally runs the 256-byte permutation-table hash.

// With feature `accuracy` or `peers` the firmware runs those reports' jobs instead of these.
#![cfg_attr(
    any(feature = "accuracy", feature = "peers"),
    allow(dead_code, unused_macros)
)]

use texcore::hash::{hash61, int_hash, lattice_value, HashKind};
use texcore::model::TextureModel;
use texcore::span::{EvalMode, EvalOptions, Sample, SpanEvaluator};
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
#[cfg(target_arch = "arm")]
pub const HASH: HashKind = HashKind::Permutation;
/// The lattice hash of the texture jobs: the permutation table on the Cortex-M, the table-free
/// integer hash on the RISC-V soft-core class.
#[cfg(not(target_arch = "arm"))]
pub const HASH: HashKind = HashKind::Integer;

/// Side of the square planes of the span and texture jobs, in pixels.
pub const PLANE: u16 = 128;

/// A job whose name ends in the hash and plane size: `<name>_perm_128` on the Cortex-M,
/// `<name>_int_128` on the RISC-V.
macro_rules! job {
    ($name:literal, $f:expr) => {
        Job {
            name: if cfg!(target_arch = "arm") {
                concat!($name, "_perm_128")
            } else {
                concat!($name, "_int_128")
            },
            run: $f,
        }
    };
}

/// With feature `accuracy`: the accuracy report's jobs (`crate::accuracy`).
#[cfg(feature = "accuracy")]
pub use crate::accuracy::JOBS;

/// With feature `peers` (and not `accuracy`): the peer-comparison jobs (`crate::peer_jobs`).
#[cfg(all(feature = "peers", not(feature = "accuracy")))]
pub use crate::peer_jobs::JOBS;

/// Every job the firmware runs, in order.
#[cfg(not(any(feature = "accuracy", feature = "peers")))]
pub static JOBS: &[Job] = &[
    Job {
        name: "int_hash_256x256",
        run: int_hash_plane,
    },
    Job {
        name: "lattice_value_int_256x256",
        run: lattice_value_int_plane,
    },
    Job {
        name: "hash61_256x256",
        run: hash61_plane,
    },
    #[cfg(all(target_arch = "arm", feature = "perm-hash"))]
    Job {
        name: "perm_hash_256x256",
        run: perm_hash_plane,
    },
    #[cfg(all(target_arch = "arm", feature = "perm-hash"))]
    Job {
        name: "lattice_value_perm_256x256",
        run: lattice_value_perm_plane,
    },
    job!(
        "span_1oct_direct",
        span_job::<0, { workload::CELLS_8 }, DIRECT>
    ),
    job!("span_1oct_fd", span_job::<0, { workload::CELLS_8 }, FD>),
    job!("span_1oct_auto", span_job::<0, { workload::CELLS_8 }, AUTO>),
    job!("span_1oct_fd32", span_job::<0, { workload::CELLS_8 }, FD32>),
    job!(
        "span_4oct_direct",
        span_job::<1, { workload::CELLS_8 }, DIRECT>
    ),
    job!("span_4oct_fd", span_job::<1, { workload::CELLS_8 }, FD>),
    job!("span_4oct_auto", span_job::<1, { workload::CELLS_8 }, AUTO>),
    job!("span_4oct_fd32", span_job::<1, { workload::CELLS_8 }, FD32>),
    job!(
        "span_zoomin4_direct",
        span_job::<1, { workload::ZOOM_IN }, DIRECT>
    ),
    job!("span_zoomin4_fd", span_job::<1, { workload::ZOOM_IN }, FD>),
    job!(
        "span_zoomin4_auto",
        span_job::<1, { workload::ZOOM_IN }, AUTO>
    ),
    job!(
        "span_zoomout4_direct",
        span_job::<1, { workload::ZOOM_OUT }, DIRECT>
    ),
    job!(
        "span_zoomout4_fd",
        span_job::<1, { workload::ZOOM_OUT }, FD>
    ),
    job!(
        "span_zoomout4_auto",
        span_job::<1, { workload::ZOOM_OUT }, AUTO>
    ),
    job!("marble_csat_direct", marble_job::<0>),
    job!("marble_csat_fd", marble_job::<1>),
    job!("marble_csat_auto", marble_job::<2>),
    // Texture-unit workloads through texcore's pixel path (see `crate::suite`).
    crate::suite::job!("config:hash", config_hash),
    crate::suite::job!("plane:wood", plane_wood),
    crate::suite::job!("plane:wood/setup", plane_wood_setup),
    crate::suite::job!("plane:marble", plane_marble),
    crate::suite::job!("plane:marble/setup", plane_marble_setup),
    crate::suite::job!("plane:clouds", plane_clouds),
    crate::suite::job!("plane:clouds/setup", plane_clouds_setup),
    crate::suite::job!("plane:water", plane_water),
    crate::suite::job!("plane:water/setup", plane_water_setup),
    crate::suite::job!("plane:fire", plane_fire),
    crate::suite::job!("plane:fire/setup", plane_fire_setup),
    crate::suite::job!("plane:planet", plane_planet),
    crate::suite::job!("plane:planet/setup", plane_planet_setup),
    crate::suite::job!("plane:planet-clouds", plane_planet_clouds),
    crate::suite::job!("plane:planet-clouds/setup", plane_planet_clouds_setup),
    crate::suite::job!("plane:zoneplate", plane_zoneplate),
    crate::suite::job!("plane:zoneplate/setup", plane_zoneplate_setup),
    crate::suite::job!("plane:mn-marble", plane_mn_marble),
    crate::suite::job!("plane:mn-marble/setup", plane_mn_marble_setup),
    crate::suite::job!("plane:mn-wood", plane_mn_wood),
    crate::suite::job!("plane:mn-wood/setup", plane_mn_wood_setup),
    crate::suite::job!("stage:noise-octave", stage_noise_octave),
    crate::suite::job!("stage:noise-octave/setup", stage_noise_octave_setup),
    crate::suite::job!("stage:noise-octave-grad", stage_noise_octave_grad),
    crate::suite::job!(
        "stage:noise-octave-grad/setup",
        stage_noise_octave_grad_setup
    ),
    crate::suite::job!("stage:quadric", stage_quadric),
    crate::suite::job!("stage:quadric/setup", stage_quadric_setup),
    crate::suite::job!("stage:color-lookup", stage_color_lookup),
    crate::suite::job!("stage:color-lookup/setup", stage_color_lookup_setup),
    crate::suite::job!("stage:csat", stage_csat),
    crate::suite::job!("stage:csat/setup", stage_csat_setup),
    crate::suite::job!("stage:raster-setup", stage_raster_setup),
    crate::suite::job!("stage:raster-setup/setup", stage_raster_setup_setup),
    crate::suite::job!("stage:perspective-every16", stage_perspective_every16),
    crate::suite::job!(
        "stage:perspective-every16/setup",
        stage_perspective_every16_setup
    ),
    crate::suite::job!("stage:perspective-affine", stage_perspective_affine),
    crate::suite::job!(
        "stage:perspective-affine/setup",
        stage_perspective_affine_setup
    ),
    crate::suite::job!("scene:floor", scene_floor),
    crate::suite::job!("scene:floor/setup", scene_floor_setup),
    crate::suite::job!("scene:overlay", scene_overlay),
    crate::suite::job!("scene:overlay/setup", scene_overlay_setup),
    #[cfg(feature = "panic-never-canary")]
    Job {
        name: "panic_never_canary",
        run: panic_never_canary,
    },
];

/// The built-in scene jobs (see `crate::suite::scene_strip`), run after [`JOBS`]: the strips of
/// each scene's frame, top to bottom, each with its `/setup` job.
#[cfg(not(any(feature = "accuracy", feature = "peers")))]
pub static SCENE_JOBS: &[Job] = &crate::suite::builtin_scene_jobs![
    0 => "wood",
    1 => "marble",
    2 => "seascape",
    3 => "fire",
    4 => "planet",
    5 => "moonrise",
    6 => "zoneplate",
    7 => "torus",
];

/// With feature `accuracy` or `peers`: none (their jobs are all in [`JOBS`]).
#[cfg(any(feature = "accuracy", feature = "peers"))]
pub static SCENE_JOBS: &[Job] = &[];

/// A job with a bounds-checked index the optimiser cannot remove (only with feature
/// `panic-never-canary`).
#[cfg(feature = "panic-never-canary")]
fn panic_never_canary(ctx: &mut Ctx) -> u32 {
    let i = core::hint::black_box(LINE + 1);
    ctx.line[i]
}

/// Fills each row `y in 0..256` of the plane `z` with `f(x, y, z)` for `x in 0..256`, folding
/// each finished row (x ascending) into the checksum, rows in ascending `y`.
#[inline(always)]
fn plane(ctx: &mut Ctx, f: impl Fn(u16, u16, u16) -> u32) -> u32 {
    let z = ctx.z;
    let mut acc = FNV_OFFSET;
    for y in 0..LINE as u16 {
        for (x, px) in (0u16..).zip(ctx.line.iter_mut()) {
            *px = f(x, y, z);
        }
        acc = fold_line(acc, &ctx.line);
    }
    acc
}

/// `int_hash(x, y, 7)` over the 256x256 plane: folds the 32-bit hash.
pub fn int_hash_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, int_hash)
}

/// `lattice_value(Integer, x, y, 7)` over the plane: folds the i16 value zero-extended from its
/// 16-bit pattern (`v as u16 as u32`).
pub fn lattice_value_int_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, |x, y, z| {
        u32::from(lattice_value(HashKind::Integer, x, y, z) as u16)
    })
}

/// `hash61(x, y, 7)` (Olano's mod-61 hash, value in `0..61`) over the plane.
pub fn hash61_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, hash61)
}

/// `perm_hash(x, y, 7)` (256-byte permutation table) over the plane: folds the byte.
#[cfg(all(target_arch = "arm", feature = "perm-hash"))]
pub fn perm_hash_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, |x, y, z| u32::from(texcore::hash::perm_hash(x, y, z)))
}

/// `lattice_value(Permutation, x, y, 7)` over the plane, folded like
/// [`lattice_value_int_plane`].
#[cfg(all(target_arch = "arm", feature = "perm-hash"))]
pub fn lattice_value_perm_plane(ctx: &mut Ctx) -> u32 {
    plane(ctx, |x, y, z| {
        u32::from(lattice_value(HashKind::Permutation, x, y, z) as u16)
    })
}

const DIRECT: u8 = 0;
const FD: u8 = 1;
const AUTO: u8 = 2;
const FD32: u8 = 3;

const fn mode(m: u8) -> EvalMode {
    match m {
        DIRECT => EvalMode::Direct,
        FD => EvalMode::Fd,
        FD32 => EvalMode::Fd32,
        _ => EvalMode::Auto,
    }
}

/// One 32-bit word per sample: `f ^ gx_lo ^ rotl(gx_hi, 8) ^ rotl(gy_lo, 16) ^ rotl(gy_hi, 24)`
/// (a few instructions a pixel; the host check recomputes it).
#[inline(always)]
pub fn mix(s: &Sample) -> u32 {
    let (gx, gy) = (s.gx as u64, s.gy as u64);
    (s.f.to_bits() as u32)
        ^ (gx as u32)
        ^ ((gx >> 32) as u32).rotate_left(8)
        ^ (gy as u32).rotate_left(16)
        ^ ((gy >> 32) as u32).rotate_left(24)
}

/// The value-noise plane `PLANE x PLANE` of [`workload::plane_span`] with octave-0 step `STEP`
/// (model `ctx.fbm[M]`: 1 or 4 octaves; gradients on, culling on, mode `MODE`): each row's
/// [`mix`] words are written to the line and the row folded, rows in ascending `y`.
pub fn span_job<const M: usize, const STEP: i32, const MODE: u8>(ctx: &mut Ctx) -> u32 {
    span_plane(ctx, M, STEP, mode(MODE))
}

/// The body of [`span_job`], shared by every instance (one copy of the evaluator in flash).
#[inline(never)]
fn span_plane(ctx: &mut Ctx, m: usize, step: i32, mode: EvalMode) -> u32 {
    let Some(model) = ctx.fbm.get(m) else {
        return 0;
    };
    let mut ev = SpanEvaluator::new(
        model,
        EvalOptions {
            mode,
            gradients: true,
            cull: true,
        },
    );
    let line = &mut ctx.line[..usize::from(PLANE)];
    let mut acc = FNV_OFFSET;
    for y in 0..PLANE {
        let span = workload::plane_span(step, y, PLANE);
        let mut px = line.iter_mut();
        ev.eval(&span, |s| {
            if let Some(p) = px.next() {
                *p = mix(&s);
            }
        });
        acc = fold_line(acc, line);
    }
    acc
}

/// The marble + csat texture (`ctx.marble[K]`: `Direct`, `Fd`, `Auto`) on the first
/// `PLANE x PLANE` pixels of the preset's check plane: colours (`Rgba8888::to_u32`) written to the
/// line, each row folded, rows in ascending `y`.
pub fn marble_job<const K: usize>(ctx: &mut Ctx) -> u32 {
    marble_plane(ctx, K)
}

/// The body of [`marble_job`], shared by every instance.
#[inline(never)]
fn marble_plane(ctx: &mut Ctx, k: usize) -> u32 {
    let Some(tex) = ctx.marble.as_mut() else {
        return 0;
    };
    tex.set_mode(match k {
        0 => EvalMode::Direct,
        1 => EvalMode::Fd,
        _ => EvalMode::Auto,
    });
    let tex = &*tex;
    let mut ev = tex.evaluator();
    let line = &mut ctx.line[..usize::from(PLANE)];
    let mut acc = FNV_OFFSET;
    for y in 0..PLANE {
        let span = workload::marble_span(y, PLANE);
        let mut px = line.iter_mut();
        ev.shade(&span, |c| {
            if let Some(p) = px.next() {
                *p = c.to_u32();
            }
        });
        acc = fold_line(acc, line);
    }
    acc
}
