# diffbot-can: a differential-drive robot whose wheels are ODrive axes on a
# CAN bus (SocketCAN), on a 64-bit ARM board (arm64).
include(${CMAKE_CURRENT_LIST_DIR}/../small.cmake)
set(BOARD_TOOLCHAIN aarch64-linux-gnu)
set(BOARD_DRIVERS
  odrive_can
)
set(BOARD_NODE_CONFIGS nodes/diffbot-can.json nodes/diffbot-can-emulated.json)
