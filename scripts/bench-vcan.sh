#!/usr/bin/env bash
# The vcan0 benchmarks (scripts/bench_vcan.py) in the kernel-test VM, release build.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
pip install -q -r tests/interop/requirements.txt
exec scripts/run-in-vm.sh 'cp target/release/canctl /tmp/canctl && CANCTL_BIN=/tmp/canctl python3 scripts/bench_vcan.py'
