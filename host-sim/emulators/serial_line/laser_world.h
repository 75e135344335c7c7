// What an emulated laser scanner sees: the SICK LMS200 on its serial line
// and the simulated laser riding a Pioneer's connection (MobileSim's SIM
// packets) both measure through it. The default is the scanner at
// (x, y, a) in `room`; troupe-sim derives from it to measure its own world.
#pragma once

#include <span>

#include "host-sim/emulators/serial_line/room.h"

namespace troupe::emulators {

class LaserWorld {
 public:
  virtual ~LaserWorld() = default;
  /// Fills `ranges_m[i]` with the range along beam i, whose bearing in the
  /// scanner's frame is first_rad + i * step_rad, m. Anything beyond the
  /// scanner's reach reads as no return.
  virtual void measure(double first_rad, double step_rad, std::span<float> ranges_m);

  /// A corridor: 20 m long, so the beams along it see nothing.
  Room room{10.0, 3.0};
  /// The scanner's pose in the room: m, m, rad.
  double x = 0, y = 0, a = 0;
};

}  // namespace troupe::emulators
