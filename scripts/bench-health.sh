#!/usr/bin/env bash
# health on the timing-emulated sim network (profile typical, 500 kbit/s): the demo network
# as it starts (healthy), then with its drive faulted and the I/O module's heartbeat stopped
# (0x1017 = 100 ms, nothing sent). Usage: scripts/bench-health.sh [RUNS]   (installs hyperfine)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v hyperfine >/dev/null || { apt-get update -qq && apt-get install -y -qq hyperfine >/dev/null; }
cargo build --release --quiet
runs=${1:-10}
bin=$PWD/target/release/canctl
dir=$(mktemp -d)
export XDG_CONFIG_HOME=$dir XDG_CACHE_HOME=$dir XDG_STATE_HOME=$dir
bus="sim:$dir/sim.json"
"$bin" --bus "$bus" sim reset --profile typical >/dev/null
hyperfine --runs "$runs" -n "health (healthy demo network)" "$bin --bus $bus -q health"
"$bin" --bus "$bus" sim reset --profile typical --fault 10:no-heartbeat >/dev/null
"$bin" --bus "$bus" sdo write 10 1017 100 --type u16 >/dev/null
"$bin" --bus "$bus" sdo write 1 5FFE 1 --type u16 >/dev/null
hyperfine --runs "$runs" -i -n "health (faulted drive, stopped heartbeat)" "$bin --bus $bus -q health"
"$bin" --bus "$bus" health || true
