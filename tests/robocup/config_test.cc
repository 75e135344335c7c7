// RoboCup worlds as Stage world files (models to statements), the console's
// commands, and errors that say file and line.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "host-sim/robocup/game/world_spec.h"
#include "sim_fixture.h"

namespace troupe::robocup {
namespace {

std::vector<Statement> parse_ok(const std::string& text) {
  std::vector<Statement> st;
  std::string error;
  EXPECT_TRUE(parse_stage_text(text, "t.world", st, error)) << error;
  return st;
}

std::string parse_error(const std::string& text) {
  std::vector<Statement> st;
  std::string error;
  EXPECT_FALSE(parse_stage_text(text, "t.world", st, error));
  return error;
}

TEST(StageWorld, ModelsBecomeStatementsWithTheirLines) {
  auto st = parse_ok(
      "# a comment\n"
      "interval_sim 20 seed 4\n"
      "define bot robocup_robot ( shape ( kind \"rect\" length 0.4 width 0.3 z [0 0.5] ) )\n"
      "bot ( name \"r1\" team \"blue\" pose [1 2 0 90]  # trailing\n"
      "  kicker ( reach 0.03\n"
      "    state ( name \"rest\" shape ( kind \"rect\" x 0.2 ) )\n"
      "    state ( name \"kick\" accel 300 ) state ( name \"other\" )\n"
      "  )\n"
      "  sensor_plugin ( plugin \"camera\" name \"front\" fov 1 )\n"
      ")\n");
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].keyword, "world");
  EXPECT_EQ(st[0].options[0], (std::pair<std::string, std::string>{"cycle", "0.02"}));
  EXPECT_EQ(st[1].keyword, "robot");
  EXPECT_EQ(st[1].args, std::vector<std::string>{"r1"});
  EXPECT_EQ(st[1].line, 4);
  const Options o = st[1].reader();
  EXPECT_EQ(o.entries()[1].first, "x");
  EXPECT_EQ(std::stod(o.entries()[3].second), kPi / 2) << "pose degrees become radians";
  ASSERT_EQ(st[1].children.size(), 3u);  // the define's shape, the kicker, the sensor
  EXPECT_EQ(st[1].children[0].keyword, "shape");
  EXPECT_EQ(st[1].children[0].args[0], "rect");
  EXPECT_EQ(st[1].children[0].options.back(), (std::pair<std::string, std::string>{"z", "0,0.5"}));
  const Statement& kicker = st[1].children[1];
  ASSERT_EQ(kicker.children.size(), 3u);
  EXPECT_EQ(kicker.children[0].children[0].keyword, "shape");
  EXPECT_EQ(kicker.children[2].args[0], "other");
  EXPECT_EQ(kicker.children[2].line, 7);
  EXPECT_EQ(st[1].children[2].keyword, "sensor");
  EXPECT_EQ(st[1].children[2].args[0], "camera");
}

TEST(StageWorld, ErrorsNameFileAndLine) {
  EXPECT_NE(parse_error("a (\n b 1\n").find("t.world:"), std::string::npos);
  EXPECT_EQ(parse_error("\ngoal ( x 1 )\n"),
            "t.world:2: 'goal' is no RoboCup model (robocup_field, ball, referee, robocup_robot)");
  EXPECT_EQ(parse_error("robocup_robot ( team \"blue\" )\n"), "t.world:1: a robocup_robot needs a name");
  EXPECT_EQ(parse_error("robocup_robot ( name \"r\" pose [1 2 3] )\n"),
            "t.world:1: pose: expected [x y z a]");
  EXPECT_EQ(
      parse_error("robocup_robot ( name \"r\" wheel ( ) )\n"),
      "t.world:1: 'wheel' in a robocup_robot (shape, kicker, motion_plugin, sensor_plugin, player, or a "
      "Stage sensor: ranger, laser, camera, fiducial, blobfinder, bumper, gripper)");
}

TEST(StageWorld, IncludesAreRelativeToTheIncludingFile) {
  const std::string dir = TROUPE_BINARY_DIR "/tests/robocup";
  std::ofstream(dir + "/inc_child.world") << "robocup_field ( length 10 )\n";
  std::ofstream(dir + "/inc_loop.world") << "include \"inc_loop.world\"\n";
  std::vector<Statement> st;
  std::string error;
  ASSERT_TRUE(parse_stage_text("include \"inc_child.world\"\nball ( )\n", dir + "/main.world", st, error))
      << error;
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].keyword, "field");
  EXPECT_EQ(st[0].file, dir + "/inc_child.world");
  EXPECT_FALSE(parse_stage_text("include \"inc_loop.world\"\n", dir + "/main.world", st, error));
  EXPECT_NE(error.find("inc_loop.world"), std::string::npos) << error;
  EXPECT_FALSE(parse_stage_text("include \"absent.world\"\n", dir + "/main.world", st, error));
  EXPECT_NE(error.find("main.world:1:"), std::string::npos) << error;
}

TEST(Commands, OneLineEachWithOptions) {
  std::vector<Statement> st;
  std::string error;
  ASSERT_TRUE(parse_commands("# hi\nstart r1 goalkeeper policy=block\nrun 2; score\n", "script", st, error))
      << error;
  ASSERT_EQ(st.size(), 3u);
  EXPECT_EQ(st[0].args, (std::vector<std::string>{"r1", "goalkeeper"}));
  EXPECT_EQ(st[0].options[0], (std::pair<std::string, std::string>{"policy", "block"}));
  EXPECT_EQ(st[2].keyword, "score");
  EXPECT_EQ(st[2].line, 3);
  EXPECT_FALSE(parse_commands("run {\n", "script", st, error));
  EXPECT_EQ(error, "script:1: '{': commands take no block");
  EXPECT_FALSE(parse_commands("start a x=\"open\n", "script", st, error));
  EXPECT_EQ(error, "script:1: unterminated quote");
  EXPECT_FALSE(parse_commands("a =3\n", "script", st, error));
  EXPECT_EQ(error, "script:1: '=3' has no key");
}

std::string world_error(const std::string& text) {
  WorldSpec spec;
  std::string error;
  EXPECT_FALSE(test::world_from_text(text, spec, error));
  return error;
}

std::string robot_error(const std::string& body) {
  return world_error("robocup_robot ( name \"r\"\n" + body + ")\n");
}

TEST(WorldFile, BadValuesAndUnknownKeysSayWhere) {
  EXPECT_NE(world_error("interval_sim 0\n").find("test.world:1: world: option 'cycle': must be in"),
            std::string::npos);
  EXPECT_NE(
      world_error("\nrobocup_field ( lenght 9 )\n").find("test.world:2: field: unknown option 'lenght'"),
      std::string::npos);
  // The ball's keys are read by the engine's loader, as in any world.
  EXPECT_NE(world_error("ball ( radius \"big\" )\n").find("test.world:1: 'radius' needs a number, not \"big\""),
            std::string::npos);
  EXPECT_NE(world_error("ball ( mass 0 )\n").find("test.world:1: a ball's mass must be in [0.001, 100] kg"),
            std::string::npos);
  EXPECT_NE(world_error("robocup_robot ( name \"r\" team \"red\" shape ( kind \"circle\" r 0.2 ) )\n")
                .find("expected one of blue, yellow"),
            std::string::npos);
  EXPECT_NE(world_error("robocup_field ( border 0.2 )\n").find("room for the goals"), std::string::npos);
  const std::string r = "robocup_robot ( name \"r\" shape ( kind \"circle\" r 0.2 ) )\n";
  EXPECT_NE(world_error(r + r).find("twice"), std::string::npos);
}

TEST(RobotFile, ShapesKickerAndPluginsAreRead) {
  WorldSpec spec;
  std::string error;
  ASSERT_TRUE(test::world_from_text(test::robot("p", "yellow", 1, 2, 0.5, test::pioneer_block(R"(
  shape ( kind "triangle" points [0 0 0.1 0 0 0.1] z [0.5 0.7] )
  shape ( kind "ellipse" rx 0.2 ry 0.1 x -0.1 )
  motion_plugin ( plugin "diff_drive" max_speed 1 )
  sensor_plugin ( plugin "camera" fov 1 x 0.2 z 0.5 period 2 )
  sensor_plugin ( plugin "camera" name "back" a 3.14 )
  player ( plugin "striker" aim_y 0.3 )
)")),
                                    spec, error))
      << error;
  ASSERT_EQ(spec.robots.size(), 1u);
  const RobotEntry& r = spec.robots[0];
  EXPECT_EQ(r.team, Team::Yellow);
  EXPECT_EQ(r.start.x, 1);
  EXPECT_EQ(r.start.y, 2);
  EXPECT_NEAR(r.start.a, 0.5, 1e-15);
  ASSERT_EQ(r.spec.shapes.size(), 3u);
  EXPECT_EQ(r.spec.shapes[1].kind, ShapeKind::Polygon);
  EXPECT_EQ(r.spec.shapes[1].z_min, 0.5);
  EXPECT_EQ(r.spec.shapes[2].kind, ShapeKind::Ellipse);
  ASSERT_TRUE(r.spec.has_kicker);
  ASSERT_EQ(r.spec.kicker.states.size(), 2u);
  EXPECT_EQ(r.spec.kicker.states[1].accel, 300);
  EXPECT_EQ(r.spec.kicker.states[1].next_index, 0);
  EXPECT_EQ(r.spec.kicker.states[1].shapes[0].tag, kKickerShapeTag);
  ASSERT_EQ(r.spec.sensors.size(), 2u);
  EXPECT_EQ(r.spec.sensors[0].mount.x, 0.2);
  EXPECT_EQ(r.spec.sensors[0].period, 2);
  EXPECT_FALSE(r.spec.sensors[0].options.has("x")) << "mount keys are not passed to the plugin";
  EXPECT_EQ(r.spec.sensors[1].name, "back");
  EXPECT_TRUE(r.has_player);
  EXPECT_EQ(r.player.plugin, "striker");
}

TEST(RobotFile, BadShapesAndKickersSayWhere) {
  const std::string circle = "shape ( kind \"circle\" r 0.2 )\n";
  EXPECT_NE(
      robot_error("shape ( kind \"hexagon\" r 1 )\n").find("test.world:2: shape: unknown shape 'hexagon'"),
      std::string::npos);
  EXPECT_NE(robot_error("shape ( kind \"polygon\" points [0 0 1 1 1 0 0 1] )\n").find("not strictly convex"),
            std::string::npos);
  EXPECT_NE(robot_error("shape ( kind \"rect\" length 1 )\n").find("a rect needs length= and width="),
            std::string::npos);
  EXPECT_NE(robot_error("shape ( kind \"circle\" r 0.2 z [0.5 0.1] )\n").find("option 'z'"),
            std::string::npos);
  EXPECT_NE(
      robot_error(circle + "kicker ( state ( name \"rest\" ) )\n").find("a rest state and a kick state"),
      std::string::npos);
  EXPECT_NE(robot_error(circle + "kicker ( state ( name \"a\" next \"c\" ) state ( name \"b\" ) )\n")
                .find("no state named 'c'"),
            std::string::npos);
  EXPECT_NE(robot_error("mass -3\n" + circle).find("mass > 0"), std::string::npos);
  EXPECT_NE(robot_error("motion_plugin ( )\n" + circle).find("name the plugin"), std::string::npos);
  EXPECT_NE(robot_error("").find("at least one shape"), std::string::npos);
}

TEST(Options, TypedGettersReportTheFirstProblem) {
  Options o("x.robot:3", "dir");
  o.set("a", "1.5");
  o.set("b", "yes");
  o.set("c", "1,2");
  o.set("f", "m.txt");
  EXPECT_EQ(o.number("a", 0), 1.5);
  EXPECT_TRUE(o.flag("b", false));
  EXPECT_EQ(o.numbers("c", 2), (std::vector<double>{1, 2}));
  EXPECT_EQ(o.path("f", ""), "dir/m.txt");
  EXPECT_EQ(o.number("missing", 7), 7);
  std::string error;
  EXPECT_TRUE(o.finish(error)) << error;
  o.set("d", "3");
  EXPECT_FALSE(o.finish(error));
  EXPECT_EQ(error, "unknown option 'd'");
  Options p("", "");
  p.set("n", "11");
  EXPECT_EQ(p.integer("n", 0, 0, 10), 0);
  EXPECT_FALSE(p.finish(error));
  EXPECT_EQ(error, "option 'n': must be in [0, 10], got 11");
}

}  // namespace
}  // namespace troupe::robocup
