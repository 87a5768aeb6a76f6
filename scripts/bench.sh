#!/usr/bin/env bash
# Whole-command timings with hyperfine: scan of 1..127 on the sim network, and cold start.
# Usage: scripts/bench.sh   (installs hyperfine from Debian if missing)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v hyperfine >/dev/null || { apt-get update -qq && apt-get install -y -qq hyperfine >/dev/null; }
cargo build --release --quiet
bin=target/release/canctl
state=$(mktemp -d)/sim.json
"$bin" --bus "sim:$state" sim reset >/dev/null
hyperfine --warmup 3 --runs 30 -N \
  "$bin --version" \
  "$bin --bus sim:$state scan" \
  "$bin --bus sim:$state scan --window 20ms"
echo "A sequential probe with a 100 ms timeout would take about 123 x 100 ms = 12.3 s for the absent ids."
