# ppc-node: a 32-bit big-endian PowerPC board. Debian has no powerpc target
# libraries, so it gets only drivers that need nothing beyond libc/libstdc++
# and kernel headers (SocketCAN); secure sessions get a libsodium built from
# Debian's source (toolchains/build-libsodium.sh).
include(${CMAKE_CURRENT_LIST_DIR}/../small.cmake)
set(BOARD_TOOLCHAIN powerpc-linux-gnu)
set(BOARD_DRIVERS
  kinematic
  odrive_can
)
set(BOARD_NODE_CONFIGS nodes/ppc-node.json)
