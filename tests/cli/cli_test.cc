// The quick start, as a user runs it: troupe-node serving the kinematic
// example, driven and watched with the troupe CLI, as separate processes.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "tests/support/child_process.h"

using troupe::testing::ChildProcess;
using troupe::testing::free_port;

namespace {

const std::string kBin = TROUPE_BINARY_DIR;
const std::string kNode = kBin + "/bin/troupe-node";
const std::string kTroupe = kBin + "/bin/troupe";
const std::string kExample = std::string(TROUPE_SOURCE_DIR) + "/examples/nodes/kinematic.json";

struct Result {
  int rc = -1;
  std::string out, err;
};

// Runs a shell command line to its end (bounded: a hang fails the test).
Result run(const std::string& command) {
  troupe::testing::ProgramResult r = troupe::testing::run_to_end({"/bin/sh", "-c", command}, 60000);
  return {r.status, r.out, r.err};
}

bool listening(uint16_t port) {
  return troupe::testing::wait_for_listener(port, 0);
}

// The first pose x in an echo line "... pose=X,Y,A ...".
double pose_x(const std::string& line) {
  size_t at = line.find("pose=");
  return at == std::string::npos ? -1e9 : std::stod(line.substr(at + 5));
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    port_ = free_port();
    host_ = "127.0.0.1:" + std::to_string(port_);
    dir_ = troupe::testing::make_temp_dir("troupe-cli-");
    std::string error;
    ASSERT_TRUE(node_.start({kNode, kExample, "--port", std::to_string(port_)}, dir_, "troupe-node", error))
        << error;
    ASSERT_TRUE(troupe::testing::wait_for_listener(port_, 5)) << "troupe-node did not start: " << node_.err();
  }
  void TearDown() override {
    EXPECT_EQ(node_.stop(), 0) << "troupe-node did not stop cleanly: " << node_.err();
    troupe::testing::remove_tree(dir_);
  }
  Result troupe(const std::string& args) { return run(kTroupe + " " + args); }

  ChildProcess node_;
  std::string dir_;
  uint16_t port_ = 0;
  std::string host_;
};

TEST_F(Cli, LsListsTheKinematicBase) {
  Result r = troupe("ls " + host_);
  EXPECT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.out, "position2d:0\tkinematic\n");
}

TEST_F(Cli, VelCommandMakesTheEchoedPoseChange) {
  Result before = troupe("echo " + host_ + " position2d:0 --count 1");
  ASSERT_EQ(before.rc, 0) << before.err;
  EXPECT_NEAR(pose_x(before.out), 0.0, 1e-6);
  Result cmd = troupe("cmd " + host_ + " position2d:0 vel 0.5 0 0");
  ASSERT_EQ(cmd.rc, 0) << cmd.err;
  EXPECT_EQ(cmd.out, "");
  // The base accelerates at 0.5 m/s^2 (the example's limit): after about a
  // second it has moved; echo until it shows.
  double x = 0;
  for (int i = 0; i < 100 && x <= 0.05; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    Result after = troupe("echo " + host_ + " position2d:0 --count 1");
    ASSERT_EQ(after.rc, 0) << after.err;
    x = pose_x(after.out);
  }
  EXPECT_GT(x, 0.05);
  Result json = troupe("echo " + host_ + " position2d:0 --count 2 --json");
  ASSERT_EQ(json.rc, 0);
  EXPECT_EQ(std::count(json.out.begin(), json.out.end(), '\n'), 2);
  EXPECT_NE(json.out.find("\"body_type\": \"Position2dState\""), std::string::npos) << json.out;
}

TEST_F(Cli, RequestsPrintTheirReply) {
  Result geo = troupe("req " + host_ + " position2d:0 geometry --json");
  ASSERT_EQ(geo.rc, 0) << geo.err;
  EXPECT_NE(geo.out.find("\"size\""), std::string::npos) << geo.out;
  Result reset = troupe("req " + host_ + " position2d:0 resetodom");
  EXPECT_EQ(reset.rc, 0) << reset.err;
  EXPECT_EQ(reset.out, "ok\n");
}

TEST_F(Cli, ErrorsAreOneLineAndNonZero) {
  auto one_line = [](const Result& r) { return std::count(r.err.begin(), r.err.end(), '\n') == 1; };
  Result no_device = troupe("echo " + host_ + " ranger:0 --count 1");
  EXPECT_EQ(no_device.rc, 1);
  EXPECT_NE(no_device.err.find("no such device ranger:0"), std::string::npos) << no_device.err;
  EXPECT_TRUE(one_line(no_device)) << no_device.err;
  Result no_host = troupe("ls no-such-host.invalid");
  EXPECT_EQ(no_host.rc, 1);
  EXPECT_NE(no_host.err.find("cannot resolve host"), std::string::npos) << no_host.err;
  EXPECT_TRUE(one_line(no_host));
  Result refused = troupe("ls 127.0.0.1:" + std::to_string(free_port()));
  EXPECT_EQ(refused.rc, 1);
  EXPECT_NE(refused.err.find("Connection refused"), std::string::npos) << refused.err;
  EXPECT_TRUE(one_line(refused));
  Result bad_verb = troupe("cmd " + host_ + " position2d:0 fly");
  EXPECT_EQ(bad_verb.rc, 2);
  EXPECT_NE(bad_verb.err.find("it has: vel, goto"), std::string::npos) << bad_verb.err;
  EXPECT_TRUE(one_line(bad_verb));
  Result bad_args = troupe("cmd " + host_ + " position2d:0 vel fast 0 0");
  EXPECT_EQ(bad_args.rc, 2);
  EXPECT_TRUE(one_line(bad_args));
  Result bad_addr = troupe("echo " + host_ + " laser:0");
  EXPECT_EQ(bad_addr.rc, 1);
  EXPECT_NE(bad_addr.err.find("unknown interface 'laser'"), std::string::npos) << bad_addr.err;
  Result unknown = troupe("frobnicate");
  EXPECT_EQ(unknown.rc, 2);
  EXPECT_NE(unknown.err.find("unknown command 'frobnicate'"), std::string::npos) << unknown.err;
}

// `troupe cmd ... vel nan 0 0` was sent (and poisoned the base); values are
// checked against their documented range before any node is contacted.
TEST_F(Cli, NonFiniteAndOutOfRangeValuesAreUsageErrors) {
  for (const char* args : {" position2d:0 vel nan 0 0", " position2d:0 vel 0.1 0 inf", " position2d:0 goto 1e30 0 0",
                           " position2d:0 vel 1e39 0 0"}) {
    Result r = troupe("cmd " + host_ + args);
    EXPECT_EQ(r.rc, 2) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  Result nan = troupe("cmd " + host_ + " position2d:0 vel nan 0 0");
  EXPECT_NE(nan.err.find("'nan' is not a finite number"), std::string::npos) << nan.err;
  Result far = troupe("cmd " + host_ + " position2d:0 goto 1e30 0 0");
  EXPECT_NE(far.err.find("pose.x is 1e+30: it must be finite, from -1e+06 to 1e+06 m"), std::string::npos) << far.err;
  Result huge = troupe("req " + host_ + " position2d:0 setodom 0 2e6 0");
  EXPECT_EQ(huge.rc, 2);
  EXPECT_NE(huge.err.find("pose.y"), std::string::npos) << huge.err;
  // No node is needed to refuse it.
  Result offline = troupe("cmd 127.0.0.1:" + std::to_string(free_port()) + " position2d:0 vel nan 0 0");
  EXPECT_EQ(offline.rc, 2) << offline.err;
  // The base was never touched: its pose is still a number.
  Result echo = troupe("echo " + host_ + " position2d:0 --count 1");
  EXPECT_EQ(echo.rc, 0);
  EXPECT_EQ(echo.out.find("nan"), std::string::npos) << echo.out;
}

TEST(CliNode, BadConfigNamesTheKeyAndNothingStarts) {
  const std::string dir = troupe::testing::make_temp_dir("troupe-cli-");
  ASSERT_FALSE(dir.empty());
  std::string path = dir + "/bad.json";
  uint16_t port = free_port();
  std::ofstream(path)
      << "{ \"port\": " << port
      << ", \"drivers\": [ { \"driver_type\": \"kinematic\", \"driver\": { \"max_speeed\": 1 },"
         " \"provides\": [\"position2d:0\"] } ] }";
  Result r = run(kNode + " " + path);
  EXPECT_EQ(r.rc, 78) << "EX_CONFIG";
  EXPECT_NE(r.err.find("bad.json:1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("unknown field: max_speeed"), std::string::npos) << r.err;
  EXPECT_FALSE(listening(port));
  troupe::testing::remove_tree(dir);
}

}  // namespace
