#!/usr/bin/env bash
# Cross-compiles every board example (examples/boards/<board>/, each its own workspace with its
# own Cargo.lock) for the target its .cargo/config.toml names: no hardware needed. The ELFs land
# in target/boards/<target>/release/. Also run by tests/tests/boards.rs.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
for dir in "$root"/examples/boards/*/; do
    board=$(basename "$dir")
    target=$(sed -n 's/^target = "\(.*\)"/\1/p' "$dir/.cargo/config.toml")
    echo "== board $board ($target)"
    (cd "$dir" && cargo fmt --check && cargo build --release --locked --target-dir "$root/target/boards")
done
