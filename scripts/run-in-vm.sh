#!/usr/bin/env bash
# run-in-vm.sh 'COMMAND'
#
# canctl's kernel-test harness, adapted from shared/tools/run-in-vm.sh (the mirror
# look-up no longer aborts on a machine without /etc/apt/sources.list).
#
# Boot a small QEMU VM running a stock Debian kernel (which has SocketCAN and
# vcan as modules), bring up vcan0, run COMMAND with bash from the current
# working directory (same path inside the VM) and exit with COMMAND's status.
#
# Inside the VM:
#   /            host root, 9p, read-only
#   $PWD         host $PWD, 9p, read-write (writes land on the host)
#   /tmp /var/tmp /root /home   overlay: host content visible, writes stay in the VM
#   /run /dev/shm               tmpfs
#   vcan0 (up; see VMCAN_VCAN), lo (up); modules can can-raw can-bcm can-isotp can-gw can-dev vcan loaded
#   the host's environment variables (except a few) are exported again
#   other modules: modprobe -d "$VMCAN_KROOT" can-j1939   (no /lib/modules on the host)
#   if python3 on the host is a pyenv shim, the real interpreter's dir goes first
#   on PATH (a shim costs ~10 s per python start under TCG)
#   stdin is /dev/null; stdout/stderr of COMMAND stream to ours, kernel console
#   goes to a temp log that is printed (tail) only when the VM itself fails
#
# First run installs what is missing (Debian packages qemu-system-x86,
# busybox-static, kmod, iproute2, can-utils; qemu-system-x86 from backports when
# the machine already has qemu-utils from backports, see below) and downloads +
# unpacks the Debian kernel package into $VMCAN_CACHE (the kernel is never
# installed on the host). Later runs need no network.
#
# Exit status: COMMAND's status; 124 if VMCAN_TIMEOUT expired; 125 if the VM
# itself failed (no status came back); 126 setup problem.
#
# Environment knobs:
#   VMCAN_TIMEOUT  seconds for the whole VM run (default 600)
#   VMCAN_ACCEL    auto|kvm|tcg (default auto: kvm only when /dev/kvm is usable
#                  and is not the PVM backend, which cannot run stock kernels)
#   VMCAN_MEM      MiB (default 1024)      VMCAN_CPUS  vCPUs (default 2)
#   VMCAN_ROOT_RW  1: export host / read-write instead of the layout above
#   VMCAN_CACHE    cache dir (default /var/cache/vmcan)
#   VMCAN_KERNEL_PKG  Debian kernel package (default: what linux-image-amd64 depends on)
#   VMCAN_VERBOSE  1: show the VM console (kernel + init log) on stderr
#   VMCAN_SETUP_ONLY 1: only install/prepare, do not boot
#   VMCAN_QEMU_EXTRA extra qemu arguments (word-split)
#   VMCAN_VCAN     vcan interfaces to create and bring up (default "vcan0")
set -euo pipefail

VMCAN_TIMEOUT=${VMCAN_TIMEOUT:-600}
VMCAN_ACCEL=${VMCAN_ACCEL:-auto}
VMCAN_MEM=${VMCAN_MEM:-1024}
VMCAN_CPUS=${VMCAN_CPUS:-2}
VMCAN_ROOT_RW=${VMCAN_ROOT_RW:-0}
VMCAN_CACHE=${VMCAN_CACHE:-/var/cache/vmcan}
VMCAN_VERBOSE=${VMCAN_VERBOSE:-0}
VMCAN_SETUP_ONLY=${VMCAN_SETUP_ONLY:-0}
VMCAN_VCAN=${VMCAN_VCAN:-vcan0}
# bump when the initramfs layout/init changes, to force a rebuild
INITRAMFS_REV=4

die() { echo "run-in-vm: $*" >&2; exit 126; }
log() { [ "$VMCAN_VERBOSE" = 1 ] && echo "run-in-vm: $*" >&2 || true; }

if [ "$VMCAN_SETUP_ONLY" != 1 ]; then
  [ $# -eq 1 ] || die "usage: $0 'COMMAND'"
fi
COMMAND=${1:-true}
[ "$(id -u)" = 0 ] || die "must run as root (apt-get, 9p export of /)"

# ---------------------------------------------------------------- prerequisites
APT_UPDATED=0
apt_install() {
  # apt_install pkg... ; idempotent, runs 'apt-get update' at most once
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "run-in-vm: installing ${missing[*]}" >&2
  apt_update_once
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends --no-remove "${missing[@]}" \
    > "$VMCAN_CACHE/apt.log" 2>&1 || { cat "$VMCAN_CACHE/apt.log" >&2; die "apt-get install failed"; }
}

installed_version() {  # prints the version if PKG is installed, else nothing
  dpkg-query -W -f='${db:Status-Status} ${Version}\n' "$1" 2>/dev/null | awk '$1=="installed"{print $2}'
}

# This machine image ships qemu-utils 1:10.x from bookworm-backports, and that
# package Breaks qemu-system-common (<< 1:8.0): a plain
# 'apt-get install qemu-system-x86' (bookworm's 7.2) silently REMOVES qemu-utils.
# So when qemu-utils >= 1:8 is installed, take qemu-system-x86 of the very same
# version from backports, through a private apt config (the system's apt sources
# stay untouched), and always pass --no-remove.
install_qemu_matching_backports() {  # VERSION
  local v=$1 codename mirror=${VMCAN_DEBIAN_MIRROR:-}
  # the mirror this machine already uses (its apt sources), unless told otherwise
  if [ -z "$mirror" ]; then
    mirror=$( { grep -hoE '^URIs:[[:space:]]*[^[:space:]]+' /etc/apt/sources.list.d/*.sources 2>/dev/null | awk '{print $2}';
               grep -hoE '^deb[[:space:]]+[^[:space:]]+' /etc/apt/sources.list 2>/dev/null | awk '{print $2}'; } \
             | grep -v security | head -n 1 | sed -E 's#/debian/?$##') || true
    [ -n "$mirror" ] || die "no Debian mirror found in the apt sources; set VMCAN_DEBIAN_MIRROR"
  fi
  codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")
  local B="$VMCAN_CACHE/apt-bpo"
  mkdir -p "$B/lists/partial" "$B/archives/partial"
  printf '%s\n' "deb $mirror/debian $codename main" \
    "deb $mirror/debian $codename-updates main" \
    "deb $mirror/debian-security $codename-security main" \
    "deb $mirror/debian $codename-backports main" > "$B/sources.list"
  local o=(-o "Dir::Etc::sourcelist=$B/sources.list" -o Dir::Etc::sourceparts=- -o "Dir::State::lists=$B/lists"
           -o "Dir::Cache::archives=$B/archives" -o APT::Sandbox::User=root)
  echo "run-in-vm: installing qemu-system-x86 $v from $codename-backports (matches qemu-utils)" >&2
  { apt-get "${o[@]}" update -qq &&
    DEBIAN_FRONTEND=noninteractive apt-get "${o[@]}" install -y -qq --no-install-recommends --no-remove \
      -t "$codename-backports" "qemu-system-x86=$v" "qemu-system-common=$v" "qemu-system-data=$v"
  } > "$VMCAN_CACHE/apt.log" 2>&1 || { cat "$VMCAN_CACHE/apt.log" >&2; die "installing qemu-system-x86 $v failed"; }
  rm -f "$B/archives/"*.deb
}

ensure_prereqs() {
  # qemu-system-x86: the VM; busybox-static: the initramfs (must be static);
  # kmod: depmod for the unpacked kernel; iproute2: 'ip' used inside the VM
  # (from the host root); can-utils: cansend/candump for tests.
  # Fast path: all the files are there -> no dpkg/apt call at all.
  [ -x /usr/bin/qemu-system-x86_64 ] && [ -x /bin/busybox ] && [ -x /sbin/depmod ] \
    && [ -x /sbin/ip ] && [ -x /usr/bin/cansend ] && [ -e /usr/share/doc/busybox-static ] && return 0
  apt_install busybox-static kmod iproute2 can-utils
  if [ ! -x /usr/bin/qemu-system-x86_64 ]; then
    local uv; uv=$(installed_version qemu-utils)
    if [ -n "$uv" ] && dpkg --compare-versions "$uv" ge 1:8; then
      install_qemu_matching_backports "$uv"
    else
      apt_install qemu-system-x86
    fi
  fi
}

# ---------------------------------------------------------------- kernel
# The kernel .deb is only unpacked (dpkg-deb -x), never installed: installing it
# would pull initramfs-tools and run postinst hooks (depmod, update-initramfs).
apt_update_once() { [ $APT_UPDATED = 1 ] || { apt-get update -qq >&2; APT_UPDATED=1; }; }
resolve_kernel_pkg() {
  apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/{print $2; exit}'
}
ensure_kernel() {
  local cur="$VMCAN_CACHE/kernel-current"
  if [ -L "$cur" ] && [ -e "$cur/.complete" ] && [ -z "${VMCAN_KERNEL_PKG:-}" ]; then
    return 0   # cached: no network needed (rm -rf $VMCAN_CACHE to pick up a newer kernel)
  fi
  local pkg=${VMCAN_KERNEL_PKG:-}
  if [ -z "$pkg" ]; then
    pkg=$(resolve_kernel_pkg)
    [ -n "$pkg" ] || { apt_update_once; pkg=$(resolve_kernel_pkg); }
    [ -n "$pkg" ] || die "cannot resolve linux-image-amd64 with apt-cache"
  fi
  local dir="$VMCAN_CACHE/$pkg"
  if [ ! -e "$dir/.complete" ]; then
    echo "run-in-vm: fetching kernel package $pkg" >&2
    rm -rf "$dir" "$dir.tmp"; mkdir -p "$dir.tmp/deb"
    if ! ( cd "$dir.tmp/deb" && apt-get download -qq "$pkg" ) >/dev/null 2>&1; then
      # stale package lists: refresh, re-resolve (unless pinned) and retry once
      apt_update_once
      if [ -z "${VMCAN_KERNEL_PKG:-}" ]; then
        pkg=$(resolve_kernel_pkg); rm -rf "$dir.tmp"; dir="$VMCAN_CACHE/$pkg"; mkdir -p "$dir.tmp/deb"
      fi
      ( cd "$dir.tmp/deb" && apt-get download -qq "$pkg" ) >&2 || die "apt-get download $pkg failed"
    fi
    dpkg-deb -x "$dir.tmp/deb/"*.deb "$dir.tmp/root"
    rm -rf "$dir.tmp/deb"
    local kver; kver=$(ls "$dir.tmp/root/lib/modules" | head -n1)
    [ -n "$kver" ] && [ -e "$dir.tmp/root/boot/vmlinuz-$kver" ] || die "unexpected layout in $pkg"
    # .debs do not ship modules.dep (postinst runs depmod); make it so that
    # 'modprobe -d $VMCAN_KROOT MODULE' works inside the VM
    depmod -b "$dir.tmp/root" "$kver"
    echo "$kver" > "$dir.tmp/kver"
    extract_vmlinux "$dir.tmp/root/boot/vmlinuz-$kver" "$dir.tmp/vmlinux" "$dir.tmp/root/boot/config-$kver"
    touch "$dir.tmp/.complete"
    mv "$dir.tmp" "$dir"
  fi
  ln -sfn "$pkg" "$cur"
}

# Booting the uncompressed ELF vmlinux through its PVH entry point skips the
# firmware's real-mode path and the in-guest decompression (about 3 s under TCG).
# Needs CONFIG_PVH=y (Debian: yes). Same idea as the kernel's extract-vmlinux.
extract_vmlinux() {  # bzImage out config
  local img=$1 out=$2 cfg=$3 magic cmd off
  grep -q '^CONFIG_PVH=y' "$cfg" || return 0
  for magic in 'xz:\xfd7zXZ\x00' 'zstd:\x28\xb5\x2f\xfd' 'gzip:\x1f\x8b\x08'; do
    cmd=${magic%%:*}
    off=$(LC_ALL=C grep -obUaP "${magic#*:}" "$img" 2>/dev/null | head -n1 | cut -d: -f1) || true
    [ -n "$off" ] || continue
    command -v "$cmd" >/dev/null || continue
    tail -c +$((off + 1)) "$img" | "$cmd" -dc > "$out.tmp" 2>/dev/null || true
    if [ "$(head -c 4 "$out.tmp" | od -An -tx1 | tr -d ' ')" = 7f454c46 ]; then
      mv "$out.tmp" "$out"; return 0
    fi
  done
  rm -f "$out.tmp"   # no vmlinux: boot the bzImage (slower, same result)
}

# ---------------------------------------------------------------- initramfs
# Modules loaded by /init, in dependency order (9p needs netfs+fscache; vcan
# needs can-dev; can-raw/bcm/isotp/gw need can).
MODULES="virtio_ring virtio virtio_pci_modern_dev virtio_pci_legacy_dev virtio_pci
virtio_console netfs fscache 9pnet 9pnet_virtio 9p overlay
can can-raw can-bcm can-isotp can-gw can-dev vcan"

write_init() {
cat > "$1" <<'INIT'
#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
RET=
say() { echo "vmcan-init: $*" > /dev/ttyS0; }
finish() {  # finish STATUS
  [ -n "$RET" ] && echo "$1" > "$RET"
  sync
  poweroff -f
  sleep 10
}
die() { say "FATAL: $*"; finish 125; }

for m in $(cat /vmcan/modules); do
  insmod "/vmcan/mod/$m.ko" 2>/dev/null || say "insmod $m failed"
done
# virtio-serial ports by name (no udev here)
mkdir -p /dev/virtio-ports
for p in /sys/class/virtio-ports/*; do
  [ -e "$p/name" ] && ln -sf "/dev/${p##*/}" "/dev/virtio-ports/$(cat "$p/name")"
done
[ -e /dev/virtio-ports/vmcan.ret ] && RET=/dev/virtio-ports/vmcan.ret
. /vmcan/params   # CWD ROOT_RW OVERLAYS VCAN

R=/newroot
mkdir -p $R
O=trans=virtio,version=9p2000.L,msize=512000
if [ "$ROOT_RW" = 1 ]; then
  mount -t 9p -o $O,cache=mmap hostroot $R || die "mount hostroot"
else
  mount -t 9p -o $O,ro,cache=loose hostroot $R || die "mount hostroot"
fi
mount -t proc proc $R/proc
mount -t sysfs sys $R/sys
mount -t devtmpfs dev $R/dev
mkdir -p $R/dev/pts $R/dev/shm 2>/dev/null
mount -t devpts -o gid=5,mode=620,ptmxmode=666 devpts $R/dev/pts
ln -sf /proc/self/fd $R/dev/fd
ln -sf /proc/self/fd/0 $R/dev/stdin
ln -sf /proc/self/fd/1 $R/dev/stdout
ln -sf /proc/self/fd/2 $R/dev/stderr
mount -t tmpfs tmpfs $R/dev/shm
mount -t tmpfs -o mode=755 tmpfs $R/run
if [ "$ROOT_RW" != 1 ]; then
  mkdir -p /ovl
  mount -t tmpfs tmpfs /ovl
  i=0
  for d in $OVERLAYS; do
    [ -d "$R$d" ] || continue
    i=$((i+1)); mkdir -p /ovl/$i/u /ovl/$i/w
    mount -t overlay -o lowerdir=$R$d,upperdir=/ovl/$i/u,workdir=/ovl/$i/w ovl$i $R$d \
      || mount -t tmpfs tmpfs $R$d
  done
  mkdir -p "$R$CWD" 2>/dev/null
  mount -t 9p -o $O,cache=mmap hostcwd "$R$CWD" || die "mount hostcwd $CWD"
fi
mkdir -p $R/run/vmcan
cp /vmcan/run.sh $R/run/vmcan/run.sh

ip link set lo up
for v in $VCAN; do
  chroot $R /sbin/ip link add dev $v type vcan || die "ip link add $v"
  chroot $R /sbin/ip link set up $v || die "ip link set up $v"
done

OUT=/dev/virtio-ports/vmcan.stdout; [ -e $OUT ] || OUT=/dev/ttyS0
ERR=/dev/virtio-ports/vmcan.stderr; [ -e $ERR ] || ERR=/dev/ttyS0
say "running command"
chroot $R /bin/bash /run/vmcan/run.sh < /dev/null > $OUT 2> $ERR
rc=$?
say "command exited with status $rc"
finish $rc
INIT
chmod 755 "$1"
}

ensure_initramfs() {
  local kdir="$VMCAN_CACHE/kernel-current"
  local kver; kver=$(cat "$kdir/kver")
  BASE_CPIO="$kdir/vmcan-base-r$INITRAMFS_REV.cpio"
  [ -s "$BASE_CPIO" ] && return 0
  local st; st=$(mktemp -d)
  mkdir -p "$st"/{bin,proc,sys,dev,newroot,vmcan/mod}
  cp /bin/busybox "$st/bin/busybox"
  case "$(LC_ALL=C ldd "$st/bin/busybox" 2>&1 || true)" in
    *"not a dynamic"*) ;; *) die "/bin/busybox is not static (install busybox-static)" ;;
  esac
  local m f
  for m in $MODULES; do
    f=$(find "$kdir/root/lib/modules/$kver/kernel" -name "$m.ko" -print -quit)
    [ -n "$f" ] || die "module $m not found in kernel package"
    cp "$f" "$st/vmcan/mod/"
  done
  echo $MODULES > "$st/vmcan/modules"
  write_init "$st/init"
  ( cd "$st" && find . -mindepth 1 | busybox cpio -o -H newc 2>/dev/null ) > "$BASE_CPIO.tmp"
  mv "$BASE_CPIO.tmp" "$BASE_CPIO"
  rm -rf "$st"
}

# ---------------------------------------------------------------- main
mkdir -p "$VMCAN_CACHE"
exec 9>"$VMCAN_CACHE/.lock"
flock 9   # serialise setup between concurrent runs
ensure_prereqs
ensure_kernel
ensure_initramfs
flock -u 9
KDIR="$VMCAN_CACHE/kernel-current"
KVER=$(cat "$KDIR/kver")
KIMG="$KDIR/root/boot/vmlinuz-$KVER"
[ -s "$KDIR/vmlinux" ] && KIMG="$KDIR/vmlinux"
[ "$VMCAN_SETUP_ONLY" = 1 ] && { echo "run-in-vm: setup done ($KVER)" >&2; exit 0; }

case "$VMCAN_ACCEL" in
  auto)
    if [ -r /dev/kvm ] && [ -w /dev/kvm ] && [ ! -d /sys/module/kvm_pvm ]; then ACCEL=kvm; else ACCEL=tcg; fi ;;
  kvm|tcg) ACCEL=$VMCAN_ACCEL ;;
  *) die "VMCAN_ACCEL must be auto, kvm or tcg" ;;
esac
if [ $ACCEL = kvm ]; then ACCEL_OPTS=(-accel kvm -cpu host); else ACCEL_OPTS=(-accel tcg,thread=multi -cpu max); fi
if [ $ACCEL = kvm ] && [ -d /sys/module/kvm_pvm ]; then
  echo "run-in-vm: warning: /dev/kvm is the PVM backend (kvm_pvm); stock kernels fail or crawl there, use TCG" >&2
fi

CWD=$(pwd -P)
[ "$CWD" != / ] || [ "$VMCAN_ROOT_RW" = 1 ] || die "run from a directory other than / (or set VMCAN_ROOT_RW=1)"
# pyenv shims are bash scripts that fork pyenv many times: ~10 s per python
# start under TCG. Put the real interpreter's bin dir first on PATH in the VM.
GUEST_PATH_PREFIX=
case "$(command -v python3 || true)" in
  */.pyenv/shims/*) GUEST_PATH_PREFIX=$(dirname "$(python3 -c 'import sys; print(sys.executable)')"): ;;
esac
TMP=$(mktemp -d /tmp/run-in-vm.XXXXXX)
cleanup() { rm -rf "$TMP"; }
trap cleanup EXIT

# per-run initramfs part: the command, environment and mount parameters
mkdir -p "$TMP/st/vmcan"
{
  echo "#!/bin/bash"
  for n in $(compgen -e); do
    case "$n" in PWD|OLDPWD|SHLVL|_|TERM_SESSION_ID) continue ;; esac
    printf 'export %s=%q\n' "$n" "${!n}"
  done
  printf 'export VMCAN_KROOT=%q VMCAN_KVER=%q\n' "$KDIR/root" "$KVER"
  printf 'export PATH=%q\n' "$GUEST_PATH_PREFIX$PATH"
  printf 'cd -- %q || exit 126\n' "$CWD"
  printf 'exec bash -c %q\n' "$COMMAND"
} > "$TMP/st/vmcan/run.sh"
{
  printf 'CWD=%q\n' "$CWD"
  printf 'ROOT_RW=%q\n' "$VMCAN_ROOT_RW"
  printf 'OVERLAYS=%q\n' "/tmp /var/tmp /root /home"
  printf 'VCAN=%q\n' "$VMCAN_VCAN"
} > "$TMP/st/vmcan/params"
( cd "$TMP/st" && find . -mindepth 1 | busybox cpio -o -H newc 2>/dev/null ) > "$TMP/run.cpio"
cat "$BASE_CPIO" "$TMP/run.cpio" > "$TMP/initrd"

FS_OPTS=(-fsdev "local,id=fsroot,path=/,security_model=none,multidevs=remap$([ "$VMCAN_ROOT_RW" = 1 ] || echo ,readonly=on)"
         -device virtio-9p-pci,fsdev=fsroot,mount_tag=hostroot)
if [ "$VMCAN_ROOT_RW" != 1 ]; then
  FS_OPTS+=(-fsdev "local,id=fscwd,path=$CWD,security_model=none,multidevs=remap"
            -device virtio-9p-pci,fsdev=fscwd,mount_tag=hostcwd)
fi
if [ "$VMCAN_VERBOSE" = 1 ]; then LOGLEVEL=${VMCAN_LOGLEVEL:-6}; else LOGLEVEL=1; fi

# The guest's stdout/stderr (and the console when verbose) reach our own
# stdout/stderr through FIFOs relayed by cat: qemu re-opening /proc/self/fd/1
# would get its own file offset and overwrite what we write to a regular file.
RELAY_PIDS=
start_relays() {
  rm -f "$TMP/out" "$TMP/err" "$TMP/con"
  mkfifo "$TMP/out" "$TMP/err"
  cat "$TMP/out" & RELAY_PIDS=$!
  cat "$TMP/err" >&2 & RELAY_PIDS="$RELAY_PIDS $!"
  if [ "$VMCAN_VERBOSE" = 1 ]; then
    mkfifo "$TMP/con"; cat "$TMP/con" >&2 & RELAY_PIDS="$RELAY_PIDS $!"
    CONSOLE="$TMP/con"
  else
    CONSOLE="$TMP/console.log"
  fi
}
stop_relays() {
  # let the relays drain; if qemu never opened a FIFO, its cat is still blocked in open()
  local p alive
  for _ in $(seq 50); do
    alive=0; for p in $RELAY_PIDS; do kill -0 "$p" 2>/dev/null && alive=1; done
    [ $alive = 0 ] && break; sleep 0.1
  done
  for p in $RELAY_PIDS; do kill "$p" 2>/dev/null; wait "$p" 2>/dev/null; done
  RELAY_PIDS=
}

INTERRUPTED=0; QPID=
run_qemu() {  # run_qemu ACCEL_OPTS...  -> sets qrc
  : > "$TMP/ret"
  start_relays
  timeout --kill-after=10 "$VMCAN_TIMEOUT" qemu-system-x86_64 \
    -nodefaults -no-user-config -display none -no-reboot \
    -machine q35 "$@" ${VMCAN_QEMU_EXTRA:-} -smp "$VMCAN_CPUS" -m "$VMCAN_MEM" \
    -kernel "$KIMG" -initrd "$TMP/initrd" \
    -append "console=ttyS0 loglevel=$LOGLEVEL panic=-1 oops=panic rdinit=/init" \
    -chardev "file,id=con,path=$CONSOLE,append=on" -serial chardev:con \
    "${FS_OPTS[@]}" \
    -device virtio-serial-pci \
    -chardev "file,id=out,path=$TMP/out,append=on" -device virtserialport,chardev=out,name=vmcan.stdout \
    -chardev "file,id=err,path=$TMP/err,append=on" -device virtserialport,chardev=err,name=vmcan.stderr \
    -chardev "file,id=ret,path=$TMP/ret" -device virtserialport,chardev=ret,name=vmcan.ret \
    < /dev/null &
  QPID=$!
  wait $QPID; qrc=$?
  # a trapped signal interrupts 'wait': keep waiting until timeout/qemu are gone
  while [ $qrc -gt 128 ] && kill -0 $QPID 2>/dev/null; do wait $QPID; qrc=$?; done
  QPID=
  stop_relays
}
# timeout(1) puts qemu in its own process group, so Ctrl-C would not reach it
trap '[ -n "$QPID" ] && kill -TERM $QPID 2>/dev/null; INTERRUPTED=1' INT TERM HUP

log "accel=$ACCEL kernel=$KVER cwd=$CWD"
set +e
T0=$SECONDS
run_qemu "${ACCEL_OPTS[@]}"
if [ $ACCEL = kvm ] && [ "$VMCAN_ACCEL" = auto ] && [ ! -s "$TMP/ret" ] && [ $INTERRUPTED = 0 ] \
   && [ $((SECONDS - T0)) -lt 5 ]; then
  echo "run-in-vm: KVM start failed (qemu exit $qrc), retrying with TCG" >&2
  ACCEL=tcg; run_qemu -accel tcg,thread=multi -cpu max
fi
set -e
[ $INTERRUPTED = 1 ] && { echo "run-in-vm: interrupted" >&2; exit 130; }
rc=$(tr -dc '0-9' < "$TMP/ret")
if [ -n "$rc" ]; then exit "$rc"; fi
if [ $qrc = 124 ] || [ $qrc = 137 ]; then
  echo "run-in-vm: timed out after ${VMCAN_TIMEOUT}s" >&2; exit 124
fi
echo "run-in-vm: VM failed (qemu exit $qrc, no status from guest)" >&2
[ -f "$TMP/console.log" ] && tail -n 30 "$TMP/console.log" | tr -d '\r' >&2
exit 125
