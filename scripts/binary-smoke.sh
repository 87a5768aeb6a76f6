#!/usr/bin/env bash
# binary-smoke.sh CANCTL [RUNNER-ARGS...]: a release binary end to end on the simulated
# network and through pseudo-terminals, as a technician would first use it. CANCTL is the
# command that starts it, e.g. `qemu-aarch64-static dist/…/canctl` for an ARM binary
# (scripts/dist-check.sh); each check prints the command and its output.
# SMOKE_PTY_CLIENT: another canctl to talk to the pty device sides that CANCTL serves (qemu-user
# cannot open a serial port for the ARM binary: it lacks the TCGETS2 ioctl, see dist-check.sh).
# Exit status: the number of failed checks (0: all passed).
set -uo pipefail
[ $# -ge 1 ] || { echo "usage: $0 CANCTL [ARGS...]" >&2; exit 2; }
canctl=("$@")
read -ra client <<<"${SMOKE_PTY_CLIENT:-$*}"
work=$(mktemp -d)
dev=
cleanup() { [ -n "$dev" ] && kill "$dev" 2>/dev/null && wait "$dev" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
# Its own settings, cache and sim state: nothing of the user's is read or changed.
export XDG_CONFIG_HOME=$work XDG_CACHE_HOME=$work XDG_STATE_HOME=$work
unset CANCTL_BUS
# A generous answer timeout: under qemu-user each frame costs emulated CPU.
printf 'timeout = "5s"\n' > "$work/canctl.toml"
failed=0

# check EXPECTED_EXIT NEEDLE -- ARGS...: run canctl, show the transcript, compare.
check() { check_with canctl "$@"; }
# check_with ARRAY-NAME EXPECTED_EXIT NEEDLE -- ARGS...: the same with that command.
check_with() {
  local -n run=$1
  local want=$2 needle=$3 got=0 by=
  [ "$1" = client ] && [ -n "${SMOKE_PTY_CLIENT:-}" ] && by="   # by $SMOKE_PTY_CLIENT"
  shift 4
  echo "\$ canctl $*$by"
  (cd "$work" && timeout 120 "${run[@]}" "$@") >"$work/out" 2>&1 </dev/null || got=$?
  head -n 12 "$work/out" | sed 's/^/  /'
  [ "$(wc -l <"$work/out")" -le 12 ] || echo "  (… $(($(wc -l <"$work/out") - 12)) more lines)"
  if [ "$got" != "$want" ] || ! grep -qF -- "$needle" "$work/out"; then
    echo "FAIL: exit $got (want $want), want output with '$needle'"
    failed=$((failed + 1))
  fi
}

# serve FRAMING: start `canctl sim FRAMING` on a pty, set $pty to the path it prints.
serve() {
  "${canctl[@]}" --bus sim sim "$1" >"$work/pty" 2>"$work/serve.err" </dev/null &
  dev=$!
  pty=
  for _ in $(seq 300); do
    pty=$(head -n1 "$work/pty")
    [ -n "$pty" ] && break
    sleep 0.1
  done
  echo "\$ canctl --bus sim sim $1   # serving on ${pty:-nothing}"
  [ -n "$pty" ] || { echo "FAIL: no pty path printed"; cat "$work/serve.err"; failed=$((failed + 1)); }
}
stop_serving() { kill "$dev" 2>/dev/null; wait "$dev" 2>/dev/null; dev=; }

cd "$work" || exit 1
check 0 "canctl " -- --version
check 0 "canctl --bus sim scan" -- --help
check 0 "reset" -- --bus sim sim reset
check 0 "4 node(s) on sim" -- --bus sim scan
check 0 "3 device(s) given a node-id" -- --bus sim lss assign --start 20
check 0 "251" -- --bus sim sdo read 1 0x1018:1 --type u32
check 0 "CAN-2057C" -- --bus sim sdo read 10 1008
check 0 "written and verified" -- --bus sim sdo write 5 ProducerHeartbeatTime 100 --verify
check 0 "" -- --bus sim config dump 5 --out sensor.dcf
check 0 "verified" -- --bus sim config apply 20 sensor.dcf --verify
check 4 "0x06020000" -- --bus sim sdo read 1 0x5555
check 3 "node 99" -- --bus sim --timeout 200ms sdo read 99 1000
check 0 "7 node(s) on sim" -- --bus sim scan

serve --epos2-rs232
if [ -n "$pty" ]; then
  check_with client 0 "251" -- --bus "epos2-rs232:$pty" sdo read 1 0x1018:1 --type u32
  check_with client 0 "node(s)" -- --bus "epos2-rs232:$pty" scan
fi
stop_serving
serve --slcan
if [ -n "$pty" ]; then
  check_with client 0 "7 node(s)" -- --bus "slcan:$pty" scan
  check_with client 0 "written and verified" -- --bus "slcan:$pty" sdo write 5 ProducerHeartbeatTime 200 --verify
fi
stop_serving

[ "$failed" = 0 ] && echo "binary-smoke: all passed (${canctl[*]})" || echo "binary-smoke: $failed failed (${canctl[*]})"
exit "$failed"
