#!/usr/bin/env bash
# scripts/dist.sh: every release artifact of the checked-out commit, into dist/.
#
#   canctl-VERSION-TARGET.tar.gz   Linux: static binary, README, licences, man pages, completions
#   canctl-VERSION-x86_64-pc-windows-gnu.zip   canctl.exe, README, licences, PowerShell completion
#   canctl_VERSION_ARCH.deb        amd64, arm64, armhf: binary, man pages, bash/zsh/fish completion
#   canctl-VERSION-TARGET.debug    the debug info split off the shipped (stripped) binary
#   SHA256SUMS                     over all of the above
#
# Linux targets are static: musl for x86_64 and aarch64; for armv7 hard-float (Raspberry Pi
# OS 32-bit) glibc linked statically, as this toolchain's rustup has no armv7 musl std.
# Linkers and objcopy are Debian's cross toolchains (.ci/run installs them; see
# TARGETS below for which); the .deb is made by dpkg-deb.
#
# Reproducible: the same commit builds the same bytes. SOURCE_DATE_EPOCH (the commit's
# time) dates every archive member, build paths are remapped (/canctl, /cargo), archives
# are sorted and carry no owner. Compare two builds with `sha256sum -c SHA256SUMS`.
# The Windows build makes its import libraries with scripts/dlltool-reproducible and links
# with scripts/mingw-link-reproducible: the order of the DLLs in the .exe's import table
# followed the names of rustc's random temporary directories (dlltool named symbols after
# them) and the path of the target directory (ld orders the import tables by the paths of
# the input files); see there. dist-check.sh repro compares every file.
#
# Environment: DIST_TARGETS (default: all four triples below; separated by spaces or
# newlines) builds a subset;
# CARGO_TARGET_DIR as usual. Refuses a tree with uncommitted changes (the artifacts would
# name a commit they were not built from) unless DIST_ALLOW_DIRTY=1.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

# triple  deb-arch  linker  objcopy  extra-rustflags
TARGETS="
x86_64-unknown-linux-musl     amd64  cc                      objcopy                     -
aarch64-unknown-linux-musl    arm64  aarch64-linux-gnu-gcc   aarch64-linux-gnu-objcopy   -
armv7-unknown-linux-gnueabihf armhf  arm-linux-gnueabihf-gcc arm-linux-gnueabihf-objcopy -Ctarget-feature=+crt-static
x86_64-pc-windows-gnu         -      x86_64-w64-mingw32-gcc  x86_64-w64-mingw32-objcopy  -
"
known=$(awk 'NF {print $1}' <<<"$TARGETS")
# One triple a line: the loop below matches whole lines.
wanted=$(tr -s ' \t' '\n\n' <<<"${DIST_TARGETS:-$known}" | sed '/^$/d')

die() { echo "dist: $*" >&2; exit 1; }
for t in $wanted; do
  grep -qxF "$t" <<<"$known" || die "unknown target '$t' in DIST_TARGETS (known: $(echo $known))"
done

version=$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -n1)
[ -n "$version" ] || die "no version in Cargo.toml"
if git rev-parse --git-dir >/dev/null 2>&1; then
  commit=$(git rev-parse HEAD)
  if [ -n "$(git status --porcelain --untracked-files=no)" ]; then
    [ "${DIST_ALLOW_DIRTY:-0}" = 1 ] || die "uncommitted changes: commit first (or DIST_ALLOW_DIRTY=1 for a trial build)"
    export CANCTL_COMMIT="${commit:0:12}-dirty"
  fi
  export SOURCE_DATE_EPOCH=${SOURCE_DATE_EPOCH:-$(git log -1 --format=%ct)}
else
  [ -n "${SOURCE_DATE_EPOCH:-}" ] || die "not a git checkout: set SOURCE_DATE_EPOCH (and CANCTL_COMMIT)"
fi
# Archive dates and zip's DOS times do not depend on who builds where.
export TZ=UTC LC_ALL=C
umask 022

target_dir=${CARGO_TARGET_DIR:-$root/target}
[[ $target_dir == /* ]] || target_dir=$root/$target_dir
cargo_home=${CARGO_HOME:-$HOME/.cargo}
out=$root/dist
rm -rf "$out"
mkdir -p "$out"
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT

# Every archive member: owned by root, dated SOURCE_DATE_EPOCH, in name order.
tar_gz() {  # DIR(relative to $stage) OUT
  find "$stage/$1" -exec touch -h -d "@$SOURCE_DATE_EPOCH" {} +
  tar -C "$stage" --sort=name --owner=0 --group=0 --numeric-owner --format=gnu \
    --mtime="@$SOURCE_DATE_EPOCH" -cf - "$1" | gzip -9n > "$2"
}

# The files every archive carries beside the binary.
docs_into() {  # DIR
  install -m 644 README.md LICENSE-MIT LICENSE-APACHE "$1/"
}

build() {  # TRIPLE LINKER EXTRA_RUSTFLAGS -> path of the binary
  local triple=$1 linker=$2 extra=$3 env_triple
  env_triple=$(tr 'a-z-' 'A-Z_' <<<"$triple")
  local flags="--remap-path-prefix=$root=/canctl --remap-path-prefix=$cargo_home=/cargo"
  [ "$extra" = - ] || flags+=" $extra"
  local link=(env "CARGO_TARGET_${env_triple}_LINKER=$linker")
  # The .exe's import table followed rustc's random temporary directories and the target
  # directory's path: scripts/dlltool-reproducible and scripts/mingw-link-reproducible say how.
  if [[ $triple == *windows-gnu ]]; then
    flags+=" -Cdlltool=$root/scripts/dlltool-reproducible"
    link=(env "CARGO_TARGET_${env_triple}_LINKER=$root/scripts/mingw-link-reproducible"
      "CANCTL_LINKER=$linker" "CANCTL_LINK_DIR=$target_dir")
  fi
  # RUSTFLAGS, not target.*.rustflags: the remapping must reach every crate.
  "${link[@]}" RUSTFLAGS="$flags" \
    cargo build --locked --quiet --profile dist --target "$triple" --bin canctl >&2
  local exe=canctl
  [[ $triple == *windows* ]] && exe=canctl.exe
  echo "$target_dir/$triple/dist/$exe"
}

# Ship it stripped; the debug info goes beside it, linked by name and checksum (gdb finds
# it through .gnu_debuglink when both lie in one directory).
split_debug() {  # OBJCOPY BIN SHIPPED DEBUG
  local objcopy=$1 bin=$2 shipped=$3 debug=$4
  local compress=--compress-debug-sections=zlib
  [[ $bin == *.exe ]] && compress=   # binutils compresses ELF sections only
  "$objcopy" --only-keep-debug $compress "$bin" "$debug"
  "$objcopy" --strip-all --add-gnu-debuglink="$debug" "$bin" "$shipped"
  chmod 755 "$shipped"; chmod 644 "$debug"
}

deb() {  # ARCH BINARY OUT
  local arch=$1 bin=$2 pkg=$stage/deb-$1
  rm -rf "$pkg"
  install -D -m 755 "$bin" "$pkg/usr/bin/canctl"
  install -d "$pkg/usr/share/man/man1"
  for page in man/*.1; do gzip -9n < "$page" > "$pkg/usr/share/man/man1/$(basename "$page").gz"; done
  install -D -m 644 completions/canctl.bash "$pkg/usr/share/bash-completion/completions/canctl"
  install -D -m 644 completions/_canctl "$pkg/usr/share/zsh/vendor-completions/_canctl"
  install -D -m 644 completions/canctl.fish "$pkg/usr/share/fish/vendor_completions.d/canctl.fish"
  install -d "$pkg/usr/share/doc/canctl"
  {
    echo "Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/"
    echo "Upstream-Name: canctl"
    echo
    echo "Files: *"
    echo "Copyright: 2026 The canctl authors"
    echo "License: MIT or Apache-2.0"
    echo " On Debian systems the Apache License 2.0 is in /usr/share/common-licenses/Apache-2.0."
    echo " The MIT licence:"
    echo " ."
    sed 's/^$/./; s/^/ /' LICENSE-MIT
  } > "$pkg/usr/share/doc/canctl/copyright"
  gzip -9n < README.md > "$pkg/usr/share/doc/canctl/README.md.gz"
  install -d "$pkg/DEBIAN"
  cat > "$pkg/DEBIAN/control" <<EOF
Package: canctl
Version: $version
Architecture: $arch
Maintainer: The canctl authors <canctl@users.noreply.invalid>
Installed-Size: $(find "$pkg/usr" -type f -printf '%s\n' | awk '{s += $1} END {print int((s + 1023) / 1024)}')
Section: utils
Priority: optional
Description: commission CANopen drives and sensors
 Scan a CANopen network, read and write objects (SDO), drive NMT and LSS, apply
 and compare device configurations (DCF), over SocketCAN, slcan adapters, a maxon
 EPOS2 on RS232 or USB, or a built-in simulated network. Static binary.
EOF
  find "$pkg" -exec touch -h -d "@$SOURCE_DATE_EPOCH" {} +
  # dpkg-deb dates the ar members by SOURCE_DATE_EPOCH and sorts the tar members itself.
  dpkg-deb --root-owner-group -Zxz --build "$pkg" "$3" >/dev/null
}

start=$SECONDS
while read -r triple arch linker objcopy extra; do
  [ -n "$triple" ] && grep -qxF "$triple" <<<"$wanted" || continue
  command -v "$linker" >/dev/null && command -v "$objcopy" >/dev/null \
    || die "$triple needs $linker and $objcopy (Debian: see .ci/run), and 'rustup target add $triple'"
  t0=$SECONDS
  bin=$(build "$triple" "$linker" "$extra")
  name=canctl-$version-$triple
  mkdir -p "$stage/$name"
  if [ "$arch" = - ]; then   # Windows: a zip, as Windows users expect
    split_debug "$objcopy" "$bin" "$stage/$name/canctl.exe" "$out/$name.debug"
    docs_into "$stage/$name"
    install -m 644 completions/_canctl.ps1 "$stage/$name/"
    find "$stage/$name" -exec touch -h -d "@$SOURCE_DATE_EPOCH" {} +
    (cd "$stage" && find "$name" | sort | zip -q -X -D -9 "$out/$name.zip" -@)
  else
    split_debug "$objcopy" "$bin" "$stage/$name/canctl" "$out/$name.debug"
    docs_into "$stage/$name"
    mkdir -p "$stage/$name/man" "$stage/$name/completions"
    install -m 644 man/*.1 "$stage/$name/man/"
    install -m 644 completions/canctl.bash completions/_canctl completions/canctl.fish "$stage/$name/completions/"
    tar_gz "$name" "$out/$name.tar.gz"
    deb "$arch" "$stage/$name/canctl" "$out/canctl_${version}_$arch.deb"
  fi
  echo "dist: $triple in $((SECONDS - t0)) s" >&2
done <<<"$TARGETS"
[ -n "$(ls "$out")" ] || die "no target built (DIST_TARGETS: '${DIST_TARGETS:-}')"
(cd "$out" && sha256sum -- * > SHA256SUMS)
echo "dist: $(ls "$out" | wc -l) files in dist/ in $((SECONDS - start)) s (commit ${commit:-$CANCTL_COMMIT}, SOURCE_DATE_EPOCH=$SOURCE_DATE_EPOCH)" >&2
