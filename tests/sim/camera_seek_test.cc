// The camera-seek example (examples/controllers/camera_seek) against
// examples/worlds/camera_seek.world: from several start poses the robot
// finds the red box with its camera alone and stops near it within a
// bounded number of simulated steps; with the box painted another colour it
// never arrives (so this test can fail).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "host-sim/troupe_sim/runner.h"
#include "tests/sim/temp_dir.h"
#include "tests/support/child_process.h"
#include "wire/client/proxies.h"

namespace troupe::sim {
namespace {

const std::string kWorld = std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/camera_seek.world";
// The most steps (0.1 s each) a run may take: a full turn of search is
// about 105 steps, the longest drive across the room about 200.
constexpr int kSteps = 450;
// Arrived: the robot's centre this close to the box's, m (the box is 0.6 m
// wide, the robot 0.4 m).
constexpr double kNear = 1.2;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Serves `world_path` paused in a thread, as troupe-sim does.
class Served {
 public:
  explicit Served(const std::string& world_path) {
    SimOptions o;
    o.world = world_path;
    o.port = 0;
    o.paused = true;
    world::Diagnostics d;
    std::string error;
    ok_ = runner_.init(o, d, error);
    EXPECT_TRUE(ok_) << d.str() << error;
    if (ok_) thread_ = std::thread([this] { runner_.run(); });
  }
  ~Served() {
    runner_.request_stop();
    if (thread_.joinable()) thread_.join();
  }
  bool ok() const { return ok_; }
  uint16_t port() const { return runner_.port(); }
  std::string target() const { return "127.0.0.1:" + std::to_string(port()); }

 private:
  Runner runner_;
  std::thread thread_;
  bool ok_ = false;
};

struct SeekRun {
  int status = -1;
  std::string out;
  double distance = 0;  // m, robot centre to box centre at the end
};

/// Puts the seeker at `start`, runs the example to its end, and measures
/// from the simulator's ground truth how near the box it stopped.
SeekRun seek_from(const Served& served, const client::Pose2& start) {
  client::Client c("127.0.0.1", served.port());
  EXPECT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  EXPECT_TRUE(sim.set_pose("seeker", start)) << c.error();
  const auto r =
      troupe::testing::run_to_end({CAMERA_SEEK, served.target(), "--steps", std::to_string(kSteps)}, 120000);
  client::Pose2 robot, box;
  EXPECT_TRUE(sim.get_pose("seeker", robot)) << c.error();
  EXPECT_TRUE(sim.get_pose("target", box)) << c.error();
  return {r.status, r.out + r.err, std::hypot(robot.x - box.x, robot.y - box.y)};
}

TEST(CameraSeek, FindsTheRedBoxFromEveryStartAndStopsNearIt) {
  Served served(kWorld);
  ASSERT_TRUE(served.ok());
  // The world's start (the box behind the robot, the blue and green boxes
  // passing through view first), two more that must search, and one with
  // the box in view at once.
  const client::Pose2 starts[] = {
      {-3, 0, float(M_PI)}, {-3, -2.5, float(M_PI / 2)}, {0, 2.8, 0}, {1, -2, float(-M_PI / 2)}};
  for (const client::Pose2& start : starts) {
    SCOPED_TRACE("start " + std::to_string(start.x) + ", " + std::to_string(start.y));
    const SeekRun run = seek_from(served, start);
    EXPECT_EQ(run.status, 0) << run.out;
    EXPECT_NE(run.out.find("target in view"), std::string::npos) << run.out;
    unsigned images = 0, steps = 0;
    const size_t at = run.out.find("arrived after ");
    ASSERT_NE(at, std::string::npos) << run.out;
    ASSERT_EQ(std::sscanf(run.out.c_str() + at, "arrived after %u images (%u steps)", &images, &steps), 2)
        << run.out;
    EXPECT_LE(steps, unsigned(kSteps));
    std::printf("start (%.1f, %.1f, %.2f rad): arrived in %u steps, %.2f m from the box\n", start.x, start.y,
                start.a, steps, run.distance);
    EXPECT_LT(run.distance, kNear) << run.out;
    // It stopped in front of the box, not inside it.
    EXPECT_GT(run.distance, 0.5) << run.out;
  }
}

TEST(CameraSeek, NeverArrivesWhenTheBoxIsAnotherColour) {
  std::string text = read_text(kWorld);
  const std::string red = "size [ 0.6 0.6 0.5 ] color \"red\"";
  const size_t at = text.find(red);
  ASSERT_NE(at, std::string::npos) << "the example world's box changed; update this test";
  text.replace(at, red.size(), "size [ 0.6 0.6 0.5 ] color \"cyan\"");
  test::TempDir dir;
  Served served(dir.write("cyan.world", text));
  ASSERT_TRUE(served.ok());
  const SeekRun run = seek_from(served, {-3, 0, float(M_PI)});
  EXPECT_EQ(run.status, 3) << run.out;
  EXPECT_NE(run.out.find("did not arrive after " + std::to_string(kSteps) + " images"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("never seen"), std::string::npos) << run.out;
  EXPECT_GT(run.distance, 5.0) << run.out;  // it turned on the spot, 6.2 m away
}

}  // namespace
}  // namespace troupe::sim
