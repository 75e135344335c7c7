#include "host-sim/robocup/bench/goalkeeper_bench.h"

namespace troupe::robocup {

const char* standard_bench_world() {
  return R"(# The standard goalkeeper benchmark world.
interval_sim 10
restitution 0.5
friction 0.3
seed 1
robocup_field ( length 9 width 5 )
ball ( radius 0.11 mass 0.43 deceleration 0.4 pose [0 0 0 0] )
referee ( goal_pause 0 )

robocup_robot ( name "keeper" team "blue" pose [-4.15 0 0 0]
  mass 15
  shape ( kind "ellipse" rx 0.18 ry 0.25 z [0 0.5] )
  kicker ( direction 0 reach 0.03
    state ( name "rest" shape ( kind "rect" x 0.19 length 0.03 width 0.26 z [0.02 0.14] ) )
    state ( name "kick" accel 250 contact 0.02 hold 0.25 next "rest" shape ( kind "rect" x 0.25 length 0.15 width 0.26 z [0.02 0.14] ) )
  )
  motion_plugin ( plugin "omni_drive" radius 0.17 wheel_speed 2.5 wheel_accel 8 )
)

robocup_robot ( name "striker" team "yellow" pose [0 0 0 180]
  mass 20
  shape ( kind "rect" length 0.44 width 0.38 z [0 0.6] )
  kicker ( direction 0 reach 0.03
    state ( name "rest" shape ( kind "rect" x 0.235 length 0.03 width 0.28 z [0.02 0.14] ) )
    state ( name "kick" accel 300 contact 0.02 hold 0.25 next "rest" shape ( kind "rect" x 0.30 length 0.16 width 0.28 z [0.02 0.14] ) )
  )
  motion_plugin ( plugin "diff_drive" max_speed 2 max_turn 6 accel 2.5 turn_accel 15 )
)
)";
}

}  // namespace troupe::robocup
