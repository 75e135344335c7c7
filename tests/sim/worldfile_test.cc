// The world-file parser on good and bad input: Stage's syntax, include and
// define, file:line on every error, and no crash on mutated files.
#include "host-sim/world/worldfile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "host-sim/world/colors.h"
#include "tests/sim/temp_dir.h"

namespace troupe::world {
namespace {

const Entity* child(const Entity& e, std::string_view type, int nth = 0) {
  for (const Entity& c : e.children) {
    if (c.type == type && nth-- == 0) return &c;
  }
  return nullptr;
}

double num(const Entity& e, std::string_view key, size_t i = 0) {
  const Property* p = e.find(key);
  EXPECT_NE(p, nullptr) << key;
  return p && i < p->values.size() ? p->values[i].number : -999;
}

TEST(WorldFile, PropertiesTuplesStringsAndComments) {
  Diagnostics d;
  WorldFile wf;
  ASSERT_TRUE(wf.parse(R"(# a comment
resolution 0.02   # trailing comment
name "big world"
size [ 16 -8.5 +1e-1 ]
model ( point[0] [0.5 .25] color "gray30" )
)",
                       "mem.world", d))
      << d.str();
  EXPECT_EQ(d.items().size(), 0u);
  const Entity& w = wf.root();
  EXPECT_DOUBLE_EQ(num(w, "resolution"), 0.02);
  EXPECT_EQ(w.find("name")->values[0].text, "big world");
  EXPECT_TRUE(w.find("name")->values[0].is_string);
  const Property* size = w.find("size");
  ASSERT_EQ(size->values.size(), 3u);
  EXPECT_TRUE(size->tuple);
  EXPECT_DOUBLE_EQ(size->values[1].number, -8.5);
  EXPECT_DOUBLE_EQ(size->values[2].number, 0.1);
  EXPECT_EQ(size->loc.line, 4);
  const Entity* m = child(w, "model");
  ASSERT_NE(m, nullptr);
  EXPECT_DOUBLE_EQ(num(*m, "point[0]", 1), 0.25);
  EXPECT_EQ(m->loc.line, 5);
}

TEST(WorldFile, DefineInheritsPropertiesAndChildrenAndInstanceExtends) {
  Diagnostics d;
  WorldFile wf;
  ASSERT_TRUE(wf.parse(R"(
define sonar sensor ( range [0 5] fov 15 )
define base position ( color "red" size [1 1] sonar( pose [1 0 0 0] ) )
define bot base ( size [2 3] sonar( pose [0 1 0 90] ) )
bot ( name "r0" color "blue" model( size [0.1 0.1] ) )
)",
                       "mem.world", d))
      << d.str();
  const Entity* r0 = child(wf.root(), "position");
  ASSERT_NE(r0, nullptr);
  EXPECT_EQ(r0->written_type, "bot");
  EXPECT_EQ(r0->find("color")->values[0].text, "blue");  // the instance wins
  EXPECT_DOUBLE_EQ(num(*r0, "size", 1), 3);              // the child define wins over its parent
  EXPECT_EQ(r0->find("size")->loc.line, 4);
  // Children: the parent define's, the define's, then the instance's.
  ASSERT_EQ(r0->children.size(), 3u);
  EXPECT_EQ(r0->children[0].type, "sensor");
  EXPECT_DOUBLE_EQ(num(r0->children[0], "pose", 0), 1);
  EXPECT_DOUBLE_EQ(num(r0->children[0], "fov"), 15);
  EXPECT_DOUBLE_EQ(num(r0->children[1], "pose", 3), 90);
  EXPECT_EQ(r0->children[2].type, "model");
  EXPECT_EQ(r0->loc.line, 5);
}

TEST(WorldFile, MacroIsOnlyKnownAfterItsDefine) {
  Diagnostics d;
  WorldFile wf;
  ASSERT_TRUE(wf.parse("thing ( )\ndefine thing position ( )\nthing ( )\n", "mem.world", d)) << d.str();
  ASSERT_EQ(wf.root().children.size(), 2u);
  EXPECT_EQ(wf.root().children[0].type, "thing");
  EXPECT_EQ(wf.root().children[1].type, "position");
}

TEST(WorldFile, RedefinitionWarnsAndKeepsTheFirst) {
  Diagnostics d;
  WorldFile wf;
  ASSERT_TRUE(wf.parse("define a position ( )\ndefine a ranger ( )\na ( )\n", "mem.world", d));
  EXPECT_EQ(wf.root().children[0].type, "position");
  ASSERT_EQ(d.warning_count(), 1u);
  EXPECT_EQ(d.items()[0].loc.line, 2);
}

TEST(WorldFile, IncludeIsRelativeToTheIncludingFile) {
  test::TempDir dir;
  dir.write("sub/robots.inc", "include \"more/sensor.inc\"\ndefine bot position ( laser() )\n");
  dir.write("sub/more/sensor.inc", "define laser ranger ( sensor( samples 3 ) )\n");
  dir.write("w.world", "include \"sub/robots.inc\"\nbot ( name \"a\" )\n");
  Diagnostics d;
  WorldFile wf;
  ASSERT_TRUE(wf.load(dir.path("w.world"), d)) << d.str();
  const Entity* bot = child(wf.root(), "position");
  ASSERT_NE(bot, nullptr);
  ASSERT_EQ(bot->children.size(), 1u);
  EXPECT_EQ(bot->children[0].type, "ranger");
  const Entity& sensor = bot->children[0].children.at(0);
  EXPECT_DOUBLE_EQ(num(sensor, "samples"), 3);
  EXPECT_NE(sensor.find("samples")->loc.file->find("sensor.inc"), std::string::npos);
}

struct BadCase {
  const char* text;
  int line;
  const char* message;
};

TEST(WorldFile, SyntaxErrorsSayFileAndLine) {
  const BadCase cases[] = {
      {"a 1\nmodel ( size [1 2 )\n", 2, "tuple holds"},
      {"model (\n pose [1 2 3 4]\n", 1, "missing ')'"},
      {"\n\nsize [1 2\n", 3, "missing ']'"},
      {"model ( name \"oops\n)", 1, "unterminated string"},
      {"x 1\n\n  ) \n", 3, "expected a property or a model"},
      {"model ( pose )\n", 1, "needs a number"},
      {"model ( @ )\n", 1, "unexpected character '@'"},
      {"define a\n", 1, "define needs"},
      {"size 1.2.3\n", 1, "malformed number"},
      {"model ( include \"x\" )\n", 1, "only allowed outside models"},
      {"define a b ( )\ndefine b a ( )\na ( )\n", 1, "defined in terms of itself"},
      {"drive diff\n", 1, "needs a number"},
  };
  for (const BadCase& c : cases) {
    Diagnostics d;
    WorldFile wf;
    EXPECT_FALSE(wf.parse(c.text, "bad.world", d)) << c.text;
    ASSERT_TRUE(d.has_errors()) << c.text;
    const Diagnostic& e = d.items().back();
    EXPECT_EQ(e.loc.line, c.line) << c.text << " -> " << e.str();
    EXPECT_EQ(*e.loc.file, "bad.world");
    EXPECT_NE(e.message.find(c.message), std::string::npos) << c.text << " -> " << e.str();
  }
}

TEST(WorldFile, MissingIncludeNamesTheIncludeLine) {
  test::TempDir dir;
  dir.write("w.world", "resolution 0.1\n\ninclude \"nowhere.inc\"\n");
  Diagnostics d;
  WorldFile wf;
  EXPECT_FALSE(wf.load(dir.path("w.world"), d));
  ASSERT_EQ(d.error_count(), 1u);
  EXPECT_EQ(d.items()[0].loc.line, 3);
  EXPECT_TRUE(d.contains("nowhere.inc"));
}

TEST(WorldFile, IncludeCycleIsAnError) {
  test::TempDir dir;
  dir.write("a.inc", "include \"b.inc\"\n");
  dir.write("b.inc", "include \"a.inc\"\n");
  dir.write("w.world", "include \"a.inc\"\n");
  Diagnostics d;
  WorldFile wf;
  EXPECT_FALSE(wf.load(dir.path("w.world"), d));
  EXPECT_TRUE(d.contains("include cycle")) << d.str();
}

TEST(WorldFile, MissingWorldFileIsAnError) {
  Diagnostics d;
  WorldFile wf;
  EXPECT_FALSE(wf.load("no/such/file.world", d));
  EXPECT_TRUE(d.contains("cannot open world file")) << d.str();
}

TEST(WorldFile, ExponentialDefinesHitTheModelLimit) {
  std::string text = "define m0 model ( )\n";
  for (int i = 1; i <= 30; ++i) {
    text += "define m" + std::to_string(i) + " model ( m" + std::to_string(i - 1) + "() m" +
            std::to_string(i - 1) + "() )\n";
  }
  text += "m30 ( )\n";
  Diagnostics d;
  WorldFile wf;
  ParseLimits limits;
  limits.max_models = 100000;
  EXPECT_FALSE(wf.parse(text, "big.world", d, limits));
  EXPECT_TRUE(d.contains("more than 100000 models")) << d.str();
}

TEST(WorldFile, ADefinesChildModelsAreOneObjectSharedByItsInstances) {
  // What makes a 100,000-robot world cost its instance lines, not 100,000
  // copies of its robot type's sensors.
  Diagnostics d;
  WorldFile wf;
  ASSERT_TRUE(wf.parse(R"(define ring ranger ( sensor ( range [0 2] ) sensor ( range [0 3] ) )
define bot position ( size [0.2 0.2 0.1] ring ( ) )
bot ( name "a" )
bot ( name "b" ring ( ) )
)",
                       "mem.world", d))
      << d.str();
  const Entity& a = wf.root().children[0];
  const Entity& b = wf.root().children[1];
  ASSERT_EQ(a.children.size(), 1u);
  ASSERT_EQ(b.children.size(), 2u);
  // The define's ring: one object in both robots, sensors and all.
  EXPECT_EQ(&a.children[0], &b.children[0]);
  EXPECT_EQ(a.children[0].type, "ranger");
  EXPECT_EQ(a.children[0].children.size(), 2u);
  EXPECT_DOUBLE_EQ(num(a.children[0].children[1], "range", 1), 3);
  // The ring b's own line adds is its own.
  EXPECT_NE(&b.children[1], &b.children[0]);
  EXPECT_EQ(b.children[1].loc.line, 4);
  // Inherited values are shared too; each robot's own are its own.
  EXPECT_EQ(a.find("size")->values.begin(), b.find("size")->values.begin());
  EXPECT_EQ(a.find("name")->values[0].text, "a");
  EXPECT_EQ(b.find("name")->values[0].text, "b");
}

TEST(WorldFile, ADefineBetweenInstancesChangesWhatLaterOnesExpandTo) {
  // Sharing must not outlive the defines it was expanded with: `lidar` is
  // a plain type for the first bot and a ranger for the second.
  Diagnostics d;
  WorldFile wf;
  ASSERT_TRUE(wf.parse(R"(define bot position ( lidar ( ) )
bot ( )
define lidar ranger ( sensor ( range [0 8] ) )
bot ( )
)",
                       "mem.world", d))
      << d.str();
  ASSERT_EQ(wf.root().children.size(), 2u);
  EXPECT_EQ(wf.root().children[0].children.at(0).type, "lidar");
  EXPECT_EQ(wf.root().children[0].children.at(0).children.size(), 0u);
  EXPECT_EQ(wf.root().children[1].children.at(0).type, "ranger");
  EXPECT_EQ(wf.root().children[1].children.at(0).written_type, "lidar");
  EXPECT_EQ(wf.root().children[1].children.at(0).children.size(), 1u);
}

TEST(WorldFile, SharedModelsStillCountAgainstTheModelLimitWhereTheyCrossIt) {
  // Three bots of a robot and two sensors are nine models: the limit of 8
  // is crossed by the third bot's second sensor (line 1), as when every
  // bot had its own copies.
  Diagnostics d;
  WorldFile wf;
  ParseLimits limits;
  limits.max_models = 8;
  EXPECT_FALSE(wf.parse("define bot position ( sensor ( ) sensor ( ) )\nbot ( )\nbot ( )\nbot ( )\n",
                        "mem.world", d, limits));
  ASSERT_EQ(d.error_count(), 1u) << d.str();
  EXPECT_TRUE(d.contains("more than 8 models")) << d.str();
  EXPECT_EQ(d.items()[0].loc.line, 1);
  // One fewer bot fits.
  Diagnostics d2;
  EXPECT_TRUE(
      wf.parse("define bot position ( sensor ( ) sensor ( ) )\nbot ( )\nbot ( )\n", "mem.world", d2, limits))
      << d2.str();
}

TEST(WorldFile, DeepNestingHitsTheDepthLimit) {
  std::string text;
  for (int i = 0; i < 200; ++i) text += "model ( ";
  for (int i = 0; i < 200; ++i) text += ") ";
  Diagnostics d;
  WorldFile wf;
  EXPECT_FALSE(wf.parse(text, "deep.world", d));
  EXPECT_TRUE(d.contains("nested deeper")) << d.str();
}

TEST(WorldFile, SimpleWorldLoadsUnchanged) {
  std::string path = std::string(TROUPE_SHARED_DATA) + "/stage/simple.world";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no Stage test data at " << path;
  Diagnostics d;
  WorldFile wf;
  ASSERT_TRUE(wf.load(path, d)) << d.str();
  EXPECT_FALSE(d.has_errors());
  int robots = 0;
  for (const Entity& e : wf.root().children) {
    if (e.written_type != "pioneer2dx") continue;
    ++robots;
    EXPECT_EQ(e.type, "position");
    // pioneer2dx: the sonar ring from pioneer2dx_base, the body block, the laser.
    ASSERT_EQ(e.children.size(), 3u);
    EXPECT_EQ(e.children[0].written_type, "p2dx_sonar");
    EXPECT_EQ(e.children[0].children.size(), 16u);
    EXPECT_EQ(e.children[1].type, "block");
    EXPECT_EQ(e.children[2].written_type, "sicklaser");
    EXPECT_EQ(e.children[2].type, "ranger");
  }
  EXPECT_EQ(robots, 2);
}

// Random byte-level mutations of simple.world: the parser must return (true
// or false), report an error for every failure, and never crash.
TEST(WorldFile, FuzzedSimpleWorldNeverCrashes) {
  std::string dir = std::string(TROUPE_SHARED_DATA) + "/stage";
  if (!std::filesystem::exists(dir + "/simple.world")) GTEST_SKIP() << "no Stage test data in " << dir;
  std::ifstream in(dir + "/simple.world");
  std::string original((std::istreambuf_iterator<char>(in)), {});
  std::mt19937_64 rng(20240601);
  const char kAlphabet[] = "()[]\"#.-+0123456789 \n\tabcdefinludepos_\x01\xff";
  int failures = 0;
  for (int round = 0; round < 400; ++round) {
    std::string text = original;
    int edits = 1 + int(rng() % 8);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0:
          text[at] = kAlphabet[rng() % (sizeof kAlphabet - 1)];
          break;
        case 1:
          text.erase(at, 1 + rng() % 16);
          break;
        default:
          text.insert(at, 1, kAlphabet[rng() % (sizeof kAlphabet - 1)]);
      }
    }
    Diagnostics d;
    WorldFile wf;
    bool ok = wf.parse(text, dir + "/fuzzed.world", d);
    if (!ok) {
      ++failures;
      EXPECT_TRUE(d.has_errors());
      EXPECT_GT(d.items().back().loc.line, 0) << d.str();
    }
  }
  EXPECT_GT(failures, 0);  // the mutations did reach the error paths
}

TEST(Colors, X11NamesGreysAndShades) {
  EXPECT_EQ(lookup_color("red"), 0xFF0000u);
  EXPECT_EQ(lookup_color("Dark Green"), 0x006400u);
  EXPECT_EQ(lookup_color("gray30"), 0x4D4D4Du);
  EXPECT_EQ(lookup_color("grey100"), 0xFFFFFFu);
  EXPECT_EQ(lookup_color("orange3"), 0xCD8500u);
  EXPECT_EQ(lookup_color("#12aBcd"), 0x12ABCDu);
  EXPECT_FALSE(lookup_color("blurple"));
  EXPECT_FALSE(lookup_color("gray101"));
}

}  // namespace
}  // namespace troupe::world
