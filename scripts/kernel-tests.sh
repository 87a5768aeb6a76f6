#!/usr/bin/env bash
# Run the tests that need the Linux CAN stack (vcan0) inside a small VM, see
# scripts/run-in-vm.sh. Builds on the host first; the VM runs the kernel tests of the built suite.
#   scripts/kernel-tests.sh            all kernel tests
#   scripts/kernel-tests.sh FILTER     only tests whose name contains FILTER
#   KERNEL_TESTS_REPEAT=N scripts/kernel-tests.sh FILTER
#                                      the same N times in one VM (a flake's count):
#                                      says how many runs failed, exit 1 if any did
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-}
# The modules of the test suite (tests/suite/) that need vcan0.
modules="socketcan_vcan interop_canopen interop_durand slcan_kernel network_vcan firmware_vcan doctor_vcan"
# Build canctl and the suite on the host, then pick the kernel tests (those whose name
# also contains FILTER) from the suite's own list, by exact name.
cargo build --quiet --bins
suite=$(cargo test --no-run --message-format=json --test suite 2>/dev/null \
  | python3 -c 'import json,sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["name"] == "suite":
        print(m["executable"])')
[ -n "$suite" ] || { echo "kernel-tests: the test suite did not build" >&2; exit 1; }
tests=$("$suite" --list --format terse | sed -n 's/: test$//p' \
  | grep -E "^($(echo $modules | tr ' ' '|'))::" | grep -F -- "$filter" || true)
[ -n "$tests" ] || { echo "kernel-tests: no kernel test's name contains '$filter'" >&2; exit 1; }
echo "kernel-tests: $(echo "$tests" | wc -l) tests from $(echo $modules | wc -w) modules" >&2
# One test at a time: all of them share vcan0. The VM reads the host's files over 9p
# without a page cache; canctl runs from a copy in VM memory. In the VM a missing vcan0 is
# a failure, not a skip.
cmd="cp target/debug/canctl /tmp/canctl && export CANCTL_BIN=/tmp/canctl CANCTL_REQUIRE_KERNEL=1; "
run="$suite --test-threads=1 --exact $(echo $tests)"
repeat=${KERNEL_TESTS_REPEAT:-1}
if [ "$repeat" = 1 ]; then
  cmd+="$run"
else
  cmd+="fails=0; for i in \$(seq $repeat); do echo \"== run \$i of $repeat\"; $run || fails=\$((fails + 1)); done; "
  cmd+="echo \"kernel-tests: \$fails of $repeat run(s) failed\"; [ \$fails = 0 ]"
fi
# The LSS tests against durand run at canctl's own pace on an emulated CPU: minutes, not seconds.
export VMCAN_TIMEOUT=${VMCAN_TIMEOUT:-$((1800 * repeat))}
exec scripts/run-in-vm.sh "$cmd"
