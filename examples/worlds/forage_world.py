#!/usr/bin/env python3
"""Writes forage.world: 50 robots with grippers and 100 pucks in a walled
14 m x 14 m arena, a 3 m x 3 m nest in the middle. Robots start on two rings
about the nest facing out; pucks lie scattered outside it, drawn from a fixed
seed so the file is the same on every run. Standard library only:
python3 forage_world.py > forage.world"""
import math
import random

ROBOTS, PUCKS = 50, 100
HALF = 7.0  # m, the arena's inner half width
NEST = 1.5  # m, the nest's half width

rng = random.Random(14)
print(f"""# forage.world: {ROBOTS} robots gather {PUCKS} pucks into the nest (the green square
# in the middle) on rigid-body physics. Written by forage_world.py. Each robot
# has a laser, a fiducial finder that sees the pucks (fiducial_return 1) and a
# gripper, and runs the forage controller. Run it:
#   troupe-sim examples/worlds/forage.world --fast --quit-time 600 --snapshot forage.png

physics "rigid"
resolution 0.02
interval_sim 100   # ms
speedup 1          # real time unless --fast
quit_time 0

window ( size [ 800 800 ] scale 55 center [ 0 0 ] )

define wall model ( color "gray30" obstacle_return 1 blob_return 0 )
wall ( name "north" pose [ 0 {HALF + 0.1} 0 0 ] size [ {2 * HALF + 0.4} 0.2 0.5 ] )
wall ( name "south" pose [ 0 {-HALF - 0.1} 0 0 ] size [ {2 * HALF + 0.4} 0.2 0.5 ] )
wall ( name "east" pose [ {HALF + 0.1} 0 0 0 ] size [ 0.2 {2 * HALF} 0.5 ] )
wall ( name "west" pose [ {-HALF - 0.1} 0 0 0 ] size [ 0.2 {2 * HALF} 0.5 ] )

# The nest: a marked floor area, no obstacle, invisible to rangers.
model ( name "nest" pose [ 0 0 0 0 ] size [ {2 * NEST} {2 * NEST} 0.01 ] color "green"
  obstacle_return 0 laser_return 0 blob_return 0 )

# Stage's puck: a small model grippers can take (gripper_return 1).
define puck model ( size [ 0.1 0.1 0.1 ] color "red" gripper_return 1 fiducial_return 1 mass 0.5 )

define forager position
(
  size [ 0.3 0.3 0.2 ]
  drive "diff"
  mass 10
  velocity_bounds [ -0.5 0.5 0 0 0 0 -120 120 ]
  acceleration_bounds [ -2 2 0 0 0 0 -600 600 ]
  localization "gps"
  localization_origin [ 0 0 0 0 ]
  color "royal blue"
  laser ( range_max 2 fov 180 samples 9 )
  fiducial ( range_max 3 range_max_id 3 fov 180 )
  # Paddles just ahead of the body: a puck touching its front is between them.
  gripper ( pose [ 0.22 0 0 0 ] size [ 0.14 0.2 0.1 ] )
  ctrl "forage nest_x=0 nest_y=0 nest_r={NEST}"
)
""")
for i in range(ROBOTS):
    ring, k = divmod(i, ROBOTS // 2)
    r = 2.2 + 0.8 * ring
    a = 2 * math.pi * (k + 0.5 * ring) / (ROBOTS // 2)
    print(f'forager ( name "f{i}" pose [ {r * math.cos(a):.3f} {r * math.sin(a):.3f} 0 {math.degrees(a):.1f} ] )')
print()
placed = []
while len(placed) < PUCKS:
    x, y = rng.uniform(-HALF + 0.3, HALF - 0.3), rng.uniform(-HALF + 0.3, HALF - 0.3)
    if max(abs(x), abs(y)) < 3.6 or any(math.hypot(x - u, y - v) < 0.4 for u, v in placed):
        continue
    placed.append((x, y))
    print(f'puck ( name "p{len(placed) - 1}" pose [ {x:.3f} {y:.3f} 0 0 ] )')
