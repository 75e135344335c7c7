#include "tests/desktop/synthetic_world.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iterator>

namespace troupe::desktop::testing {
namespace {

void fill_box(OccupancyGrid& g, double x0, double y0, double x1, double y1, CellState s) {
  int64_t c0 = 0, r0 = 0, c1 = 0, r1 = 0;
  g.world_to_cell(x0, y0, c0, r0);
  g.world_to_cell(x1, y1, c1, r1);
  for (int64_t r = r0; r <= r1; ++r) {
    for (int64_t c = c0; c <= c1; ++c) {
      if (g.contains(c, r)) g.set(uint32_t(c), uint32_t(r), s);
    }
  }
}

}  // namespace

OccupancyGrid make_test_map() {
  OccupancyGrid g(240, 180, 0.05, {-1.0, -1.0, 0.0}, CellState::Free);
  // Outer walls, 0.1 m thick, around [-1, 11] x [-1, 8].
  fill_box(g, -1.0, -1.0, 11.0, -0.9, CellState::Occupied);
  fill_box(g, -1.0, 7.9, 11.0, 8.0, CellState::Occupied);
  fill_box(g, -1.0, -1.0, -0.9, 8.0, CellState::Occupied);
  fill_box(g, 10.9, -1.0, 11.0, 8.0, CellState::Occupied);
  // A wall splitting the world at x = 4.5 with two doors of different widths.
  fill_box(g, 4.5, -1.0, 4.6, 1.0, CellState::Occupied);
  fill_box(g, 4.5, 2.0, 4.6, 5.0, CellState::Occupied);
  fill_box(g, 4.5, 6.5, 4.6, 8.0, CellState::Occupied);
  // Boxes that break the symmetry.
  fill_box(g, 1.0, 5.0, 2.0, 5.6, CellState::Occupied);
  fill_box(g, 7.0, 1.0, 7.4, 3.5, CellState::Occupied);
  fill_box(g, 8.5, 5.5, 9.5, 6.5, CellState::Occupied);
  fill_box(g, 0.0, 1.5, 0.3, 1.8, CellState::Occupied);
  return g;
}

std::vector<float> cast_scan(const OccupancyGrid& map, const Pose2& pose, const TestLaser& laser) {
  std::vector<float> out(laser.beams);
  double step = map.resolution() / 5;
  for (size_t i = 0; i < laser.beams; ++i) {
    double b = pose.a + laser.start_angle() + double(i) * laser.angular_res();
    double c = std::cos(b), s = std::sin(b), r = 0;
    for (; r < laser.max_range; r += step) {
      int64_t col = 0, row = 0;
      map.world_to_cell(pose.x + r * c, pose.y + r * s, col, row);
      if (!map.contains(col, row) || map.at(uint32_t(col), uint32_t(row)) == CellState::Occupied) break;
    }
    out[i] = float(std::min(r, laser.max_range));
  }
  return out;
}

std::vector<Pose2> test_route(double step_m) {
  const Pose2 waypoints[] = {{1.5, 0.5, 0}, {3.5, 0.5, 0}, {3.5, 1.5, 0}, {6.0, 1.5, 0}, {6.0, 4.5, 0},
                             {9.5, 4.5, 0}, {9.5, 0.5, 0}, {8.0, 0.5, 0}, {8.0, 4.5, 0}, {5.5, 5.8, 0},
                             {3.5, 5.8, 0}, {3.0, 3.5, 0}, {1.0, 3.5, 0}, {1.0, 0.5, 0}, {3.5, 0.5, 0}};
  std::vector<Pose2> out;
  Pose2 at = waypoints[0];
  at.a = 0;
  out.push_back(at);
  for (size_t w = 1; w < std::size(waypoints); ++w) {
    double heading = std::atan2(waypoints[w].y - at.y, waypoints[w].x - at.x);
    // Turn on the spot, then drive straight.
    while (std::fabs(wrap_angle(heading - at.a)) > 1e-9) {
      double d = wrap_angle(heading - at.a);
      at.a = wrap_angle(at.a + std::clamp(d, -step_m, step_m));
      out.push_back(at);
    }
    double len = std::hypot(waypoints[w].x - at.x, waypoints[w].y - at.y);
    int n = std::max(1, int(std::ceil(len / step_m)));
    Pose2 from = at;
    for (int k = 1; k <= n; ++k) {
      at = {from.x + (waypoints[w].x - from.x) * k / n, from.y + (waypoints[w].y - from.y) * k / n, heading};
      out.push_back(at);
    }
  }
  return out;
}

std::string write_carmen_log(const OccupancyGrid& map, const std::vector<Pose2>& poses,
                             const TestLaser& laser, double period_s) {
  std::string text = "# synthetic log of the test world\nPARAM robot_front_laser_max 8.0 nohost 0\n";
  char buf[128];
  for (size_t i = 0; i < poses.size(); ++i) {
    const Pose2& p = poses[i];
    double t = 100.0 + double(i) * period_s;
    std::snprintf(buf, sizeof buf, "ODOM %.6f %.6f %.6f 0 0 0 %.6f synth %.6f\n", p.x, p.y, p.a, t, t);
    text += buf;
    text += "FLASER " + std::to_string(laser.beams);
    for (float r : cast_scan(map, p, laser)) {
      std::snprintf(buf, sizeof buf, " %.3f", r);
      text += buf;
    }
    std::snprintf(buf, sizeof buf, " %.6f %.6f %.6f %.6f %.6f %.6f %.6f synth %.6f\n", p.x, p.y, p.a, p.x,
                  p.y, p.a, t + 1e-3, t + 1e-3);
    text += buf;
  }
  return text;
}

std::string scratch_dir() {
  std::string tmpl = (std::filesystem::temp_directory_path() / "troupe-desktop-XXXXXX").string();
  if (mkdtemp(tmpl.data()) == nullptr) std::abort();
  return tmpl;
}

}  // namespace troupe::desktop::testing
