#!/usr/bin/env bash
# vm-socketcand.sh SOCKETCAND_SRC [TRANSCRIPT]
#
# Own run, NOT in CI: canctl as the client of linux-can/socketcand itself, in the
# kernel-test VM (scripts/run-in-vm.sh). SOCKETCAND_SRC is a checkout of
# https://github.com/linux-can/socketcand (its code stays out of this repository), also
# taken from $SOCKETCAND_SRC. It is built here, on the host (meson/ninja when there, else
# gcc: the VM runs the host's binaries).
#
# Inside the VM, on vcan0: the python-canopen device (tests/interop/local_node.py, node 10)
# and the durand devices (tests/interop/durand_node.py: node 20 and 3 LSS devices without a
# node-id), socketcand -i vcan0 -l lo, and canctl --bus socketcand:127.0.0.1:29536/vcan0:
# buses, scan, SDO of every transfer type, lss assign, health; the bytes socketcand sends
# (raw capture); then the figures: a 64 KiB block upload and download from the sim devices
# (canctl sim --socketcan vcan0) on an emulated 1 Mbit/s bus (vcan echo=1 + netem rate
# 1mbit: a 16-byte CAN skb takes 128 us), through socketcand and over SocketCAN directly,
# as a share of the bus limit (frames on the bus x 128 us / first-to-last frame time, from
# candump's time stamps).
#
# The transcript goes to standard output and to TRANSCRIPT when given.
set -euo pipefail

if [ "${1:-}" = --in-vm ]; then
  # ------------------------------------------------------------------ inside the VM
  set +e
  cp target/debug/canctl /tmp/canctl
  cp "$SOCKETCAND_BIN" /tmp/socketcand
  C=/tmp/canctl
  PORT=29536
  BUS=socketcand:127.0.0.1:$PORT/vcan0
  export XDG_STATE_HOME=/tmp/state XDG_CONFIG_HOME=/tmp/config XDG_CACHE_HOME=/tmp/cache
  unset CANCTL_BUS
  # Python devices on an emulated CPU answer in hundreds of ms, not the 500 ms default.
  mkdir -p /tmp/config/canctl && echo 'timeout = "2s"' > /tmp/config/canctl/config.toml
  PIDS=()
  trap 'for p in "${PIDS[@]}"; do kill "$p" 2>/dev/null; done' EXIT

  say() { printf '\n## %s\n' "$*"; }
  run() {  # run ARGS...: one canctl command through socketcand, with its exit code
    printf '\n$ canctl --bus %s %s\n' "$BUS" "$*"
    timeout 600 "$C" --bus "$BUS" "$@" 2>&1
    printf '[exit %s]\n' "$?"
  }
  wait_line() {  # wait_line FILE TEXT SECONDS
    local i
    for ((i = 0; i < $3 * 10; i++)); do grep -q "$2" "$1" 2>/dev/null && return 0; sleep 0.1; done
    echo "vm-socketcand: no '$2' in $1 within $3 s:"; cat "$1"; return 1
  }

  # VM_SOCKETCAND_PARTS: what to run, "commands figures" (default) or one of them.
  parts=${VM_SOCKETCAND_PARTS:-commands figures}
  if [[ $parts == *commands* ]]; then
  say "devices on vcan0"
  python3 tests/interop/local_node.py vcan0 10 > /tmp/local.log 2>&1 & PIDS+=($!)
  # durand ends at the end of its input: hold it open.
  (sleep 100000 | python3 tests/interop/durand_node.py vcan0 --node 20 --unconfigured 3 --seconds 3000 > /tmp/durand.log 2>&1) & PIDS+=($!)
  wait_line /tmp/local.log READY 120 && echo "python-canopen LocalNode 10: READY"
  wait_line /tmp/durand.log READY 120 && echo "durand: node 20 and 3 LSS devices without a node-id: READY"

  say "socketcand $(/tmp/socketcand -h 2>&1 | head -n 1)"
  echo '$ socketcand -v -i vcan0 -l lo -p 29536'
  stdbuf -oL /tmp/socketcand -v -i vcan0 -l lo -p $PORT > /tmp/socketcand.log 2>&1 & PIDS+=($!)
  wait_line /tmp/socketcand.log "binding socket" 30
  sleep 1
  cat /tmp/socketcand.log

  say "what socketcand sends, raw (two clients: one sends, the other hears)"
  python3 - <<'PY'
import socket, time
def client():
    s = socket.create_connection(("127.0.0.1", 29536), timeout=5)
    s.settimeout(0.2)
    return s
def talk(s, text, wait=1.0):
    if text:
        s.sendall(text.encode()); print(">>", text)
    got, end = b"", time.time() + wait
    while time.time() < end:
        try:
            got += s.recv(4096)
        except socket.timeout:
            pass
    if got:
        # The devices' heartbeats ride along: the first units of each read, and how many more.
        units = [u + ">" for u in got.decode(errors="replace").split(">") if u.strip()]
        more = f" (+{len(units) - 4} more units)" if len(units) > 4 else ""
        print("<<", "".join(units[:4]) + more)
a, b = client(), client()
for s in (a, b):
    talk(s, "", 1)
    talk(s, "< open vcan0 >")
    talk(s, "< rawmode >")
talk(b, "< echo >")
talk(b, "< nonsense >")
talk(a, "< send 080 0 >", 0.1); talk(b, "", 1)
talk(a, "< send 000 2 80 14 >", 0.1); talk(b, "", 1.5)
talk(a, "< send 614 8 40 18 10 01 00 00 00 00 >", 0.1); talk(b, "", 1.5)
a.close(); talk(b, "", 0.5); b.close()
PY

  say "canctl through socketcand"
  run buses --wait 3s
  run scan
  # The same scan over SocketCAN directly, for comparison (python devices on an emulated CPU
  # answer late: a node that only answers the 2nd probe here does so without socketcand too).
  printf '\n$ canctl --bus vcan0 scan\n'; "$C" --bus vcan0 scan 2>&1; printf '[exit %s]\n' "$?"
  # SDO transfers with -v: the first request and answer show the transfer type (client
  # command 40 expedited/segmented upload, A4 block upload, C6/C2 block download, 21/23
  # download), then how many SDO frames went each way.
  sdo() {
    printf '\n$ canctl --bus %s -v sdo %s\n' "$BUS" "$*"
    timeout 600 "$C" --bus "$BUS" -v sdo "$@" 2> /tmp/trace.txt
    local rc=$?
    grep -vE '  (70|71|72|73|74|75|76|77)[0-9A-F] ' /tmp/trace.txt > /tmp/sdo-trace.txt
    head -n 2 /tmp/sdo-trace.txt
    printf '  ... %s SDO frames in all (requests %s, answers %s)\n' "$(wc -l < /tmp/sdo-trace.txt)" \
      "$(grep -cE '  6[0-9A-F]{2} ' /tmp/sdo-trace.txt)" "$(grep -cE '  5[89A-F][0-9A-F] ' /tmp/sdo-trace.txt)"
    printf '[exit %s]\n' "$rc"
  }
  sdo read 20 1018:1 --type u32
  sdo read 10 0x1008 --type vs
  sdo read 20 0x2200:5 --type d --no-block --out /tmp/888.bin
  sdo read 20 0x2200:8 --type d --out /tmp/65536.bin
  head -c 4096 /dev/urandom > /tmp/4k.bin
  sdo write 20 0x2100 @/tmp/4k.bin --type d --no-block
  sdo write 20 0x2100 @/tmp/4k.bin --type d
  sdo read 20 0x2100 --type d --out /tmp/4k.back
  cmp /tmp/4k.bin /tmp/4k.back && echo "0x2100 read back: the 4096 bytes written"
  sdo write 10 0x2000:4 0xDEADBEEF --type u32 --verify
  sdo write 10 0x2000:14 @/tmp/4k.bin --type d
  run lss assign --start 20
  run scan
  run health
  run nmt start all
  kill "${PIDS[@]}" 2>/dev/null; PIDS=()
  tail -n 5 /tmp/socketcand.log
  fi
  [[ $parts == *figures* ]] || exit 0

  say "figures: 64 KiB block transfer, vcan0 as a 1 Mbit/s bus (vcan echo=1, netem rate 1mbit)"
  ip link del vcan0; rmmod vcan
  modprobe -d "$VMCAN_KROOT" vcan echo=1; modprobe -d "$VMCAN_KROOT" sch_netem
  ip link add dev vcan0 type vcan && ip link set up vcan0
  tc qdisc add dev vcan0 root netem rate 1mbit
  tc qdisc show dev vcan0
  # The figures' canctl: a release build when there is one (an emulated CPU is slow enough).
  if [ -x target/release/canctl ]; then cp target/release/canctl /tmp/canctl-release; C=/tmp/canctl-release; fi
  echo "canctl for the figures: $([ "$C" = /tmp/canctl ] && echo debug || echo release) build"
  "$C" --bus sim:/tmp/bench-sim.json sim --socketcan vcan0 2> /tmp/sim.log & SIM=$!; PIDS+=($SIM)
  wait_line /tmp/sim.log . 60
  /tmp/socketcand -i vcan0 -l lo -p $((PORT + 1)) -n > /tmp/socketcand2.log 2>&1 & SCD=$!; PIDS+=($SCD)
  sleep 2
  ME0=$(awk '{ print $16 + $17 }' /proc/$$/stat)
  head -c 65536 /dev/urandom > /tmp/64k.bin
  ticks() {  # ticks PID: CPU clock ticks of PID and of its children it has reaped
    awk '{ print $14 + $15 + $16 + $17 }' "/proc/$1/stat"
  }
  measure() {  # measure LABEL BUS ARGS...: one transfer, its frames and time on the bus
    local label=$1 bus=$2; shift 2
    candump -ta vcan0 > /tmp/dump.txt & local dump=$!
    sleep 1
    local t0 t1 sim0 scd0 hz
    hz=$(getconf CLK_TCK)
    sim0=$(ticks "$SIM"); scd0=$(ticks "$SCD")
    t0=$(date +%s%N)
    "$C" --bus "$bus" "$@" > /dev/null 2> /tmp/err.txt; local rc=$?
    t1=$(date +%s%N)
    # CPU of the client (this shell's reaped children: canctl), the sim, socketcand (its
    # connection's process, reaped by the daemon when it ends: after the sleep).
    local me sim1 scd1
    me=$(awk '{ print $16 + $17 }' /proc/$$/stat)
    sleep 0.5
    sim1=$(ticks "$SIM"); scd1=$(ticks "$SCD")
    kill $dump; wait $dump 2>/dev/null
    local cpu
    cpu=$(awk -v hz="$hz" -v sim=$((sim1 - sim0)) -v scd=$((scd1 - scd0)) -v me=$((me - ME0)) \
      'BEGIN { printf "CPU ms: canctl %d, sim %d, socketcand %d", 1000 * me / hz, 1000 * sim / hz, 1000 * scd / hz }')
    ME0=$(awk '{ print $16 + $17 }' /proc/$$/stat)
    # The transfer's time on the bus: its first to its last SDO frame (0x601/0x581; the
    # devices' heartbeats go on around it). Its limit: the frames a 64 KiB block transfer
    # takes (9363 segments, 74 acknowledgements, 5 to begin and end) x 128 us; candump
    # itself may miss frames on a busy emulated CPU, so its count is only shown.
    awk -v label="$label" -v rc=$rc -v wall=$(((t1 - t0) / 1000000)) '
      $3 == "601" || $3 == "581" { t = substr($1, 2, length($1) - 2) + 0; if (n == 0) first = t; last = t; n++ }
      END { span = last - first; limit = 9442 * 0.000128; share = 0; if (span > 0) share = 100 * limit / span
            printf "%-34s exit %d  bus time %7.1f ms  limit %6.1f ms  share %5.1f %%  (process %d ms; candump saw %d SDO frames)\n",
                   label, rc, span * 1000, limit * 1000, share, wall, n }' /tmp/dump.txt
    echo "    $cpu"
    [ $rc = 0 ] || cat /tmp/err.txt
  }
  for i in 1 2 3; do
    measure "upload, socketcan:vcan0" vcan0 sdo read 1 1F50:1 --type d --out /tmp/up.bin
    measure "upload, socketcand (linux-can)" socketcand:127.0.0.1:$((PORT + 1))/vcan0 sdo read 1 1F50:1 --type d --out /tmp/up.bin
    measure "download, socketcan:vcan0" vcan0 sdo write 1 1F50:1 @/tmp/64k.bin --type d
    measure "download, socketcand (linux-can)" socketcand:127.0.0.1:$((PORT + 1))/vcan0 sdo write 1 1F50:1 @/tmp/64k.bin --type d
  done
  cmp /tmp/64k.bin /tmp/up.bin && echo "the last upload read back the 65536 bytes downloaded"
  exit 0
fi

# ------------------------------------------------------------------ on the host
cd "$(dirname "$0")/.."
src=${1:-${SOCKETCAND_SRC:-}}
[ -n "$src" ] && [ -f "$src/src/socketcand.c" ] \
  || { echo "usage: $0 SOCKETCAND_SRC [TRANSCRIPT] (a checkout of github.com/linux-can/socketcand)" >&2; exit 2; }
src=$(cd "$src" && pwd -P)
out=${2:-}
build="$src/build-vm"
if [ ! -x "$build/socketcand" ]; then
  if command -v meson >/dev/null && command -v ninja >/dev/null; then
    meson setup "$build" "$src" >&2 && ninja -C "$build" >&2
  else
    # What meson.build does with its options off: config.h and the daemon's sources.
    mkdir -p "$build"
    version=$(sed -n "s/^project('socketcand', 'c', version : '\([^']*\)').*/\1/p" "$src/meson.build")
    printf '#define PACKAGE_VERSION "%s"\n#define PACKAGE_NAME "socketcand"\n#define PACKAGE_BUGREPORT "%s"\n' \
      "${version:-unknown}" "https://github.com/linux-can/socketcand/issues" > "$build/config.h"
    gcc -O2 -I "$build" -I "$src" -I "$src/include" -o "$build/socketcand" \
      "$src"/src/{socketcand,statistics,beacon,state_bcm,state_raw,state_isotp,state_control,state_nobus}.c -lpthread
  fi
fi
cargo build --quiet --bins
pip install -q -r tests/interop/requirements.txt
export SOCKETCAND_BIN="$build/socketcand"
# Python devices and LSS at canctl's pace on an emulated CPU: minutes.
export VMCAN_TIMEOUT=${VMCAN_TIMEOUT:-1800}
if [ -n "$out" ]; then
  scripts/run-in-vm.sh "bash scripts/vm-socketcand.sh --in-vm" 2>&1 | tee "$out"
else
  exec scripts/run-in-vm.sh "bash scripts/vm-socketcand.sh --in-vm"
fi
