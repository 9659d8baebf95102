#!/usr/bin/env bash
# Coverage-guided fuzzing (cargo-fuzz, libFuzzer) of the targets in fuzz/: each target runs for
# SECONDS (default 60) from its committed seed corpus (fuzz/corpus/<target>/, read-only here);
# new inputs go to fuzz/target/corpus/<target>/ (kept between runs, so a longer run continues).
# Targets run side by side, one a core (FUZZ_JOBS overrides). A crash fails the script
# (non-zero exit, after the running targets end) and leaves the input in fuzz/artifacts/<target>/.
#
#   bash .ci/fuzz.sh            # CI: about a minute per target
#   bash .ci/fuzz.sh 600        # a longer run: ten minutes per target
#   bash .ci/fuzz.sh 60 raster  # one target
#
# Needs a nightly toolchain and cargo-fuzz (installed here when missing; the rest of the build
# stays on the stable toolchain of rust-toolchain.toml). Debug assertions on (arithmetic overflow
# panics, as in `cargo test`). No sanitizer: texcore and texsim contain
# no unsafe code, so panics, wrong results (the targets' assertions) and resource limits are
# what is looked for; libFuzzer's -rss_limit_mb and -timeout bound memory and time per input.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(scene_file span_eval raster color_filter mesh)
fi

rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal
command -v cargo-fuzz >/dev/null || cargo +stable install cargo-fuzz --locked

# Sizes past these cover every field the targets read (the scene loader's own limits apply to
# larger files, but fuzzing them only slows the search).
declare -A max_len=([scene_file]=8192 [span_eval]=512 [raster]=256 [color_filter]=4096 [mesh]=8192)

cd fuzz
echo "-- build (nightly, cargo-fuzz)"
cargo +nightly fuzz build --sanitizer none --release --debug-assertions
# One target a core at a time (FUZZ_JOBS, default: the machine's cores); each target's log is
# printed when it ends.
run_target() {
  local t=$1 status=0
  local work="target/corpus/$t"
  mkdir -p "$work"
  cargo +nightly fuzz run --sanitizer none --release --debug-assertions "$t" "$work" "corpus/$t" -- \
    -max_total_time="$seconds" -max_len="${max_len[$t]:-4096}" -rss_limit_mb=2048 \
    -timeout=20 -print_final_stats=1 >"target/fuzz-$t.log" 2>&1 || status=$?
  # The run's figures: executions, coverage (libFuzzer's `cov:` edges, `ft:` features), corpus.
  {
    echo "-- fuzz $t for ${seconds}s"
    grep -E '^#[0-9]+ +(INITED|DONE)|^stat::(number_of_executed_units|peak_rss_mb)' \
      "target/fuzz-$t.log" || true
    if [ "$status" -ne 0 ]; then
      echo "fuzz target $t failed (exit $status); log: fuzz/target/fuzz-$t.log"
      tail -n 40 "target/fuzz-$t.log"
    fi
  } >&2
  return "$status"
}

jobs_max="${FUZZ_JOBS:-$(nproc)}"
failed=0
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs_max" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
  run_target "$t" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done
exit "$failed"
