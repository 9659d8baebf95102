//! Host simulator for texcore: the f64 reference model, scene loading, rendering and reports.
#![deny(missing_docs, unsafe_code)]

pub mod accuracy;
pub mod bridge;
pub mod cli;
pub mod device;
pub mod metrics;
pub mod output;
pub mod reference;
pub mod report;
pub mod scenefile;
pub mod scenes;
pub mod truth;
pub mod unit;
