#!/usr/bin/env bash
# Whole-command timings with hyperfine: scan of 1..127 on the sim network, cold start, and
# what a <Tab> costs (completion reads the scan cache and the dictionary, never the bus).
# Usage: scripts/bench.sh   (installs hyperfine from Debian if missing)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v hyperfine >/dev/null || { apt-get update -qq && apt-get install -y -qq hyperfine >/dev/null; }
cargo build --release --quiet
bin=target/release/canctl
state=$(mktemp -d)/sim.json
export XDG_CACHE_HOME=$(dirname "$state")
"$bin" --bus "sim:$state" sim reset >/dev/null
"$bin" --bus "sim:$state" scan >/dev/null 2>&1
hyperfine --warmup 3 --runs 30 -N \
  "$bin --version" \
  "$bin --bus sim:$state scan" \
  "$bin --bus sim:$state scan --window 20ms" \
  "env COMPLETE=bash _CLAP_COMPLETE_INDEX=5 $bin -- canctl --bus sim:$state sdo read ''" \
  "env COMPLETE=bash _CLAP_COMPLETE_INDEX=6 $bin -- canctl --bus sim:$state sdo read 5 0x"
echo "A sequential probe with a 100 ms timeout would take about 123 x 100 ms = 12.3 s for the absent ids."
