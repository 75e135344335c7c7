// A ball and a kicker in a Stage world (examples/worlds/kick.world): a
// robot driven into the ball pushes it; a kick sends it off far faster,
// in the engine (sim/kicker.h) and through troupe-sim's actuator:0 over
// TCP; a kick with nothing touching the plate, or while the kicker
// recovers, moves nothing; the world file's mistakes in `ball` and
// `kicker` are reported with file:line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "host-sim/sim/kicker.h"
#include "host-sim/sim/loader.h"
#include "host-sim/sim/world.h"
#include "tests/sim/served_world.h"
#include "tests/sim/temp_dir.h"
#include "wire/client/proxies.h"

namespace troupe::sim {
namespace {

std::string kick_world_path() {
  return std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/kick.world";
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

RobotId id_of(const World& w, const char* name) {
  const auto id = w.find_robot(name);
  EXPECT_TRUE(id.has_value()) << name;
  return id.value_or(0);
}

double speed(const World& w, RobotId id) {
  const Pose& v = w.state(id).velocity;
  return std::hypot(v.x, v.y);
}

// Drives `robot` at `vx` m/s for `steps` steps; the ball's fastest speed
// on the way, m/s.
double drive(World& w, RobotId robot, double vx, int steps) {
  const RobotId ball = id_of(w, "ball");
  EXPECT_TRUE(w.command(robot, Command::velocity(vx, 0, 0)));
  double fastest = 0;
  for (int i = 0; i < steps; ++i) {
    w.step();
    fastest = std::max(fastest, speed(w, ball));
  }
  EXPECT_TRUE(w.command(robot, Command::velocity(0, 0, 0)));
  return fastest;
}

TEST(KickWorld, LoadsWithABallAndAKickerOnARigidWorld) {
  world::Diagnostics d;
  WorldDesc desc;
  ASSERT_TRUE(load_world_file(kick_world_path(), desc, d)) << d.str();
  EXPECT_EQ(d.items().size(), 0u) << d.str();
  EXPECT_EQ(desc.physics, Physics::Rigid);
  ASSERT_EQ(desc.robots.size(), 3u);
  const RobotDesc& ball = desc.robots[0];
  EXPECT_EQ(ball.name, "ball");
  EXPECT_TRUE(ball.puck);
  ASSERT_TRUE(ball.rigid.has_value());
  EXPECT_FALSE(ball.rigid->driven);
  EXPECT_DOUBLE_EQ(ball.mass, 0.43);
  EXPECT_DOUBLE_EQ(ball.rigid->linear_deceleration, 0.4);
  const RobotDesc& striker = desc.robots[1];
  ASSERT_EQ(striker.kickers.size(), 1u);
  EXPECT_DOUBLE_EQ(striker.kickers[0].pose.x, 0.215);
  EXPECT_DOUBLE_EQ(striker.pose.x, -0.5);
  EXPECT_DOUBLE_EQ(striker.kickers[0].accel * striker.kickers[0].contact, 5.0);
  EXPECT_TRUE(desc.robots[2].kickers.empty());
}

TEST(KickWorld, ARobotDrivenIntoTheBallPushesIt) {
  world::Diagnostics d;
  auto w = World::load(kick_world_path(), 1, d);
  ASSERT_TRUE(w) << d.str();
  const RobotId ball = id_of(*w, "ball");
  // The pusher faces the ball from 0.6 m south of it.
  const double fastest = drive(*w, id_of(*w, "pusher"), 0.5, 20);
  EXPECT_GT(w->state(ball).pose.y, 0.2) << "the ball went north, pushed";
  EXPECT_NEAR(w->state(ball).pose.x, 0, 0.05);
  EXPECT_GT(fastest, 0.3);
}

TEST(KickWorld, AKickSendsTheBallOffFasterThanPushing) {
  world::Diagnostics d;
  auto pushed = World::load(kick_world_path(), 1, d);
  auto kicked = World::load(kick_world_path(), 1, d);
  ASSERT_TRUE(pushed && kicked) << d.str();
  const double push_speed = drive(*pushed, id_of(*pushed, "pusher"), 0.5, 20);

  Kickers kickers(*kicked);
  const RobotId striker = id_of(*kicked, "striker"), ball = id_of(*kicked, "ball");
  ASSERT_EQ(kickers.count(), 1u);
  EXPECT_EQ(kickers.owner(0), striker);
  EXPECT_EQ(kickers.of(striker).count, 1u);
  EXPECT_EQ(kickers.kick(0), 0) << "the plate is 0.06 m short of the ball";
  EXPECT_EQ(speed(*kicked, ball), 0);
  // Up to the ball, until the plate nudges it: then it touches.
  ASSERT_TRUE(kicked->command(striker, Command::velocity(0.2, 0, 0)));
  for (int i = 0; i < 20 && kicked->state(ball).pose.x < 0.002; ++i) kicked->step();
  ASSERT_TRUE(kicked->command(striker, Command::velocity(0, 0, 0)));
  ASSERT_GE(kicked->state(ball).pose.x, 0.002) << "the striker reached the ball";
  EXPECT_TRUE(kickers.ready(0)) << "a kick that touched nothing still uses the kicker, but its hold is over";
  ASSERT_EQ(kickers.kick(0), 1);
  EXPECT_FALSE(kickers.ready(0)) << "recovering for its hold time";
  EXPECT_EQ(kickers.kick(0), 0) << "no second kick while it recovers";
  kicked->step();
  const double kick_speed = speed(*kicked, ball);
  EXPECT_GT(kick_speed, 4.0) << "5 m/s from the kick, less the floor's slowing";
  EXPECT_GT(kick_speed, 4 * push_speed);
  const Pose at = kicked->state(ball).pose;
  kicked->step();
  EXPECT_GT(kicked->state(ball).pose.x, at.x + 0.3) << "east, along the plate's heading";
  EXPECT_FALSE(kickers.ready(0)) << "0.2 s of its 0.3 s hold";
  kicked->step();
  EXPECT_TRUE(kickers.ready(0)) << "its hold is over";
}

TEST(KickWorld, SameSeedSameKick) {
  world::Diagnostics d;
  Pose end[2];
  for (Pose& p : end) {
    auto w = World::load(kick_world_path(), 7, d);
    ASSERT_TRUE(w) << d.str();
    Kickers kickers(*w);
    drive(*w, id_of(*w, "striker"), 0.2, 6);
    kickers.kick(0);
    for (int i = 0; i < 30; ++i) w->step();
    p = w->state(id_of(*w, "ball")).pose;
  }
  EXPECT_EQ(end[0].x, end[1].x);
  EXPECT_EQ(end[0].y, end[1].y);
}

// ---- The world file's mistakes ----------------------------------------------

TEST(KickWorldFile, UnknownKeysInBallAndKickerAndABallInARobotWarnWithFileAndLine) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  ASSERT_TRUE(load_world_file(dir.write("t.world", R"(physics "rigid"
resolution 0.02
ball ( radius 0.1 bounce 3 )
position ( name "k" size [0.4 0.4 0.3]
  kicker ( pose [0.2 0 0 0] size [0.03 0.3 0.1] accel 100 power 9 )
  ball ( )
)
)"),
                              w, d))
      << d.str();
  EXPECT_FALSE(d.has_errors()) << d.str();
  const std::string text = d.str();
  EXPECT_NE(text.find("t.world:3"), std::string::npos) << text;
  EXPECT_NE(text.find("bounce"), std::string::npos) << text;
  EXPECT_NE(text.find("t.world:5"), std::string::npos) << text;
  EXPECT_NE(text.find("power"), std::string::npos) << text;
  EXPECT_NE(text.find("t.world:6: warning: a ball inside a model is ignored"), std::string::npos) << text;
  // What was right is kept.
  ASSERT_EQ(w.robots.size(), 2u);
  EXPECT_EQ(w.robots[0].rigid->shapes[0].radius, 0.1);
  ASSERT_EQ(w.robots[1].kickers.size(), 1u);
  EXPECT_EQ(w.robots[1].kickers[0].accel, 100);
}

TEST(KickWorldFile, AKickerOrABallOnAKinematicWorldIsRefused) {
  troupe::test::TempDir dir;
  for (const char* physics : {"", "physics \"kinematic\"\n"}) {
    world::Diagnostics d;
    WorldDesc w;
    EXPECT_FALSE(load_world_file(dir.write("t.world", std::string(physics) + R"(resolution 0.02
position ( name "k" size [0.4 0.4 0.3]
  kicker ( pose [0.2 0 0 0] size [0.03 0.3 0.1] )
)
)"),
                                 w, d));
    const std::string text = d.str();
    EXPECT_NE(text.find("t.world:" + std::to_string(physics[0] ? 4 : 3)), std::string::npos) << text;
    EXPECT_NE(text.find("a kicker needs physics \"rigid\""), std::string::npos) << text;
  }
  world::Diagnostics d;
  WorldDesc w;
  EXPECT_FALSE(load_world_file(dir.write("t.world", "resolution 0.02\nball ( )\n"), w, d));
  EXPECT_NE(d.str().find("t.world:2"), std::string::npos) << d.str();
  EXPECT_NE(d.str().find("a ball needs physics \"rigid\""), std::string::npos) << d.str();
}

TEST(KickWorldFile, BadBallAndKickerValuesAreErrorsWithFileAndLine) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc w;
  EXPECT_FALSE(load_world_file(dir.write("t.world", R"(physics "rigid"
ball ( radius -1 )
ball ( mass 0 )
position ( kicker ( accel -5 ) )
position ( kicker ( hold 100 ) )
)"),
                               w, d));
  const std::string text = d.str();
  for (const char* where : {"t.world:2", "t.world:3", "t.world:4", "t.world:5"}) {
    EXPECT_NE(text.find(where), std::string::npos) << where << "\n" << text;
  }
  EXPECT_NE(text.find("a ball's radius must be in [0.01, 1] m"), std::string::npos) << text;
  EXPECT_NE(text.find("accel must be in [0, 100000] m/s^2"), std::string::npos) << text;
}

// ---- Served: troupe-sim's runner over TCP -----------------------------------

const std::string& kick_world_text() {
  static const std::string text = read_text(kick_world_path());
  return text;
}

class KickServed : public test::ServedWorld {
 protected:
  KickServed() : ServedWorld(kick_world_text().c_str()) {}

  // The ball's fastest speed over `steps` steps, m/s, from the poses
  // simulation:0 reports after each 0.1 s step.
  double ball_speed_over(client::SimulationProxy& sim, int steps) {
    double fastest = 0;
    client::Pose2 before, after;
    EXPECT_TRUE(sim.get_pose("ball", before));
    for (int i = 0; i < steps; ++i) {
      EXPECT_TRUE(sim.step(1));
      EXPECT_TRUE(sim.get_pose("ball", after));
      fastest = std::max(fastest, std::hypot(double(after.x - before.x), double(after.y - before.y)) / 0.1);
      before = after;
    }
    return fastest;
  }
};

TEST_F(KickServed, TheKickerIsActuator0AndAKickSendsTheBallFasterThanAPush) {
  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices));
  std::vector<std::string> names;
  for (const auto& d : devices) names.push_back(d.text());
  // The ball is a model with a pose like the robots' (a puck's position2d).
  EXPECT_EQ(names,
            (std::vector<std::string>{"ball/position2d:0", "striker/position2d:0", "striker/actuator:0",
                                      "pusher/position2d:0", "simulation:0", "map:0"}));
  wire::Address striker_at, pusher_at, kicker_at;
  ASSERT_TRUE(c.resolve("striker/position2d:0", striker_at));
  ASSERT_TRUE(c.resolve("pusher/position2d:0", pusher_at));
  ASSERT_TRUE(c.resolve("striker/actuator:0", kicker_at));
  client::Position2dProxy striker(c, striker_at), pusher(c, pusher_at);
  client::ActuatorProxy kicker(c, kicker_at.index(), kicker_at.robot());
  client::SimulationProxy sim(c);
  ASSERT_TRUE(striker.is_open() && pusher.is_open() && kicker.is_open() && sim.is_open());
  ASSERT_TRUE(sim.step(1));
  ASSERT_TRUE(c.sync());
  EXPECT_EQ(kicker.mode(), wire::ActuatorMode::Ready);

  // The pusher drives into the ball: it rolls along at about its speed.
  ASSERT_TRUE(pusher.set_velocity(0.5f, 0, 0));
  const double pushed = ball_speed_over(sim, 10);
  EXPECT_GT(pushed, 0.3);
  ASSERT_TRUE(pusher.set_velocity(0, 0, 0));
  // Back where it was, at rest, for the striker's turn.
  ASSERT_TRUE(sim.reset());
  ASSERT_TRUE(sim.step(1));

  // Up to the ball, until the plate nudges it: then it touches.
  ASSERT_TRUE(striker.set_velocity(0.2f, 0, 0));
  client::Pose2 ball;
  for (int i = 0; i < 20 && ball.x < 0.002f; ++i) {
    ASSERT_TRUE(sim.step(1));
    ASSERT_TRUE(sim.get_pose("ball", ball));
  }
  ASSERT_TRUE(striker.set_velocity(0, 0, 0));
  ASSERT_GE(ball.x, 0.002f) << "the striker reached the ball";
  ASSERT_TRUE(kicker.kick());
  const double kicked = ball_speed_over(sim, 1);
  EXPECT_EQ(kicker.mode(), wire::ActuatorMode::Kicking) << "recovering for 0.3 s";
  EXPECT_GT(kicked, 4.0);
  EXPECT_GT(kicked, 4 * pushed) << "pushed at " << pushed << " m/s, kicked at " << kicked;
  ball_speed_over(sim, 3);
  EXPECT_EQ(kicker.mode(), wire::ActuatorMode::Ready);
  ASSERT_TRUE(sim.get_pose("ball", ball));
  EXPECT_GT(ball.x, 1.0) << "east of the striker, along its heading";
}

}  // namespace
}  // namespace troupe::sim
