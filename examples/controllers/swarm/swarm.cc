// swarm: aggregation or dispersion from local sensing only.
//
//   ctrl "swarm aggregate"                 # gather into clusters
//   ctrl "swarm disperse spacing=1.5"      # spread out
//
// Neighbours are seen with the robot's fiducial finder (other robots show
// fiducial_return); walls and anything else with its ranger.
// aggregate: heads for the centroid of the neighbours it sees and stops
// once its nearest neighbour is within `spacing`; alone, it wanders.
// disperse: moves directly away from the nearest neighbour (or obstacle, for
// a robot without a fiducial finder) until none is within `spacing`.
// speed: m/s. spacing: m. avoid: obstacle distance that makes it turn, m.
#include <algorithm>
#include <cmath>
#include <vector>

#include "host-sim/sim/controller.h"

namespace troupe::examples {
namespace {

using sim::Command;
using sim::RobotHandle;
using sim::SensorKind;

constexpr double kPi = 3.14159265358979323846;

class Swarm final : public sim::Controller {
 public:
  Swarm(bool aggregate, double speed, double spacing, double avoid)
      : aggregate_(aggregate), speed_(speed), spacing_(spacing), avoid_(avoid) {}

  bool init(RobotHandle& robot, std::string& error) override {
    has_fiducial_ = robot.count(SensorKind::Fiducial) > 0;
    if (aggregate_ && !has_fiducial_) {
      error = "swarm aggregate needs a fiducial finder to see its neighbours";
      return false;
    }
    if (robot.count(SensorKind::Ranger) == 0) {
      error = "swarm needs a ranger";
      return false;
    }
    for (const auto& t : robot.ranger_desc(0).transducers) {
      const int s = std::max(1, t.samples);
      for (int i = 0; i < s; ++i) {
        bearings_.push_back(
            std::remainder(t.pose.a + (s > 1 ? -t.fov / 2 + t.fov * i / (s - 1) : 0.0), 2 * kPi));
      }
    }
    robot.want(SensorKind::Ranger, 0, true);
    if (has_fiducial_) robot.want(SensorKind::Fiducial, 0, true);
    return true;
  }

  void update(RobotHandle& robot) override {
    const sim::RangerView scan = robot.ranger(0);
    if (scan.step == UINT64_MAX) return;
    // Nearest obstacle of any kind, and whether it is ahead.
    double nearest = 1e9, nearest_bearing = 0, ahead = 1e9;
    for (size_t i = 0; i < scan.ranges.size() && i < bearings_.size(); ++i) {
      if (scan.ranges[i] < nearest) {
        nearest = scan.ranges[i];
        nearest_bearing = bearings_[i];
      }
      if (std::fabs(bearings_[i]) < kPi / 4) ahead = std::min(ahead, double(scan.ranges[i]));
    }
    // Neighbours from the fiducial finder.
    double sx = 0, sy = 0, closest = 1e9, closest_bearing = 0;
    int seen = 0;
    if (has_fiducial_) {
      for (const sim::FiducialReading& f : robot.fiducial(0).readings) {
        sx += f.pose.x;
        sy += f.pose.y;
        ++seen;
        if (f.range < closest) {
          closest = f.range;
          closest_bearing = f.bearing;
        }
      }
    } else {
      closest = nearest;
      closest_bearing = nearest_bearing;
      seen = nearest < 1e9;
    }
    if (aggregate_) {
      if (seen == 0) return wander(robot, ahead);
      if (closest < spacing_) return robot.command(Command::velocity(0, 0, 0));
      if (ahead < avoid_) return robot.command(Command::velocity(0, 0, nearest_bearing > 0 ? -1.0 : 1.0));
      const double bearing = std::atan2(sy / seen, sx / seen);
      return steer(robot, bearing);
    }
    if (seen == 0 || closest >= spacing_) return robot.command(Command::velocity(0, 0, 0));
    steer(robot, std::remainder(closest_bearing + kPi, 2 * kPi));
  }

 private:
  // Turn towards `bearing` (rad, robot frame), driving once roughly facing it.
  void steer(RobotHandle& robot, double bearing) {
    const double turn = std::clamp(1.5 * bearing, -1.5, 1.5);
    robot.command(Command::velocity(std::fabs(bearing) < kPi / 3 ? speed_ : 0.0, 0, turn));
  }

  void wander(RobotHandle& robot, double ahead) {
    if (ahead < avoid_) return robot.command(Command::velocity(0, 0, 1.0));
    if (--wiggle_ <= 0) {
      wiggle_ = 10 + int(robot.uniform(0) * 30);
      bias_ = (robot.uniform(1) - 0.5) * 1.5;
    }
    robot.command(Command::velocity(speed_, 0, bias_));
  }

  bool aggregate_;
  double speed_, spacing_, avoid_;
  bool has_fiducial_ = false;
  std::vector<double> bearings_;
  int wiggle_ = 0;
  double bias_ = 0;
};

}  // namespace
}  // namespace troupe::examples

TROUPE_CONTROLLER_EXPORT troupe::sim::Controller* troupe_controller_create(const char* args) {
  troupe::sim::ControllerArgs a(args);
  const bool aggregate = a.flag("aggregate"), disperse = a.flag("disperse");
  const double speed = a.number("speed", 0.3), spacing = a.number("spacing", 0.8),
               avoid = a.number("avoid", 0.35);
  if (!a.ok() || aggregate == disperse || speed < 0 || spacing <= 0 || avoid < 0) return nullptr;
  return new troupe::examples::Swarm(aggregate, speed, spacing, avoid);
}
