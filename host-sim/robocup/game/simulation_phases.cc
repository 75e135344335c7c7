// The phases of a simulation cycle that involve plugins and the referee.
#include <algorithm>

#include "host-sim/robocup/game/simulation.h"
#include "host-sim/robocup/physics/kick.h"

namespace troupe::robocup {
namespace {

// What one player may send per cycle: the channel is a radio link, not a
// bulk pipe, and a runaway player must not flood the others.
constexpr size_t kMaxMessagesPerCycle = 8;
constexpr size_t kMaxMessageBytes = 1024;

}  // namespace

void Simulation::run_players() {
  for (int i = 0; i < robot_count(); ++i) {
    Robot& r = robots_[size_t(i)];
    if (!r.player) continue;
    PlayerInput in;
    in.readings = r.readings;
    in.inbox = inbox_;
    in.kicker_ready = r.spec.has_kicker && r.kicker_state == 0;
    PlayerOutput out;
    r.player->act(*this, {r.name, i, r.team, &r.player_rng}, in, out);
    r.command = out.command;
    if (out.kick) r.kick_requested = true;
    size_t sent = 0;
    for (std::string& data : out.broadcast) {
      if (sent == kMaxMessagesPerCycle || data.size() > kMaxMessageBytes) {
        problem("robot " + r.name + ": player '" + r.player_name + "': broadcast over " +
                std::to_string(kMaxMessagesPerCycle) + " messages of " + std::to_string(kMaxMessageBytes) +
                " bytes per cycle; the rest was dropped");
        break;
      }
      outbox_.push_back({r.name, r.team, time_s(), std::move(data)});
      ++sent;
    }
  }
}

void Simulation::run_motion() {
  const double dt = cycle_s();
  for (Robot& r : robots_) {
    if (!r.motion) {
      // No drive: the wheels hold the robot where it is.
      world_.set_velocity(r.body, {});
      continue;
    }
    const Pose2 pose = world_.pose(r.body);
    const Vec2 v = rotate(world_.velocity_at(r.body, pose.position()), -pose.a);
    const Twist current{v.x, v.y, world_.velocity(r.body).w};
    const Twist next = r.motion->drive(r.command, current, dt);
    const Vec2 world_v = rotate(next.linear(), pose.a);
    world_.set_origin_velocity(r.body, {world_v.x, world_v.y, next.w});
  }
}

void Simulation::run_kickers() {
  for (Robot& r : robots_) {
    const bool requested = r.kick_requested;
    r.kick_requested = false;
    if (!r.spec.has_kicker) continue;
    const KickerSpec& k = r.spec.kicker;
    int enter = -1;
    const KickerState& now = k.states[size_t(r.kicker_state)];
    if (now.hold_s > 0 && now.next_index >= 0 && time_s() - r.kicker_since_s >= now.hold_s - 1e-9) {
      enter = now.next_index;
    } else if (requested && r.kicker_state == 0) {
      enter = 1;
    }
    if (enter < 0) continue;
    set_kicker_state(r, enter);
    const KickerState& s = k.states[size_t(enter)];
    if (s.accel <= 0) continue;
    // A ball touching the plate of the new state is kicked: it gains
    // accel * contact along the kick direction.
    kick_ball(world_, r.body, s.shapes, k.reach, k.direction, s.accel * s.contact_s, ball_);
  }
}

Vec2 Simulation::free_spot(Vec2 wanted) {
  // Step towards the centre spot until no robot is in the way.
  const Vec2 toward = length(wanted) > 0 ? -normalized(wanted) : Vec2{0, 0};
  const Pose2 saved = world_.pose(ball_);
  Vec2 spot = wanted;
  for (int k = 0; k < 12; ++k) {
    spot = wanted + toward * (0.25 * k);
    world_.set_pose(ball_, {spot.x, spot.y, 0});
    bool clear = true;
    for (const Robot& r : robots_) {
      if (world_.distance(ball_, r.body).distance < world_.settings().contact_slop) clear = false;
    }
    if (clear) break;
  }
  world_.set_pose(ball_, saved);
  return spot;
}

void Simulation::run_referee() {
  const BallInfo b = ball();
  const RefereeDecision d = referee_.judge(time_s(), b.position, b.radius);
  if (d.place_ball) place_ball(free_spot(d.ball_to), {0, 0});
  if (d.reset) reset();
}

void Simulation::run_sensors() {
  const uint64_t step = world_.steps();
  for (int i = 0; i < robot_count(); ++i) {
    Robot& r = robots_[size_t(i)];
    for (size_t k = 0; k < r.sensors.size(); ++k) {
      Sensor& s = r.sensors[k];
      if (step % uint64_t(s.spec.period) != 0) continue;
      SensorReading& out = r.readings[k];
      out.detections.clear();
      out.ranges.clear();
      out.time_s = time_s();
      s.plugin->sense(*this, {i, s.spec.mount, s.spec.mount_z, &s.rng}, out);
      out.valid = true;
    }
  }
}

}  // namespace troupe::robocup
