#!/usr/bin/env bash
# Type-checks the firmware crate for both device targets in every feature set a report builds:
# - the size report's `texcore-probe` sets (`texsim report size`, `FEATURE_SETS` in
#   host-sim/src/report/size.rs), each in its own profile: `release-size` compiles texcore's
#   size-lean code shape (`cfg(texcore_lean)`, from opt-level "z"), `release` its fast shape;
# - the job-suite firmware with default features and with `--no-default-features --features full`
#   (the Cortex-M build without the permutation hash);
# - the accuracy report's four firmware parts (`texsim report accuracy`).
# `cargo check` (no code generation, no link) with warnings denied: one invocation per
# combination. The linked builds are made by the tests (`firmware_qemu`) and by the reports.
# tests/tests/ci_matrix.rs checks that the sets below are the size report's.
set -euo pipefail
cd "$(dirname "$0")/.."
export RUSTFLAGS="-D warnings"

# name|features|profile, as in FEATURE_SETS (features comma-separated, empty for none).
probe_sets=(
  "minimal||release-size"
  "fd|fd|release-size"
  "csat|csat|release-size"
  "ramp|ramp|release-size"
  "ramp-diff|ramp,differences|release-size"
  "mip|mip|release-size"
  "bases|smooth-fade,gradient-noise,mnoise,perm-hash|release-size"
  "eval|turbulence-fd,fd32,reanchor|release-size"
  "perturb|perturb|release-size"
  "render|render|release-size"
  "render-diff|render,ramp,render-differences|release-size"
  "multipass|fd,multipass|release-size"
  "atlas|atlas|release-size"
  "lighting|render,lighting|release-size"
  "full|full,perm-hash|release-size"
  "full-fast|full,perm-hash|release"
)

for target in thumbv7em-none-eabihf riscv32imc-unknown-none-elf; do
  for set in "${probe_sets[@]}"; do
    IFS='|' read -r name features profile <<<"$set"
    echo "-- $target: texcore-probe $name ($profile)"
    cargo check -q -p firmware --bin texcore-probe --target "$target" --profile "$profile" \
      --no-default-features ${features:+--features "$features"}
  done
  echo "-- $target: firmware (default features)"
  cargo check -q -p firmware --bins --target "$target" --release
  echo "-- $target: firmware --no-default-features --features full"
  cargo check -q -p firmware --bins --target "$target" --release --no-default-features --features full
  echo "-- $target: firmware approximate-scenes"
  cargo check -q -p firmware --bins --target "$target" --release --features approximate-scenes
  for part in accuracy-planes accuracy-small-tables accuracy-large-tables accuracy-scenes; do
    echo "-- $target: firmware $part"
    cargo check -q -p firmware --bins --target "$target" --release --features "$part"
  done
done
