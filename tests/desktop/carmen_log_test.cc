// CARMEN log parsing: the record types, the FLASER beam conventions, and
// what happens to malformed lines.
#include "drivers/common_desktop/carmen_log.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <fstream>

#include "tests/desktop/synthetic_world.h"

namespace troupe::desktop {
namespace {

std::string flaser(int n, double value, const char* tail) {
  std::string s = "FLASER " + std::to_string(n);
  for (int i = 0; i < n; ++i) s += " " + std::to_string(value);
  return s + " " + tail + "\n";
}

TEST(CarmenLog, ReadsOdomFlaserRobotlaserTruepos) {
  std::string text =
      "# comment\n"
      "PARAM robot_front_laser_max 8.1 nohost 0\n"
      "ODOM 1.5 -2.0 0.25 0.3 -0.1 0 12.5 host 12.5\n" +
      flaser(180, 2.0, "1 2 0.5 1.1 2.1 0.6 13.0 host 13.0") +
      "ROBOTLASER1 0 -1.5 3.0 0.5 20.0 0.01 0 7 1 2 3 4 5 6 7 0 0.1 0.2 0.3 1.1 1.2 1.3 0.5 0.1 0.2 0.3 0.4 "
      "14.0 host 14.0\n"
      "TRUEPOS 5 6 0.7 5.1 6.1 0.8 15.0 host 15.0\n"
      "NEFF 30\n"
      "SYNC 1 2 3\n";
  CarmenLog log = parse_carmen(text, "t.log");
  EXPECT_EQ(log.error_count, 0u) << (log.errors.empty() ? "" : log.errors.front());
  ASSERT_EQ(log.odometry.size(), 1u);
  EXPECT_DOUBLE_EQ(log.odometry[0].pose.x, 1.5);
  EXPECT_DOUBLE_EQ(log.odometry[0].pose.a, 0.25);
  EXPECT_DOUBLE_EQ(log.odometry[0].tv, 0.3);
  EXPECT_DOUBLE_EQ(log.odometry[0].time_s, 12.5);
  EXPECT_EQ(log.odometry[0].line, 3u);

  ASSERT_EQ(log.scans.size(), 2u);
  const LaserReading& f = log.scans[0];
  EXPECT_EQ(f.ranges.size(), 180u);
  EXPECT_NEAR(f.angular_res, kPi / 180, 1e-12);  // 180 beams: 1 degree apart
  EXPECT_NEAR(f.start_angle, -kPi / 2, 1e-12);
  EXPECT_DOUBLE_EQ(f.max_range, 8.1);  // from the PARAM line
  EXPECT_DOUBLE_EQ(f.laser_pose.x, 1);
  EXPECT_DOUBLE_EQ(f.robot_pose.y, 2.1);
  EXPECT_DOUBLE_EQ(f.time_s, 13.0);

  const LaserReading& r = log.scans[1];
  ASSERT_EQ(r.ranges.size(), 7u);
  EXPECT_FLOAT_EQ(r.ranges[6], 7.0f);
  EXPECT_DOUBLE_EQ(r.start_angle, -1.5);
  EXPECT_DOUBLE_EQ(r.angular_res, 0.5);
  EXPECT_DOUBLE_EQ(r.max_range, 20.0);
  EXPECT_DOUBLE_EQ(r.laser_pose.a, 0.3);
  EXPECT_DOUBLE_EQ(r.robot_pose.x, 1.1);
  EXPECT_DOUBLE_EQ(r.time_s, 14.0);

  ASSERT_EQ(log.true_poses.size(), 1u);
  EXPECT_DOUBLE_EQ(log.true_poses[0].true_pose.y, 6);
  EXPECT_DOUBLE_EQ(log.true_poses[0].odom_pose.a, 0.8);

  ASSERT_EQ(log.order.size(), 4u);
  EXPECT_EQ(log.order[0].kind, RecordKind::Odometry);
  EXPECT_EQ(log.order[2].kind, RecordKind::Laser);
  EXPECT_EQ(log.order[2].index, 1u);
  EXPECT_EQ(log.order[3].kind, RecordKind::TruePose);
  EXPECT_EQ(log.skipped_lines, 3u);  // PARAM, NEFF, SYNC
}

TEST(CarmenLog, FlaserBeamSpacingFollowsTheCount) {
  for (int n : {180, 181, 360, 361}) {
    CarmenLog log = parse_carmen(flaser(n, 1.0, "0 0 0 0 0 0 1 h 1"), "t");
    ASSERT_EQ(log.scans.size(), 1u) << n;
    double expected = n % 2 ? kPi / (n - 1) : kPi / n;
    EXPECT_NEAR(log.scans[0].angular_res, expected, 1e-12) << n;
    // The last beam of 181/361 lies on +90 degrees, of 180/360 one step short.
    double last = log.scans[0].start_angle + (n - 1) * log.scans[0].angular_res;
    EXPECT_NEAR(last, n % 2 ? kPi / 2 : kPi / 2 - expected, 1e-9) << n;
  }
}

TEST(CarmenLog, MalformedLinesAreReportedWithLineNumbersAndSkipped) {
  std::string text =
      "ODOM 1 2 3 0 0 0 10 h 10\n"            // 1: good
      "ODOM 1 2 x 0 0 0 11 h 11\n"            // 2: not a number
      "ODOM 1 2 3 0 0\n"                      // 3: short
      "FLASER 5 1 2 3 0 0 0 0 0 0 12 h 12\n"  // 4: 5 ranges announced, 3 given
      "FLASER -3 1 2 3\n"                     // 5: bad count
      "FLASER 2 1 -2 0 0 0 0 0 0 13 h 13\n"   // 6: negative range
      "ODOM 1 2 3 0 0 0 nan h 14\n"           // 7: timestamp not finite
      "ODOM 1 2 3 0 0 0 15 h 15 extra\n"      // 8: trailing field
      "FLASER 99999999999 1\n"                // 9: absurd count, refused before allocating
      "ODOM 4 5 6 0 0 0 16 h 16\n";           // 10: good
  CarmenLog log = parse_carmen(text, "bad.log");
  ASSERT_EQ(log.odometry.size(), 2u);
  EXPECT_EQ(log.odometry[1].line, 10u);
  EXPECT_EQ(log.scans.size(), 0u);
  ASSERT_EQ(log.error_count, 8u);
  ASSERT_EQ(log.errors.size(), 8u);
  const char* expected[] = {"bad.log:2: ODOM: field 4 ('x') is not a number",
                            "bad.log:3: ODOM: line ends early",
                            "bad.log:4: FLASER:",
                            "bad.log:5: FLASER: beam count '-3'",
                            "bad.log:6: FLASER: range 1 is negative",
                            "bad.log:7: ODOM: timestamp",
                            "bad.log:8: ODOM: expected 10 fields, found 11",
                            "bad.log:9: FLASER: beam count"};
  for (size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(log.errors[i].rfind(expected[i], 0), 0u) << "got: " << log.errors[i];
  }
}

TEST(CarmenLog, ErrorMessagesAreCappedButAllCounted) {
  std::string text;
  for (int i = 0; i < 50; ++i) text += "ODOM broken\n";
  CarmenOptions opt;
  opt.max_error_messages = 5;
  CarmenLog log = parse_carmen(text, "t", opt);
  EXPECT_EQ(log.error_count, 50u);
  EXPECT_EQ(log.errors.size(), 5u);
  EXPECT_EQ(log.line_count, 50u);
}

TEST(CarmenLog, ReadsGzipAndPlainFilesAlike) {
  std::string dir = testing::scratch_dir();
  std::string text = "ODOM 1 2 0.5 0 0 0 10 h 10\r\n" + flaser(180, 3.0, "0 0 0 0 0 0 11 h 11");
  {
    std::ofstream(dir + "/plain.log") << text;
    gzFile gz = gzopen((dir + "/packed.log.gz").c_str(), "wb");
    ASSERT_NE(gz, nullptr);
    ASSERT_EQ(gzwrite(gz, text.data(), unsigned(text.size())), int(text.size()));
    gzclose(gz);
  }
  for (const char* name : {"/plain.log", "/packed.log.gz"}) {
    CarmenLog log;
    std::string error;
    ASSERT_TRUE(read_carmen(dir + name, log, error)) << error;
    EXPECT_EQ(log.error_count, 0u) << name;  // the CR of a CRLF line is whitespace
    EXPECT_EQ(log.odometry.size(), 1u) << name;
    EXPECT_EQ(log.scans.size(), 1u) << name;
  }
}

TEST(CarmenLog, TruncatedGzipAndMissingFilesAreErrors) {
  std::string dir = testing::scratch_dir();
  std::string text;
  for (int i = 0; i < 2000; ++i) text += "ODOM 1 2 0.5 0 0 0 " + std::to_string(i) + " h 0\n";
  gzFile gz = gzopen((dir + "/full.gz").c_str(), "wb");
  gzwrite(gz, text.data(), unsigned(text.size()));
  gzclose(gz);
  std::string packed;
  {
    std::ifstream in(dir + "/full.gz", std::ios::binary);
    packed.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(dir + "/cut.gz", std::ios::binary) << packed.substr(0, packed.size() / 2);
  CarmenLog log;
  std::string error;
  EXPECT_FALSE(read_carmen(dir + "/cut.gz", log, error));
  EXPECT_NE(error.find("cut.gz: read error"), std::string::npos) << error;
  EXPECT_FALSE(read_carmen(dir + "/absent.log", log, error));
  EXPECT_NE(error.find("absent.log: cannot open"), std::string::npos) << error;
}

TEST(CarmenLog, TheBundledAcesLog) {
  std::string path = std::string(TROUPE_SHARED_DATA) + "/carmen/aces-corrected.log.gz";
  if (!std::ifstream(path))
    GTEST_SKIP() << "no " << path << " (the shared test data is not beside the project)";
  CarmenLog log;
  std::string error;
  ASSERT_TRUE(read_carmen(path, log, error)) << error;
  EXPECT_EQ(log.error_count, 0u);
  EXPECT_EQ(log.scans.size(), 440u);
  EXPECT_EQ(log.odometry.size(), 7814u);
  EXPECT_EQ(log.scans[0].ranges.size(), 180u);
  EXPECT_DOUBLE_EQ(log.scans[0].max_range, 50.0);
  // A corrected log: the laser pose and the "odometry" pose of a scan agree.
  EXPECT_DOUBLE_EQ(log.scans[7].laser_pose.x, log.scans[7].robot_pose.x);
}

}  // namespace
}  // namespace troupe::desktop
