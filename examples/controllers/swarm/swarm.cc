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
// The behaviour itself is swarm_logic.h, shared with the over-the-wire
// example (examples/controllers/swarm_clients).
#include <algorithm>
#include <cmath>
#include <vector>

#include "examples/controllers/swarm/swarm_logic.h"
#include "host-sim/sim/controller.h"

namespace troupe::examples {
namespace {

using sim::Command;
using sim::RobotHandle;
using sim::SensorKind;

class Swarm final : public sim::Controller {
 public:
  explicit Swarm(const SwarmParams& params) : params_(params) {}

  bool init(RobotHandle& robot, std::string& error) override {
    in_.has_fiducial = robot.count(SensorKind::Fiducial) > 0;
    if (params_.aggregate && !in_.has_fiducial) {
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
        in_.bearings.push_back(
            std::remainder(t.pose.a + (s > 1 ? -t.fov / 2 + t.fov * i / (s - 1) : 0.0), 6.283185307179586));
      }
    }
    robot.want(SensorKind::Ranger, 0, true);
    if (in_.has_fiducial) robot.want(SensorKind::Fiducial, 0, true);
    return true;
  }

  size_t memory_size() const override { return sizeof(SwarmState); }

  void update(RobotHandle& robot) override {
    const sim::RangerView scan = robot.ranger(0);
    if (scan.step == UINT64_MAX) return;
    in_.ranges.assign(scan.ranges.begin(), scan.ranges.end());
    in_.neighbours.clear();
    if (in_.has_fiducial) {
      for (const sim::FiducialReading& f : robot.fiducial(0).readings)
        in_.neighbours.push_back({f.pose.x, f.pose.y});
    }
    const SwarmCommand c = swarm_decide(params_, in_, robot.memory_as<SwarmState>(),
                                        [&](int k) { return robot.uniform(uint64_t(k)); });
    robot.command(Command::velocity(c.v, 0, c.w));
  }

 private:
  SwarmParams params_;
  // Scratch refilled every step (ranges, neighbours) and the beams'
  // bearings init() derives; what the robot remembers (SwarmState) is the
  // World's memory.
  SwarmInputs in_;
};

sim::Controller* make_swarm(const char* args) {
  sim::ControllerArgs a(args);
  SwarmParams p;
  const bool aggregate = a.flag("aggregate"), disperse = a.flag("disperse");
  p.aggregate = aggregate;
  p.speed = a.number("speed", p.speed);
  p.spacing = a.number("spacing", p.spacing);
  p.avoid = a.number("avoid", p.avoid);
  if (!a.ok() || aggregate == disperse || p.speed < 0 || p.spacing <= 0 || p.avoid < 0) return nullptr;
  return new Swarm(p);
}

}  // namespace
}  // namespace troupe::examples

TROUPE_CONTROLLER("swarm", troupe::examples::make_swarm)
