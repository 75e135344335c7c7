#!/bin/sh
# Installs and downloads what the vcan test's VM needs, into OUT (a folder in
# the build tree): Debian 12's qemu-system-x86, busybox-static, cpio and
# iproute2 packages, and the kernel image package linux-image-amd64 depends
# on, unpacked, from which it keeps the kernel, the four CAN modules and the
# twelve media modules of the kernel's virtual camera, vivid (in their load
# order, written to modules/order.txt).
# Run as root (or with sudo available) on a fresh Debian 12 machine.
#
#   tests/vcan/fetch_vm.sh OUT
set -eu

out=${1:?usage: fetch_vm.sh OUT}
mkdir -p "$out"
cd "$out"

if [ "$(id -u)" = 0 ]; then as_root=""; else as_root="sudo"; fi
export DEBIAN_FRONTEND=noninteractive

need=""
command -v qemu-system-x86_64 >/dev/null || need="$need qemu-system-x86"
dpkg-query -W -f='${Status}' busybox-static 2>/dev/null | grep -q "ok installed" || need="$need busybox-static"
command -v cpio >/dev/null || need="$need cpio"
[ -x /sbin/ip ] || need="$need iproute2"
updated=no
if [ -n "$need" ]; then
  echo "fetch_vm: installing$need"
  $as_root apt-get update -q
  updated=yes
  # shellcheck disable=SC2086
  $as_root apt-get install -y -q --no-install-recommends $need
fi

if [ -f vmlinuz ] && [ -f modules/vcan.ko ] && [ -f modules/vivid.ko ]; then
  echo "fetch_vm: kernel already in $out"
  exit 0
fi

image=$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-/ {print $2; exit}')
if [ -z "$image" ] && [ "$updated" = no ]; then
  $as_root apt-get update -q
  image=$(apt-cache depends linux-image-amd64 | awk '/Depends: linux-image-/ {print $2; exit}')
fi
[ -n "$image" ] || { echo "fetch_vm: linux-image-amd64 names no kernel image package" >&2; exit 1; }
echo "fetch_vm: downloading $image"
rm -rf deb unpacked && mkdir -p deb unpacked modules
(cd deb && timeout 900 apt-get download "$image")
dpkg-deb -x deb/*.deb unpacked
cp unpacked/boot/vmlinuz-* vmlinuz
# In insmod order: each after the modules its depends= line names.
media=drivers/media
: > modules/order.txt
for m in net/can/can.ko net/can/can-raw.ko drivers/net/can/dev/can-dev.ko drivers/net/can/vcan.ko \
  $media/mc/mc.ko $media/v4l2-core/videodev.ko $media/common/videobuf2/videobuf2-common.ko \
  $media/common/videobuf2/videobuf2-v4l2.ko $media/common/videobuf2/videobuf2-memops.ko \
  $media/common/videobuf2/videobuf2-vmalloc.ko $media/common/videobuf2/videobuf2-dma-contig.ko \
  $media/v4l2-core/v4l2-dv-timings.ko $media/rc/rc-core.ko $media/cec/core/cec.ko \
  $media/common/v4l2-tpg/v4l2-tpg.ko $media/test-drivers/vivid/vivid.ko; do
  found=$(find unpacked/lib/modules -path "*/kernel/$m*" | head -n 1)
  [ -n "$found" ] || { echo "fetch_vm: $image has no $m" >&2; exit 1; }
  case "$found" in
    *.xz) xz -dc "$found" > "modules/$(basename "$m")" ;;
    *.zst) zstd -dqc "$found" > "modules/$(basename "$m")" ;;
    *) cp "$found" "modules/$(basename "$m")" ;;
  esac
  basename "$m" .ko >> modules/order.txt
done
echo "$image" > kernel-package.txt
rm -rf deb unpacked
echo "fetch_vm: kernel $(cat kernel-package.txt), CAN and vivid modules in $out"
