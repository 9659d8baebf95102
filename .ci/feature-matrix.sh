#!/usr/bin/env bash
# Compiles texcore with each feature alone, with none and with all, for the host and both device
# targets: features are additive, so every combination here must compile without warnings.
# `cargo check` (type checking and const evaluation, no code generation): for a library that is
# every error a build would give, at a fraction of the time. The linked device builds are the
# firmware's (tests, reports, .ci/firmware-matrix.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
features=(perm-hash fd gradients smooth-fade gradient-noise mnoise csat mip ramp differences perturb turbulence-fd fd32 reanchor fused multipass atlas defmt embedded-graphics lighting)
for target in x86_64-unknown-linux-gnu thumbv7em-none-eabihf riscv32imc-unknown-none-elf; do
  echo "-- $target: no features"
  RUSTFLAGS="-D warnings" cargo check -q -p texcore --no-default-features --target "$target"
  for f in "${features[@]}"; do
    echo "-- $target: $f"
    RUSTFLAGS="-D warnings" cargo check -q -p texcore --no-default-features --features "$f" --target "$target"
  done
  # The general span loop's strategies depend on pairs of features (`reanchor` needs a basis that is
  # not a cubic to take effect).
  for f in smooth-fade,reanchor gradient-noise,fd32 mnoise,turbulence-fd; do
    echo "-- $target: $f"
    RUSTFLAGS="-D warnings" cargo check -q -p texcore --no-default-features --features "$f" --target "$target"
  done
  echo "-- $target: full,atlas,defmt,embedded-graphics"
  RUSTFLAGS="-D warnings" cargo check -q -p texcore --features "full,atlas,defmt,embedded-graphics" --target "$target"
  # Lighting with the loaded meshes (their face normals) and defmt.
  echo "-- $target: lighting,atlas,defmt"
  RUSTFLAGS="-D warnings" cargo check -q -p texcore --no-default-features --features "lighting,atlas,defmt" --target "$target"
  echo "-- $target: full,multipass,defmt"
  RUSTFLAGS="-D warnings" cargo check -q -p texcore --features "full,multipass,defmt" --target "$target"
  # `fused` with the fades (its quintic rows) and with the lean code shape's neighbours.
  echo "-- $target: fused,smooth-fade,defmt"
  RUSTFLAGS="-D warnings" cargo check -q -p texcore --no-default-features --features "fused,smooth-fade,defmt" --target "$target"
  # The ramp beside every other filter and with perturbed materials (its per-sample path).
  echo "-- $target: full,ramp,defmt"
  RUSTFLAGS="-D warnings" cargo check -q -p texcore --features "full,ramp,defmt" --target "$target"
  # The renderer's differences with the ramp and every filter (the `approximate-scenes` firmware).
  echo "-- $target: full,ramp,differences,defmt"
  RUSTFLAGS="-D warnings" cargo check -q -p texcore --features "full,ramp,differences,defmt" --target "$target"
  # The shapes' and scenes' drawables with the widths from differences.
  echo "-- $target: embedded-graphics,differences"
  RUSTFLAGS="-D warnings" cargo check -q -p texcore --no-default-features --features "embedded-graphics,differences" --target "$target"
done

# The workloads crate on the host without its defaults and with each of its features alone (the
# accuracy features are firmware-only: a device build picks one of their parts).
for f in "" perm-hash atlas lighting multipass approximate rgb565-frames peers; do
  echo "-- workloads: --no-default-features ${f:+--features $f}"
  RUSTFLAGS="-D warnings" cargo check -q -p workloads --no-default-features ${f:+--features "$f"}
done
