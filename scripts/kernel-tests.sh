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
tests=$("$suite" --list --format terse | sed -n 's/: test$//p' \
  | grep -E "^($(echo $modules | tr ' ' '|'))::" | grep -F -- "$filter" || true)
[ -n "$tests" ] || { echo "kernel-tests: no kernel test's name contains '$filter'" >&2; exit 1; }
echo "kernel-tests: $(echo "$tests" | wc -l) tests from $(echo $modules | wc -w) modules" >&2
# One test at a time, each in its own process: all of them share vcan0, and the time each
# took is said at the end (the slowest first: where the VM's minutes go). The VM reads the
# host's files over 9p without a page cache; canctl and the suite run from copies in VM
# memory. In the VM a missing vcan0 is a failure, not a skip.
repeat=${KERNEL_TESTS_REPEAT:-1}
cmd="cp target/release/canctl /tmp/canctl && cp $suite /tmp/suite && export CANCTL_BIN=/tmp/canctl CANCTL_REQUIRE_KERNEL=1; "
cmd+="fails=0; runs=0; : > /tmp/times; "
cmd+="for i in \$(seq $repeat); do for t in $(echo $tests); do "
cmd+="  began=\$EPOCHREALTIME; /tmp/suite --test-threads=1 --exact \$t || { fails=\$((fails + 1)); echo \"FAILED: \$t (run \$i)\"; }; "
cmd+="  runs=\$((runs + 1)); awk -v a=\$began -v b=\$EPOCHREALTIME -v t=\$t 'BEGIN { printf \"%7.1f s  %s\\n\", b - a, t }' >> /tmp/times; "
cmd+="done; done; "
cmd+="echo '== kernel tests, slowest first'; sort -rn /tmp/times | head -20; "
cmd+="echo \"kernel-tests: \$fails of \$runs test run(s) failed\"; [ \$fails = 0 ]"
# The LSS tests against durand run at canctl's own pace on an emulated CPU: minutes, not seconds.
export VMCAN_TIMEOUT=${VMCAN_TIMEOUT:-$((1800 * repeat))}
# canctl and the suite are copied into the VM's memory (the suite is a 140 MB debug build).
export VMCAN_MEM=${VMCAN_MEM:-2048}
exec scripts/run-in-vm.sh "$cmd"
