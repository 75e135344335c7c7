#include "host-sim/sim/kicker.h"

#include "host-sim/robocup/physics/kick.h"

namespace troupe::sim {

Kickers::Kickers(World& world) : world_(world) {
  const WorldDesc& desc = world.desc();
  for (RobotId r = 0; r < RobotId(desc.robots.size()); ++r) {
    const RobotDesc& robot = desc.robots[r];
    if (robot.puck) pucks_.push_back(r);
    of_robot_.push_back({uint32_t(kickers_.size()), uint32_t(robot.kickers.size())});
    for (const KickerDesc& k : robot.kickers) {
      Kicker kicker;
      kicker.robot = r;
      kicker.desc = k;
      const robocup::Shape rect = robocup::make_rect({k.pose.x, k.pose.y}, k.size.x, k.size.y, k.pose.a);
      kicker.plate = k.height > 0 ? robocup::with_height(rect, 0, k.height) : rect;
      kickers_.push_back(kicker);
    }
  }
}

IndexRange Kickers::of(RobotId robot) const {
  return robot < of_robot_.size() ? of_robot_[robot] : IndexRange{};
}

bool Kickers::ready(uint32_t index) const {
  const Kicker& k = kickers_.at(index);
  const double now = world_.time();
  // A reset world's clock runs from 0 again: a kick "in the future" is gone.
  return now < k.kicked_at || now >= k.kicked_at + k.desc.hold - 1e-9;
}

int Kickers::kick(uint32_t index) {
  if (!ready(index)) return 0;
  Kicker& k = kickers_.at(index);
  k.kicked_at = world_.time();
  robocup::World* rigid = world_.rigid();
  const robocup::BodyId body = world_.rigid_body(k.robot);
  if (rigid == nullptr || body == robocup::kNoBody) return 0;
  int kicked = 0;
  for (RobotId puck : pucks_) {
    const robocup::BodyId ball = world_.rigid_body(puck);
    // A puck a gripper carries has no body of its own while carried.
    if (ball == robocup::kNoBody || !rigid->valid(ball)) continue;
    if (robocup::kick_ball(*rigid, body, {&k.plate, 1}, k.desc.reach, k.desc.pose.a,
                           k.desc.accel * k.desc.contact, ball)) {
      ++kicked;
    }
  }
  // The robots' states (poses and what clients see) follow the rigid world.
  if (kicked > 0) world_.rigid_moved();
  return kicked;
}

}  // namespace troupe::sim
