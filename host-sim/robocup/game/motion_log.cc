#include "host-sim/robocup/game/motion_log.h"

#include <cstdio>

namespace troupe::robocup {

bool write_motion_log(Simulation& sim, int robot, const MotionLogSettings& s, std::ostream& out,
                      std::string& error) {
  if (robot < 0 || robot >= sim.robot_count()) {
    error = "no such robot";
    return false;
  }
  if (!sim.player_of(robot).empty()) {
    error = "the robot runs a player; the recorder must command it alone";
    return false;
  }
  Rng rng(s.seed);
  auto heading = [&rng] { return rng.uniform(-kPi, kPi); };
  const double hx = sim.field().length / 2 - 1.0, hy = sim.field().width / 2 - 1.0;
  out << "# troupe motion log: time_s vx vy w cmd_vx cmd_vy cmd_w (robot frame, SI)\n";
  MotionCommand cmd;
  double change_at = 0;
  const long steps = std::lround(s.seconds / sim.cycle_s());
  char line[256];
  for (long i = 0; i < steps; ++i) {
    if (rng.uniform() < s.push_rate * sim.cycle_s()) {
      const BodyId body = sim.robot_body(robot);
      const Twist v = sim.physics().velocity(body);
      const Vec2 dv = direction(heading()) * (s.push_speed * rng.uniform());
      sim.physics().set_velocity(body, {v.vx + dv.x, v.vy + dv.y, v.w});
      out << "break\n";  // the push is not the drive's doing
    }
    const RobotInfo r = sim.robot(robot);
    if (std::fabs(r.pose.x) > hx || std::fabs(r.pose.y) > hy) {
      sim.place_robot(robot, {0, 0, heading()});
      out << "break\n";
      continue;
    }
    if (sim.time_s() >= change_at) {
      cmd.vx = rng.uniform(s.min_vx, s.max_vx);
      cmd.vy = rng.uniform(-s.max_vy, s.max_vy);
      cmd.w = rng.uniform(-s.max_w, s.max_w);
      change_at = sim.time_s() + rng.uniform(s.hold_min_s, s.hold_max_s);
    }
    const Vec2 v = rotate(r.velocity.linear(), -r.pose.a);
    snprintf(line, sizeof line, "%.4f %.6f %.6f %.6f %.6f %.6f %.6f\n", sim.time_s(), v.x, v.y, r.velocity.w,
             cmd.vx, cmd.vy, cmd.w);
    out << line;
    sim.command(robot, cmd);
    sim.step();
  }
  return bool(out);
}

}  // namespace troupe::robocup
