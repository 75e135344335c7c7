# desktop: the desktop peer of a robot (x86-64 or whatever the host is). It
# runs the abstract drivers that offload heavy work from the robot board:
# remote devices passed through, localization, fusion, log replay, maps,
# the ROS 2 bridge, and a V4L2 camera (a webcam on the desktop peer).
# Reads JSON node configs; builds only troupe-node (no tests, simulator).
set(BOARD_TOOLCHAIN native)
set(BOARD_BUILD_TYPE Release)
set(BOARD_CONFIG_FORMAT json)
set(BOARD_DRIVERS
  passthrough
  mcl
  fusion
  logreplay
  mapfile
  v4l2
  ros2
)
set(BOARD_NODE_CONFIGS nodes/desktop.json nodes/ros2.json)
# Its node serves the robot's devices on to other machines: secure sessions,
# as on the robot (the passthrough's link to the robot has them anyway).
set(BOARD_SECURE ON)
