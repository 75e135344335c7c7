// Values at the boundary: every number of every command and request, found
// through the reflection schema, set to NaN, +-infinity, huge, negative and
// zero, against a node with the kinematic base (and recorders for the other
// interfaces) and against troupe-sim's server on a small world. Non-finite
// and huge values are refused with a Nack BadValue naming the field; the
// others are refused or accepted, and whatever is accepted leaves the robot
// finite and the node serving.
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "drivers/kinematic/kinematic.h"
#include "host-sim/troupe_sim/runner.h"
#include "tests/runtime/value_probe.h"
#include "tests/sim/temp_dir.h"
#include "tests/wire/samples.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using wire::ErrorCode;
using wire::Interface;
using wire::Kind;

constexpr float kRefused[] = {NAN, INFINITY, -INFINITY, 1e30f, -1e30f};
constexpr float kEdges[] = {0.0f, -0.0f, -1.0f, -1e-3f, 1e6f, -1e6f, 3e38f};

bool finite(const client::Pose2& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.a); }

// Commands, requests and Open: what a client sends to a device.
std::vector<WireSample> device_samples() {
  std::vector<WireSample> out;
  for (WireSample& s : wire_samples()) {
    Kind k = wire::trusted_message(s.frame)->header()->kind();
    if (k == Kind::Command || k == Kind::Request || k == Kind::Open) out.push_back(std::move(s));
  }
  return out;
}

// Runs every probe through `raw`; `after_each` checks the robot.
void probe_every_value(RawConnection& raw, const std::function<void(const std::string&)>& after_each) {
  uint32_t seq = 1;
  for (const WireSample& s : device_samples()) {
    // The sample itself is well-formed: whatever a driver answers, the node's
    // check lets it through.
    Answer plain = exchange(raw, s.frame, ++seq);
    ASSERT_TRUE(plain.ok) << s.name;
    EXPECT_FALSE(plain.replied && (plain.code == ErrorCode::BadValue || plain.code == ErrorCode::BadBody))
        << s.name << ": " << plain.text;
    for (const ValueSite& site : value_sites(s.frame)) {
      const std::string what = s.name + " " + site.field;
      if (site.type == ValueSite::Type::Float) {
        for (float v : kRefused) {
          Answer a = exchange(raw, with_float(s.frame, site, v), ++seq);
          ASSERT_TRUE(a.ok) << what << " = " << v;
          ASSERT_TRUE(a.replied) << what << " = " << v << " was not refused";
          EXPECT_EQ(a.kind, Kind::Nack) << what;
          EXPECT_EQ(a.code, ErrorCode::BadValue) << what << " = " << v << ": " << a.text;
          EXPECT_NE(a.text.find(site.field), std::string::npos) << what << ": " << a.text;
        }
        for (float v : kEdges) {
          Answer a = exchange(raw, with_float(s.frame, site, v), ++seq);
          ASSERT_TRUE(a.ok) << what << " = " << v;
          if (a.replied && a.code == ErrorCode::BadValue) {
            EXPECT_NE(a.text.find(site.field), std::string::npos) << what << ": " << a.text;
          }
          after_each(what);
        }
      } else {
        std::vector<uint64_t> values = {0, site.bytes == 8 ? UINT64_MAX : (uint64_t{1} << (8 * site.bytes)) - 1};
        if (site.type == ValueSite::Type::Enum) values.push_back(200);
        for (uint64_t v : values) {
          Answer a = exchange(raw, with_unsigned(s.frame, site, v), ++seq);
          ASSERT_TRUE(a.ok) << what << " = " << v;
          if (site.type == ValueSite::Type::Enum && v == 200) {
            EXPECT_EQ(a.code, ErrorCode::BadValue) << what << " = 200: " << a.text;
          }
          after_each(what);
        }
      }
    }
  }
}

class KinematicValues : public ::testing::Test {
 protected:
  void SetUp() override {
    node_.add_device(Interface::Position2d, 0, new drivers::kinematic::Kinematic, "kinematic");
    for (Interface i : {Interface::Ranger, Interface::Bumper, Interface::Fiducial, Interface::Actuator,
                        Interface::Localize, Interface::Map, Interface::Simulation, Interface::Opaque,
                        Interface::Camera}) {
      node_.add_device(i, 0, new Recorder);
    }
    node_.start();
    client_ = std::make_unique<client::Client>("127.0.0.1", node_.port());
    ASSERT_TRUE(client_->connect()) << client_->error();
    base_ = std::make_unique<client::Position2dProxy>(*client_);
    ASSERT_TRUE(base_->is_open());
  }

  // The next odometry sample the base publishes.
  client::Pose2 fresh_pose() {
    uint64_t seen = base_->samples();
    for (int i = 0; i < 200 && base_->samples() < seen + 2; ++i) client_->spin_once(10);
    EXPECT_GE(base_->samples(), seen + 2);
    return base_->pose();
  }

  NodeThread node_{test_options()};
  std::unique_ptr<client::Client> client_;
  std::unique_ptr<client::Position2dProxy> base_;
};

// The issue's failure: `troupe cmd ... vel nan 0 0` made the base's pose and
// velocity NaN for good; neither `vel 0` nor an odometry reset recovered it.
TEST_F(KinematicValues, ANaNVelocityIsRefusedAndTheBaseDrivesOn) {
  ASSERT_TRUE(base_->set_velocity(NAN, 0, 0));
  EXPECT_TRUE(client_->sync());
  EXPECT_NE(client_->error().find("vel.x"), std::string::npos) << client_->error();
  client::Pose2 before = fresh_pose();
  ASSERT_TRUE(finite(before) && finite(base_->velocity()));
  ASSERT_TRUE(base_->set_velocity(0.5f, 0, 0));
  ASSERT_TRUE(client_->sync());
  client::Pose2 p = before;
  for (int i = 0; i < 50 && p.x < before.x + 0.02f; ++i) p = fresh_pose();
  EXPECT_TRUE(finite(p));
  EXPECT_GT(p.x, before.x + 0.02f);
}

TEST_F(KinematicValues, EveryFieldOfEveryCommandAndRequest) {
  RawConnection raw(node_.port());
  ASSERT_TRUE(raw.ok());
  probe_every_value(raw, [&](const std::string& what) {
    ASSERT_TRUE(finite(base_->pose()) && finite(base_->velocity())) << "after " << what;
  });
  client::Pose2 p = fresh_pose();
  EXPECT_TRUE(finite(p) && finite(base_->velocity()));
  std::vector<client::DeviceEntry> list;
  EXPECT_TRUE(client_->device_list(list));
  EXPECT_EQ(list.size(), 10u);
}

// troupe-sim serves its robots through a Node, so the same check stands in
// front of its server: `vel nan` once crashed it within one step.
class SimValues : public ::testing::Test {
 protected:
  void SetUp() override {
    sim::SimOptions o;
    o.world = dir_.write("w.world", R"(
resolution 0.02
interval_sim 100
define bot position ( size [0.4 0.4] localization "gps" localization_origin [0 0 0 0] )
bot ( name "r0" pose [0 0 0 0] ranger ( sensor ( range [0 5] fov 180 samples 19 ) ) )
bot ( name "r1" pose [2 1 0 90] )
)");
    o.port = 0;
    o.view = false;
    o.speed = 0;  // as fast as it goes: many steps while the probes run
    world::Diagnostics d;
    std::string error;
    ASSERT_TRUE(runner_.init(o, d, error)) << d.str() << error;
    thread_ = std::thread([this] { runner_.run(); });
  }
  void TearDown() override {
    runner_.request_stop();
    if (thread_.joinable()) thread_.join();
  }

  bool robots_finite(client::SimulationProxy& sim) {
    client::Pose2 p, v;
    for (const char* name : {"r0", "r1"}) {
      if (!sim.get_pose(name, p, v) || !finite(p) || !finite(v)) return false;
    }
    return true;
  }

  troupe::test::TempDir dir_;
  sim::Runner runner_;
  std::thread thread_;
};

TEST_F(SimValues, ANaNVelocityIsRefusedAndTheSimulatorStepsOn) {
  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::Position2dProxy base(c, 0, 0);
  client::SimulationProxy sim(c);
  ASSERT_TRUE(base.set_velocity(NAN, 0, 0));
  ASSERT_TRUE(c.sync());
  EXPECT_NE(c.error().find("vel.x"), std::string::npos) << c.error();
  ASSERT_TRUE(base.set_velocity(0.3f, 0, INFINITY));
  ASSERT_TRUE(c.sync());
  EXPECT_NE(c.error().find("vel.a"), std::string::npos) << c.error();
  ASSERT_TRUE(sim.pause());
  uint64_t before = sim.steps();
  ASSERT_TRUE(sim.step(3));
  EXPECT_GE(sim.steps(), before + 3);
  EXPECT_TRUE(robots_finite(sim));
}

TEST_F(SimValues, EveryFieldOfEveryCommandAndRequest) {
  RawConnection raw(runner_.port());
  ASSERT_TRUE(raw.ok());
  client::Client c("127.0.0.1", runner_.port());
  ASSERT_TRUE(c.connect()) << c.error();
  client::SimulationProxy sim(c);
  probe_every_value(raw, [&](const std::string&) {});
  EXPECT_TRUE(robots_finite(sim));
  ASSERT_TRUE(sim.pause());
  ASSERT_TRUE(sim.step(2));
  EXPECT_TRUE(robots_finite(sim));
}

}  // namespace
}  // namespace troupe::testing
