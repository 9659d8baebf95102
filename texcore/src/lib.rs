//! # texcore: a fixed-point procedural solid-texture unit
//!
//! `texcore` evaluates the parameterized solid texture model of Hart et al. (1999),
//!
//! ```text
//! p(s) = c(f(s)),    f(s) = q(s) + sum_k a_k n_k(T_k s)
//! ```
//!
//! (a quadric plus a fixed number of noise terms, looked up in a colour table), antialiased by
//! box-filtering the colour table with a width taken from the analytic gradient of `f`.
//!
//! Guarantees:
//! - `no_std`, no allocation, and no floating point anywhere in the pixel path: the host and the
//!   device produce the same bits. The exact definition of every number is `docs/model.md`.
//! - Capacities (noise terms, colour-table entries) are const generics, checked once at
//!   construction; evaluation never panics.
//!
//! Raw kernels (hashes, noise bases, fades) live apart from the configured wrappers
//! ([`model::TextureModel`], [`table::ColorTable`]).
//!
//! ## Code size
//!
//! texcore follows the optimisation goal of the build. At `opt-level = "s"` or `"z"` (for
//! example a `[profile.release] opt-level = "z"` in the firmware's workspace, or a
//! `[profile.release.package.texcore]` override) it compiles its **size-lean** shape: small
//! helpers are left to the compiler instead of forced inline, and the span evaluator's merged
//! forward-difference loop is one loop that tests the span's shape per pixel instead of eight
//! specialisations and the component passes over long cells; when the general loop can forward
//! difference (feature `turbulence-fd`), the merged loop is left out altogether and the general
//! loop steps every term (one state per term instead of one merged state: about 2.7 KB less code,
//! about twice the instructions on long forward-differenced spans, a few percent on a mesh
//! scene; per-pixel trilinear terms then interpolate in lerp form, without the merged loop's
//! per-cell monomial kernel). At every other level it compiles the fast shape. Both shapes give bit-identical samples (unit tests compare them in every
//! build); the lean one is what `texsim report size` measures, and its price in instructions is in
//! `docs/performance.md`. The build script sets `cfg(texcore_lean)` from cargo's `OPT_LEVEL`;
//! passing `--cfg texcore_lean` in `RUSTFLAGS` selects it at any level.
#![cfg_attr(not(test), no_std)]
#![cfg_attr(docsrs, feature(doc_cfg))]
#![deny(missing_docs, unsafe_code)]

#[cfg(feature = "atlas")]
pub mod atlas;
pub mod bandlimit;
pub mod color;
#[cfg(feature = "embedded-graphics")]
#[cfg_attr(docsrs, doc(cfg(feature = "embedded-graphics")))]
pub mod draw;
pub mod filter;
pub mod format;
#[cfg(feature = "lighting")]
pub mod gouraud;
pub mod hash;
#[cfg(feature = "lighting")]
pub mod light;
#[cfg(feature = "perturb")]
#[cfg_attr(docsrs, doc(cfg(feature = "perturb")))]
pub mod material;
pub mod model;
#[cfg(feature = "multipass")]
pub mod multipass;
pub mod names;
pub mod noise;
#[cfg(feature = "atlas")]
pub mod packed_mesh;
pub mod prelude;
pub mod presets;
pub mod quadric;
pub mod raster;
pub mod ready;
pub mod render;
pub mod scene;
pub mod sink;
pub mod span;
pub mod table;
#[cfg(test)]
mod test_rng;
pub mod texture;
pub mod transform;
mod wide;

pub use format::*;

// The crate README's and the project README's Rust examples compile and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct CrateReadme;
