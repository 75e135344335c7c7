# powerpc: 32-bit big-endian PowerPC (e.g. MPC5200, e500 boards). Debian 12
# has no powerpc archive (a ports architecture), so there are no target
# packages to unpack: only drivers that need nothing beyond libc/libstdc++
# and kernel headers (SocketCAN) build for it, and secure sessions, whose
# libsodium is built from Debian's source (toolchains/build-libsodium.sh).
set(TROUPE_TARGET_TRIPLE powerpc-linux-gnu)
set(TROUPE_TARGET_PROCESSOR powerpc)
set(TROUPE_TARGET_DEB_ARCH powerpc)
set(TROUPE_TARGET_QEMU qemu-ppc)
include(${CMAKE_CURRENT_LIST_DIR}/debian_cross.cmake)
