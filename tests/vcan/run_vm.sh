#!/bin/sh
# Boots a Debian kernel in qemu (software emulation, no KVM) with vcan0 up
# and the kernel's virtual camera vivid loaded (/dev/video0, its platform
# device vivid.0), and runs a statically linked test program in it; exits 0
# when the program passed. The console goes to OUT/console.log. With
# TROUPE_VM_NEEDS_VIDEO=1 a VM without /dev/video0 fails the test.
#
#   tests/vcan/run_vm.sh OUT TEST_PROGRAM [ARGS...]
#
# OUT holds the kernel and modules (fetched by fetch_vm.sh when missing) and
# the initramfs built here: busybox-static, /sbin/ip with its libraries (the
# busybox ip cannot create vcan links), the CAN and vivid modules (loaded in
# the order fetch_vm.sh wrote) and the program.
set -eu

out=${1:?usage: run_vm.sh OUT TEST_PROGRAM [ARGS...]}
program=${2:?usage: run_vm.sh OUT TEST_PROGRAM [ARGS...]}
shift 2
here=$(cd "$(dirname "$0")" && pwd)
vm_timeout=${TROUPE_VCAN_TIMEOUT:-900}

[ -f "$out/vmlinuz" ] && [ -f "$out/modules/vcan.ko" ] && [ -f "$out/modules/vivid.ko" ] || "$here/fetch_vm.sh" "$out"
for tool in qemu-system-x86_64 cpio gzip; do
  command -v "$tool" >/dev/null || { echo "run_vm: $tool is missing (run tests/vcan/fetch_vm.sh)" >&2; exit 1; }
done
if readelf -l "$program" 2>/dev/null | grep -q "program interpreter"; then
  echo "run_vm: $program is not statically linked" >&2
  exit 1
fi

root="$out/initramfs"
rm -rf "$root"
mkdir -p "$root/bin" "$root/sbin" "$root/lib/modules" "$root/proc" "$root/sys" "$root/dev" "$root/tmp"
cp /bin/busybox "$root/bin/busybox"
cp /sbin/ip "$root/sbin/ip"
# ip's libraries and loader, at the paths ldd gives.
ldd /sbin/ip | awk '{for (i = 1; i <= NF; i++) if ($i ~ /^\//) print $i}' | while read -r lib; do
  mkdir -p "$root$(dirname "$lib")"
  cp -L "$lib" "$root$lib"
done
cp "$out"/modules/*.ko "$out/modules/order.txt" "$root/lib/modules/"
cp "$program" "$root/bin/test-program"

args=""
for a in "$@"; do args="$args '$a'"; done
cat > "$root/init" <<INIT
#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/bin:/sbin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev 2>/dev/null
# vivid: one instance with only a video capture node (/dev/video0), the
# single-planar API.
for m in \$(cat /lib/modules/order.txt); do
  opts=""
  [ \$m = vivid ] && opts="n_devs=1 node_types=0x1 multiplanar=1"
  insmod /lib/modules/\$m.ko \$opts || echo "VM-SETUP: insmod \$m failed"
done
ip link set lo up
video=""
for i in 1 2 3 4 5; do
  if [ -c /dev/video0 ] && [ -e /sys/bus/platform/drivers/vivid/vivid.0 ]; then
    video=/dev/video0
    echo "VIVID-SETUP: /dev/video0 up"
    break
  fi
  sleep 1
done
if ip link add dev vcan0 type vcan && ip link set up vcan0; then
  echo "VCAN-SETUP: vcan0 up"
  TROUPE_TEST_CAN_INTERFACE=vcan0 TROUPE_TEST_VIDEO_DEVICE=\$video TROUPE_TEST_VIVID_PLATFORM=vivid.0 \\
    /bin/test-program $args
  echo "VCAN-EXIT: \$?"
else
  echo "VCAN-SETUP: cannot create vcan0"
fi
poweroff -f
INIT
chmod +x "$root/init"
(cd "$root" && find . | cpio -o -H newc --quiet | gzip -1) > "$out/initrd.gz"

log="$out/console.log"
echo "run_vm: booting $(cat "$out/kernel-package.txt" 2>/dev/null || echo kernel) with $(basename "$program") (console: $log)"
set +e
timeout --kill-after=10 "$vm_timeout" qemu-system-x86_64 -accel tcg -m 512 -smp 1 \
  -kernel "$out/vmlinuz" -initrd "$out/initrd.gz" \
  -append "console=ttyS0 panic=-1 quiet" -nographic -no-reboot -monitor none > "$log" 2>&1
rc=$?
set -e
tr -d '\r' < "$log" | grep -v "^\s*$" | tail -n 60
if [ $rc = 124 ] || [ $rc = 137 ]; then
  echo "run_vm: the VM did not finish within ${vm_timeout} s" >&2
  exit 1
fi
grep -q "VCAN-SETUP: vcan0 up" "$log" || { echo "run_vm: vcan0 was not set up" >&2; exit 1; }
if [ "${TROUPE_VM_NEEDS_VIDEO:-0}" = 1 ] && ! grep -q "VIVID-SETUP: /dev/video0 up" "$log"; then
  echo "run_vm: vivid's /dev/video0 did not appear" >&2
  exit 1
fi
grep -q "VCAN-EXIT: 0" "$log" || { echo "run_vm: the test program failed in the VM" >&2; exit 1; }
echo "run_vm: passed"
