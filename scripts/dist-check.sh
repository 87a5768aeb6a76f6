#!/usr/bin/env bash
# dist-check.sh [STEP...]: prove the artifacts in dist/ (built by scripts/dist.sh) work where
# they are meant to. Steps (default: all, in this order):
#   sums     sha256sum -c SHA256SUMS; every Linux binary static, stripped, without build paths
#   native   the x86_64 binary on the sim and through ptys (scripts/binary-smoke.sh)
#   qemu     the aarch64 and armv7 binaries the same way, under qemu-user
#   vcan     the aarch64 binary under qemu-user on vcan0 in the kernel-test VM, against the
#            python-canopen device of the kernel tests: scan, SDO read and verified write, NMT
#   windows  the .exe from the zip under wine (scripts/windows-smoke.sh)
#   deb      each .deb on a clean Debian root (debootstrap): man canctl, bash completion,
#            dpkg -r leaves no file behind
#   crate    cargo publish --dry-run of every crate of the workspace (each verified against the
#            packages of the ones below it); the library's docs without the cli feature (docs.rs)
#   repro    a second build of every target (DIST_REPRO_TARGETS, default all of dist.sh's)
#            from a clone in another directory and another target dir, each file compared
#            byte for byte with dist/: tarballs, .debs, the Windows zip, debug files, sums
# Each step prints its time. Needs root for deb (chroot), as .ci/run has.
# qemu-user translates no SOL_CAN_RAW socket option (ENOPROTOOPT): canctl then goes on
# without error frames and kernel filters, as it says, so the vcan step is a real SocketCAN
# run of the ARM code; a bus-off can only be seen on an ARM kernel.
set -euo pipefail
cd "$(dirname "$0")/.."
steps=${*:-sums native qemu vcan windows deb crate repro}
version=$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -n1)
d=$PWD/dist
u=$(mktemp -d)
trap 'rm -rf "$u"' EXIT
bin() { echo "$u/canctl-$version-$1/canctl"; }
failed=

# The binaries are in the tarballs: unpack each once, as a user would.
unpacked=0
unpack() {
  local t
  [ $unpacked = 0 ] || return 0
  unpacked=1
  for t in x86_64-unknown-linux-musl aarch64-unknown-linux-musl armv7-unknown-linux-gnueabihf; do
    tar -C "$u" -xzf "$d/canctl-$version-$t.tar.gz" || return 1
  done
}

step_sums() {
  unpack || return 1
  (cd "$d" && sha256sum -c --quiet SHA256SUMS) || return 1
  echo "SHA256SUMS: every file matches"
  local t b kind
  for t in x86_64-unknown-linux-musl aarch64-unknown-linux-musl armv7-unknown-linux-gnueabihf; do
    b=$(bin "$t")
    # Not `tee /dev/stderr`: reopened, a log file given as stderr is written from its start.
    kind=$(file -b "$b")
    echo "$kind"
    grep -qE "(statically|static-pie) linked.*, stripped" <<<"$kind" || { echo "$b: not static and stripped"; return 1; }
    if grep -aqE "$PWD|$HOME|/root/|/work/|/home/" "$b"; then
      echo "$b holds a path of the build machine:"; grep -aoE "($PWD|$HOME|/root/|/work/|/home/)[^ ]{0,60}" "$b" | head -5
      return 1
    fi
  done
  echo "no build-machine path in the binaries"
}

step_native() { unpack && scripts/binary-smoke.sh "$(bin x86_64-unknown-linux-musl)"; }

# qemu-user does not translate the TCGETS2 ioctl that opening a serial port takes: serialport
# (4.10) reads and sets the bit rate only by termios2 on Linux, with no fallback to TCGETS.
# Debian 12's 7.2 answers ENOSYS ("cannot open /dev/pts/N: Function not implemented"), the
# backports 10.0.2 that CI installs ENOTTY; a static aarch64/armv7 C probe on a pty under
# 10.0.2 gets TCGETS answered and TCGETS2 refused. linux-user's termios2 support came after
# 10.1 (distributions patch 10.1.2 for glibc 2.42, which uses TCGETS2 in isatty); there is
# no qemu-system-aarch64 here for an ARM kernel. So the ARM binary serves the pty device
# sides (sim --slcan, --epos2-rs232) and the x86_64 one is the client there; the client's
# only ARM-specific part left unrun is serialport's termios2 ioctls, which ARM kernels have.
step_qemu() {
  unpack || return 1
  local native; native=$(bin x86_64-unknown-linux-musl)
  local rc=0
  SMOKE_PTY_CLIENT=$native scripts/binary-smoke.sh qemu-aarch64-static "$(bin aarch64-unknown-linux-musl)" || rc=1
  SMOKE_PTY_CLIENT=$native scripts/binary-smoke.sh qemu-arm-static "$(bin armv7-unknown-linux-gnueabihf)" || rc=1
  return $rc
}

step_vcan() {
  unpack || return 1
  local arm; arm="qemu-aarch64-static $(bin aarch64-unknown-linux-musl)"
  VMCAN_TIMEOUT=600 scripts/run-in-vm.sh "set -eu
    cd tests/interop; python3 local_node.py vcan0 20 >/tmp/node.log 2>&1 &
    for i in \$(seq 300); do grep -q READY /tmp/node.log && break; sleep 0.2; done
    grep -q READY /tmp/node.log || { cat /tmp/node.log; exit 1; }
    $arm --version
    $arm --bus vcan0 scan --window 500ms | tee /tmp/scan
    grep -q 'python-canopen LocalNode' /tmp/scan
    [ \"\$($arm --bus vcan0 sdo read 20 0x1000)\" = 401 ] || { echo 'device type not 401'; exit 1; }
    $arm --bus vcan0 sdo write 20 0x1017 200 --verify
    $arm --bus vcan0 nmt start 20
    $arm --bus vcan0 nmt state 20 | tee /tmp/state
    grep -q operational /tmp/state"
}

step_windows() {
  local w rc=0; w=$(mktemp -d)
  unzip -q "$d/canctl-$version-x86_64-pc-windows-gnu.zip" -d "$w" || return 1
  ls "$w"/*/
  scripts/windows-smoke.sh "$w/canctl-$version-x86_64-pc-windows-gnu/canctl.exe" || rc=1
  rm -rf "$w"
  return $rc
}

# A Debian root of the machine's own release, with man and bash-completion. The arm64 and
# armhf packages install there as foreign architectures (they have no dependencies).
step_deb() {
  local r; r=$(mktemp -d /tmp/canctl-debroot.XXXXXX)
  chmod 755 "$r"   # a root only root may enter: man-db's triggers run as user man
  local mirror=${DIST_DEBIAN_MIRROR:-$(grep -hoE '^(URIs:|deb)[[:space:]]+[^[:space:]]+' /etc/apt/sources.list.d/*.sources /etc/apt/sources.list 2>/dev/null \
    | awk '{print $2}' | grep -v security | head -n1)}
  local codename; codename=$(. /etc/os-release && echo "$VERSION_CODENAME")
  debootstrap --variant=minbase --include=man-db,bash-completion "$codename" "$r" "$mirror" >"$r.log" 2>&1 \
    || { tail -n 20 "$r.log"; return 1; }
  chroot "$r" dpkg --add-architecture arm64
  chroot "$r" dpkg --add-architecture armhf
  local arch deb rc=0
  for arch in amd64 arm64 armhf; do
    deb=canctl_${version}_$arch.deb
    echo "-- $deb"
    cp "$d/$deb" "$r/tmp/"
    (cd "$r" && find . -xdev \( -path ./proc -o -path ./tmp -o -path ./var/lib/dpkg -o -path ./var/log -o -path ./var/cache \) -prune -o -print | sort) >"$r.before"
    chroot "$r" dpkg -i "/tmp/$deb" || { rc=1; continue; }
    chroot "$r" dpkg -L canctl | sed 's/^/  /'
    echo "\$ man canctl | head -n 4"
    chroot "$r" env MANPAGER=cat COLUMNS=80 man canctl 2>&1 | head -n 4 | sed 's/^/  /'
    chroot "$r" env MANPAGER=cat man canctl-sdo-read | grep -q "Read an object (SDO upload)" || { echo "FAIL: man canctl-sdo-read"; rc=1; }
    # Debian's ~/.bashrc turns bash-completion on; it loads a command's completion on the
    # first Tab (_completion_loader), which is what this asks for.
    echo "\$ bash -ic 'complete -p canctl'"
    chroot "$r" env HOME=/tmp/home bash -c 'mkdir -p ~ && cp /etc/skel/.bashrc ~ && bash -ic "_completion_loader canctl; complete -p canctl"' 2>/dev/null \
      | sed 's/^/  /' | tee "$r.complete"
    grep -q "complete .* canctl$" "$r.complete" || { echo "FAIL: no bash completion for canctl"; rc=1; }
    chroot "$r" dpkg -r canctl || rc=1
    (cd "$r" && find . -xdev \( -path ./proc -o -path ./tmp -o -path ./var/lib/dpkg -o -path ./var/log -o -path ./var/cache \) -prune -o -print | sort) >"$r.after"
    if ! diff "$r.before" "$r.after"; then echo "FAIL: dpkg -r left files behind (above)"; rc=1; else echo "dpkg -r: the root holds the same files as before the install"; fi
    rm -rf "$r/tmp/$deb" "$r/tmp/home"
  done
  rm -rf "$r" "$r".*
  return $rc
}

step_crate() {
  local log; log=$(mktemp)
  # Each crate is verified against the packages of the ones below it, which cargo treats as
  # registry crates: never unpacked again while $CARGO_HOME/registry/src/-HASH/ (HASH of the
  # package folder's path) holds them, never rebuilt while the target folder holds a build of
  # them. A second run in the same tree (a developer's, a reused CI machine) would verify
  # against the first run's sources. So our crates' unpackings and builds are removed before
  # and after; the target folder stays the tree's own, whose builds of the crates.io
  # dependencies (the test suite's, in CI) the verification reuses.
  local unpacked="${CARGO_HOME:-$HOME/.cargo}/registry/src"
  local built=${CARGO_TARGET_DIR:-target}/debug
  forget_our_crates() {
    rm -rf "$unpacked"/-*/canctl-* "$built"/.fingerprint/canctl-* "$built"/build/canctl-* \
      "$built"/deps/libcanctl* "$built"/deps/canctl*
  }
  forget_our_crates
  # The package leaves tests, benchmarks and the tests' canctl-seams out on purpose: cargo's
  # notes about that are noise.
  cargo publish --locked --dry-run --workspace >"$log" 2>&1 || {
    cat "$log"; rm -f "$log"; forget_our_crates; echo "FAIL: cargo publish --dry-run --workspace"; return 1
  }
  grep -vE "^warning: (ignoring (test|benchmark|example|binary .canctl-seams.)|manifest has no)|^  (\||= note)" "$log"
  rm -f "$log"; forget_our_crates
  cargo doc --locked --quiet --lib --no-deps --no-default-features
  echo "the library's docs build without the cli feature (docs.rs)"
}

# Another directory, another target dir, the same commit: the same bytes.
step_repro() {
  local w
  w=$(mktemp -d /tmp/canctl-repro.XXXXXX)
  # Its build is gigabytes: gone once the files are made, and gone on a failure too.
  git clone --quiet --no-hardlinks . "$w/src" || { rm -rf "$w"; return 1; }
  (cd "$w/src" && export CARGO_TARGET_DIR="$w/target" && if [ -n "${DIST_REPRO_TARGETS:-}" ]; then
    export DIST_TARGETS=$DIST_REPRO_TARGETS; fi && scripts/dist.sh) || { rm -rf "$w"; return 1; }
  rm -rf "$w/target"
  echo "second build in $w/src:"; (cd "$w/src/dist" && ls -l)
  local f rc=0 n=0
  for f in "$w"/src/dist/*; do
    # A subset's SHA256SUMS lists fewer files than dist/'s: compare it only for a full build.
    [ "$(basename "$f")" = SHA256SUMS ] && [ -n "${DIST_REPRO_TARGETS:-}" ] && continue
    if cmp "$f" "$d/$(basename "$f")"; then echo "identical: $(basename "$f")"; n=$((n + 1)); else rc=1; fi
  done
  [ $n -gt 0 ] || { echo "FAIL: the second build made no file"; rc=1; }
  rm -rf "$w"
  return $rc
}

for s in $steps; do
  echo "== dist-check: $s"
  t0=$SECONDS
  if "step_$s"; then echo "== dist-check: $s passed in $((SECONDS - t0)) s"; else
    echo "== dist-check: $s FAILED after $((SECONDS - t0)) s"; failed+=" $s"; fi
done
[ -z "$failed" ] || { echo "dist-check: failed:$failed"; exit 1; }
echo "dist-check: all passed ($steps)"
