//! The firmware side of the texture-unit workloads: job wrappers around [`crate::planes`],
//! [`crate::stages`] and [`crate::scenes`] (which the host shares), the per-target lattice hash,
//! and the static band buffers of the scene renders.
//!
//! Job names (registered in [`crate::jobs::JOBS`] with [`crate::job!`]):
//! - `config:hash`: checksum 1 when this build shades with the permutation hash, 2 with the
//!   integer hash (the host computes its expected checksums with the same hash);
//! - `plane:<material>`: a material's 64 x 64 check plane with csat ([`crate::planes`]);
//! - `stage:<stage>`: one stage of the pixel path alone ([`crate::stages`]);
//! - `band:<mode>`: one evaluation mode over a 320 x 8 band of value noise ([`crate::band`]);
//! - `scene:<scene>`: a scene at display size through the banded renderer ([`crate::scenes`]);
//! - `scene:<builtin>@<k>`: strip `k` of a built-in scene's frame ([`crate::scenes::builtin_strip`],
//!   [`crate::scenes::STRIPS`] strips), its checksum continuing strip `k - 1`'s, so that the last
//!   strip's checksum is the whole frame's;
//! - `<job>/setup`: the same job's set-up alone (textures, tables, inputs); the host subtracts
//!   its count to get the per-pixel cost of the work itself.

// With feature `accuracy` or `peers` the firmware runs those reports' jobs instead of these.
#![cfg_attr(feature = "accuracy", allow(unused_macros, unused_imports))]

use crate::job::Ctx;
use crate::scenes::{self, DEPTH_PIXELS, RGBA_BAND_PIXELS, SCENE_GROUPS};
use crate::{planes, stages};
use texcore::color::Rgba8888;
use texcore::hash::HashKind;
use texcore::render::GroupRows;

/// The lattice hash of this build: Perlin's permutation table on the Cortex-M4F (with the
/// default `perm-hash` feature), the table-free integer hash on rv32imc (an FPGA soft-core
/// without ROM tables; texcore is built without `perm-hash` there).
#[cfg(all(target_arch = "arm", feature = "perm-hash"))]
pub const HASH: HashKind = HashKind::Permutation;
/// See above.
#[cfg(not(all(target_arch = "arm", feature = "perm-hash")))]
pub const HASH: HashKind = HashKind::Integer;

/// Whether the suite's jobs are stubbed out (return 0 without running texcore): only in the
/// base `panic-never` link check without `panic-never-pixel-path` (the script also links the
/// suite itself with `panic-never-pixel-path`, strictly; see `firmware/check-panic-never.sh`).
const STUBBED: bool = cfg!(all(
    feature = "panic-never",
    not(feature = "panic-never-pixel-path")
));

/// [`HASH`], opaque to the optimiser (so no job is computed at compile time).
#[inline(always)]
fn hash() -> HashKind {
    core::hint::black_box(HASH)
}

/// `config:hash`: 1 = permutation hash, 2 = integer hash.
pub fn config_hash(_: &mut Ctx) -> u32 {
    #[allow(unreachable_patterns)]
    match hash() {
        HashKind::Integer => 2,
        _ => 1,
    }
}

macro_rules! plane_jobs {
    ($($name:literal => $job:ident, $setup:ident;)*) => {$(
        #[doc = concat!("`plane:", $name, "`.")]
        pub fn $job(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            planes::plane_checksum($name, hash())
        }
        #[doc = concat!("`plane:", $name, "/setup`.")]
        pub fn $setup(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            planes::setup_checksum($name, hash())
        }
    )*};
}

plane_jobs! {
    "wood" => plane_wood, plane_wood_setup;
    "marble" => plane_marble, plane_marble_setup;
    "clouds" => plane_clouds, plane_clouds_setup;
    "water" => plane_water, plane_water_setup;
    "fire" => plane_fire, plane_fire_setup;
    "planet" => plane_planet, plane_planet_setup;
    "planet-clouds" => plane_planet_clouds, plane_planet_clouds_setup;
    "zoneplate" => plane_zoneplate, plane_zoneplate_setup;
    "mn-marble" => plane_mn_marble, plane_mn_marble_setup;
    "mn-wood" => plane_mn_wood, plane_mn_wood_setup;
}

macro_rules! stage_jobs {
    ($($f:ident => $job:ident, $setup:ident;)*) => {$(
        #[doc = concat!("`stage:", stringify!($f), "`.")]
        pub fn $job(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            stages::$f(hash(), true)
        }
        #[doc = concat!("`stage:", stringify!($f), "/setup`.")]
        pub fn $setup(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            stages::$f(hash(), false)
        }
    )*};
}

stage_jobs! {
    noise_octave => stage_noise_octave, stage_noise_octave_setup;
    noise_octave_grad => stage_noise_octave_grad, stage_noise_octave_grad_setup;
    quadric => stage_quadric, stage_quadric_setup;
    color_lookup => stage_color_lookup, stage_color_lookup_setup;
    csat => stage_csat, stage_csat_setup;
    raster_setup => stage_raster_setup, stage_raster_setup_setup;
    perspective_every16 => stage_perspective_every16, stage_perspective_every16_setup;
    perspective_affine => stage_perspective_affine, stage_perspective_affine_setup;
}

macro_rules! peers_jobs {
    ($($k:literal => $job:ident, $setup:ident;)*) => {$(
        #[doc = concat!("`peers:` workload ", stringify!($k), " of `peers_workload::WORKLOADS`.")]
        pub fn $job(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            crate::peers_workload::WORKLOADS[$k].run(hash(), true)
        }
        #[doc = concat!("Its `/setup` job.")]
        pub fn $setup(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            crate::peers_workload::WORKLOADS[$k].run(hash(), false)
        }
    )*};
}

peers_jobs! {
    0 => peers_value_1oct, peers_value_1oct_setup;
    1 => peers_value_4oct, peers_value_4oct_setup;
    2 => peers_value_4oct_grad, peers_value_4oct_grad_setup;
    3 => peers_value_4oct_span16, peers_value_4oct_span16_setup;
    4 => peers_value_1oct_direct, peers_value_1oct_direct_setup;
    5 => peers_smooth_1oct, peers_smooth_1oct_setup;
    6 => peers_perlin_1oct, peers_perlin_1oct_setup;
}

macro_rules! band_jobs {
    ($($(#[$m:meta])* $name:literal => $job:ident, $setup:ident;)*) => {$(
        $(#[$m])*
        #[doc = concat!("`band:", $name, "`.")]
        pub fn $job(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            crate::band::band($name).map_or(0, |b| b.run(hash(), true))
        }
        $(#[$m])*
        #[doc = concat!("`band:", $name, "/setup`.")]
        pub fn $setup(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            crate::band::band($name).map_or(0, |b| b.run(hash(), false))
        }
    )*};
}

band_jobs! {
    "direct" => band_direct, band_direct_setup;
    "fd" => band_fd, band_fd_setup;
    #[cfg(feature = "multipass")]
    "multipass-native" => band_multipass_native, band_multipass_native_setup;
    #[cfg(feature = "multipass")]
    "multipass-16.8" => band_multipass_16_8, band_multipass_16_8_setup;
    #[cfg(feature = "multipass")]
    "multipass-8" => band_multipass_8, band_multipass_8_setup;
    "direct-1oct" => band_direct_1oct, band_direct_1oct_setup;
    "fd-1oct" => band_fd_1oct, band_fd_1oct_setup;
    #[cfg(feature = "multipass")]
    "multipass-native-1oct" => band_multipass_native_1oct, band_multipass_native_1oct_setup;
}

/// The RGBA band and the depth band of the scene renders: one band of [`scenes::BAND_ROWS`] rows
/// of the widest scene, in static RAM (no frame buffer anywhere); and the bins of the built-in
/// scene renders ([`SCENE_GROUPS`] entries of 4 bytes). With `rgb565-frames` the depth band
/// holds a band of the RGB565 frames' [`scenes::RGB565_BAND_ROWS`] rows, and the RGBA band,
/// which only a scene that blends takes, [`scenes::RGBA_BAND_ROWS`].
#[repr(C)]
struct Bands {
    rgba: [Rgba8888; RGBA_BAND_PIXELS],
    depth: [u16; DEPTH_PIXELS],
    bins: [GroupRows; SCENE_GROUPS],
}

static mut BANDS: Bands = Bands {
    rgba: [Rgba8888::TRANSPARENT; RGBA_BAND_PIXELS],
    depth: [0; DEPTH_PIXELS],
    // Any value: the renderer resets every bin it uses on each call. `new(0, 0)` is all zero bits,
    // so the whole static stays in `.bss` (`EMPTY` is not, and would put ~20 KB into `.data`).
    bins: [GroupRows::new(0, 0); SCENE_GROUPS],
};

/// Runs `f` with the band buffers and the bins.
#[allow(unsafe_code)]
fn with_bands(f: impl FnOnce(&mut [Rgba8888], &mut [u16], &mut [GroupRows]) -> u32) -> u32 {
    // SAFETY: the firmware is single-threaded, no interrupt handler touches `BANDS`, and jobs
    // run one at a time and never re-enter this function, so this is the only live reference.
    let bands = unsafe { &mut *core::ptr::addr_of_mut!(BANDS) };
    f(&mut bands.rgba, &mut bands.depth, &mut bands.bins)
}

/// Runs `f` with the memory of the RGBA band and the depth band as one RGB565 band of
/// [`ATLAS_BAND_PIXELS`] entries (the atlas draw's colour band: those jobs use neither scene
/// band, and `Bands` lays the two out one after the other), and the bins.
#[cfg(feature = "atlas")]
#[allow(unsafe_code)]
fn with_atlas_band(f: impl FnOnce(&mut [u16], &mut [GroupRows]) -> u32) -> u32 {
    let base = core::ptr::addr_of_mut!(BANDS);
    // SAFETY: as `with_bands`, this is the only live reference into `BANDS`. The first
    // ATLAS_BAND_PIXELS u16s from `BANDS`' start are exactly the RGBA band and the depth band
    // (`#[repr(C)]`, checked below), which `bins` does not overlap; `BANDS` is aligned for
    // `Rgba8888` (4 bytes), so for `u16`, and every bit pattern is a valid `u16`, `u8`
    // (`Rgba8888`'s fields) and `u16` again for the scene jobs that use the bands later.
    let (band, bins) = unsafe {
        (
            core::slice::from_raw_parts_mut(base.cast::<u16>(), ATLAS_BAND_PIXELS),
            &mut *core::ptr::addr_of_mut!((*base).bins),
        )
    };
    f(band, bins)
}

/// The `u16`s of the RGBA band and the depth band together (`with_atlas_band`).
#[cfg(feature = "atlas")]
const ATLAS_BAND_PIXELS: usize =
    (core::mem::size_of::<[Rgba8888; RGBA_BAND_PIXELS]>() + 2 * DEPTH_PIXELS) / 2;
// The two bands are one run of memory, and it holds the atlas draw's band.
#[cfg(feature = "atlas")]
const _: () = {
    assert!(
        core::mem::offset_of!(Bands, depth) == core::mem::size_of::<[Rgba8888; RGBA_BAND_PIXELS]>()
    );
    assert!(ATLAS_BAND_PIXELS >= crate::atlas::DRAW_PIXELS);
};

macro_rules! scene_jobs {
    ($($f:ident => $job:ident, $setup:ident;)*) => {$(
        #[allow(dead_code)] // the scenes too heavy for the Cortex-M counter are not registered there
        #[doc = concat!("`scene:", stringify!($f), "`.")]
        pub fn $job(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            with_bands(|b, d, _| scenes::$f(hash(), true, b, d))
        }
        #[doc = concat!("`scene:", stringify!($f), "/setup`.")]
        #[allow(dead_code)]
        pub fn $setup(_: &mut Ctx) -> u32 {
            if STUBBED {
                return 0;
            }
            with_bands(|b, d, _| scenes::$f(hash(), false, b, d))
        }
    )*};
}

scene_jobs! {
    floor => scene_floor, scene_floor_setup;
    overlay => scene_overlay, scene_overlay_setup;
}

/// `atlas:marble-bake`: the marble scene baked into a device atlas (`crate::atlas`).
#[cfg(feature = "atlas")]
pub fn atlas_bake(_: &mut Ctx) -> u32 {
    if STUBBED {
        return 0;
    }
    crate::atlas::bake_job(hash(), true)
}

/// `atlas:marble-bake/setup`.
#[cfg(feature = "atlas")]
pub fn atlas_bake_setup(_: &mut Ctx) -> u32 {
    if STUBBED {
        return 0;
    }
    crate::atlas::bake_job(hash(), false)
}

/// `atlas:marble`: the marble scene's frame drawn from its device atlas (`crate::atlas`).
#[cfg(feature = "atlas")]
pub fn atlas_draw(_: &mut Ctx) -> u32 {
    if STUBBED {
        return 0;
    }
    with_atlas_band(|band, g| crate::atlas::draw_job(hash(), true, g, band))
}

/// `atlas:marble/setup`.
#[cfg(feature = "atlas")]
pub fn atlas_draw_setup(_: &mut Ctx) -> u32 {
    if STUBBED {
        return 0;
    }
    with_atlas_band(|band, g| crate::atlas::draw_job(hash(), false, g, band))
}

/// `scene:marble-lit` (feature `lighting`): the built-in marble scene with a light, whole frame
/// ([`scenes::lit_frame_job`]).
#[cfg(feature = "lighting")]
pub fn scene_marble_lit(_: &mut Ctx) -> u32 {
    if STUBBED {
        return 0;
    }
    with_bands(|b, d, g| scenes::lit_frame_job("marble-lit", hash(), true, b, d, g))
}

/// `scene:marble-lit/setup` (feature `lighting`).
#[cfg(feature = "lighting")]
pub fn scene_marble_lit_setup(_: &mut Ctx) -> u32 {
    if STUBBED {
        return 0;
    }
    with_bands(|b, d, g| scenes::lit_frame_job("marble-lit", hash(), false, b, d, g))
}

/// `scene:<APPROXIMATE_SCENES[S]><APPROXIMATE_MODES[M] suffix>` (feature `approximate`): the
/// built-in scene's whole frame in an approximate mode ([`scenes::approximate_frame_job`]).
#[cfg(feature = "approximate")]
pub fn scene_approximate<const S: usize, const M: usize>(_: &mut Ctx) -> u32 {
    approximate_frame(S, M, true)
}

/// The `/setup` job of [`scene_approximate`] (feature `approximate`).
#[cfg(feature = "approximate")]
pub fn scene_approximate_setup<const S: usize, const M: usize>(_: &mut Ctx) -> u32 {
    approximate_frame(S, M, false)
}

/// The body of [`scene_approximate`] and [`scene_approximate_setup`].
#[cfg(feature = "approximate")]
#[inline(never)]
fn approximate_frame(s: usize, m: usize, work: bool) -> u32 {
    if STUBBED {
        return 0;
    }
    let (Some(name), Some(&(mode, _))) = (
        scenes::APPROXIMATE_SCENES.get(s),
        scenes::APPROXIMATE_MODES.get(m),
    ) else {
        return 0;
    };
    with_bands(|b, d, g| scenes::approximate_frame_job(name, mode, hash(), work, b, d, g))
}

/// `scene:<BUILTIN_SCENES[S]>@<K>`: strip `K` of a built-in scene's frame.
pub fn scene_strip<const S: usize, const K: usize>(ctx: &mut Ctx) -> u32 {
    builtin_strip(ctx, S, K, true)
}

/// `scene:<BUILTIN_SCENES[S]>@<K>/setup`.
pub fn scene_strip_setup<const S: usize, const K: usize>(ctx: &mut Ctx) -> u32 {
    builtin_strip(ctx, S, K, false)
}

/// The body of [`scene_strip`] and [`scene_strip_setup`], shared by every instance. Strip `k`
/// continues the checksum that strip `k - 1` of the same scene left in [`Ctx::frame_checksums`]
/// (and returns 0 if there is none: the jobs run out of order) and leaves its own for strip
/// `k + 1`; it never changes its own input, so its two measured runs compute the same.
#[inline(never)]
fn builtin_strip(ctx: &mut Ctx, s: usize, k: usize, work: bool) -> u32 {
    if STUBBED {
        return 0;
    }
    let Some(name) = scenes::BUILTIN_SCENES.get(s) else {
        return 0;
    };
    let above = match k {
        0 => scenes::FRAME_START,
        _ => match ctx.frame_checksums.get(k) {
            Some(&Some((scene, c))) if scene == s => c,
            _ => return 0,
        },
    };
    let c = with_bands(|b, d, g| scenes::builtin_strip(name, hash(), work, k, above, b, d, g));
    if work {
        if let Some(next) = ctx.frame_checksums.get_mut(k + 1) {
            *next = Some((s, c));
        }
    }
    c
}

/// The jobs (and `/setup` jobs) of the built-in scenes: `$s` is the index in
/// [`scenes::BUILTIN_SCENES`] of the scene `$name`; one job per strip, in order.
macro_rules! builtin_scene_jobs {
    ($($s:literal => $name:literal),* $(,)?) => {[$(
        $crate::job!(concat!("scene:", $name, "@0"), $crate::suite::scene_strip::<$s, 0>),
        $crate::job!(concat!("scene:", $name, "@0/setup"), $crate::suite::scene_strip_setup::<$s, 0>),
        $crate::job!(concat!("scene:", $name, "@1"), $crate::suite::scene_strip::<$s, 1>),
        $crate::job!(concat!("scene:", $name, "@1/setup"), $crate::suite::scene_strip_setup::<$s, 1>),
        $crate::job!(concat!("scene:", $name, "@2"), $crate::suite::scene_strip::<$s, 2>),
        $crate::job!(concat!("scene:", $name, "@2/setup"), $crate::suite::scene_strip_setup::<$s, 2>),
        $crate::job!(concat!("scene:", $name, "@3"), $crate::suite::scene_strip::<$s, 3>),
        $crate::job!(concat!("scene:", $name, "@3/setup"), $crate::suite::scene_strip_setup::<$s, 3>),
    )*]};
}
pub(crate) use builtin_scene_jobs;

// `builtin_scene_jobs!` spells the strips out.
const _: () = assert!(scenes::STRIPS == 4);
