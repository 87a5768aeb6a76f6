#!/usr/bin/env bash
# Deterministic simulation testing on demand: N seeded scenarios (default 1,000,000) of
# tests/dst/, from seed START (default a fresh one from the clock, printed), on the
# release build. CI runs `scripts/dst.sh 10000 0x5EED0000`: the same 10,000 every time. Every failing seed is printed with the command that
# replays it (CANCTL_DST_SEED=... cargo test --test dst).
#   scripts/dst.sh [N] [START]
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-1000000}
start=${2:-$(date +%s)}
echo "dst: $n scenarios from seed $start" >&2
CANCTL_DST_SCENARIOS=$n CANCTL_DST_START=$start \
  cargo test --locked --release --test dst seeded_scenarios_keep_every_invariant -- --nocapture
