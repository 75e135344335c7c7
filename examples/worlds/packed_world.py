#!/usr/bin/env python3
"""Writes packed1000.world: Stage's 1,000-robot benchmark start, the robots
packed 0.25 m apart (centre to centre) in one 40 x 25 block, each with a ring
of 12 sonars of 2 m, wandering. Headings are multiples of 90 degrees drawn
from a fixed seed, so the file is the same on every run. Standard library
only: python3 packed_world.py > packed1000.world"""
import math
import random

COLS, ROWS, PITCH = 40, 25, 0.25  # robots per row, rows, m between centres
SIDE = 0.2  # m: 0.25 m squares would touch, and none could move

rng = random.Random(17)
print(f"""# packed1000.world: {COLS * ROWS} robots packed {PITCH} m apart in one block (Stage's
# 1,000-robot benchmark start), each with 12 sonars of 2 m, wandering, in a
# walled 24 x 16 m hall. Every beam has a few hundred robots within its reach.
# Written by packed_world.py. Run it (sim_bench's packed row loads it too):
#   troupe-sim examples/worlds/packed1000.world --fast --quit-time 60 --no-serve

resolution 0.02
interval_sim 100   # ms
speedup 1          # real time unless --fast
quit_time 0

window ( size [ 800 600 ] scale 30 center [ 0 0 ] )

define wall model ( color "gray30" )
wall ( name "north" size [ 24 0.2 1 ] pose [ 0 8 0 0 ] )
wall ( name "south" size [ 24 0.2 1 ] pose [ 0 -8 0 0 ] )
wall ( name "east" size [ 0.2 16 1 ] pose [ 12 0 0 0 ] )
wall ( name "west" size [ 0.2 16 1 ] pose [ -12 0 0 0 ] )

define ring12 ranger
(""")
for i in range(12):
    a = math.radians(30 * i)
    print(f"  sensor ( pose [ {0.125 * math.cos(a):.4f} {0.125 * math.sin(a):.4f} 0 {30 * i:.1f} ] "
          "range [ 0 2 ] fov 15 samples 1 )")
print(f""")
define packbot position
(
  size [ {SIDE} {SIDE} 0.2 ]
  velocity_bounds [ -0.5 0.5 0 0 0 0 -90 90 ]
  ring12 ( )
  ctrl "wander avoid=0.4"
)
""")
for y in range(ROWS):
    for x in range(COLS):
        px, py = (x - 0.5 * (COLS - 1)) * PITCH, (y - 0.5 * (ROWS - 1)) * PITCH
        print(f'packbot ( name "r{y * COLS + x}" pose [ {px:.3f} {py:.3f} 0 {rng.randrange(4) * 90} ] )')
