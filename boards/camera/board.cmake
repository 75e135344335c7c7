# camera: the core plus one V4L2 camera (a USB webcam, or the Raspberry Pi
# camera through its V4L2 driver) on a 32-bit ARM board (armhf). Without
# secure sessions, like the core, so that its size against the core's is
# the driver's cost alone (boards/size_report.py).
include(${CMAKE_CURRENT_LIST_DIR}/../small.cmake)
set(BOARD_TOOLCHAIN arm-linux-gnueabihf)
set(BOARD_SECURE OFF)
set(BOARD_DRIVERS
  v4l2
)
set(BOARD_NODE_CONFIGS nodes/camera.json)
