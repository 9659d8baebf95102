//! Host simulator for texcore: the f64 reference model, scene loading, rendering and reports.
#![deny(missing_docs, unsafe_code)]

pub mod accuracy;
pub mod atlas;
pub mod bridge;
pub mod cli;
pub mod defmt_log;
pub mod device;
pub mod flags;
pub mod interrupt;
pub mod mesh;
pub mod metrics;
pub mod multipass;
pub mod output;
pub mod reference;
pub mod report;
pub mod scenefile;
pub mod scenes;
pub mod stream;
pub mod truth;
pub mod unit;
