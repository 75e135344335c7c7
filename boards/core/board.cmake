# core: no drivers at all. The size reference: this build for armhf,
# stripped, must stay within 64 KiB (tests/cross, label size).
include(${CMAKE_CURRENT_LIST_DIR}/../small.cmake)
set(BOARD_TOOLCHAIN arm-linux-gnueabihf)
# Without secure sessions: the core's size is the runtime's own
# (-DTROUPE_SECURE=ON gives the secure core of boards/size_report.py).
set(BOARD_SECURE OFF)
set(BOARD_DRIVERS
)
set(BOARD_NODE_CONFIGS nodes/core.json)
