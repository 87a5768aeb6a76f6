#!/usr/bin/env bash
# Run the tests that need the Linux CAN stack (vcan0) inside a small VM, see
# scripts/run-in-vm.sh. Builds on the host first; the VM runs the kernel tests of the built suite.
#   scripts/kernel-tests.sh            all kernel tests
#   scripts/kernel-tests.sh FILTER     only tests whose name contains FILTER
#   KERNEL_TESTS_WORKERS=N             N tests at a time (default 3; 1: one after another)
#   KERNEL_TESTS_REPEAT=N scripts/kernel-tests.sh FILTER
#                                      the same N times in one VM (a flake's count):
#                                      says how many runs failed, exit 1 if any did
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-}
# The modules of the test suite (tests/suite/) that need vcan0.
modules="interop_durand socketcan_vcan slcan_kernel interop_canopen firmware_vcan network_vcan doctor_vcan"
# Build canctl and the suite on the host, then pick the kernel tests (those whose name
# also contains FILTER) from the suite's own list, by exact name.
# canctl itself is the release build: on the VM's emulated CPU a debug build moved a 64 KiB
# domain in minutes (the suite runs the debug build on the host, overflow checks and all).
# CI has it from the main job already.
cargo build --quiet --release --bins
suite=$(cargo test --no-run --message-format=json --test suite 2>/dev/null \
  | python3 -c 'import json,sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["name"] == "suite":
        print(m["executable"])')
[ -n "$suite" ] || { echo "kernel-tests: the test suite did not build" >&2; exit 1; }
all=$("$suite" --list --format terse | sed -n 's/: test$//p')
tests=$(for m in $modules; do grep "^$m::" <<<"$all" | grep -F -- "$filter"; done || true)
[ -n "$tests" ] || { echo "kernel-tests: no kernel test's name contains '$filter'" >&2; exit 1; }
echo "kernel-tests: $(echo "$tests" | wc -l) tests from $(echo $modules | wc -w) modules" >&2
# Several tests at a time, each in its own process and each worker on its own vcan
# interface (scripts/kernel-tests-vm.sh). The VM reads the host's files over 9p without a
# page cache; canctl and the suite run from copies in VM memory. In the VM a missing vcan
# interface is a failure, not a skip. The modules are listed slowest first (the durand LSS
# tests take minutes), so that no long test starts last.
repeat=${KERNEL_TESTS_REPEAT:-1}
workers=${KERNEL_TESTS_WORKERS:-3}
cmd="scripts/kernel-tests-vm.sh $suite $repeat $workers $(echo $tests)"
# The LSS tests against durand run at canctl's own pace on an emulated CPU: minutes, not seconds.
export VMCAN_TIMEOUT=${VMCAN_TIMEOUT:-$((1800 * repeat))}
# canctl and the suite are copied into the VM's memory (the suite is a 140 MB debug build).
export VMCAN_MEM=${VMCAN_MEM:-2048}
exec scripts/run-in-vm.sh "$cmd"
