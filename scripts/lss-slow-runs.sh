#!/usr/bin/env bash
# LSS at canctl's defaults against slow devices: N runs (default 10) each of `lss fastscan`
# and of `lss assign --start 20` on the sim's `slow` profile (answers 5-80 ms late) with 8
# devices without a node-id, each run on a fresh network with its own seed. Prints one line
# a run: exit code, time, steps and step (fastscan), devices assigned and what a scan then
# sees (assign). Uses the release build.
set -uo pipefail
cd "$(dirname "$0")/.."
runs=${1:-10}
cargo build --release --quiet
canctl=target/release/canctl
dir=$(mktemp -d)
bus="sim:$dir/sim.json"
json() { python3 -c "import json,sys
try:
    j = json.load(sys.stdin); print($1)
except Exception:
    print('no JSON')"; }
for i in $(seq 1 "$runs"); do
  $canctl --bus "$bus" sim reset --profile slow --unconfigured 8 --seed "$i" >/dev/null
  start=$(date +%s.%N)
  out=$($canctl --bus "$bus" lss fastscan --format json 2>/dev/null); code=$?
  echo "fastscan run $i: exit $code, $(echo "$(date +%s.%N) - $start" | bc) s, $(echo "$out" | json '"steps", j["steps"], "step_ms", j["step_ms"]')"
done
for i in $(seq 1 "$runs"); do
  $canctl --bus "$bus" sim reset --profile slow --unconfigured 8 --seed $((100 + i)) >/dev/null
  start=$(date +%s.%N)
  out=$($canctl --bus "$bus" lss assign --start 20 --format json 2>/dev/null); code=$?
  took=$(echo "$(date +%s.%N) - $start" | bc)
  after=$($canctl --bus "$bus" scan --format json 2>/dev/null | json 'len(j["nodes"]), "nodes,", j["lss_unconfigured"], "without a node-id"')
  echo "assign run $i: exit $code, $took s, $(echo "$out" | json 'len(j["assigned"])') assigned; then scan: $after"
done
rm -rf "$dir"
