#!/usr/bin/env bash
# durand_netem.sh delay MS [loss PCT] | plain
#
# Real latency on vcan0 (or $CANCTL_TEST_VCAN) for tests/suite/interop_durand.rs: vcan with
# echo=1 (without it the CAN core loops frames back before the qdisc and netem has no
# effect) and a netem qdisc holding every frame MS ms, and with `loss PCT` dropping that
# share of the frames (both ways, as an overloaded adapter or gateway does); `plain` gives
# back an ordinary interface. Where vcan was loaded with echo=1 already (the kernel-test VM,
# whose other tests run alongside on their own interfaces) only the qdisc changes;
# elsewhere vcan is reloaded. Needs root; in the VM modules come from $VMCAN_KROOT.
set -euo pipefail
iface=${CANCTL_TEST_VCAN:-vcan0}
echoing() { [ "$(cat /sys/module/vcan/parameters/echo 2>/dev/null)" = Y ]; }

load() { modprobe ${VMCAN_KROOT:+-d "$VMCAN_KROOT"} "$@"; }

recreate() {  # module parameters for vcan
  ip link del "$iface" 2>/dev/null || true
  rmmod vcan 2>/dev/null || true
  load vcan "$@"
  ip link add dev "$iface" type vcan
  ip link set up "$iface"
}

case "${1:-}" in
  delay)
    echoing || recreate echo=1
    echoing || { echo "durand_netem: vcan could not be reloaded with echo=1 (another vcan interface in use?)" >&2; exit 1; }
    load sch_netem
    tc qdisc replace dev "$iface" root netem delay "${2:?delay in ms}ms" ${3:+loss "${4:?loss in percent}%"}
    ;;
  plain)
    if echoing && [ -n "${CANCTL_TEST_VCAN:-}" ]; then tc qdisc del dev "$iface" root 2>/dev/null || true
    else recreate; fi
    ;;
  *)
    echo "usage: $0 delay MS [loss PCT] | plain" >&2
    exit 2
    ;;
esac
