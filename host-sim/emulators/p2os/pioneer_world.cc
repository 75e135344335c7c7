#include "host-sim/emulators/p2os/pioneer_world.h"

#include <algorithm>
#include <cmath>

namespace troupe::emulators {

bool PioneerWorld::move(double left, double right, double track, double dt, PioneerPose& p) {
  double v = 0.5 * (left + right), w = (right - left) / track;
  if (std::fabs(w) < 1e-9) {
    p.x += v * dt * std::cos(p.a);
    p.y += v * dt * std::sin(p.a);
  } else {
    double a1 = p.a + w * dt;
    p.x += v / w * (std::sin(a1) - std::sin(p.a));
    p.y -= v / w * (std::cos(a1) - std::cos(p.a));
    p.a = a1;
  }
  return false;
}

double PioneerWorld::observe(double waited_s, PioneerPose&) {
  return waited_s;
}

void PioneerWorld::sense(const PioneerPose& p, const drivers::p2os::RobotParams& robot, PioneerSenses& s) {
  double c = std::cos(p.a), sn = std::sin(p.a);
  size_t n = std::min<size_t>(robot.sonar_count, PioneerSenses::kMaxSonar);
  for (size_t i = 0; i < n; ++i) {
    const drivers::p2os::SonarPose& t = robot.sonar[i];
    double x = p.x + c * t.x - sn * t.y, y = p.y + sn * t.x + c * t.y;
    s.sonar_m[i] = float(room.range(x, y, p.a + t.a));
  }
}

}  // namespace troupe::emulators
