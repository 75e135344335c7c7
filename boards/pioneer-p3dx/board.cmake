# pioneer-p3dx: a Pioneer 2/3-DX base (P2OS over a serial port) with a SICK
# LMS200 laser, on a 32-bit ARM board (armhf).
include(${CMAKE_CURRENT_LIST_DIR}/../small.cmake)
set(BOARD_TOOLCHAIN arm-linux-gnueabihf)
set(BOARD_DRIVERS
  p2os
  sicklms200
)
set(BOARD_NODE_CONFIGS ../../examples/nodes/pioneer-p3dx.json)
