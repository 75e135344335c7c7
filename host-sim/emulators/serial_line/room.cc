#include "host-sim/emulators/serial_line/room.h"

#include "host-sim/emulators/serial_line/laser_world.h"

#include <cmath>
#include <limits>

namespace troupe::emulators {

double Room::range(double x, double y, double a) const {
  if (std::fabs(x) > half_x || std::fabs(y) > half_y) return 0;
  double dx = std::cos(a), dy = std::sin(a);
  double best = std::numeric_limits<double>::infinity();
  // The wall ahead along each axis the ray moves on.
  if (dx > 1e-12) best = std::fmin(best, (half_x - x) / dx);
  if (dx < -1e-12) best = std::fmin(best, (-half_x - x) / dx);
  if (dy > 1e-12) best = std::fmin(best, (half_y - y) / dy);
  if (dy < -1e-12) best = std::fmin(best, (-half_y - y) / dy);
  return best;
}

void LaserWorld::measure(double first, double step, std::span<float> ranges) {
  for (size_t i = 0; i < ranges.size(); ++i)
    ranges[i] = float(room.range(x, y, a + first + double(i) * step));
}

}  // namespace troupe::emulators
