#!/usr/bin/env bash
# The Windows build of canctl, run under wine: the simulated bus end to end, completion,
# and the exit codes of the contract. Needs mingw-w64 and wine64 (Debian packages) and the
# x86_64-pc-windows-gnu target (rustup); .ci/run installs them.
#   scripts/windows-smoke.sh              builds canctl.exe (release) and runs it
#   scripts/windows-smoke.sh CANCTL.EXE   runs that one: the release artifact (dist-check.sh)
set -euo pipefail
cd "$(dirname "$0")/.."

if [ $# -ge 1 ]; then
  out=$(cd "$(dirname "$1")" && pwd)
  exe="$out/$(basename "$1")"
else
  target=x86_64-pc-windows-gnu
  cargo build --locked --release --quiet --target "$target"
  out="$PWD/target/$target/release"
  exe="$out/canctl.exe"
fi
# Debian 12's wine lacks ProcessPrng, which Rust's std uses for random numbers on Windows.
x86_64-w64-mingw32-gcc -shared -O2 -o "$out/bcryptprimitives.dll" \
  scripts/wine/bcryptprimitives.c scripts/wine/bcryptprimitives.def

export WINEDEBUG=-all WINEPREFIX="${WINEPREFIX:-$(mktemp -d)}"
# A fresh prefix is made by the first program run in it. On a loaded machine that once came
# out unusable ("could not load kernel32.dll"), and every run after it failed alike: make it
# first, and again from nothing if canctl.exe cannot start in it.
for attempt in 1 2 3; do
  wineboot --init >/dev/null 2>&1 </dev/null || true
  wineserver -w || true
  if wine "$exe" --version >/dev/null 2>&1 </dev/null; then break; fi
  echo "windows-smoke: the wine prefix is not usable (attempt $attempt): made again" >&2
  wineserver -k 2>/dev/null || true
  rm -rf "$WINEPREFIX" && mkdir -p "$WINEPREFIX"
done
work=$(mktemp -d)
state='sim:Z:'"$work"'/sim.json'
failed=0

# check NAME EXPECTED_EXIT NEEDLE -- ARGS...: run canctl.exe, compare exit code and output.
check() {
  local name=$1 want=$2 needle=$3
  shift 4
  local got=0
  (cd "$work" && wine "$exe" "$@") >"$work/out" 2>&1 </dev/null || got=$?
  if [ "$got" != "$want" ] || ! grep -qF -- "$needle" "$work/out"; then
    echo "FAIL $name: exit $got (want $want), output:"; sed 's/^/    /' "$work/out"
    failed=$((failed + 1))
  else
    echo "ok   $name (exit $got)"
  fi
}

check "version" 0 "canctl " -- --version
check "sim reset" 0 "reset" -- --bus "$state" sim reset
check "scan" 0 "4 node(s) on sim" -- --bus "$state" scan
check "sdo read" 0 "251" -- --bus "$state" sdo read 1 0x1018:1 --type u32
check "sdo read segmented" 0 "CAN-2057C" -- --bus "$state" sdo read 10 1008
check "sdo write --verify" 0 "written and verified" -- --bus "$state" sdo write 5 1017 100 --verify
check "value out of range: exit 2" 2 "use -128 to 10" -- --bus "$state" sdo write 1 6060 99
check "no answer: exit 3" 3 "node 99" -- --bus "$state" --timeout 100ms sdo read 99 1000
check "SDO abort: exit 4" 4 "0x06020000" -- --bus "$state" sdo read 1 0x5555
check "lss assign" 0 "3 device(s) given a node-id" -- --bus "$state" lss assign --start 20
check "config dump" 0 "" -- --bus "$state" config dump 5 --out sensor.dcf
check "config diff" 0 "" -- --bus "$state" config diff 20 sensor.dcf
check "no SocketCAN here: exit 2" 2 "SocketCAN is Linux's" -- --bus can0 scan
check "no pty here: exit 2" 2 "pseudo-terminal" -- --bus "$state" sim --epos2-rs232
check "no bus: exit 2" 2 "no bus given" -- scan
(cd "$work" && COMPLETE=fish wine "$exe" -- canctl --bus "$state" nmt start '') >"$work/out" 2>&1 </dev/null || true
if grep -q '^5	' "$work/out" && grep -q '^all' "$work/out"; then
  echo "ok   completion offers the scanned node-ids"
else
  echo "FAIL completion:"; sed 's/^/    /' "$work/out"; failed=$((failed + 1))
fi

rm -rf "$work"
[ "$failed" = 0 ] || { echo "windows-smoke: $failed failed"; exit 1; }
echo "windows-smoke: all passed under wine"
