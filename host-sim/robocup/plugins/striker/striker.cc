// striker: a scripted shooter. It gets behind the ball on the line to its
// aim point, drives onto the ball and kicks once; then it stands still.
// The goalkeeper benchmark starts it for every shot.
//
//   player striker aim_y=0.5 goal=opponent charge_speed=1 max_speed=1.5 drive=diff front=0.25
//
// aim_y: where on the goal line it aims, m from the goal's centre;
// goal: opponent | blue | yellow; front: the kicker plate's distance ahead
// of the robot's origin, m (default: 0.8 times the robot's reach).
#include "host-sim/robocup/plugins/common/control.h"

namespace troupe::robocup::plugins {
namespace {

class Striker final : public PlayerPlugin {
 public:
  bool configure(Options& o, std::string& error) override {
    aim_y_ = o.number("aim_y", 0, -10, 10);
    goal_ = o.choice("goal", "opponent", {"opponent", "blue", "yellow"});
    shot_.charge_speed = o.number("charge_speed", 1.0, 0.05, 10);
    limits_.max_speed = o.number("max_speed", 1.5, 0.05, 10);
    omni_ = o.choice("drive", "diff", {"omni", "diff"}) == "omni";
    front_ = o.number("front", -1, 0, 5);
    return o.finish(error);
  }

  void start(WorldControl& world, const PlayerContext& c) override {
    const bool at_yellow = goal_ == "yellow" || (goal_ == "opponent" && c.team == Team::Blue);
    aim_ = {(at_yellow ? 1 : -1) * world.field().length / 2, aim_y_};
    shot_.ball_radius = world.ball().radius;
    // The kicker plate is the robot's farthest point ahead.
    // The kicker plate's front, ahead of the robot's origin: given, or
    // guessed from the robot's size.
    shot_.front = front_ >= 0 ? front_ : world.robot(c.index).radius * 0.8;
    kicked_ = false;
  }

  void act(WorldControl& world, const PlayerContext& c, const PlayerInput& in, PlayerOutput& out) override {
    if (kicked_) return;
    const RobotInfo me = world.robot(c.index);
    const ShotStep step = shoot(omni_, me.pose, world.ball().position, aim_, in.kicker_ready, shot_, limits_);
    out.command = step.command;
    if (step.kick) {
      out.kick = true;
      kicked_ = true;
      out.broadcast.push_back("kick");
    }
  }

 private:
  double aim_y_ = 0;
  std::string goal_ = "opponent";
  Vec2 aim_;
  ShotSettings shot_;
  DriveLimits limits_;
  double front_ = -1;
  bool omni_ = false, kicked_ = false;
};

}  // namespace
}  // namespace troupe::robocup::plugins

TROUPE_PLUGIN_EXPORT const TroupePluginInfo* troupe_plugin_v1() {
  using namespace troupe::robocup;
  return plugin_info<PlayerPlugin, plugins::Striker>(PluginKind::Player, "striker");
}
