//! The independent f64 reference of the texcore texture model (`docs/model.md`, ideal math).
//!
//! Written from the contract and the papers, not from texcore's fixed-point code; it shares only
//! the lattice hashes and corner values of [`texcore::hash`], so both sides see the same lattice.
//! Everything here is exact real arithmetic in f64: lattice points `u = T s` without rounding, exact
//! fades and interpolation, the exact quadric and the exact box filter. texcore's deviations from
//! these numbers are what the accuracy reports measure.
//!
//! - [`noise`]: value, gradient and mNoise bases with analytic gradients;
//! - [`quadric`]: `q(s)` and `2 Q [s; 1]`;
//! - [`model`]: [`RefModel`], `f`, `grad f`, the filter width and the Nyquist rule;
//! - [`table`]: [`RefTable`], nearest/linear look-up, the exact box filter and the MIP look-up;
//! - [`perturbed`]: Miné & Neyret's domain-perturbed marble and wood;
//! - [`plane`]: the [`Plane`] of solid coordinates sampled by `texsim check`, f64 renders.

pub mod model;
pub mod noise;
pub mod perturbed;
pub mod plane;
pub mod quadric;
pub mod table;

pub use model::{Footprint, Norm, Nyquist, RefModel, RefTerm};
pub use noise::{Basis, Fade, NoiseSample, MNOISE_SCALE};
pub use plane::{Plane, RefImage};
pub use table::{Filter, Lookup, RefTable, Rgba, Wrap};
