#!/usr/bin/env bash
# Run the tests that need the Linux CAN stack (vcan0) inside a small VM, see
# scripts/run-in-vm.sh. Builds on the host first; the VM runs the built test binaries.
#   scripts/kernel-tests.sh            all kernel tests
#   scripts/kernel-tests.sh FILTER     only tests whose name contains FILTER
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-}
# Build the binaries (and find the test executables) on the host.
cargo build --quiet --bins
bins=$(cargo test --no-run --message-format=json --test socketcan_vcan --test interop_canopen --test interop_durand --test slcan_kernel --test network_vcan --test firmware_vcan --test doctor_vcan 2>/dev/null \
  | python3 -c 'import json,sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["kind"] == ["test"]:
        print(m["executable"])')
[ -n "$bins" ] || { echo "kernel-tests: no test binaries built" >&2; exit 1; }
# One test process at a time, one test at a time: all of them share vcan0. The VM reads
# the host's files over 9p without a page cache; canctl runs from a copy in VM memory.
# In the VM a missing vcan0 is a failure, not a skip.
cmd="cp target/debug/canctl /tmp/canctl && export CANCTL_BIN=/tmp/canctl CANCTL_REQUIRE_KERNEL=1; "
for b in $bins; do
  cmd+="echo \"== $(basename "$b")\"; $b --test-threads=1 $filter || exit \$?; "
done
# The LSS tests against durand run at canctl's own pace on an emulated CPU: minutes, not seconds.
export VMCAN_TIMEOUT=${VMCAN_TIMEOUT:-1800}
exec scripts/run-in-vm.sh "$cmd"
