#!/usr/bin/env bash
# Build every fuzz target and run each briefly: what CI does so that the targets cannot
# rot unseen. Works on stable Rust: libFuzzer's coverage comes from LLVM's sancov pass,
# as cargo-fuzz sets it up (without a sanitizer, which needs nightly).
#   fuzz/smoke.sh            build, then run each target for 15 s
#   fuzz/smoke.sh SECONDS    run each for that long (0: build only)
set -euo pipefail
cd "$(dirname "$0")"
seconds=${1:-15}
command -v c++ >/dev/null || { apt-get update -qq && apt-get install -y -qq g++ >/dev/null; }
host=$(rustc -vV | sed -n 's/^host: //p')
# --target keeps these flags off build scripts and proc macros, which must not be instrumented.
export RUSTFLAGS="--cfg fuzzing -Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares -Cdebug-assertions -Coverflow-checks"
cargo build --release --target "$host" --bins
[ "$seconds" = 0 ] && exit 0
for bin in fuzz_targets/*.rs; do
  name=$(basename "$bin" .rs)
  mkdir -p "corpus/$name" artifacts
  echo "== fuzz $name for ${seconds}s"
  "target/$host/release/$name" -max_total_time="$seconds" -artifact_prefix=artifacts/ "corpus/$name" 2>&1 | tail -1
done
