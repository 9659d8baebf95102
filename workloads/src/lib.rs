//! texcore's device workloads, defined once: the firmware runs them under exact instruction
//! counting (`firmware`), the host simulator uses the same code to know the job list, the work
//! units of every job and to recompute their checksums (`host_sim::report`, `host_sim::accuracy`,
//! `tests/tests/firmware_qemu.rs`).
//!
//! - [`mod@job`]: a job (`fn(&mut Ctx) -> u32` returning a checksum), its context, the checksum fold
//!   and the one [`job!`] macro that names a job;
//! - [`jobs`]: the list the firmware runs, in order;
//! - [`mod@bench`]: lattice hash, span evaluator and marble benchmarks;
//! - [`suite`]: the texture-unit suite's job wrappers around [`planes`], [`stages`], [`scenes`],
//!   [`band`];
//! - `atlas` (feature `atlas`): a built-in scene baked into a texture atlas and drawn from it;
//! - [`accuracy`]: the accuracy report's configurations and device jobs;
//! - `peers` and `peer_jobs` (feature `peers`): texcore's modes next to `fastnoise-lite` on the
//!   peers' plane (`texsim report peers`), the kernels and the peers firmware's job lists.
//!
//! Uses nothing but `texcore` and `core` (and, with feature `peers`, `fastnoise-lite`): no allocation, no panics on the job paths (the
//! firmware's `panic-never` build links every job with a panic handler that cannot link).
#![no_std]
#![deny(unsafe_code)]
#![deny(missing_docs)]

// (Its rows use the permutation hash: the firmware compiles it only for the accuracy builds.)
#[cfg(any(feature = "accuracy", feature = "full"))]
#[allow(missing_docs)]
pub mod accuracy;
#[cfg(feature = "atlas")]
pub mod atlas;
pub mod band;
pub mod bench;
pub mod job;
pub mod jobs;
#[cfg(feature = "peers")]
pub mod peer_jobs;
#[cfg(feature = "peers")]
pub mod peers;
pub mod peers_workload;
pub mod planes;
pub mod scenes;
pub mod stages;
pub mod suite;
