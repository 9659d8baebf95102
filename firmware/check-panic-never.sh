#!/usr/bin/env bash
# panic-never link check for the device firmware.
#
# Builds the firmware in release for both device targets with feature `panic-never`, whose panic
# handler calls an undefined symbol (texcore_firmware_panic_is_reachable): the link succeeds only
# if no panicking path (bounds check, overflow check, unwrap, assert, ...) survives optimisation
# anywhere in the linked code: the harness, the logger and every job, i.e. the texcore code
# under test. Then, as a control, builds with `panic-never-canary` (a job with a reachable
# bounds-check panic) and requires that link to FAIL on the undefined symbol, so a passing check
# is known to mean something.
#
# Exit 0 when all is as required, 1 otherwise. Uses its own target dir (target/panic-never) so
# the normal release artefacts are untouched.
set -uo pipefail
cd "$(dirname "$0")/.."

targets=(thumbv7em-none-eabihf riscv32imc-unknown-none-elf)
target_dir="${CARGO_TARGET_DIR:-target}/panic-never"
symbol=texcore_firmware_panic_is_reachable
status=0

for t in "${targets[@]}"; do
    log=$(mktemp)
    if cargo build --release -p firmware --target "$t" --features panic-never \
        --target-dir "$target_dir" >"$log" 2>&1; then
        echo "panic-never: $t: OK (no reachable panic)"
    else
        echo "panic-never: $t: FAILED: a panicking path is reachable, or the build broke:" >&2
        grep -E "error|$symbol|>>>" "$log" >&2 || cat "$log" >&2
        echo "  (disassemble the normal release build and look for callers of core::panicking::*" >&2
        echo "   to find the panicking branch)" >&2
        status=1
    fi
    if cargo build --release -p firmware --target "$t" --features panic-never,panic-never-canary \
        --target-dir "$target_dir" >"$log" 2>&1; then
        echo "panic-never: $t: FAILED: the canary (a reachable panic) linked; the check does not work" >&2
        status=1
    elif grep -q "undefined symbol: $symbol" "$log"; then
        echo "panic-never: $t: canary correctly rejected"
    else
        echo "panic-never: $t: FAILED: canary build failed for another reason:" >&2
        tail -20 "$log" >&2
        status=1
    fi
    rm -f "$log"
done
exit $status
