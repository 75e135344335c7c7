// The sicklms200 driver in a real node, against the LMS200 emulator on a
// pty: configuring the scanner, the scans it publishes, its requests, and
// the errors a bad config gives.
#include <cmath>

#include "tests/sicklms200/sick_fixture.h"

namespace troupe::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;
namespace sick = drivers::sicklms200;

TEST_F(SickNode, ConfiguresTheScannerAndStreams) {
  start();
  ASSERT_TRUE(streaming());
  EXPECT_EQ(scanner_->baud(), 38400u);
  EXPECT_EQ(scanner_->units(), sick::Units::Millimetres);
  EXPECT_EQ(scanner_->mode(), emulators::SickEmulator::Mode::Continuous);
  const wire::RangerScan* scan = newest_scan();
  ASSERT_NE(scan, nullptr);
  ASSERT_EQ(scan->ranges()->size(), 181u);
  EXPECT_FLOAT_EQ(scan->min_angle(), float(-kPi / 2));
  EXPECT_FLOAT_EQ(scan->angular_res(), float(kPi / 180));
  EXPECT_FLOAT_EQ(scan->max_range(), 8.191f);
  EXPECT_FLOAT_EQ(scan->scale(), 0.001f);
  // The corridor: walls 3 m to either side, nothing within reach ahead.
  EXPECT_EQ(scan->ranges()->Get(0), 3000);
  EXPECT_EQ(scan->ranges()->Get(180), 3000);
  EXPECT_EQ(scan->ranges()->Get(90), 8191);
  EXPECT_EQ(mismatched_, 0u);
}

TEST_F(SickNode, HalfDegreeResolution) {
  start({}, R"("resolution_cdeg": 50)");
  ASSERT_TRUE(streaming());
  const wire::RangerScan* scan = newest_scan();
  ASSERT_EQ(scan->ranges()->size(), 361u);
  EXPECT_FLOAT_EQ(scan->angular_res(), float(kPi / 360));
  EXPECT_EQ(scanner_->resolution_cdeg(), 50);
  EXPECT_EQ(mismatched_, 0u);
}

TEST_F(SickNode, HundredDegreesAtAQuarter) {
  start({}, R"("scan_width_deg": 100, "resolution_cdeg": 25, "baud": 500000)");
  ASSERT_TRUE(streaming());
  const wire::RangerScan* scan = newest_scan();
  ASSERT_EQ(scan->ranges()->size(), 401u);
  EXPECT_FLOAT_EQ(scan->min_angle(), float(-50 * kPi / 180));
  EXPECT_EQ(scanner_->baud(), 500000u);
  EXPECT_EQ(mismatched_, 0u);
}

TEST_F(SickNode, StaysAtNineThousandSixHundredWhenAsked) {
  start({}, R"("baud": 9600)");
  ASSERT_TRUE(streaming());
  EXPECT_EQ(scanner_->baud(), 9600u);
}

TEST_F(SickNode, FindsAScannerLeftAtAnotherSpeed) {
  emulators::SickEmulator::Config config;
  config.power_up_baud = 500000;  // as an earlier driver left it (power-up is 9600)
  start(config, R"("reply_timeout_ms": 300)");
  ASSERT_TRUE(streaming());
  EXPECT_EQ(scanner_->baud(), 38400u);
}

TEST_F(SickNode, ScansFollowTheWorld) {
  emulators::SickWorld world;
  start({}, "", &world);
  ASSERT_TRUE(streaming());
  world.y = 1.0;  // 2 m from the left wall, 4 m from the right
  ASSERT_TRUE(loop_.run_until(
      [&] {
        const wire::RangerScan* s = newest_scan();
        return s && s->ranges()->Get(0) == 4000 && s->ranges()->Get(180) == 2000;
      },
      10));
}

TEST_F(SickNode, GeometryAndConfig) {
  start({}, R"("pose_x": 0.16, "pose_yaw": 0.1)");
  ASSERT_TRUE(streaming());
  uint32_t g = client_.request(kLaser, uint8_t(wire::RangerReqSub::Geometry));
  uint32_t c = client_.request(kLaser, uint8_t(wire::RangerReqSub::GetConfig));
  ASSERT_TRUE(loop_.run_until([&] { return client_.reply(g) && client_.reply(c); }, 5));
  const wire::RangerGeometry* geometry = client_.reply(g)->body_as_RangerGeometry();
  ASSERT_NE(geometry, nullptr);
  EXPECT_FLOAT_EQ(geometry->pose()->x(), 0.16f);
  EXPECT_FLOAT_EQ(geometry->pose()->yaw(), 0.1f);
  const wire::RangerConfig* config = client_.reply(c)->body_as_RangerConfig();
  ASSERT_NE(config, nullptr);
  EXPECT_FLOAT_EQ(config->min_angle(), float(-kPi / 2));
  EXPECT_FLOAT_EQ(config->max_angle(), float(kPi / 2));
  EXPECT_FLOAT_EQ(config->max_range(), 8.191f);
  // 38400 baud carries 3840 bytes a second; a 181-value scan is 372 bytes.
  EXPECT_NEAR(config->frequency(), 3840.0 / 372.0, 1e-3);
}

TEST_F(SickNode, ReconfiguresAScannerSomeoneElseChanged) {
  start();
  ASSERT_TRUE(streaming());
  // Another program (or a power cycle with other stored settings) switches
  // the scanner to centimetres behind the driver's back.
  {
    RawPort other(scanner_->path(), B38400);
    ASSERT_TRUE(other.ok());
    ASSERT_TRUE(other.write(sick::enter_config().view()));
    loop_.run_for(0.1);
    uint8_t block[sick::kConfigBytes] = {};
    ASSERT_TRUE(other.write(sick::write_config(block).view()));
    loop_.run_for(0.1);
    ASSERT_TRUE(other.write(sick::mode_change(sick::Mode::Continuous).view()));
    loop_.run_for(0.1);
  }
  ASSERT_EQ(scanner_->units(), sick::Units::Centimetres);
  ASSERT_TRUE(loop_.run_until([&] { return scanner_->units() == sick::Units::Millimetres; }, 10));
  uint32_t n = client_.count(kLaser);
  ASSERT_TRUE(loop_.run_until([&] { return client_.count(kLaser) > n + 2; }, 10));
  EXPECT_EQ(newest_scan()->ranges()->Get(0), 3000);
}

TEST_F(SickNode, BadOptionsKeepTheNodeFromStarting) {
  struct Case {
    const char* options;
    const char* error;
  } cases[] = {
      {R"("baud": 57600)", "runs at 9600, 19200, 38400 or 500000 bit/s, not 57600"},
      {R"("resolution_cdeg": 25)", "\"resolution_cdeg\" 25: the scanner offers"},
      {R"("scan_width_deg": 90)", "\"scan_width_deg\" 90"},
      {R"("reply_attempts": 0)", "\"reply_attempts\" must be > 0"},
  };
  for (const Case& c : cases) {
    NodeUnderTest node;
    std::string error;
    EXPECT_FALSE(node.start(config(c.options), error)) << c.options;
    EXPECT_NE(error.find(c.error), std::string::npos) << error;
    EXPECT_NE(error.find("drivers[0] (sicklms200)"), std::string::npos) << error;
  }
  NodeUnderTest node;
  std::string error;
  std::string two = R"({ "drivers": [ { "driver_type": "sicklms200", "driver": { "port": "x" },
                         "provides": ["ranger:0", "ranger:1"] } ] })";
  EXPECT_FALSE(node.start(two, error));
  EXPECT_NE(error.find("exactly one ranger"), std::string::npos) << error;
}

}  // namespace
}  // namespace troupe::testing
