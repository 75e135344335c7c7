// Iconic vision shared by the camera and omni-vision plugins: which
// objects (ball, goals, posts, robots, lines) a sensor at a pose sees
// within its field of view and range, unoccluded, with seeded noise.
#pragma once

#include <algorithm>
#include <cmath>

#include "host-sim/robocup/api/plugin.h"
#include "host-sim/robocup/plugins/common/noise.h"

namespace troupe::robocup::plugins {

struct VisionSettings {
  /// Full opening angle, rad (2 pi: all around).
  double fov = 1.0;
  /// m.
  double min_range = 0.1, max_range = 5.0;
  /// Noise: standard deviation of the range as a fraction of it, and of
  /// the bearing, rad. `miss`: probability an object in view is not seen.
  double range_noise = 0, bearing_noise = 0, miss = 0;
  bool ball = true, goals = true, posts = true, robots = true, lines = false;
  /// Objects hidden behind robots or structures are not seen.
  bool occlusion = true;
};

/// Reads the settings common to the vision plugins from `o`.
inline void read_vision(Options& o, VisionSettings& v) {
  v.fov = o.number("fov", v.fov, 1e-3, 2 * kPi);
  v.min_range = o.number("min_range", v.min_range, 0, 100);
  v.max_range = o.number("range", v.max_range, 0.01, 100);
  v.range_noise = o.number("range_noise", v.range_noise, 0, 1);
  v.bearing_noise = o.number("bearing_noise", v.bearing_noise, 0, 1);
  v.miss = o.number("miss", v.miss, 0, 1);
  v.ball = o.flag("ball", v.ball);
  v.goals = o.flag("goals", v.goals);
  v.posts = o.flag("posts", v.posts);
  v.robots = o.flag("robots", v.robots);
  v.lines = o.flag("lines", v.lines);
  v.occlusion = o.flag("occlusion", v.occlusion);
  if (o.ok() && v.min_range >= v.max_range) o.fail("min_range", "must be below range");
}

class Vision {
 public:
  Vision(const VisionSettings& s, const WorldView& w, const SensorContext& c, SensorReading& out)
      : s_(s), w_(w), c_(c), out_(out) {
    const RobotInfo me = w.robot(c.robot);
    sensor_ = me.pose.compose(c.mount);
  }

  void see_all() {
    if (s_.ball) {
      const BallInfo b = w_.ball();
      see(ObjectKind::Ball, 0, b.position, 0, b.radius, -1, -1, 0);
    }
    for (const Landmark& l : w_.field().landmarks) {
      const bool want = l.kind == ObjectKind::Goal ? s_.goals : s_.posts;
      if (want) see(l.kind, l.id, l.position, 0, 0.4, -1, -1, l.radius + 0.02);
    }
    if (s_.robots) {
      for (int i = 0; i < w_.robot_count(); ++i) {
        if (i == c_.robot) continue;
        const RobotInfo r = w_.robot(i);
        see(ObjectKind::Robot, i, r.pose.position(), r.pose.a, 0.3, int(r.team), i, 0);
      }
    }
    if (s_.lines) see_lines();
  }

 private:
  // One object at `at` (world): in range, in view, visible, then noisy.
  void see(ObjectKind kind, int id, Vec2 at, double yaw, double z, int team, int target_robot,
           double clearance) {
    const Vec2 local = sensor_.to_local(at);
    double range = length(local), bearing = std::atan2(local.y, local.x);
    if (range < s_.min_range || range > s_.max_range) return;
    if (std::fabs(bearing) > s_.fov / 2) return;
    if (s_.occlusion && !w_.line_of_sight(sensor_.position(), at, z, c_.robot, target_robot, clearance))
      return;
    if (chance(*c_.rng, s_.miss)) return;
    range *= 1 + gaussian(*c_.rng, s_.range_noise);
    bearing += gaussian(*c_.rng, s_.bearing_noise);
    Detection d;
    d.kind = kind;
    d.id = id;
    d.x = range * std::cos(bearing);
    d.y = range * std::sin(bearing);
    d.yaw = wrap_angle(yaw - sensor_.a);
    d.team = team;
    out_.detections.push_back(d);
  }

  // Lines: the nearest point of each line in range; the centre circle's
  // nearest point. Lines lie on the floor, nothing stands on them to hide
  // them except robots, which are ignored here (a line is long).
  void see_lines() {
    const Vec2 p = sensor_.position();
    const auto& lines = w_.field().lines;
    for (size_t i = 0; i < lines.size(); ++i) {
      const Vec2 a = lines[i].a, b = lines[i].b, ab = b - a;
      const double t = std::clamp(dot(p - a, ab) / length_squared(ab), 0.0, 1.0);
      see_line_point(int(i), a + ab * t, std::atan2(ab.y, ab.x));
    }
    const double r = w_.field().center_circle_radius;
    if (r > 0) {
      const Vec2 dir = length(p) > 1e-9 ? normalized(p) : Vec2{1, 0};
      see_line_point(-1, dir * r, std::atan2(dir.y, dir.x) + kPi / 2);
    }
  }

  void see_line_point(int id, Vec2 at, double direction_rad) {
    const Vec2 local = sensor_.to_local(at);
    double range = length(local), bearing = std::atan2(local.y, local.x);
    if (range < s_.min_range || range > s_.max_range || std::fabs(bearing) > s_.fov / 2) return;
    if (chance(*c_.rng, s_.miss)) return;
    range *= 1 + gaussian(*c_.rng, s_.range_noise);
    bearing += gaussian(*c_.rng, s_.bearing_noise);
    Detection d;
    d.kind = ObjectKind::Line;
    d.id = id;
    d.x = range * std::cos(bearing);
    d.y = range * std::sin(bearing);
    // A line has no arrow: fold its direction into [-pi/2, pi/2].
    double yaw = wrap_angle(direction_rad - sensor_.a);
    if (yaw > kPi / 2) yaw -= kPi;
    if (yaw < -kPi / 2) yaw += kPi;
    d.yaw = yaw;
    out_.detections.push_back(d);
  }

  const VisionSettings& s_;
  const WorldView& w_;
  const SensorContext& c_;
  SensorReading& out_;
  Pose2 sensor_;
};

}  // namespace troupe::robocup::plugins
