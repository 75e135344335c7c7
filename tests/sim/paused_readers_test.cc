// A paused troupe-sim taking many readers, one client each, as swarm-clients
// connects a thousand: each new reader's sensor is computed for it and sent
// to it alone. Before, every new reader recomputed the whole world's sensors
// and sent every reader its sample again: the n-th client cost n samples
// (a thousand clients took a minute to connect). Counted, not timed: every
// client holds exactly one sample, and it is the one a whole refresh gives.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tests/sim/served_world.h"
#include "wire/client/proxies.h"

namespace troupe::sim {
namespace {

constexpr int kCols = 20, kRows = 10;  // robots, 1 m apart

// A 24 x 14 m room holding kCols x kRows robots, each with a ring of 8
// sonars of 3 m that see the walls and their neighbours.
const std::string& grid_world() {
  static const std::string text = [] {
    std::ostringstream w;
    w << "resolution 0.02\ninterval_sim 100\n"
         "define wall model ( )\n"
         "wall ( name \"north\" size [ 24 0.2 1 ] pose [ 0 7 0 0 ] )\n"
         "wall ( name \"south\" size [ 24 0.2 1 ] pose [ 0 -7 0 0 ] )\n"
         "wall ( name \"east\" size [ 0.2 14 1 ] pose [ 12 0 0 0 ] )\n"
         "wall ( name \"west\" size [ 0.2 14 1 ] pose [ -12 0 0 0 ] )\n"
         "define ring ranger ( sensor ( range [ 0 3 ] fov 360 samples 8 ) )\n"
         "define bot position ( size [ 0.3 0.3 0.2 ] ring ( ) )\n";
    for (int i = 0; i < kCols * kRows; ++i) {
      w << "bot ( name \"b" << i << "\" pose [ " << -9.5 + i % kCols << " " << -4.5 + i / kCols << " 0 "
        << (i * 37) % 360 << " ] )\n";
    }
    return w.str();
  }();
  return text;
}

// A scan as the wire carries it (ranges in steps of about 1 mm: u16 with a
// per-scan scale) against the engine's floats, m.
bool same_scan(const std::vector<float>& wire, const std::vector<float>& engine) {
  if (wire.size() != engine.size()) return false;
  for (size_t b = 0; b < wire.size(); ++b) {
    if (std::abs(wire[b] - engine[b]) > 1e-3f) return false;
  }
  return true;
}

class PausedReaders : public test::ServedWorld {
 protected:
  PausedReaders() : ServedWorld(grid_world().c_str()) {}

  struct Reader {
    std::unique_ptr<client::Client> client;
    std::unique_ptr<client::RangerProxy> ranger;
  };
  // One client per robot but the last, connected one after another, each waiting for
  // its ranger's first sample as swarm-clients does (the bound ends a hang).
  // Every robot's scan in a world loaded from the same text with every
  // ranger computed at once (b0 moved to `b0_at` first when given).
  std::vector<std::vector<float>> whole_world_scans(const Pose* b0_at) {
    world::Diagnostics diags;
    std::unique_ptr<World> w = World::load(dir_.write("same.world", grid_world()), 0, diags);
    std::vector<std::vector<float>> scans;
    if (!w) {
      ADD_FAILURE() << diags.str();
      return scans;
    }
    for (RobotId i = 0; i < w->robot_count(); ++i)
      w->set_wanted({SensorKind::Ranger, w->robot(i).rangers.first}, true);
    if (b0_at) w->set_pose(0, *b0_at);
    w->refresh_sensors();
    for (RobotId i = 0; i < w->robot_count(); ++i) {
      const RangerView v = w->ranger(w->robot(i).rangers.first);
      scans.emplace_back(v.ranges.begin(), v.ranges.end());
    }
    return scans;
  }
  // 0.5 m ahead of b1's first beam (world frame: m, m, rad).
  Pose ahead_of_b1() {
    world::Diagnostics diags;
    std::unique_ptr<World> w = World::load(dir_.write("same.world", grid_world()), 0, diags);
    if (!w) return {};
    const Pose beam = w->ranger_beams(w->robot(1).rangers.first).front();
    return {beam.x + 0.5 * std::cos(beam.a), beam.y + 0.5 * std::sin(beam.a), 0};
  }

  std::vector<Reader> connect_all() {
    std::vector<Reader> readers(kCols * kRows - 1);
    for (size_t i = 0; i < readers.size(); ++i) {
      Reader& r = readers[i];
      r.client = std::make_unique<client::Client>("127.0.0.1", runner_.port());
      EXPECT_TRUE(r.client->connect()) << r.client->error();
      r.ranger = std::make_unique<client::RangerProxy>(*r.client, 0, uint16_t(i));
      EXPECT_TRUE(r.ranger->is_open()) << i << ": " << r.client->error();
      for (int k = 0; k < 2000 && r.ranger->samples() == 0; ++k) r.client->spin_once(10);
      EXPECT_EQ(r.ranger->samples(), 1u) << "robot " << i;
      EXPECT_EQ(r.ranger->count(), 8u) << "robot " << i;
    }
    // Whatever the server sent any of them before answering this round
    // trip has arrived.
    for (Reader& r : readers) EXPECT_TRUE(r.client->sync()) << r.client->error();
    return readers;
  }
};

TEST_F(PausedReaders, EachNewReaderGetsItsOwnScanOnceAndOlderReadersNothingAgain) {
  std::vector<Reader> readers = connect_all();
  ASSERT_FALSE(HasFailure());
  const std::vector<std::vector<float>> whole = whole_world_scans(nullptr);
  for (size_t i = 0; i < readers.size(); ++i) {
    // One sample each: the first client was not sent a scan again for
    // each of the 198 that came after it.
    EXPECT_EQ(readers[i].ranger->samples(), 1u) << "robot " << i;
    EXPECT_EQ(readers[i].ranger->time_us(), 0u) << "paused: no step ran";
    // Computed one new reader at a time, the scans are a whole refresh's.
    EXPECT_TRUE(same_scan(readers[i].ranger->ranges(), whole[i])) << "robot " << i;
  }
}

TEST_F(PausedReaders, ARobotTeleportedWhilePausedGivesEveryReaderTheScanOfWhereRobotsNowStand) {
  std::vector<Reader> readers = connect_all();
  ASSERT_FALSE(HasFailure());
  // b0 jumps 0.5 m ahead of b1's first sonar, which then sees it.
  const Pose to = ahead_of_b1();
  const std::vector<std::vector<float>> whole = whole_world_scans(&to);
  ASSERT_FALSE(same_scan(readers[1].ranger->ranges(), whole[1])) << "the teleport should change b1's scan";
  client::Client admin("127.0.0.1", runner_.port());
  ASSERT_TRUE(admin.connect()) << admin.error();
  client::SimulationProxy sim(admin);
  ASSERT_TRUE(sim.set_pose("b0", {float(to.x), float(to.y), float(to.a)}));
  // A reader for the last robot's scan, which nobody read: the paused
  // world computes it, and since a robot moved, every reader gets the scan
  // of where robots now stand.
  const uint16_t last = kCols * kRows - 1;
  client::Client late("127.0.0.1", runner_.port());
  ASSERT_TRUE(late.connect()) << late.error();
  client::RangerProxy ranger(late, 0, last);
  for (int k = 0; k < 2000 && ranger.samples() == 0; ++k) late.spin_once(10);
  ASSERT_EQ(ranger.samples(), 1u);
  EXPECT_TRUE(same_scan(ranger.ranges(), whole[last]));
  for (int k = 0; k < 2000 && readers[1].ranger->samples() < 2; ++k) readers[1].client->spin_once(10);
  ASSERT_EQ(readers[1].ranger->samples(), 2u) << "b1's reader was not sent its new scan";
  EXPECT_TRUE(same_scan(readers[1].ranger->ranges(), whole[1]));
}

}  // namespace
}  // namespace troupe::sim
