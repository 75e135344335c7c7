// The desktop drivers inside a real node, built from a JSON node config:
// logreplay plays a synthetic CARMEN log, mapfile serves the map from a PNG,
// mcl fetches it through driver-to-driver requests and localizes, fusion
// fuses odometry with mcl's fixes. A probe driver in the same node watches
// what they publish and sends requests like a client would.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>

#include "drivers/common_desktop/carmen_log.h"
#include "runtime/node_config.h"
#include "tests/desktop/synthetic_world.h"
#include "wire/address.h"

namespace troupe {
namespace {

using desktop::Pose2;

// Watches devices of the node and talks to them.
class Probe : public Driver {
 public:
  bool setup(Node& node, const DriverSetup&, std::string&) override {
    for (auto [iface, index] : {std::pair{wire::Interface::Position2d, 0},
                                {wire::Interface::Position2d, 1},
                                {wire::Interface::Position2d, 2},
                                {wire::Interface::Position2d, 3},
                                {wire::Interface::Localize, 0},
                                {wire::Interface::Ranger, 0}}) {
      DeviceId d = node.find_device(wire::Address(0, uint16_t(iface), uint16_t(index)));
      if (d != kNoDevice) node.subscribe(d, this);
    }
    return true;
  }
  void on_data(DeviceId source, const wire::Message& m) override {
    const wire::Address& a = node_->address(source);
    uint64_t t = wire::time_us(*m.header());
    if (const wire::Position2dState* s = m.body_as_Position2dState()) {
      Pose2 p{s->pose()->x(), s->pose()->y(), s->pose()->a()};
      if (a.index() == 1) truth[t] = p;
      if (a.index() == 2) estimates[t] = p;
      if (a.index() == 3) {
        fused[t] = p;
        ASSERT_NE(s->covariance(), nullptr);
        fused_var_ok = fused_var_ok && s->covariance()->xx() > 0 && s->covariance()->aa() > 0;
      }
    } else if (const wire::LocalizeState* l = m.body_as_LocalizeState()) {
      ++localize_count;
      lost_count += l->lost() ? 1 : 0;
      float total = 0;
      for (const wire::Hypothesis* h : *l->hypotheses()) total += h->weight();
      weights_ok = weights_ok && total > 0.99f && total < 1.01f;
      if (l->hypotheses()->size() > 0) top_weight = l->hypotheses()->Get(0)->weight();
    } else if (m.body_type() == wire::Body::RangerScan) {
      ++scans;
    }
  }
  void on_reply(DeviceId, const wire::Message& m) override {
    replies.push_back(m.header()->kind());
    const wire::Error* e = m.body_as_Error();
    reply_texts.push_back(e && e->text() ? e->text()->str() : "");
    if (const wire::MapInfo* info = m.body_as_MapInfo()) map_size = {info->width(), info->height()};
    if (const wire::MapTile* tile = m.body_as_MapTile()) tile_bytes = tile->cells()->size();
  }
  using Driver::node_;

  std::map<uint64_t, Pose2> truth, estimates, fused;
  size_t localize_count = 0, lost_count = 0, scans = 0;
  bool weights_ok = true, fused_var_ok = true;
  float top_weight = 0;
  std::vector<wire::Kind> replies;
  std::vector<std::string> reply_texts;
  std::pair<uint32_t, uint32_t> map_size{0, 0};
  size_t tile_bytes = 0;
};

struct World {
  std::string dir, log_path, map_path;
  size_t poses = 0;
};

World make_world() {
  World w;
  w.dir = desktop::testing::scratch_dir();
  desktop::OccupancyGrid map = desktop::testing::make_test_map();
  std::vector<Pose2> route = desktop::testing::test_route(0.2);
  w.poses = route.size();
  w.log_path = w.dir + "/drive.log";
  w.map_path = w.dir + "/map.png";
  std::ofstream(w.log_path) << desktop::testing::write_carmen_log(map, route, {}, 0.2)
                            << "FLASER 3 1 2\n";  // a malformed line at the end: reported, skipped
  std::string error;
  EXPECT_TRUE(desktop::save_png_map(w.map_path, map, error)) << error;
  return w;
}

bool load(const std::string& dir, const std::string& json, LoadedConfig& cfg, std::string& error) {
  std::string path = dir + "/node.json";
  std::ofstream(path) << json;
  return load_config(path, cfg, error);
}

std::string desktop_config(const World& w, const std::string& mcl_extra) {
  return R"({ "name": "desktop-test", "port": 0, "drivers": [
    { "driver_type": "logreplay",
      "driver": { "file": ")" +
         w.log_path + R"(", "speed": 25.0, "start_delay": 0.1 },
      "provides": ["position2d:0", "ranger:0", "position2d:1"] },
    { "driver_type": "mcl",
      "driver": { "max_particles": 4000, "min_particles": 300, "seed": 3, "laser_max_range": 8.0,
                  "rot_rot": 0.05, "rot_trans": 0.05, "trans_trans": 0.05, "trans_rot": 0.05 )" +
         mcl_extra + R"( },
      "uses": ["position2d:0", "ranger:0", "map:0"],
      "provides": ["localize:0", "position2d:2"] },
    { "driver_type": "mapfile",
      "driver": { "file": ")" +
         w.map_path + R"(", "resolution": 0.05, "origin_x": -1, "origin_y": -1 },
      "provides": ["map:0"] },
    { "driver_type": "fusion",
      "uses": ["position2d:0", "localize:0"],
      "provides": ["position2d:3"] }
  ] })";
}

// Runs the node until the probe saw `scans` scans (or a generous wall-clock
// limit passes, which only guards against a hang).
void run(Node& node, Probe& probe, size_t scans) {
  auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (probe.scans < scans && std::chrono::steady_clock::now() < give_up) node.poll(20'000);
  // The last scan has no odometry after it: mcl waits odom_wait (0.5 s) for
  // it, then uses the newest.
  auto settle = std::chrono::steady_clock::now() + std::chrono::milliseconds(800);
  while (std::chrono::steady_clock::now() < settle) node.poll(20'000);
}

TEST(DesktopDrivers, GlobalLocalizationOnAReplayedLog) {
  World w = make_world();
  LoadedConfig cfg;
  std::string error;
  ASSERT_TRUE(load(w.dir, desktop_config(w, ""), cfg, error)) << error;
  Node node(node_options(*cfg.root));
  ASSERT_TRUE(build_node(node, cfg, error)) << error;
  auto owned = std::make_unique<Probe>();
  Probe& probe = *owned;
  ASSERT_TRUE(node.add_driver(std::move(owned), {}, error)) << error;
  ASSERT_TRUE(node.start(error)) << error;
  run(node, probe, w.poses);
  ASSERT_EQ(probe.scans, w.poses);
  // Each scan waits for the odometry after it (the last one for odom_wait);
  // mcl answers every scan, stamped with the scan's time, which is the
  // time of the scan's truth too.
  EXPECT_EQ(probe.localize_count, w.poses);
  EXPECT_TRUE(probe.weights_ok);
  // Global localization may first settle on a place that looks alike (the
  // seed decides); the filter must notice, find itself within the first
  // quarter of the log, and then keep tracking.
  size_t compared = 0, found_at = 0, tracked = 0, after_found = 0;
  double late_sum = 0;
  size_t late_n = 0, i = 0;
  for (const auto& [t, est] : probe.estimates) {
    auto it = probe.truth.find(t);
    if (it == probe.truth.end()) continue;
    ++compared;
    double e = desktop::distance(est, it->second);
    if (found_at == 0 && e < 0.25) found_at = compared;
    if (found_at != 0) {
      ++after_found;
      tracked += e < 0.25;
    }
    if (++i > probe.estimates.size() / 2) {
      late_sum += e;
      ++late_n;
    }
  }
  EXPECT_EQ(compared, w.poses);
  ASSERT_GT(late_n, 0u);
  EXPECT_LT(late_sum / double(late_n), 0.08) << "mean error over the second half";
  ASSERT_NE(found_at, 0u) << "never within 0.25 m of the truth";
  EXPECT_LT(found_at, compared / 4) << "scans until first within 0.25 m";
  EXPECT_GT(double(tracked) / double(after_found), 0.95) << "share within 0.25 m once found";
  EXPECT_GT(probe.top_weight, 0.9f);
  // Fusion followed: published with a covariance, near the truth at the end.
  ASSERT_FALSE(probe.fused.empty());
  EXPECT_TRUE(probe.fused_var_ok);
  EXPECT_LT(desktop::distance(probe.fused.rbegin()->second, probe.truth.rbegin()->second), 0.3);
  node.shutdown();
}

TEST(DesktopDrivers, RequestsToMapAndLocalize) {
  World w = make_world();
  LoadedConfig cfg;
  std::string error;
  ASSERT_TRUE(load(w.dir,
                   desktop_config(w, R"(, "initial_x": 1.5, "initial_y": 0.5, "initial_var_xy": 0.01)"), cfg,
                   error))
      << error;
  Node node(node_options(*cfg.root));
  ASSERT_TRUE(build_node(node, cfg, error)) << error;
  auto owned = std::make_unique<Probe>();
  Probe& probe = *owned;
  ASSERT_TRUE(node.add_driver(std::move(owned), {}, error)) << error;
  DeviceId map = node.find_device(wire::Address(0, uint16_t(wire::Interface::Map), 0));
  DeviceId loc = node.find_device(wire::Address(0, uint16_t(wire::Interface::Localize), 0));

  node.begin();
  ASSERT_TRUE(node.request(map, uint8_t(wire::MapReqSub::Info), 1, wire::Body::NONE, 0, &probe));
  EXPECT_EQ(probe.map_size, (std::pair<uint32_t, uint32_t>{240, 180}));
  auto tile = [&](uint32_t col, uint32_t row, uint32_t width, uint32_t height) {
    auto& b = node.begin();
    auto body = wire::CreateMapTileRequest(b, col, row, width, height);
    return node.request(map, uint8_t(wire::MapReqSub::Tile), 2, wire::Body::MapTileRequest, body.Union(),
                        &probe);
  };
  ASSERT_TRUE(tile(10, 20, 30, 7));
  EXPECT_EQ(probe.replies.back(), wire::Kind::Ack);
  EXPECT_EQ(probe.tile_bytes, (30u * 7 + 3) / 4);
  ASSERT_TRUE(tile(230, 0, 20, 5));  // leaves the map
  EXPECT_EQ(probe.replies.back(), wire::Kind::Nack);
  EXPECT_NE(probe.reply_texts.back().find("not inside the 240x180 map"), std::string::npos)
      << probe.reply_texts.back();
  ASSERT_TRUE(tile(0, 0, 0, 5));
  EXPECT_EQ(probe.replies.back(), wire::Kind::Nack);

  // SetPose with a bad covariance is refused; a good one and Global are taken.
  auto set_pose = [&](float var) {
    auto& b = node.begin();
    wire::Pose2d mean(1.5f, 0.5f, 0.0f);
    wire::Cov2d cov(var, 0, 0, var, 0, 0.01f);
    auto body = wire::CreateLocalizeSetPose(b, &mean, &cov);
    return node.request(loc, uint8_t(wire::LocalizeReqSub::SetPose), 3, wire::Body::LocalizeSetPose,
                        body.Union(), &probe);
  };
  ASSERT_TRUE(set_pose(-1.0f));
  EXPECT_EQ(probe.replies.back(), wire::Kind::Nack);
  ASSERT_TRUE(set_pose(0.01f));
  EXPECT_EQ(probe.replies.back(), wire::Kind::Ack);
  node.begin();
  ASSERT_TRUE(node.request(loc, uint8_t(wire::LocalizeReqSub::Global), 4, wire::Body::NONE, 0, &probe));
  EXPECT_EQ(probe.replies.back(), wire::Kind::Ack);
  // Garbage on the devices mcl reads (a broken driver or a hostile relay),
  // once mcl has its map: ignored, and nothing else is disturbed.
  auto ready =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(50);  // before the log's start_delay
  while (std::chrono::steady_clock::now() < ready) node.poll(5'000);
  DeviceId odom = node.find_device(wire::Address(0, uint16_t(wire::Interface::Position2d), 0));
  DeviceId ranger = node.find_device(wire::Address(0, uint16_t(wire::Interface::Ranger), 0));
  for (float bad : {std::nanf(""), std::numeric_limits<float>::infinity(), 0.0f}) {
    auto& b = node.begin();
    std::vector<uint16_t> ranges(181, 1000);
    auto body = wire::CreateRangerScan(b, b.CreateVector(ranges), bad == 0 ? -1.0f : 0.001f, bad, bad, 8.0f);
    node.publish(ranger, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, body.Union());
    auto& b2 = node.begin();
    wire::Pose2d pose(bad, 0, 0);
    auto body2 = wire::CreatePosition2dState(b2, &pose);
    node.publish(odom, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState, body2.Union());
  }
  EXPECT_EQ(probe.localize_count, 0u) << "a garbage scan was localized";
  probe.scans = 0;
  probe.estimates.clear();
  probe.truth.clear();
  // Tracking again from the start pose, then the log plays: mcl must have
  // fetched its map by itself meanwhile.
  ASSERT_TRUE(set_pose(0.01f));
  run(node, probe, w.poses);
  ASSERT_FALSE(probe.estimates.empty());
  EXPECT_LT(desktop::distance(probe.estimates.rbegin()->second, probe.truth.rbegin()->second), 0.15);
  node.shutdown();
}

// The robot's node restarts while mcl runs on the desktop: the robot stands
// still for 5 s while it reboots, then its odometry starts again from its
// origin (or, for a source that starts elsewhere, from any pose, caught by
// odom_max_speed), while the timestamps run on. mcl must not take the jump
// as motion: the estimate stays with the robot and mcl never says it is
// lost. (Taken as motion, the jump carries the belief metres away.)
TEST(DesktopDrivers, MclIgnoresTheOdometryJumpOfARestartedRobot) {
  struct Case {
    const char* what;
    Pose2 restart_at;  // the odometry's first pose after the restart
    const char* mcl_extra;
  };
  const Case cases[] = {
      {"reset to its origin", {0, 0, 0}, ""},
      {"restarted elsewhere, speed bound", {3.0, -2.0, 1.0}, R"(, "odom_max_speed": 2.0)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    World w = make_world();
    std::string json = desktop_config(
        w, std::string(R"(, "initial_x": 1.5, "initial_y": 0.5, "initial_var_xy": 0.01)") + c.mcl_extra);
    // The log's devices are fed by hand here: its replay never starts.
    json.replace(json.find("\"start_delay\": 0.1"), 18, "\"start_delay\": 3000");
    LoadedConfig cfg;
    std::string error;
    ASSERT_TRUE(load(w.dir, json, cfg, error)) << error;
    Node node(node_options(*cfg.root));
    ASSERT_TRUE(build_node(node, cfg, error)) << error;
    auto owned = std::make_unique<Probe>();
    Probe& probe = *owned;
    ASSERT_TRUE(node.add_driver(std::move(owned), {}, error)) << error;
    DeviceId odom = node.find_device(wire::Address(0, uint16_t(wire::Interface::Position2d), 0));
    DeviceId ranger = node.find_device(wire::Address(0, uint16_t(wire::Interface::Ranger), 0));
    // mcl fetches its map through the node's loop.
    auto ready = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
    while (std::chrono::steady_clock::now() < ready) node.poll(5'000);

    desktop::OccupancyGrid map = desktop::testing::make_test_map();
    desktop::testing::TestLaser laser;
    std::vector<Pose2> route = desktop::testing::test_route(0.2);
    route.resize(std::min<size_t>(route.size(), 120));
    const size_t k = route.size() / 2;  // the restart, while standing at route[k - 1]
    uint64_t t = 1'000'000;
    auto feed = [&](const Pose2& truth, const Pose2& odometry) {
      auto& b = node.begin();
      wire::Pose2d pose(float(odometry.x), float(odometry.y), float(odometry.a));
      auto body = wire::CreatePosition2dState(b, &pose);
      node.publish(odom, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState, body.Union(),
                   t);
      std::vector<float> r = desktop::testing::cast_scan(map, truth, laser);
      std::vector<uint16_t> mm(r.size());
      for (size_t i = 0; i < r.size(); ++i) mm[i] = uint16_t(std::lround(r[i] * 1000));
      auto& b2 = node.begin();
      auto scan = wire::CreateRangerScan(b2, b2.CreateVector(mm), 0.001f, float(laser.start_angle()),
                                         float(laser.angular_res()), float(laser.max_range));
      node.publish(ranger, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, scan.Union(), t);
      auto est = probe.estimates.find(t);
      EXPECT_NE(est, probe.estimates.end()) << "no estimate at " << t << " us";
      return est == probe.estimates.end() ? 1e9 : desktop::distance(est->second, truth);
    };
    // The odometry is the route itself (a good robot), then a new origin.
    double worst = 0;
    for (size_t i = 0; i < k; ++i, t += 200'000) worst = std::max(worst, feed(route[i], route[i]));
    t += 5'000'000;  // rebooting
    const Pose2 stood = route[k - 1];
    for (size_t i = k - 1; i < route.size(); ++i, t += 200'000) {
      Pose2 restarted = desktop::compose(c.restart_at, desktop::relative(stood, route[i]));
      worst = std::max(worst, feed(route[i], restarted));
    }
    EXPECT_LT(worst, 0.25) << "the estimate strayed " << worst << " m from the robot";
    EXPECT_EQ(probe.lost_count, 0u);
    EXPECT_EQ(probe.localize_count, route.size() + 1);
    node.shutdown();
  }
}

TEST(DesktopDrivers, ConfigMistakesAreReportedAndTheNodeDoesNotStart) {
  World w = make_world();
  struct Case {
    std::string json;
    std::string expect;
  };
  const Case cases[] = {
      {R"({ "drivers": [ { "driver_type": "logreplay", "driver": { "file": "no-such.log" },
            "provides": ["position2d:0"] } ] })",
       "no-such.log: cannot open"},
      {R"({ "drivers": [ { "driver_type": "logreplay", "driver": { "file": ")" + w.log_path +
           R"(", "speed": 0 }, "provides": ["position2d:0"] } ] })",
       "\"speed\""},
      {R"({ "drivers": [ { "driver_type": "mapfile", "driver": { "file": ")" + w.log_path +
           R"(" }, "provides": ["map:0"] } ] })",
       "not a readable PNG"},
      {R"({ "drivers": [ { "driver_type": "mapfile", "driver": { "file": ")" + w.map_path +
           R"(" }, "provides": ["map:0"] },
           { "driver_type": "mcl", "uses": ["map:0"], "provides": ["localize:0"] } ] })",
       "mcl needs \"uses\""},
      {R"({ "drivers": [ { "driver_type": "logreplay", "driver": { "file": ")" + w.log_path +
           R"(" }, "provides": ["position2d:0", "ranger:0"] },
           { "driver_type": "mapfile", "driver": { "file": ")" +
           w.map_path + R"(" }, "provides": ["map:0"] },
           { "driver_type": "mcl", "driver": { "min_particles": 500, "max_particles": 100 },
             "uses": ["position2d:0", "ranger:0", "map:0"], "provides": ["localize:0"] } ] })",
       "min_particles"},
      {R"({ "drivers": [ { "driver_type": "logreplay", "driver": { "file": ")" + w.log_path +
           R"(" }, "provides": ["position2d:0", "ranger:0"] },
           { "driver_type": "fusion", "driver": { "gyro_sigma": -1 },
             "uses": ["position2d:0"], "provides": ["position2d:1"] } ] })",
       "must be > 0"},
  };
  for (const Case& c : cases) {
    LoadedConfig cfg;
    std::string error;
    ASSERT_TRUE(load(w.dir, c.json, cfg, error)) << error;
    Node node(node_options(*cfg.root));
    EXPECT_FALSE(build_node(node, cfg, error)) << c.expect;
    EXPECT_NE(error.find(c.expect), std::string::npos) << "error was: " << error;
  }
}

TEST(DesktopDrivers, TheExampleConfigParses) {
  LoadedConfig cfg;
  std::string error;
  ASSERT_TRUE(load_config(std::string(TROUPE_SOURCE_DIR) + "/examples/nodes/log_mcl.json", cfg, error))
      << error;
  ASSERT_NE(cfg.root->drivers(), nullptr);
  EXPECT_EQ(cfg.root->drivers()->size(), 4u);
}

TEST(DesktopDrivers, LogReplayPlaysTheAcesLogAsDevices) {
  std::string path = std::string(TROUPE_SHARED_DATA) + "/carmen/aces-corrected.log.gz";
  if (!std::ifstream(path))
    GTEST_SKIP() << "no " << path << " (the shared test data is not beside the project)";
  std::string dir = desktop::testing::scratch_dir();
  LoadedConfig cfg;
  std::string error;
  // Corrected odometry: one odometry sample per scan, at speed 1000 the
  // 1,320 s log plays in about 1.3 s.
  ASSERT_TRUE(load(dir,
                   R"({ "port": 0, "drivers": [ { "driver_type": "logreplay",
      "driver": { "file": ")" +
                       path + R"(", "speed": 1000, "odometry": "Corrected", "seed": 5 },
      "provides": ["position2d:0", "ranger:0", "position2d:1"] } ] })",
                   cfg, error))
      << error;
  Node node(node_options(*cfg.root));
  ASSERT_TRUE(build_node(node, cfg, error)) << error;
  auto owned = std::make_unique<Probe>();
  Probe& probe = *owned;
  ASSERT_TRUE(node.add_driver(std::move(owned), {}, error)) << error;
  run(node, probe, 440);
  EXPECT_EQ(probe.scans, 440u);
  EXPECT_EQ(probe.truth.size(), 440u);
  // The ground truth is the corrected pose of each scan: the first is
  // FLASER line 144's (0.89706, -0.180771, -0.454003).
  EXPECT_NEAR(probe.truth.begin()->second.x, 0.89706, 1e-5);
  EXPECT_NEAR(probe.truth.begin()->second.a, -0.454003, 1e-5);
}

}  // namespace
}  // namespace troupe
