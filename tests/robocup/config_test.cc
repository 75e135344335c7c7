// The world and robot file format: statements, blocks, quotes, includes,
// and errors that say file and line.
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
  EXPECT_TRUE(parse_config_text(text, "t.world", st, error)) << error;
  return st;
}

std::string parse_error(const std::string& text) {
  std::vector<Statement> st;
  std::string error;
  EXPECT_FALSE(parse_config_text(text, "t.world", st, error));
  return error;
}

TEST(ConfigText, StatementsBlocksAndQuotes) {
  auto st = parse_ok(
      "# a comment\n"
      "robot r1 file=\"my robots/a.robot\" team=blue  # trailing\n"
      "kicker reach=0.03 {\n"
      "  state rest { shape rect x=0.2 }\n"
      "  state kick accel=300; state other\n"
      "}\n");
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].keyword, "robot");
  EXPECT_EQ(st[0].args, std::vector<std::string>{"r1"});
  ASSERT_EQ(st[0].options.size(), 2u);
  EXPECT_EQ(st[0].options[0].second, "my robots/a.robot");
  EXPECT_EQ(st[0].line, 2);
  ASSERT_EQ(st[1].children.size(), 3u);
  EXPECT_EQ(st[1].children[0].children[0].keyword, "shape");
  EXPECT_EQ(st[1].children[2].args[0], "other");
  EXPECT_EQ(st[1].children[2].line, 5);
}

TEST(ConfigText, ErrorsNameFileAndLine) {
  EXPECT_EQ(parse_error("a\nb {\n c\n"), "t.world:4: missing '}'");
  EXPECT_EQ(parse_error("a\n}\n"), "t.world:2: '}' without '{'");
  EXPECT_EQ(parse_error("a x=\"open\n"), "t.world:1: unterminated quote");
  EXPECT_EQ(parse_error("a =3\n"), "t.world:1: '=3' has no key");
}

TEST(ConfigText, IncludesAreRelativeToTheIncludingFile) {
  const std::string dir = TROUPE_BINARY_DIR "/tests/robocup";
  std::ofstream(dir + "/inc_child.world") << "field length=10\n";
  std::ofstream(dir + "/inc_loop.world") << "include \"inc_loop.world\"\n";
  std::vector<Statement> st;
  std::string error;
  ASSERT_TRUE(parse_config_text("include \"inc_child.world\"\nball\n", dir + "/main.world", st, error))
      << error;
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st[0].keyword, "field");
  EXPECT_EQ(st[0].file, dir + "/inc_child.world");
  EXPECT_FALSE(parse_config_text("include \"inc_loop.world\"\n", dir + "/main.world", st, error));
  EXPECT_NE(error.find("deeper than 8"), std::string::npos) << error;
  EXPECT_FALSE(parse_config_text("include \"absent.world\"\n", dir + "/main.world", st, error));
  EXPECT_NE(error.find("main.world:1: include:"), std::string::npos) << error;
}

std::string world_error(const std::string& text) {
  WorldSpec spec;
  std::string error;
  EXPECT_FALSE(test::world_from_text(text, spec, error));
  return error;
}

TEST(WorldFile, BadValuesAndUnknownKeysSayWhere) {
  EXPECT_NE(world_error("world cycle=0\n").find("test.world:1: world: option 'cycle': must be in"),
            std::string::npos);
  EXPECT_NE(world_error("\nfield lenght=9\n").find("test.world:2: field: unknown option 'lenght'"),
            std::string::npos);
  EXPECT_NE(world_error("ball radius=big\n").find("option 'radius': expected a number, got 'big'"),
            std::string::npos);
  EXPECT_NE(world_error("robot r team=red {\n shape circle r=0.2\n}\n").find("expected one of blue, yellow"),
            std::string::npos);
  EXPECT_NE(world_error("goal x=1\n").find("unknown statement"), std::string::npos);
  EXPECT_NE(world_error("field border=0.2\n").find("room for the goals"), std::string::npos);
  EXPECT_NE(
      world_error("robot r {\n shape circle r=0.2\n}\nrobot r {\n shape circle r=0.2\n}\n").find("twice"),
      std::string::npos);
}

TEST(RobotFile, ShapesKickerAndPluginsAreRead) {
  WorldSpec spec;
  std::string error;
  ASSERT_TRUE(test::world_from_text("robot p team=yellow x=1 y=2 a=0.5 {" + test::pioneer_block(R"(
  shape triangle points=0,0,0.1,0,0,0.1 z=0.5,0.7
  shape ellipse rx=0.2 ry=0.1 x=-0.1
  motion diff_drive max_speed=1
  sensor camera fov=1 x=0.2 z=0.5 period=2
  sensor camera name=back a=3.14
  player striker aim_y=0.3
})"),
                                    spec, error))
      << error;
  ASSERT_EQ(spec.robots.size(), 1u);
  const RobotEntry& r = spec.robots[0];
  EXPECT_EQ(r.team, Team::Yellow);
  EXPECT_EQ(r.start, (Pose2{1, 2, 0.5}));
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
  auto robot_error = [](const std::string& body) { return world_error("robot r {\n" + body + "}\n"); };
  EXPECT_NE(robot_error("shape hexagon r=1\n").find("test.world:2: shape: unknown shape 'hexagon'"),
            std::string::npos);
  EXPECT_NE(robot_error("shape polygon points=0,0,1,1,1,0,0,1\n").find("not strictly convex"),
            std::string::npos);
  EXPECT_NE(robot_error("shape rect length=1\n").find("a rect needs length= and width="), std::string::npos);
  EXPECT_NE(robot_error("shape circle r=0.2 z=0.5,0.1\n").find("option 'z'"), std::string::npos);
  EXPECT_NE(
      robot_error("shape circle r=0.2\nkicker {\n state rest\n}\n").find("a rest state and a kick state"),
      std::string::npos);
  EXPECT_NE(
      robot_error("shape circle r=0.2\nkicker {\n state a next=c\n state b\n}\n").find("no state named 'c'"),
      std::string::npos);
  EXPECT_NE(robot_error("mass -3\nshape circle r=0.2\n").find("mass > 0"), std::string::npos);
  EXPECT_NE(robot_error("motion\nshape circle r=0.2\n").find("name the plugin"), std::string::npos);
  EXPECT_NE(world_error("robot r {\n}\n").find("at least one shape"), std::string::npos);
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
