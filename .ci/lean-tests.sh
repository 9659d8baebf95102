#!/usr/bin/env bash
# texcore's unit, integration and doc tests in its size-lean code shape (`cfg(texcore_lean)`,
# what the device builds at opt-level "s"/"z" compile: see texcore/build.rs and the crate docs,
# "Code size"), with every feature and with none. The shape's cfg-exclusive halves (for example
# `AreaDivisor` in texcore/src/raster/setup.rs) are compiled by no other test build. A separate
# target directory keeps the main build cache valid.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR=target/lean
export RUSTFLAGS="--cfg texcore_lean"
export RUSTDOCFLAGS="--cfg texcore_lean"
cargo test -q -p texcore --features fused
cargo test -q -p texcore --no-default-features --lib
