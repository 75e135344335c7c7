// troupe-sim runs and serves a RoboCup match written as a Stage world
// (examples/robocup/match.world): the real program over TCP, its devices,
// the one simulation:0 handler (models with the ball and the field, poses,
// the game), a goal scored and counted; and batch runs end with the score.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "host-sim/robocup/game/world_desc.h"
#include "tests/support/child_process.h"
#include "tests/support/png_decode.h"
#include "wire/client/client.h"
#include "wire/client/proxies.h"

namespace troupe::robocup {
namespace {

using client::Client;

const std::string kSim = TROUPE_BINARY_DIR "/bin/troupe-sim";
const std::string kMatch = TROUPE_SOURCE_DIR "/examples/robocup/match.world";

class MatchInTroupeSim : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::make_temp_dir("troupe-match");
    ASSERT_FALSE(dir_.empty());
    std::string error;
    ASSERT_TRUE(sim_.start({kSim, kMatch, "--port", "0", "--no-view", "--paused"}, dir_, "sim", error))
        << error;
    ASSERT_TRUE(sim_.wait_for("listening on", false, 60000)) << sim_.err();
    const std::string out = sim_.out();
    port_ = uint16_t(std::stoi(out.substr(out.rfind(':') + 1)));
  }
  void TearDown() override {
    sim_.stop();
    testing::remove_tree(dir_);
  }

  std::string dir_;
  testing::ChildProcess sim_;
  uint16_t port_ = 0;
};

TEST_F(MatchInTroupeSim, ServesTheMatchThroughTheOneSimulationHandler) {
  Client c("127.0.0.1", port_);
  ASSERT_TRUE(c.connect()) << c.error();
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices));
  std::vector<std::string> names;
  for (const auto& d : devices) names.push_back(d.text());
  EXPECT_NE(std::find(names.begin(), names.end(), "yellow3/actuator:0"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "blue1/ranger:0"), names.end());

  // The viewer's model list: 8 robots, then the ball as a disc, and the field.
  const wire::Address sim_addr(0, uint16_t(wire::Interface::Simulation), 0);
  const client::Reply models = c.request(sim_addr, uint8_t(wire::SimulationReqSub::Models));
  ASSERT_TRUE(models.ok()) << models.text;
  const wire::SimModelList* list = models.message()->body_as_SimModelList();
  ASSERT_TRUE(list && list->models() && list->field());
  ASSERT_EQ(list->models()->size(), 9u);
  EXPECT_EQ(list->models()->Get(0)->name()->str(), "blue0");
  EXPECT_EQ(list->models()->Get(8)->name()->str(), "ball");
  EXPECT_EQ(list->models()->Get(8)->shape(), wire::SimShape::Disc);
  EXPECT_EQ(list->field()->length(), 9.0f);

  client::SimulationProxy sim(c);

  // A goal for blue: the ball behind the yellow goal line.
  ASSERT_TRUE(sim.set_pose("ball", {4.8f, 0, 0}));
  ASSERT_TRUE(sim.step(2));
  client::Pose2 ball;
  ASSERT_TRUE(sim.get_pose("ball", ball));
  EXPECT_GT(ball.x, 4.5f);
  client::GameState game;
  ASSERT_TRUE(sim.get_game(game));
  EXPECT_EQ(game.score_blue, 1u);
  EXPECT_EQ(game.score_yellow, 0u);
  // The referee's event on standard output, as it happened.
  EXPECT_TRUE(sim_.wait_for("goal blue (blue 1 : yellow 0)\n", false, 10000)) << sim_.out();
  // Bad requests are refused and the match goes on.
  EXPECT_FALSE(sim.set_pose("nobody", {0, 0, 0}));
  EXPECT_NE(c.error().find("no model named 'nobody'"), std::string::npos) << c.error();
  EXPECT_TRUE(sim.step(1));
}

// The field players' omni cameras (examples/robocup/robots/pioneer.inc) are
// the engine's Stage camera models, served beside the RoboCup sensors: blue1
// at (-2.5, 1.2) facing the yellow goal sees the green carpet, the white
// lines and the orange ball at the centre spot, 2.8 m away. A PNG reader
// gets the raw reader's pixels, decoded by libpng.
TEST_F(MatchInTroupeSim, AFieldPlayersOmniCameraServesTheFieldInColour) {
  Client raw_client("127.0.0.1", port_), png_client("127.0.0.1", port_);
  ASSERT_TRUE(raw_client.connect()) << raw_client.error();
  ASSERT_TRUE(png_client.connect()) << png_client.error();
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(raw_client.device_list(devices));
  std::vector<std::string> names;
  for (const auto& d : devices) names.push_back(d.text());
  // The RoboCup sensors keep their indices; the camera has its own interface.
  for (const char* name : {"blue1/camera:0", "blue1/ranger:0", "blue1/ranger:1", "blue1/fiducial:0"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;

  client::CameraProxy raw(raw_client, 0, 1);
  client::CameraProxy png(png_client, 0, 1, wire::ImageCompression::Png);
  client::SimulationProxy sim(raw_client);
  ASSERT_TRUE(raw.is_open() && png.is_open() && sim.is_open());
  ASSERT_TRUE(sim.step(2));
  ASSERT_TRUE(raw_client.sync() && png_client.sync());
  const client::Image& image = raw.image();
  ASSERT_EQ(image.width, 128u);
  ASSERT_EQ(image.height, 128u);
  ASSERT_EQ(image.format, wire::PixelFormat::Rgb8);
  const FieldColors colors;
  size_t carpet = 0, lines = 0, ball = 0;
  for (size_t i = 0; i + 2 < image.data.size(); i += 3) {
    const uint32_t c = uint32_t(image.data[i]) << 16 | uint32_t(image.data[i + 1]) << 8 | image.data[i + 2];
    carpet += c == colors.carpet;
    lines += c == colors.lines;
    ball += c == colors.ball;
  }
  EXPECT_GT(carpet, 128u * 128u / 4);
  EXPECT_GT(lines, 30u);
  EXPECT_GT(ball, 2u);
  ASSERT_EQ(png.image().compression, wire::ImageCompression::Png);
  troupe::test::DecodedPng d;
  std::string why;
  ASSERT_TRUE(troupe::test::decode_png(png.image().data, d, why)) << why;
  EXPECT_EQ(d.width, 128u);
  EXPECT_EQ(d.pixels, image.data);
}

TEST(MatchBatch, RunsToItsQuitTimeAndSaysTheScore) {
  const auto r = testing::run_to_end({kSim, kMatch, "--no-serve", "--fast", "--quit-time", "3"}, 120000);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("final: blue 0 yellow 0 after 3.00 s simulated in "), std::string::npos) << r.out;
  const auto refused = testing::run_to_end({kSim, kMatch, "--no-serve", "--snapshot", "x.png"}, 60000);
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("--snapshot is for Stage worlds"), std::string::npos) << refused.err;
}

// --profile prints the match's phases as it prints a Stage world's: the
// cycle's table (300 cycles of 10 ms in 3 s), then the physics step's.
TEST(MatchBatch, ProfilePrintsTheCyclesPhases) {
  const auto r =
      testing::run_to_end({kSim, kMatch, "--no-serve", "--fast", "--quit-time", "3", "--profile"}, 120000);
  EXPECT_EQ(r.status, 0) << r.err;
  for (const char* row : {"\nphase              total ms      us/step   share\nplayers ", "\nsensors ",
                          "(300 steps)\nphysics, by phase:\n", "\nimpacts "}) {
    EXPECT_NE(r.err.find(row), std::string::npos) << row << " not in:\n" << r.err;
  }
}

}  // namespace
}  // namespace troupe::robocup
