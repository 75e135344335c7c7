// wander: ranger-based obstacle avoidance. Cruises forward, drifting towards
// the more open side; when something is close ahead it turns on the spot,
// towards the more open side, for a while; now and then it picks a new
// heading at random (the run's seeded random numbers).
//
//   ctrl "wander"                      # defaults
//   ctrl "wander speed=0.4 turn=1.0 avoid=0.5 ranger=1"
//
// speed: cruising speed, m/s. turn: turn rate when avoiding, rad/s.
// avoid: distance ahead that makes it turn, m. ranger: which ranger to use
// (default: the one with the most beams, e.g. a Pioneer's laser).
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

class Wander final : public sim::Controller {
 public:
  Wander(double speed, double turn, double avoid, int ranger)
      : speed_(speed), turn_(turn), avoid_(avoid), ranger_(ranger) {}

  bool init(RobotHandle& robot, std::string& error) override {
    const uint32_t n = robot.count(SensorKind::Ranger);
    if (n == 0) {
      error = "wander needs a ranger";
      return false;
    }
    if (ranger_ < 0) {
      size_t most = 0;
      for (uint32_t k = 0; k < n; ++k) {
        size_t beams = 0;
        for (const auto& t : robot.ranger_desc(k).transducers) beams += size_t(std::max(1, t.samples));
        if (beams > most) {
          most = beams;
          ranger_ = int(k);
        }
      }
    }
    if (ranger_ >= int(n)) {
      error = "wander: the robot has no ranger " + std::to_string(ranger_);
      return false;
    }
    // Each beam's bearing on the robot, as the ranger spreads its samples,
    // sorted once into the sectors update() looks at.
    uint32_t beam = 0;
    for (const auto& t : robot.ranger_desc(uint32_t(ranger_)).transducers) {
      const int s = std::max(1, t.samples);
      for (int i = 0; i < s; ++i, ++beam) {
        const double b = std::remainder(t.pose.a + (s > 1 ? -t.fov / 2 + t.fov * i / (s - 1) : 0.0), 2 * kPi);
        if (std::fabs(b) < 35 * kPi / 180) ahead_beams_.push_back(beam);
        if (b > 0 && b <= kPi / 2) left_beams_.push_back(beam);
        if (b < 0 && b >= -kPi / 2) right_beams_.push_back(beam);
      }
    }
    beams_ = beam;
    robot.want(SensorKind::Ranger, uint32_t(ranger_), true);
    return true;
  }

  size_t memory_size() const override { return sizeof(Memory); }

  void update(RobotHandle& robot) override {
    Memory& m = robot.memory_as<Memory>();
    const sim::RangerView scan = robot.ranger(uint32_t(ranger_));
    if (scan.step == UINT64_MAX || scan.ranges.size() != beams_) {
      robot.command(Command::velocity(0, 0, 0));  // no data yet
      return;
    }
    auto nearest = [&](const std::vector<uint32_t>& beams) {
      double r = 1e9;
      for (uint32_t i : beams) r = std::min(r, double(scan.ranges[i]));
      return r;
    };
    const double ahead = nearest(ahead_beams_), left = nearest(left_beams_), right = nearest(right_beams_);
    if (m.avoiding > 0 || ahead < avoid_ || robot.state().stalled) {
      if (m.avoiding == 0) {
        m.direction = left > right ? 1.0 : -1.0;
        m.avoiding = 5 + int(robot.uniform(0) * 10);
      }
      --m.avoiding;
      robot.command(Command::velocity(0, 0, m.direction * turn_));
      return;
    }
    if (--m.wiggle <= 0) {
      m.wiggle = 20 + int(robot.uniform(1) * 30);
      m.bias = (robot.uniform(2) - 0.5) * turn_;
    }
    const double drift = std::clamp(0.5 * (std::min(left, 2.0) - std::min(right, 2.0)), -0.5, 0.5);
    robot.command(Command::velocity(speed_, 0, drift * turn_ + m.bias));
  }

 private:
  // What it remembers between steps (the World's bytes; all zero at the
  // start).
  struct Memory {
    int avoiding;      // steps of turning on the spot left
    double direction;  // of that turn: 1 left, -1 right
    int wiggle;        // steps until the next random bias
    double bias;       // rad/s added while cruising
  };

  double speed_, turn_, avoid_;
  int ranger_;
  // The beams (indices into the scan) ahead (within 35 degrees), on the
  // left and on the right.
  std::vector<uint32_t> ahead_beams_, left_beams_, right_beams_;
  size_t beams_ = 0;
};

sim::Controller* make_wander(const char* args) {
  sim::ControllerArgs a(args);
  const double speed = a.number("speed", 0.4), turn = a.number("turn", 1.0), avoid = a.number("avoid", 0.5);
  const int ranger = int(a.number("ranger", -1));
  if (!a.ok() || speed < 0 || turn < 0 || avoid < 0) return nullptr;
  return new Wander(speed, turn, avoid, ranger);
}

}  // namespace
}  // namespace troupe::examples

TROUPE_CONTROLLER("wander", troupe::examples::make_wander)
