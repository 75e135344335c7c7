# armhf: 32-bit ARMv7-A, hard float, Thumb-2 (Debian's default for this
# compiler). Raspberry Pi 2/3 on a 32-bit OS, BeagleBone, i.MX6 boards.
#   cmake -S . -B build/core-armhf -G Ninja \
#     -DCMAKE_TOOLCHAIN_FILE=toolchains/arm-linux-gnueabihf.cmake -DTROUPE_BOARD=core
set(TROUPE_TARGET_TRIPLE arm-linux-gnueabihf)
set(TROUPE_TARGET_PROCESSOR arm)
set(TROUPE_TARGET_DEB_ARCH armhf)
set(TROUPE_TARGET_QEMU qemu-arm)
include(${CMAKE_CURRENT_LIST_DIR}/debian_cross.cmake)
