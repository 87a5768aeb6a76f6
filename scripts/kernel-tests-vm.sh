#!/usr/bin/env bash
# Inside the kernel-test VM (scripts/kernel-tests.sh runs it there):
#   kernel-tests-vm.sh SUITE REPEAT WORKERS TEST...
# Runs each TEST REPEAT times, WORKERS tests at a time, each in its own process. Most of
# these tests wait (on the devices' timeouts, on python peers), so the VM's CPUs have room
# for more than one. Each worker has a vcan interface of its own (vcan0, vcan1, ...; the
# tests take it from CANCTL_TEST_VCAN), and vcan echoes (echo=1) from the start, so that
# the durand tests behind netem change only their own interface's qdisc instead of
# reloading vcan under the others. The slcan tests share the one slcan0 name the kernel
# gives: they take turns. The time each test took is said at the end, the slowest first.
set -uo pipefail
suite=$1 repeat=$2 workers=$3
shift 3
cp target/release/canctl /tmp/canctl && cp "$suite" /tmp/suite || exit 1
export CANCTL_BIN=/tmp/canctl CANCTL_REQUIRE_KERNEL=1

# vcan again, echoing, with one interface per worker.
ip link del vcan0 2>/dev/null
rmmod vcan 2>/dev/null
modprobe -d "$VMCAN_KROOT" vcan echo=1 || { echo "kernel-tests: vcan echo=1 could not be loaded" >&2; exit 1; }
for ((w = 0; w < workers; w++)); do
  ip link add dev "vcan$w" type vcan && ip link set up "vcan$w" || exit 1
done

: > /tmp/queue; : > /tmp/times; : > /tmp/failed
for ((i = 1; i <= repeat; i++)); do printf '%s\n' "$@" | sed "s/\$/ $i/" >> /tmp/queue; done
runs=$(wc -l < /tmp/queue)

# The next test and its run number from the queue, empty when it is done.
next() {
  flock /tmp/queue.lock bash -c 'head -n 1 /tmp/queue; sed -i 1d /tmp/queue'
}

worker() {  # IFACE
  local t i began out rc
  while read -r t i < <(next) && [ -n "$t" ]; do
    began=$EPOCHREALTIME
    case $t in
      slcan_kernel::*) out=$(flock /tmp/slcan.lock env CANCTL_TEST_VCAN="$1" /tmp/suite --test-threads=1 --exact "$t" 2>&1) ;;
      *) out=$(CANCTL_TEST_VCAN="$1" /tmp/suite --test-threads=1 --exact "$t" 2>&1) ;;
    esac
    rc=$?
    # One test's output at a time, whole.
    flock /tmp/print.lock bash -c 'printf "%s\n" "$1"' _ "$out"
    [ $rc = 0 ] || flock /tmp/print.lock bash -c 'echo "FAILED: $1 (run $2)" | tee -a /tmp/failed' _ "$t" "$i"
    awk -v a="$began" -v b="$EPOCHREALTIME" -v t="$t" 'BEGIN { printf "%7.1f s  %s\n", b - a, t }' >> /tmp/times
  done
}

began=$EPOCHREALTIME
for ((w = 0; w < workers; w++)); do worker "vcan$w" & done
wait
echo '== kernel tests, slowest first'
sort -rn /tmp/times | head -20
fails=$(wc -l < /tmp/failed)
awk -v a="$began" -v b="$EPOCHREALTIME" -v w="$workers" 'BEGIN { printf "kernel-tests: %.0f s with %d workers\n", b - a, w }'
echo "kernel-tests: $fails of $runs test run(s) failed"
[ "$fails" = 0 ]
