// goalkeeper: a player that guards its team's goal with one of six
// policies (keeper_policy.h) and clears a ball that reaches its kicker.
//
//   player goalkeeper policy=block line=0.35 reach=0.8 max_speed=2 drive=omni
//                     random_period=1 pattern_period=4 mix_period=2 clear=1
//                     latency=0.1 noise=0
//
// policy: none | random | pattern | block | intercept | mixed.
// latency: the keeper sees the ball as it was this long ago, s (a vision
// pipeline's delay); noise: standard deviation of the seen ball position, m.
// line: distance in front of the goal line, m; reach: how far off centre it
// goes, m (default: half the goal less 0.2 m); drive: omni (holonomic base)
// or diff (a differential base standing sideways, driving along the line).
#include <deque>

#include "host-sim/robocup/plugins/common/control.h"
#include "host-sim/robocup/plugins/goalkeeper/keeper_policy.h"

namespace troupe::robocup::plugins {
namespace {

class Goalkeeper final : public PlayerPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    const std::string policy =
        o.choice("policy", "block", {"none", "random", "pattern", "block", "intercept", "mixed"});
    parse_policy(policy, policy_);
    geometry_.line = o.number("line", geometry_.line, 0, 3);
    reach_ = o.number("reach", -1, 0, 10);
    limits_.max_speed = o.number("max_speed", 2.0, 0.01, 20);
    limits_.gain = o.number("gain", 6, 0.1, 100);
    omni_ = o.choice("drive", "omni", {"omni", "diff"}) == "omni";
    settings_.random_period_s = o.number("random_period", settings_.random_period_s, 0.01, 1000);
    settings_.pattern_period_s = o.number("pattern_period", settings_.pattern_period_s, 0.1, 1000);
    settings_.mix_period_s = o.number("mix_period", settings_.mix_period_s, 0.01, 1000);
    latency_s_ = o.number("latency", 0.1, 0, 5);
    noise_ = o.number("noise", 0, 0, 5);
    clear_ = o.flag("clear", true);
    return o.finish(error);
  }

  void start(WorldControl& world, const PlayerContext& c) override {
    const FieldGeometry& f = world.field();
    geometry_.forward = c.team == Team::Blue ? 1 : -1;
    geometry_.goal_x = -geometry_.forward * f.length / 2;
    geometry_.goal_half_width = f.goal_width / 2;
    geometry_.reach = reach_ >= 0 ? reach_ : std::max(0.0, f.goal_width / 2 - 0.2);
  }

  void act(WorldControl& world, const PlayerContext& c, const PlayerInput& in, PlayerOutput& out) override {
    const RobotInfo me = world.robot(c.index);
    const BallInfo ball = world.ball();
    const Seen seen = perceive(world, ball, *c.rng);
    const Vec2 target = keeper_target(policy_, geometry_, settings_, me.pose.position(), seen.position,
                                      seen.velocity, world.time_s(), memory_, *c.rng);
    if (policy_ == KeeperPolicy::None) {
      out.command = {};
    } else if (omni_) {
      // Face the field so the kicker points away from the goal.
      out.command = omni_to(me.pose, target, geometry_.forward > 0 ? 0 : kPi, limits_);
    } else {
      // Sideways on the line: forward motion runs along it.
      const double heading = kPi / 2;
      const double along = rotate(target - me.pose.position(), -heading).x;
      if (std::fabs(me.pose.position().x - geometry_.line_x()) > 0.15) {
        out.command = diff_to(me.pose, target, heading, limits_);
      } else {
        const double v = std::clamp(limits_.gain * along * std::cos(wrap_angle(me.pose.a - heading)),
                                    -limits_.max_speed, limits_.max_speed);
        out.command = {v, 0, std::clamp(limits_.turn_gain * wrap_angle(heading - me.pose.a), -4.0, 4.0)};
      }
    }
    if (clear_ && in.kicker_ready) {
      const Vec2 local = me.pose.to_local(ball.position);
      out.kick = local.x > 0 && local.x < me.radius + ball.radius + 0.05 && std::fabs(local.y) < 0.15;
    }
  }

 private:
  struct Seen {
    double time_s;
    Vec2 position, velocity;
  };
  // The ball as the keeper's vision reports it: `latency` old, noisy.
  Seen perceive(const WorldView& world, const BallInfo& ball, Rng& rng) {
    const double now = world.time_s();
    Vec2 noise;
    if (noise_ > 0) {
      noise.x = rng.gaussian(noise_);
      noise.y = rng.gaussian(noise_);
    }
    seen_.push_back({now, ball.position + noise, ball.velocity});
    while (seen_.size() > 1 && seen_[1].time_s <= now - latency_s_ + 1e-9) seen_.pop_front();
    return seen_.front();
  }

  KeeperPolicy policy_ = KeeperPolicy::Block;
  std::deque<Seen> seen_;
  double latency_s_ = 0.1, noise_ = 0;
  KeeperGeometry geometry_;
  KeeperSettings settings_;
  KeeperMemory memory_;
  DriveLimits limits_;
  double reach_ = -1;
  bool omni_ = true, clear_ = true;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<PlayerPlugin, plugins::Goalkeeper>(PluginKind::Player, "goalkeeper");
}
