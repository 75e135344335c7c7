#!/bin/sh
# prepare-sysroot.sh DEB_ARCH DEST PACKAGE...
#
# Unpacks Debian packages of a target architecture (armhf, arm64) into DEST,
# a sysroot folder inside a build tree, for cross builds that link target
# libraries. Why not `apt-get install libserial-dev:armhf`: libserial-dev is
# not Multi-Arch, so installing the target's removes the host's. The
# packages are only downloaded and unpacked here, never installed. Their
# shlibs files (which package provides which library, from which version)
# are kept in DEST/.troupe-shlibs: a board's .deb names its dependencies
# from them (boards/deb_depends.cmake).
#
#   toolchains/prepare-sysroot.sh armhf build/pioneer-p3dx/sysroot libserial-dev libserial1
#
# Needs the target architecture in dpkg's list (added, with an apt-get
# update, when run as root). Does nothing when DEST already holds exactly
# these packages. powerpc has no Debian archive: only libsodium can be
# asked for there, and it is built from Debian's source.
set -eu

if [ $# -lt 3 ]; then
  echo "usage: $0 DEB_ARCH DEST PACKAGE..." >&2
  exit 2
fi
arch=$1
dest=$2
shift 2
packages="$*"
stamp="$dest/.troupe-sysroot"
# Changes when what this script leaves in DEST changes, so older sysroots
# are made again.
layout=2

if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$layout $arch: $packages" ]; then
  exit 0
fi
if [ "$arch" = powerpc ]; then
  # Debian 12 has no powerpc archive, so no package can be unpacked. The
  # libraries that have a source recipe here are built from Debian's source
  # instead (libsodium: toolchains/build-libsodium.sh, static only).
  for p in $packages; do
    case "$p" in
      libsodium-dev|libsodium23) ;;
      *) echo "$0: Debian 12 has no powerpc archive: no package $p exists for it;" \
              "a powerpc board takes only drivers that need nothing beyond libc" \
              "(and libsodium, built from source)" >&2
         exit 1 ;;
    esac
  done
  rm -rf "$dest"
  mkdir -p "$dest"
  sh "$(dirname "$0")/build-libsodium.sh" powerpc-linux-gnu "$dest"
  echo "$layout $arch: $packages" > "$stamp"
  exit 0
fi

if [ "$arch" != "$(dpkg --print-architecture)" ] &&
   ! dpkg --print-foreign-architectures | grep -qx "$arch"; then
  if [ "$(id -u)" != 0 ]; then
    echo "$0: dpkg does not know architecture $arch; as root run:" >&2
    echo "  dpkg --add-architecture $arch && apt-get update" >&2
    exit 1
  fi
  echo "$0: adding architecture $arch to dpkg, then apt-get update" >&2
  dpkg --add-architecture "$arch"
  apt-get update -qq || echo "$0: apt-get update reported errors; trying the download anyway" >&2
fi

work=$(mktemp -d)
chmod a+rwx "$work"  # apt downloads as user _apt when it can
trap 'rm -rf "$work"' EXIT
names=""
for p in $packages; do names="$names $p:$arch"; done
download() { (cd "$work" && apt-get download -qq $names); }
if ! download; then
  # Stale package lists name versions the mirror no longer has.
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq || true
    download
  else
    echo "$0: apt-get download failed; as root run: apt-get update" >&2
    exit 1
  fi
fi

rm -rf "$dest"
mkdir -p "$dest"
mkdir -p "$dest/.troupe-shlibs"
for deb in "$work"/*.deb; do
  dpkg-deb -x "$deb" "$dest"
  name=$(dpkg-deb -f "$deb" Package)
  dpkg-deb -I "$deb" shlibs > "$dest/.troupe-shlibs/$name.shlibs" 2>/dev/null ||
    rm -f "$dest/.troupe-shlibs/$name.shlibs"
done
# Absolute symbolic links (libfoo.so -> /usr/lib/...) would point into the
# host; make them point inside the sysroot.
find "$dest" -type l | while read -r link; do
  target=$(readlink "$link")
  case "$target" in
    /*) ln -sfn "$dest$target" "$link" ;;
  esac
done
echo "$layout $arch: $packages" > "$stamp"
echo "$0: $packages ($arch) unpacked into $dest" >&2
