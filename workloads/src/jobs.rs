//! The job list: every workload the firmware runs, in order ([`JOBS`], then [`SCENE_JOBS`]).
//!
//! The hash, span and marble benchmarks come from [`crate::bench`], the texture-unit suite from
//! [`crate::suite`]; with feature `accuracy` the list is the accuracy report's
//! ([`crate::accuracy`]) instead.

#![cfg_attr(feature = "accuracy", allow(unused_imports))]

#[allow(unused_imports)]
use crate::bench::*;
use crate::job;
use crate::job::Job;
#[allow(unused_imports)]
use crate::suite::*;
#[allow(unused_imports)]
use texcore::texture::workload;

/// With feature `accuracy`: the accuracy report's jobs (`crate::accuracy`).
#[cfg(feature = "accuracy")]
pub use crate::accuracy::JOBS;

/// Every job the firmware runs, in order.
#[cfg(not(feature = "accuracy"))]
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
    job!(per_target
        "span_1oct_direct",
        span_job::<0, { workload::CELLS_8 }, DIRECT>
    ),
    job!(per_target "span_1oct_fd", span_job::<0, { workload::CELLS_8 }, FD>),
    job!(per_target "span_1oct_auto", span_job::<0, { workload::CELLS_8 }, AUTO>),
    job!(per_target "span_1oct_fd32", span_job::<0, { workload::CELLS_8 }, FD32>),
    job!(per_target
        "span_4oct_direct",
        span_job::<1, { workload::CELLS_8 }, DIRECT>
    ),
    job!(per_target "span_4oct_fd", span_job::<1, { workload::CELLS_8 }, FD>),
    job!(per_target "span_4oct_auto", span_job::<1, { workload::CELLS_8 }, AUTO>),
    job!(per_target "span_4oct_fd32", span_job::<1, { workload::CELLS_8 }, FD32>),
    job!(per_target
        "span_zoomin4_direct",
        span_job::<1, { workload::ZOOM_IN }, DIRECT>
    ),
    job!(per_target "span_zoomin4_fd", span_job::<1, { workload::ZOOM_IN }, FD>),
    job!(per_target
        "span_zoomin4_auto",
        span_job::<1, { workload::ZOOM_IN }, AUTO>
    ),
    job!(per_target
        "span_zoomout4_direct",
        span_job::<1, { workload::ZOOM_OUT }, DIRECT>
    ),
    job!(per_target
        "span_zoomout4_fd",
        span_job::<1, { workload::ZOOM_OUT }, FD>
    ),
    job!(per_target
        "span_zoomout4_auto",
        span_job::<1, { workload::ZOOM_OUT }, AUTO>
    ),
    job!(per_target "marble_csat_direct", marble_job::<0>),
    job!(per_target "marble_csat_fd", marble_job::<1>),
    job!(per_target "marble_csat_auto", marble_job::<2>),
    // Texture-unit workloads through texcore's pixel path (see `crate::suite`).
    job!("config:hash", config_hash),
    job!("plane:wood", plane_wood),
    job!("plane:wood/setup", plane_wood_setup),
    job!("plane:marble", plane_marble),
    job!("plane:marble/setup", plane_marble_setup),
    job!("plane:clouds", plane_clouds),
    job!("plane:clouds/setup", plane_clouds_setup),
    job!("plane:water", plane_water),
    job!("plane:water/setup", plane_water_setup),
    job!("plane:fire", plane_fire),
    job!("plane:fire/setup", plane_fire_setup),
    job!("plane:planet", plane_planet),
    job!("plane:planet/setup", plane_planet_setup),
    job!("plane:planet-clouds", plane_planet_clouds),
    job!("plane:planet-clouds/setup", plane_planet_clouds_setup),
    job!("plane:zoneplate", plane_zoneplate),
    job!("plane:zoneplate/setup", plane_zoneplate_setup),
    job!("plane:mn-marble", plane_mn_marble),
    job!("plane:mn-marble/setup", plane_mn_marble_setup),
    job!("plane:mn-wood", plane_mn_wood),
    job!("plane:mn-wood/setup", plane_mn_wood_setup),
    job!("stage:noise-octave", stage_noise_octave),
    job!("stage:noise-octave/setup", stage_noise_octave_setup),
    job!("stage:noise-octave-grad", stage_noise_octave_grad),
    job!(
        "stage:noise-octave-grad/setup",
        stage_noise_octave_grad_setup
    ),
    job!("stage:quadric", stage_quadric),
    job!("stage:quadric/setup", stage_quadric_setup),
    job!("stage:color-lookup", stage_color_lookup),
    job!("stage:color-lookup/setup", stage_color_lookup_setup),
    job!("stage:csat", stage_csat),
    job!("stage:csat/setup", stage_csat_setup),
    job!("stage:raster-setup", stage_raster_setup),
    job!("stage:raster-setup/setup", stage_raster_setup_setup),
    job!("stage:perspective-every16", stage_perspective_every16),
    job!(
        "stage:perspective-every16/setup",
        stage_perspective_every16_setup
    ),
    job!("stage:perspective-affine", stage_perspective_affine),
    job!(
        "stage:perspective-affine/setup",
        stage_perspective_affine_setup
    ),
    job!("peers:value-1oct", peers_value_1oct),
    job!("peers:value-1oct/setup", peers_value_1oct_setup),
    job!("peers:value-4oct", peers_value_4oct),
    job!("peers:value-4oct/setup", peers_value_4oct_setup),
    job!("peers:value-4oct-grad", peers_value_4oct_grad),
    job!("peers:value-4oct-grad/setup", peers_value_4oct_grad_setup),
    job!("peers:value-4oct-span16", peers_value_4oct_span16),
    job!(
        "peers:value-4oct-span16/setup",
        peers_value_4oct_span16_setup
    ),
    job!("peers:value-1oct-direct", peers_value_1oct_direct),
    job!(
        "peers:value-1oct-direct/setup",
        peers_value_1oct_direct_setup
    ),
    job!("peers:smooth-1oct", peers_smooth_1oct),
    job!("peers:smooth-1oct/setup", peers_smooth_1oct_setup),
    job!("peers:perlin-1oct", peers_perlin_1oct),
    job!("peers:perlin-1oct/setup", peers_perlin_1oct_setup),
    job!("band:direct", band_direct),
    job!("band:direct/setup", band_direct_setup),
    job!("band:fd", band_fd),
    job!("band:fd/setup", band_fd_setup),
    #[cfg(feature = "multipass")]
    job!("band:multipass-native", band_multipass_native),
    #[cfg(feature = "multipass")]
    job!("band:multipass-native/setup", band_multipass_native_setup),
    #[cfg(feature = "multipass")]
    job!("band:multipass-16.8", band_multipass_16_8),
    #[cfg(feature = "multipass")]
    job!("band:multipass-16.8/setup", band_multipass_16_8_setup),
    #[cfg(feature = "multipass")]
    job!("band:multipass-8", band_multipass_8),
    #[cfg(feature = "multipass")]
    job!("band:multipass-8/setup", band_multipass_8_setup),
    job!("band:direct-1oct", band_direct_1oct),
    job!("band:direct-1oct/setup", band_direct_1oct_setup),
    job!("band:fd-1oct", band_fd_1oct),
    job!("band:fd-1oct/setup", band_fd_1oct_setup),
    #[cfg(feature = "multipass")]
    job!("band:multipass-native-1oct", band_multipass_native_1oct),
    #[cfg(feature = "multipass")]
    job!(
        "band:multipass-native-1oct/setup",
        band_multipass_native_1oct_setup
    ),
    job!("scene:floor", scene_floor),
    job!("scene:floor/setup", scene_floor_setup),
    job!("scene:overlay", scene_overlay),
    job!("scene:overlay/setup", scene_overlay_setup),
    #[cfg(feature = "atlas")]
    job!("atlas:marble-bake", atlas_bake),
    #[cfg(feature = "atlas")]
    job!("atlas:marble-bake/setup", atlas_bake_setup),
    #[cfg(feature = "atlas")]
    job!("atlas:marble", atlas_draw),
    #[cfg(feature = "atlas")]
    job!("atlas:marble/setup", atlas_draw_setup),
    #[cfg(feature = "lighting")]
    job!("scene:marble-lit", scene_marble_lit),
    #[cfg(feature = "lighting")]
    job!("scene:marble-lit/setup", scene_marble_lit_setup),
    #[cfg(feature = "panic-never-canary")]
    Job {
        name: "panic_never_canary",
        run: panic_never_canary,
    },
];

/// The built-in scene jobs (see `crate::suite::scene_strip`), run after [`JOBS`]: the strips of
/// each scene's frame, top to bottom, each with its `/setup` job.
#[cfg(not(feature = "accuracy"))]
pub static SCENE_JOBS: &[Job] = &builtin_scene_jobs![
    0 => "wood",
    1 => "marble",
    2 => "seascape",
    3 => "fire",
    4 => "planet",
    5 => "moonrise",
    6 => "zoneplate",
    7 => "torus",
];

/// With feature `accuracy`: none (the accuracy report's jobs are all in [`JOBS`]).
#[cfg(feature = "accuracy")]
pub static SCENE_JOBS: &[Job] = &[];

/// With feature `approximate`: the built-in scenes in the approximate modes of `texsim render
/// --aa ramp [--widths differences]` (`crate::suite::scene_approximate`), each a whole frame with
/// its `/setup` job, after the hash the device shades with; the firmware's `approximate-scenes`
/// build runs them instead of [`JOBS`] (they do not fit its flash beside the whole suite).
#[cfg(feature = "approximate")]
pub static APPROXIMATE_JOBS: &[Job] = &[
    job!("config:hash", config_hash),
    job!("scene:fire~ramp", scene_approximate::<0, 0>),
    job!("scene:fire~ramp/setup", scene_approximate_setup::<0, 0>),
    job!("scene:fire~ramp-diff", scene_approximate::<0, 1>),
    job!(
        "scene:fire~ramp-diff/setup",
        scene_approximate_setup::<0, 1>
    ),
    job!("scene:marble~ramp", scene_approximate::<1, 0>),
    job!("scene:marble~ramp/setup", scene_approximate_setup::<1, 0>),
    job!("scene:marble~ramp-diff", scene_approximate::<1, 1>),
    job!(
        "scene:marble~ramp-diff/setup",
        scene_approximate_setup::<1, 1>
    ),
];
