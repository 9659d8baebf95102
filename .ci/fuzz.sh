#!/usr/bin/env bash
# Coverage-guided fuzzing (cargo-fuzz, libFuzzer) of the targets in fuzz/: each target runs for
# SECONDS (default 60) from its committed seed corpus (fuzz/corpus/<target>/, read-only here);
# new inputs go to fuzz/target/corpus/<target>/ (kept between runs, so a longer run continues).
# A crash stops the script (non-zero exit) and leaves the input in fuzz/artifacts/<target>/.
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
for t in "${targets[@]}"; do
  work="target/corpus/$t"
  mkdir -p "$work"
  echo "-- fuzz $t for ${seconds}s"
  status=0
  cargo +nightly fuzz run --sanitizer none --release --debug-assertions "$t" "$work" "corpus/$t" -- \
    -max_total_time="$seconds" -max_len="${max_len[$t]:-4096}" -rss_limit_mb=2048 \
    -timeout=20 -print_final_stats=1 >"target/fuzz-$t.log" 2>&1 || status=$?
  # The run's figures: executions, coverage (libFuzzer's `cov:` edges, `ft:` features), corpus.
  grep -E '^#[0-9]+ +(INITED|DONE)|^stat::(number_of_executed_units|peak_rss_mb)' \
    "target/fuzz-$t.log" || true
  if [ "$status" -ne 0 ]; then
    echo "fuzz target $t failed (exit $status); log: fuzz/target/fuzz-$t.log" >&2
    tail -n 40 "target/fuzz-$t.log" >&2
    exit 1
  fi
done
