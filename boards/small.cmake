# Build options shared by the small boards (armhf, arm64, powerpc): built for
# size, configs compiled at build time, no host tools. A board file includes
# this first and then states only its differences.

set(BOARD_BUILD_TYPE MinSizeRel)  # -Os -DNDEBUG
set(BOARD_CONFIG_FORMAT binary)   # no JSON parser in the node
set(BOARD_HOST_TOOLS OFF)
# The core throws nothing and asks no types at run time. A driver whose
# library throws (libserial) adds -fexceptions to its own target.
set(BOARD_COMPILE_OPTIONS -fno-exceptions -fno-rtti -ffunction-sections -fdata-sections)
set(BOARD_LINK_OPTIONS -Wl,--gc-sections -Wl,--as-needed -Wl,-O1)
# Robots on a network: the node accepts only the clients its config lists
# by key. It costs the armhf node about 16 KB plus libsodium.so beside it
# (boards/README.md, "Secure sessions on the boards"); core turns it off to
# stay the size reference of the runtime itself.
set(BOARD_SECURE ON)
# Link-time optimisation: the core shrinks by about a sixth (armhf).
set(BOARD_LTO ON)
