// forage: gathering pucks into a nest with a gripper.
//
//   ctrl "forage nest_x=0 nest_y=0 nest_r=1.5"
//
// The robot wanders (turning away from what its ranger sees within
// `avoid`) until its fiducial finder sees a puck (fiducial id `puck`) that
// lies outside the nest; it drives at the nearest such puck and closes its
// gripper once the puck is within `grab` of its centre, straight ahead.
// Holding a puck, it heads for the nest, opens its gripper once inside
// `drop` of the nest's centre, backs off and searches again. A puck pushed
// rather than gripped (rigid worlds) is gathered too, as long as it ends
// up in the nest. It needs a ranger, a fiducial finder mounted at its
// centre, a gripper, and its pose in the world's frame (gps localization
// from the world's origin: `localization_origin [0 0 0 0]`).
// nest_x, nest_y, nest_r, grab, drop, avoid: m. speed: m/s.
#include <algorithm>
#include <cmath>

#include "host-sim/sim/controller.h"

namespace troupe::examples {
namespace {

using sim::Command;
using sim::RobotHandle;
using sim::SensorKind;

constexpr double kPi = 3.141592653589793;

struct ForageParams {
  double nest_x = 0, nest_y = 0, nest_r = 1.5;
  double speed = 0.4;
  double grab = 0.27;
  double drop = 0.8;
  double avoid = 0.5;
  int puck = 1;
};

class Forage final : public sim::Controller {
 public:
  explicit Forage(const ForageParams& p) : p_(p) {}

  bool init(RobotHandle& robot, std::string& error) override {
    if (robot.count(SensorKind::Ranger) == 0 || robot.count(SensorKind::Fiducial) == 0 ||
        robot.gripper_count() == 0) {
      error = "forage needs a ranger, a fiducial finder and a gripper";
      return false;
    }
    for (const auto& t : robot.ranger_desc(0).transducers) {
      const int s = std::max(1, t.samples);
      for (int i = 0; i < s; ++i)
        bearings_.push_back(t.pose.a + (s > 1 ? -t.fov / 2 + t.fov * i / (s - 1) : 0.0));
    }
    robot.want(SensorKind::Ranger, 0, true);
    robot.want(SensorKind::Fiducial, 0, true);
    return true;
  }

  size_t memory_size() const override { return sizeof(Memory); }

  void update(RobotHandle& robot) override {
    Memory& m = robot.memory_as<Memory>();
    const sim::RangerView scan = robot.ranger(0);
    if (scan.step == UINT64_MAX) return;
    const sim::Pose me = robot.state().pose;
    const sim::GripperView g = robot.gripper(0);
    const double to_nest_x = p_.nest_x - me.x, to_nest_y = p_.nest_y - me.y;
    const double nest_distance = std::hypot(to_nest_x, to_nest_y);
    double v = 0, w = 0;
    switch (m.mode) {
      case Mode::Search: {
        if (g.holding) {
          m.mode = Mode::Carry;
          break;
        }
        if (g.closed) {
          robot.set_gripper(0, false);  // closed on nothing: try again
          break;
        }
        const sim::FiducialReading* target = nearest_loose_puck(robot, me);
        if (target == nullptr) {
          wander(robot, scan, m, v, w);
        } else if (target->range < p_.grab && std::fabs(target->bearing) < 0.35) {
          robot.set_gripper(0, true);
        } else {
          w = 2.0 * target->bearing;
          v = std::fabs(target->bearing) < 0.5 ? std::min(p_.speed, target->range) : 0.0;
        }
        break;
      }
      case Mode::Carry: {
        if (!g.holding) {
          m.mode = Mode::Search;
          break;
        }
        if (nest_distance < p_.drop) {
          robot.set_gripper(0, false);
          m.mode = Mode::Leave;
          m.leave_steps = 25;
          break;
        }
        const double bearing = std::remainder(std::atan2(to_nest_y, to_nest_x) - me.a, 2 * kPi);
        w = 2.0 * bearing;
        v = std::fabs(bearing) < 0.6 ? p_.speed : 0.0;
        // Near the nest everything ahead is pucks already gathered: push on.
        if (nest_distance > p_.nest_r + 0.5) avoid(scan, 0.6 * p_.avoid, v, w, true);
        break;
      }
      case Mode::Leave:
        // Back out of the nest, turn, then search again.
        v = m.leave_steps > 12 ? -0.5 * p_.speed : 0.0;
        w = m.leave_steps > 12 ? 0.0 : 1.5;
        if (--m.leave_steps <= 0) m.mode = Mode::Search;
        break;
    }
    if (robot.state().stalled && m.mode != Mode::Leave) {
      // Stuck against something: turn on the spot for a while.
      v = 0;
      w = robot.uniform(0) < 0.5 ? -1.5 : 1.5;
    }
    robot.command(Command::velocity(v, 0, w));
  }

 private:
  enum class Mode { Search, Carry, Leave };  // Search first: all-zero memory searches

  // What it remembers between steps (the World's bytes; all zero at the
  // start).
  struct Memory {
    Mode mode;
    int leave_steps;   // steps of backing out of the nest left
    int wander_steps;  // steps until the next random turn
    double turn;       // rad/s while wandering
  };

  // The nearest puck seen that is not in the nest yet, or nullptr.
  const sim::FiducialReading* nearest_loose_puck(RobotHandle& robot, const sim::Pose& me) const {
    const sim::FiducialReading* best = nullptr;
    const double c = std::cos(me.a), s = std::sin(me.a);
    for (const sim::FiducialReading& f : robot.fiducial(0).readings) {
      if (f.id != p_.puck) continue;
      const double x = me.x + c * f.pose.x - s * f.pose.y, y = me.y + s * f.pose.x + c * f.pose.y;
      if (std::hypot(x - p_.nest_x, y - p_.nest_y) < p_.nest_r) continue;
      if (best == nullptr || f.range < best->range) best = &f;
    }
    return best;
  }

  // Turns away from the nearer side when something is within `within` ahead.
  // The simulator's ranger sees the puck the robot carries (Stage's would
  // not): while `holding`, readings of it (straight ahead, within reach of
  // the gripper) are not obstacles.
  void avoid(const sim::RangerView& scan, double within, double& v, double& w, bool holding = false) const {
    double left = 1e9, right = 1e9;
    for (size_t i = 0; i < scan.ranges.size() && i < bearings_.size(); ++i) {
      if (std::fabs(bearings_[i]) > 1.2) continue;
      if (holding && std::fabs(bearings_[i]) < 0.5 && scan.ranges[i] < p_.grab + 0.1) continue;
      (bearings_[i] > 0 ? left : right) = std::min(bearings_[i] > 0 ? left : right, double(scan.ranges[i]));
    }
    if (std::min(left, right) >= within) return;
    v = 0;
    w = left < right ? -1.5 : 1.5;
  }

  void wander(RobotHandle& robot, const sim::RangerView& scan, Memory& m, double& v, double& w) const {
    if (--m.wander_steps <= 0) {
      m.turn = (robot.uniform(1) - 0.5) * 1.6;
      m.wander_steps = 10 + int(robot.uniform(2) * 30);
    }
    v = p_.speed;
    w = m.turn;
    avoid(scan, p_.avoid, v, w);
  }

  ForageParams p_;
  std::vector<double> bearings_;  // rad, robot frame, one per ranger beam
};

sim::Controller* make_forage(const char* args) {
  sim::ControllerArgs a(args);
  ForageParams p;
  p.nest_x = a.number("nest_x", p.nest_x);
  p.nest_y = a.number("nest_y", p.nest_y);
  p.nest_r = a.number("nest_r", p.nest_r);
  p.speed = a.number("speed", p.speed);
  p.grab = a.number("grab", p.grab);
  p.drop = a.number("drop", p.drop);
  p.avoid = a.number("avoid", p.avoid);
  p.puck = int(a.number("puck", p.puck));
  if (!a.ok() || p.nest_r <= 0 || p.speed <= 0 || p.grab <= 0 || p.drop <= 0 || p.avoid < 0) return nullptr;
  return new Forage(p);
}

}  // namespace
}  // namespace troupe::examples

TROUPE_CONTROLLER("forage", troupe::examples::make_forage)
