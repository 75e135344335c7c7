# arm64: 64-bit ARMv8-A. Raspberry Pi 3/4/5 on a 64-bit OS, Jetson, i.MX8.
set(TROUPE_TARGET_TRIPLE aarch64-linux-gnu)
set(TROUPE_TARGET_PROCESSOR aarch64)
set(TROUPE_TARGET_DEB_ARCH arm64)
set(TROUPE_TARGET_QEMU qemu-aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/debian_cross.cmake)
