// Small worlds built in code, with geometry simple enough to compute the
// expected readings by hand.
#pragma once

#include <string>
#include <vector>

#include "host-sim/sim/desc.h"

namespace troupe::sim::test {

inline std::vector<Vec2> box(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

/// A room whose inner faces are at x = +-half_x and y = +-half_y (m), walls
/// `thick` m thick, at `resolution` m.
inline WorldDesc room(double half_x, double half_y, double resolution = 0.02, double thick = 0.2) {
  WorldDesc w;
  w.resolution = resolution;
  StaticDesc s;
  s.name = "walls";
  s.size = {2 * half_x + 2 * thick, 2 * half_y + 2 * thick};
  const double X = half_x, Y = half_y, T = thick;
  s.polygons = {box(-X - T, -Y - T, X + T, -Y), box(-X - T, Y, X + T, Y + T), box(-X - T, -Y, -X, Y),
                box(X, -Y, X + T, Y)};
  s.look.color = 0x404040;
  w.statics.push_back(s);
  return w;
}

/// A square robot `side` m wide with generous limits (so motion tests see
/// the commanded velocity at once unless they set bounds themselves).
inline RobotDesc robot(const std::string& name, Pose pose, double side = 0.4) {
  RobotDesc r;
  r.name = name;
  r.pose = pose;
  r.size = {side, side};
  r.polygons = {box(-side / 2, -side / 2, side / 2, side / 2)};
  for (int a = 0; a < 3; ++a) {
    r.velocity[a] = {-10, 10};
    r.acceleration[a] = {-1000, 1000};
  }
  r.localization = Localization::Gps;
  r.has_localization_origin = true;  // world frame
  return r;
}

/// A scanning laser at `pose` on the robot: `samples` beams over `fov` rad.
inline RangerDesc laser(int samples, double fov, double range_max, Pose pose = {}) {
  RangerDesc r;
  r.name = "laser";
  TransducerDesc t;
  t.pose = pose;
  t.samples = samples;
  t.fov = fov;
  t.range_max = range_max;
  r.transducers.push_back(t);
  return r;
}

}  // namespace troupe::sim::test
