#!/usr/bin/env bash
# Instruction profile of one firmware job under QEMU, per function.
#
#   firmware/profile.sh TARGET JOB     e.g. firmware/profile.sh thumbv7em-none-eabihf marble_csat_fd
#
# Builds the firmware with only the jobs whose name contains JOB (TEXFW_ONLY, read at build
# time by src/harness.rs), runs it under QEMU with the translation-block trace
# (-d in_asm,exec,nochain: every executed block is logged), and sums block size x executions per
# function symbol. The counts include the calibration and both measurements of the job; divide by
# the pixels of two runs for per-pixel figures. Needs python3 and llvm-nm (or rust-nm).
set -euo pipefail
target="${1:?usage: profile.sh TARGET JOB}"
job="${2:?usage: profile.sh TARGET JOB}"
cd "$(dirname "$0")/.."
TEXFW_ONLY="$job" cargo build --release -p firmware --target "$target"
elf="target/$target/release/firmware"
case "$target" in
thumb*) qemu=(qemu-system-arm -machine mps2-an386 -cpu cortex-m4) ;;
riscv*) qemu=(qemu-system-riscv32 -machine virt -bios none) ;;
*) echo "profile.sh: unknown target $target" >&2; exit 2 ;;
esac
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
"${qemu[@]}" -icount shift=0,align=off,sleep=off -display none -monitor none -serial none \
    -chardev null,id=s -semihosting-config enable=on,target=native,chardev=s \
    -kernel "$elf" -d in_asm,exec,nochain -D "$log" </dev/null >/dev/null || true
nm=$(command -v llvm-nm || command -v rust-nm)
python3 - "$log" "$elf" "$nm" <<'PY'
import bisect, collections, re, subprocess, sys
log, elf, nm = sys.argv[1:4]
syms = []
for line in subprocess.run([nm, "-C", "-n", elf], capture_output=True, text=True).stdout.splitlines():
    p = line.split(None, 2)
    if len(p) == 3 and p[1] in "tTwW":
        syms.append((int(p[0], 16) & ~1, p[2]))
syms.sort()
addrs = [a for a, _ in syms]
def sym(a):
    i = bisect.bisect_right(addrs, a) - 1
    return syms[i][1] if i >= 0 else "?"
size, runs, start = {}, collections.Counter(), None
ins = re.compile(r"^0x([0-9a-f]+):")
exe = re.compile(r"^Trace \d+: 0x[0-9a-f]+ \[[0-9a-f]+/([0-9a-f]+)/")
with open(log, errors="replace") as f:
    for line in f:
        if line.startswith("IN:"):
            start = None
            continue
        m = ins.match(line)
        if m:
            a = int(m.group(1), 16)
            start = a if start is None else start
            size[start] = size.get(start, 0) + 1
            continue
        m = exe.match(line)
        if m:
            runs[int(m.group(1), 16)] += 1
per = collections.Counter()
for a, n in runs.items():
    per[sym(a)] += size.get(a, 0) * n
total = sum(per.values())
print(f"{total} instructions")
for name, n in per.most_common(30):
    print(f"{n:12d} {100 * n / total:6.2f}%  {name[:120]}")
PY
