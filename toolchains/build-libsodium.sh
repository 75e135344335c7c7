#!/bin/sh
# build-libsodium.sh TRIPLE DEST
#
# Builds Debian 12's libsodium (1.0.18-1+deb12u1: the upstream release plus
# Debian's patches) from source with TRIPLE-gcc into the sysroot DEST, as a
# static archive only: DEST/usr/include/sodium*.h and
# DEST/usr/lib/TRIPLE/libsodium.a.
#
# Why from source: Debian 12 has no powerpc archive (a ports architecture),
# so there is no libsodium-dev:powerpc to unpack, while secure sessions
# (wire/noise) need libsodium on every secure board. Why Debian's source and
# not upstream's: the same code and security fixes as the armhf and arm64
# boards' libsodium23. Why static only: there is no libsodium23 package to
# depend on for powerpc, so the node carries what it uses (the linker takes
# only the objects the Noise code calls: X25519, ChaCha20-Poly1305, BLAKE2b,
# randombytes). Why --enable-minimal: it drops the primitives troupe never
# calls (signatures, scrypt, XSalsa20 boxes...), which halves the build; the
# ones above stay.
#
# The tarballs are fetched from the Debian pool by apt-helper, which checks
# the pinned SHA-256 (those of the source package's .dsc). Called by
# toolchains/prepare-sysroot.sh, whose stamp makes it run once per sysroot.
set -eu

if [ $# -ne 2 ]; then
  echo "usage: $0 TRIPLE DEST" >&2
  exit 2
fi
triple=$1
dest=$2

pool=http://deb.debian.org/debian/pool/main/libs/libsodium
# The pool keeps only the versions Debian still ships: once a later stable
# update replaces this one, its files move to snapshot.debian.org, which
# serves every file Debian ever published by its SHA-1. The SHA-256 is
# checked wherever a file comes from.
snapshot=http://snapshot.debian.org/file
orig=libsodium_1.0.18.orig.tar.gz
orig_sha1=cd8a76b79aeb077e8d3eea478ea6241972593dfd
orig_sha256=d59323c6b712a1519a5daf710b68f5e7fde57040845ffec53850911f10a5d4f4
debian=libsodium_1.0.18-1+deb12u1.debian.tar.xz
debian_sha1=8f6747a2f806fe6f534471283475750765ab2cb8
debian_sha256=f410474e46346b06b162defa05b1be26906aeed6cf309e3d4ebe30b4d1350733

if ! command -v "$triple-gcc" >/dev/null 2>&1; then
  echo "$0: $triple-gcc is not installed (apt-get install gcc-$triple)" >&2
  exit 1
fi
# Debian's source tarball is upstream's git tag, without a configure script:
# Debian (dh_autoreconf) and this script make it with autoreconf.
for tool in autoreconf libtoolize make patch; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "$0: $tool is not installed (apt-get install autoconf automake libtool make patch)" >&2
    exit 1
  fi
done
helper=/usr/lib/apt/apt-helper
if [ ! -x "$helper" ]; then
  echo "$0: $helper (package apt) is missing; it downloads and checks the libsodium source" >&2
  exit 1
fi

work=$(mktemp -d)
chmod a+rwx "$work"  # apt-helper downloads as user _apt when it can
trap 'rm -rf "$work"' EXIT
for file in "$orig $orig_sha1 $orig_sha256" "$debian $debian_sha1 $debian_sha256"; do
  set -- $file
  if ! "$helper" download-file "$pool/$1" "$work/$1" "SHA256:$3" >/dev/null 2>"$work/download.log" &&
     ! "$helper" download-file "$snapshot/$2" "$work/$1" "SHA256:$3" >/dev/null 2>>"$work/download.log"; then
    cat "$work/download.log" >&2
    echo "$0: could not download $1 with SHA-256 $3 from $pool or $snapshot." >&2
    echo "  Check that deb.debian.org is reachable (apt-get update works), or build the board" >&2
    echo "  without secure sessions: -DTROUPE_SECURE=OFF." >&2
    exit 1
  fi
done

src="$work/libsodium-1.0.18"
tar -xzf "$work/$orig" -C "$work"
tar -xJf "$work/$debian" -C "$src"
# Debian's quilt series, applied in order (format 3.0 (quilt), -p1 patches).
if [ -f "$src/debian/patches/series" ]; then
  grep -v '^#' "$src/debian/patches/series" | while read -r p; do
    [ -n "$p" ] && patch -s -d "$src" -p1 < "$src/debian/patches/$p"
  done
fi

# Debian's optimisation level (-O2; the cipher and curve loops are hot in a
# handshake); sections per function so the node's --gc-sections keeps only
# what it calls.
(cd "$src" && autoreconf -fi >"$work/autoreconf.log" 2>&1) ||
  { tail -30 "$work/autoreconf.log" >&2; echo "$0: autoreconf failed" >&2; exit 1; }
(cd "$src" && CFLAGS="-O2 -ffunction-sections -fdata-sections" ./configure --quiet \
   --host="$triple" --prefix=/usr --libdir="/usr/lib/$triple" \
   --disable-shared --enable-static --enable-minimal --disable-dependency-tracking --with-pic=no \
   >"$work/configure.log" 2>&1) || { tail -30 "$work/configure.log" >&2; echo "$0: configure failed" >&2; exit 1; }
jobs=$(nproc 2>/dev/null || echo 1)
[ "$jobs" -gt 2 ] && jobs=2  # a shared machine's cores: two at most
# libtool's chatter goes to a log, shown only when the build fails.
if ! make -s -C "$src/src/libsodium" -j "$jobs" >"$work/make.log" 2>&1 ||
   ! make -s -C "$src/src/libsodium" install DESTDIR="$dest" >>"$work/make.log" 2>&1; then
  tail -30 "$work/make.log" >&2
  echo "$0: building libsodium for $triple failed" >&2
  exit 1
fi
rm -f "$dest/usr/lib/$triple/libsodium.la"
echo "$0: libsodium 1.0.18 (Debian 12 source) built for $triple into $dest" >&2
