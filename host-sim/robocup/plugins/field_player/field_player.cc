// field_player: a simple team player for matches. Every cycle it tells
// its team on the broadcast channel how far it is from the ball; the
// nearest player of the team chases the ball and shoots at the opponent's
// goal, the others hold their home spots facing the ball.
//
//   player field_player home_x=-1.5 home_y=1 drive=diff max_speed=1.5 charge_speed=1.2 shoot_range=6
//                       front=0.25
//
// home_x, home_y: the home spot in the team's frame (x towards the
// opponent's goal, from the centre spot), m; shoot_range: kick only this
// close to the goal, m (farther, it dribbles); front: the kicker plate's
// distance ahead of the robot's origin, m (default: 0.8 times its reach).
#include <cstdlib>
#include <map>

#include "host-sim/robocup/plugins/common/control.h"

namespace troupe::robocup::plugins {
namespace {

class FieldPlayer final : public PlayerPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    home_ = {o.number("home_x", -1.5, -20, 20), o.number("home_y", 0, -20, 20)};
    omni_ = o.choice("drive", "diff", {"omni", "diff"}) == "omni";
    front_ = o.number("front", -1, 0, 5);
    limits_.max_speed = o.number("max_speed", 1.5, 0.05, 10);
    shot_.charge_speed = o.number("charge_speed", 1.2, 0.05, 10);
    shoot_range_ = o.number("shoot_range", 6, 0, 100);
    return o.finish(error);
  }

  void start(WorldControl& world, const PlayerContext& c) override {
    forward_ = c.team == Team::Blue ? 1 : -1;
    goal_ = {forward_ * world.field().length / 2, 0};
    shot_.ball_radius = world.ball().radius;
    // The kicker plate's front, ahead of the robot's origin: given, or
    // guessed from the robot's size.
    shot_.front = front_ >= 0 ? front_ : world.robot(c.index).radius * 0.8;
  }

  void act(WorldControl& world, const PlayerContext& c, const PlayerInput& in, PlayerOutput& out) override {
    const RobotInfo me = world.robot(c.index);
    const Vec2 ball = world.ball().position;
    const double mine = length(ball - me.pose.position());
    // The nearest of the team chases; ties go to the smaller name.
    bool chase = true;
    for (const Message& m : in.inbox) {
      if (m.team != c.team || m.from == c.robot || m.data.rfind("ball ", 0) != 0) continue;
      const double theirs = std::strtod(m.data.c_str() + 5, nullptr);
      if (theirs < mine - 0.05 || (std::fabs(theirs - mine) <= 0.05 && m.from < c.robot)) chase = false;
    }
    out.broadcast.push_back("ball " + std::to_string(mine));
    if (world.game().phase != GamePhase::Play) return;
    if (chase) {
      const ShotStep s = shoot(omni_, me.pose, ball, goal_, in.kicker_ready, shot_, limits_);
      out.command = s.command;
      out.kick = s.kick && length(goal_ - ball) < shoot_range_;
      return;
    }
    const Vec2 home{forward_ * home_.x, forward_ * home_.y};
    const Vec2 to_ball = ball - me.pose.position();
    out.command = drive_to(omni_, me.pose, home, std::atan2(to_ball.y, to_ball.x), limits_);
  }

 private:
  Vec2 home_, goal_;
  double forward_ = 1, shoot_range_ = 6;
  double front_ = -1;
  bool omni_ = false;
  DriveLimits limits_;
  ShotSettings shot_;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<PlayerPlugin, plugins::FieldPlayer>(PluginKind::Player, "field_player");
}
