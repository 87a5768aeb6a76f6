#!/usr/bin/env bash
# network apply on the timing-emulated sim network (profile typical, 500 kbit/s): the
# example project (9 nodes: 4 configured, 5 LSS sensors) from factory state, one node at a
# time (--jobs 1) against all at once (--jobs 8); with the node-ids given over LSS by the
# run itself (--assign) and without (lss assign first, so only SDO is timed); then a second
# run, which writes nothing. Usage: scripts/bench-network.sh [RUNS]   (installs hyperfine)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v hyperfine >/dev/null || { apt-get update -qq && apt-get install -y -qq hyperfine >/dev/null; }
cargo build --release --quiet
runs=${1:-10}
bin=$PWD/target/release/canctl
dir=$(mktemp -d)
export XDG_CONFIG_HOME=$dir XDG_CACHE_HOME=$dir XDG_STATE_HOME=$dir
bus="sim:$dir/sim.json"
project=examples/sim-machine
factory="$bin --bus $bus sim reset --profile typical --unconfigured 5"
numbered="$factory && $bin --bus $bus lss assign --start 20"
for jobs in 1 8; do
  hyperfine --runs "$runs" --prepare "$factory" -n "apply --assign --jobs $jobs (factory state)" \
    "$bin --bus $bus -q network apply $project --assign --jobs $jobs"
  hyperfine --runs "$runs" --prepare "$numbered" -n "apply --jobs $jobs (ids already given)" \
    "$bin --bus $bus -q network apply $project --jobs $jobs"
done
eval "$numbered" >/dev/null 2>&1
"$bin" --bus "$bus" -q network apply "$project" >/dev/null
for jobs in 1 8; do
  hyperfine --runs "$runs" -n "second run --jobs $jobs (writes nothing)" \
    "$bin --bus $bus -q network apply $project --jobs $jobs"
done
for jobs in 1 8; do
  hyperfine --runs "$runs" -n "network check --jobs $jobs" "$bin --bus $bus -q network check $project --jobs $jobs"
done
"$bin" --bus "$bus" network apply "$project" --jobs 8 2>&1 | tail -1
