#!/usr/bin/env bash
# panic-never link check for the device firmware.
#
# Builds the firmware in release for both device targets with feature `panic-never`, whose panic
# handler calls an undefined symbol (texcore_firmware_panic_is_reachable): the link succeeds only
# if no panicking path (bounds check, overflow check, unwrap, assert, ...) survives optimisation
# anywhere in the linked code: the harness, the logger and every job, i.e. the texcore code
# under test. The default features link the texture-unit suite (workloads/src/suite.rs), so the
# check covers texcore's pixel path: presets and colour tables, the span evaluator with every
# noise basis and evaluation mode, the colour stage with csat and MIP, the perturbed materials,
# the rasterizer and the banded renderer with depth and blending, the atlas bake and draw, and
# the multipass band evaluator (the `band:multipass-*` jobs). Then, as a control, builds with
# `panic-never-canary` (a job with a reachable bounds-check panic) and requires that link to FAIL
# on the undefined symbol, so a passing check is known to mean something.
#
# Exit 0 when all is as required, 1 otherwise. Uses its own target dir (target/panic-never) so
# the normal release artefacts are untouched.
set -uo pipefail
cd "$(dirname "$0")/.."

targets=(thumbv7em-none-eabihf riscv32imc-unknown-none-elf)
target_dir="${CARGO_TARGET_DIR:-target}/panic-never"
# The firmware's default features.
checked="perm-hash,full,atlas,multipass"
symbol=texcore_firmware_panic_is_reachable
status=0

# Lists the source lines (texcore and firmware) of every branch to a panic function in the
# normal release build for the Cortex-M4F (built if needed), via llvm-objdump's line annotations
# (Thumb branches name their target symbol; rv32imc calls go through auipc/jalr and do not, and
# the texcore source is the same on both targets).
where_panics() {
    local objdump
    objdump=$(command -v llvm-objdump || command -v rust-objdump || true)
    if [ -z "$objdump" ]; then
        echo "    (install llvm-objdump to list them)"
        return
    fi
    local t=thumbv7em-none-eabihf
    cargo build -q --release -p firmware --target "$t" >/dev/null 2>&1 || return
    "$objdump" -d -l --no-show-raw-insn -C "${CARGO_TARGET_DIR:-target}/$t/release/firmware" |
        awk '/^; \// { src = ($2 ~ /(texcore|firmware)\/src\//) ? $2 : src }
             /(core::panicking::|slice_index_fail|panic_bounds_check|len_mismatch_fail)/ && /[ \t](bl|blx|b|b\.w|beq|bne|bhs|blo|bhi|bls|jal|j|call|tail)[ \t]/ && src != "" { print "    " src }' |
        sort -u
}

# texcore's pixel path (the texture-unit suite: presets, colour tables, span evaluator, colour
# stage, perturbed materials, rasterizer and banded renderer) is linked with feature
# `panic-never-pixel-path`, and must link too (strict, the default): a reachable panic there
# fails the script, with the listing this prints. PANIC_NEVER_PIXEL_PATH=report only reports it
# (for local bisecting); the base check (harness, logger, hash jobs; the suite stubbed out) must
# pass either way.
for t in "${targets[@]}"; do
    log=$(mktemp)
    if cargo build --release -p firmware --target "$t" --no-default-features \
        --features "$checked",panic-never,panic-never-pixel-path \
        --target-dir "$target_dir" >"$log" 2>&1; then
        echo "panic-never: $t: pixel path OK (no reachable panic in texcore's pixel path)"
    elif grep -q "undefined symbol: $symbol" "$log"; then
        echo "panic-never: $t: pixel path: a panicking path is reachable in texcore's pixel path;" \
            "the branches (source lines of calls to core::panicking::* / slice_index_fail):"
        where_panics
        if [ "${PANIC_NEVER_PIXEL_PATH:-strict}" != report ]; then
            status=1
        fi
    else
        echo "panic-never: $t: pixel path: FAILED: the build broke:" >&2
        tail -20 "$log" >&2
        status=1
    fi
    # The same at opt-level "z" (profile release-size), where texcore compiles its size-lean
    # code shape (cfg(texcore_lean)): the code the size report measures.
    if cargo build --profile release-size -p firmware --target "$t" --no-default-features \
        --features "$checked",panic-never,panic-never-pixel-path --target-dir "$target_dir" >"$log" 2>&1; then
        echo "panic-never: $t: pixel path OK at opt-level z (size-lean shape)"
    else
        echo "panic-never: $t: pixel path at opt-level z (release-size): FAILED:" >&2
        grep -E "error|$symbol|>>>" "$log" >&2 || tail -20 "$log" >&2
        status=1
    fi
    if cargo build --release -p firmware --target "$t" --no-default-features \
        --features "$checked",panic-never \
        --target-dir "$target_dir" >"$log" 2>&1; then
        echo "panic-never: $t: OK (no reachable panic)"
    else
        echo "panic-never: $t: FAILED: a panicking path is reachable, or the build broke:" >&2
        grep -E "error|$symbol|>>>" "$log" >&2 || cat "$log" >&2
        echo "  the linker only names the panic handler; the panicking branches (source lines of" >&2
        echo "  calls to core::panicking::* / slice_index_fail in the normal release build):" >&2
        where_panics >&2
        status=1
    fi
    if cargo build --release -p firmware --target "$t" --no-default-features \
        --features "$checked",panic-never,panic-never-canary \
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
