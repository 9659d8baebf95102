#!/usr/bin/env bash
# Cargo runner for the device targets (.cargo/config.toml): runs a firmware ELF under QEMU.
#
#   firmware/qemu-run.sh path/to/firmware.elf
#
# - Cortex-M4F ELF: qemu-system-arm -machine mps2-an386 -cpu cortex-m4
# - RISC-V ELF:     qemu-system-riscv32 -machine virt -bios none
# Both with -icount shift=0,align=off,sleep=off (one instruction = 1 ns of virtual time: exact and
# reproducible counts), semihosting on a stdio chardev (the defmt stream), no display, no serial.
#
# The defmt stream is decoded with `defmt-print -e ELF` when that is on PATH
# (`cargo install defmt-print`), otherwise with texsim's own decoder (`texsim defmt-decode ELF`,
# built on demand; the raw stream is also saved next to the ELF). TEXFW_RAW=1 only saves the raw
# stream (decode it later with either tool, or through host_sim::device).
# Exits with the firmware's exit code (0 pass, 1 check failed, 101 panic), 124 on timeout
# (TEXFW_TIMEOUT seconds, default 300), 127 if QEMU is missing.
set -uo pipefail

elf="${1:?usage: qemu-run.sh FIRMWARE.elf}"
shift

# e_machine (ELF header offset 18, little endian): 0x28 ARM, 0xf3 RISC-V.
machine=$(od -An -t x2 -j 18 -N 2 "$elf" | tr -d ' ')
case "$machine" in
0028)
    qemu=qemu-system-arm
    board=(-machine mps2-an386 -cpu cortex-m4)
    ;;
00f3)
    qemu=qemu-system-riscv32
    board=(-machine virt -bios none)
    ;;
*)
    echo "qemu-run.sh: $elf is not an ARM or RISC-V ELF (e_machine=$machine)" >&2
    exit 2
    ;;
esac

if ! command -v "$qemu" >/dev/null 2>&1; then
    echo "qemu-run.sh: $qemu not found; install QEMU (.ci/install-qemu.sh)" >&2
    exit 127
fi

cmd=("$qemu" "${board[@]}"
    -icount shift=0,align=off,sleep=off
    -display none -monitor none -serial none
    -chardev stdio,id=texfw-semihosting
    -semihosting-config enable=on,target=native,chardev=texfw-semihosting
    -kernel "$elf")
to=(timeout --foreground "${TEXFW_TIMEOUT:-300}")
command -v timeout >/dev/null 2>&1 || to=()

root="$(cd "$(dirname "$0")/.." && pwd)"
if command -v defmt-print >/dev/null 2>&1; then
    "${to[@]}" "${cmd[@]}" </dev/null | defmt-print -e "$elf"
    status=${PIPESTATUS[0]}
elif [ -z "${TEXFW_RAW:-}" ] && cargo build -q --manifest-path "$root/Cargo.toml" -p host-sim --bin texsim 2>/dev/null; then
    # texsim's own decoder (defmt-decoder, the same as host_sim::device); the raw stream is
    # kept next to the ELF as well.
    texsim="$(cargo metadata -q --format-version 1 --no-deps --manifest-path "$root/Cargo.toml" |
        sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')/debug/texsim"
    raw="$elf.defmt"
    "${to[@]}" "${cmd[@]}" </dev/null | tee "$raw" | "$texsim" defmt-decode "$elf"
    status=${PIPESTATUS[0]}
else
    raw="$elf.defmt"
    "${to[@]}" "${cmd[@]}" </dev/null >"$raw"
    status=$?
    echo "qemu-run.sh: raw defmt stream ($(wc -c <"$raw") bytes) saved to $raw" >&2
    echo "qemu-run.sh: decode with 'cargo run -p host-sim --bin texsim -- defmt-decode $elf < $raw'" >&2
    echo "qemu-run.sh: (or 'defmt-print -e $elf < $raw'), or run the checks:" >&2
    echo "qemu-run.sh: cargo test -p texcore-tests --test firmware_qemu" >&2
fi
case $status in
0) echo "qemu-run.sh: firmware PASSED (exit 0)" >&2 ;;
124) echo "qemu-run.sh: timed out after ${TEXFW_TIMEOUT:-300}s" >&2 ;;
*) echo "qemu-run.sh: firmware FAILED (exit $status)" >&2 ;;
esac
exit "$status"
