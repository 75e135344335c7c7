// A rectangular room, the emulators' default surroundings: walls at
// x = +-half_x and y = +-half_y (m) around the origin. Enough for ranges
// that change as the robot moves, with nothing else to configure.
#pragma once

namespace troupe::emulators {

struct Room {
  /// Half the room's extent along x and y, m.
  double half_x = 3.0, half_y = 3.0;

  /// Distance from (x, y) along heading `a` to the first wall, m; 0 from
  /// outside the room.
  double range(double x, double y, double a) const;
};

}  // namespace troupe::emulators
