//! Shared helpers for the cross-crate integration tests.

#![deny(missing_docs)]

pub mod child;
