# host: the development board. Builds on the machine it runs on, reads JSON
# node configs, and builds the client, CLI, simulator and tests too.
set(BOARD_DRIVERS
  kinematic
  odrive_can
  p2os
  sicklms200
  v4l2
  logreplay
  mapfile
  mcl
  fusion
  passthrough
  replay
  ros2
)
set(BOARD_CONFIG_FORMAT json)
set(BOARD_HOST_TOOLS ON)
set(BOARD_NODE_CONFIGS ../../examples/nodes/kinematic.json)
