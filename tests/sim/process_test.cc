// The real troupe-sim program over TCP, as users and hostile clients reach
// it: a NaN velocity from the troupe CLI is refused and logged while the
// simulator goes on; a huge Step runs in slices while another client is
// answered; stepping past the world's quit time ends the run with a log
// line and exit status 0, and the Step's client is told why.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <optional>

#include "tests/attack/wire_peer.h"
#include "tests/support/child_process.h"

namespace troupe::sim {
namespace {

using attack::Bytes;
using attack::Frames;
using attack::WirePeer;

constexpr int kReplyMs = 20000;  // bounds a hung simulator, not a requirement

const std::string kBin = std::string(TROUPE_BINARY_DIR) + "/bin/";

// A 10 m wide room (walls north and south) with r0 and r1.
std::string world(double quit_time) {
  return "resolution 0.05\ninterval_sim 100\nquit_time " + std::to_string(quit_time) +
         "\nmodel ( name \"room\" size [10.4 10.4] obstacle_return 1\n"
         "  block ( points 4 point[0] [0 0] point[1] [10.4 0] point[2] [10.4 0.2] point[3] [0 0.2] )\n"
         "  block ( points 4 point[0] [0 10.2] point[1] [10.4 10.2] point[2] [10.4 10.4] point[3] [0 10.4] ) "
         ")\n"
         "define bot position ( size [0.4 0.3] )\n"
         "bot ( name \"r0\" pose [0 0 0 0] )\nbot ( name \"r1\" pose [-3 2 0 90] )\n";
}

class SimProcess : public ::testing::Test {
 protected:
  // troupe-sim on the room, paused, on a free port of 127.0.0.1 unless
  // `more` says otherwise.
  void start(double quit_time = 0, const std::vector<std::string>& more = {}) {
    std::vector<std::string> argv = {kBin + "troupe-sim", write_world(quit_time), "--port", "0", "--no-view",
                                     "--paused"};
    argv.insert(argv.end(), more.begin(), more.end());
    std::string error;
    ASSERT_TRUE(sim_.start(argv, dir_, "sim", error)) << error;
    ASSERT_TRUE(sim_.wait_for("listening on ", false, kReplyMs)) << sim_.err();
    const std::string out = sim_.out();
    const std::string at = out.substr(out.find("listening on ") + 13);
    port_ = uint16_t(std::atoi(at.c_str() + at.find(':') + 1));
    host_ = "127.0.0.1:" + std::to_string(port_);
  }
  std::string write_world(double quit_time) {
    if (dir_.empty()) dir_ = testing::make_temp_dir("troupe-sim-process-");
    EXPECT_FALSE(dir_.empty());
    const std::string path = dir_ + "/room.world";
    std::ofstream(path) << world(quit_time);
    return path;
  }
  void TearDown() override {
    sim_.kill_hard();
    testing::remove_tree(dir_);
  }
  testing::ProgramResult troupe(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {kBin + "troupe"};
    argv.insert(argv.end(), args.begin(), args.end());
    return testing::run_to_end(argv, kReplyMs);
  }
  // The SimClock in the reply to a clock request, or nothing.
  static std::optional<uint64_t> steps(const std::optional<Bytes>& reply) {
    const wire::Message* m = reply ? attack::message(*reply) : nullptr;
    const wire::SimClock* c = m ? m->body_as_SimClock() : nullptr;
    return c ? std::optional<uint64_t>(c->steps()) : std::nullopt;
  }

  std::string dir_;
  testing::ChildProcess sim_;
  uint16_t port_ = 0;
  std::string host_;
  Frames f_;
};

TEST_F(SimProcess, ANaNVelocityIsRefusedAndTheSimulatorGoesOn) {
  start();
  // As the user typed it: the CLI sends it, or refuses it itself.
  for (const char* bad : {"nan", "inf", "-inf"}) {
    const auto cmd = troupe({"cmd", host_, "r0/position2d:0", "vel", bad, "0", "0"});
    EXPECT_TRUE(cmd.status == 0 || cmd.err.find(bad) != std::string::npos) << cmd.err;
  }
  // And as a hand-made frame, which the CLI cannot stop.
  WirePeer client;
  ASSERT_TRUE(client.connect(port_));
  const float nan = std::nanf(""), inf = INFINITY;
  for (const auto& v : {std::array<float, 3>{nan, 0, 0}, {0, inf, 0}, {0, 0, -inf}}) {
    ASSERT_TRUE(client.send(f_.vel(attack::kPosition0, v[0], v[1], v[2])));
    ASSERT_TRUE(client.send(f_.go_to(attack::kPosition0, v[0], v[1], v[2])));
  }
  uint32_t seq = 0;
  ++seq;
  EXPECT_EQ(steps(client.ask(f_.sim_step(seq, 20), seq, kReplyMs)), 20u);
  ASSERT_TRUE(sim_.running()) << sim_.err();
  auto pose_of = [&](const std::string& model) {
    ++seq;
    const auto reply = client.ask(f_.sim_get_pose(seq, model), seq, kReplyMs);
    const wire::Message* m = reply ? attack::message(*reply) : nullptr;
    const wire::SimPose* p = m ? m->body_as_SimPose() : nullptr;
    return p && p->pose() ? std::optional<wire::Pose2d>(*p->pose()) : std::nullopt;
  };
  auto pose = pose_of("r0");
  ASSERT_TRUE(pose);
  EXPECT_EQ(pose->x(), 0);  // not moved, and finite
  EXPECT_EQ(pose->y(), 0);
  // A teleport to NaN is refused with a reason; the robot stays put.
  const auto teleport = troupe({"req", host_, "simulation:0", "setpose", "r1", "nan", "0", "0"});
  EXPECT_NE(teleport.status, 0);
  ++seq;
  EXPECT_EQ(attack::reply_kind(client.ask(f_.sim_set_pose(seq, "r1", 0, inf, 0), seq, kReplyMs)),
            wire::Kind::Nack);
  pose = pose_of("r1");
  ASSERT_TRUE(pose);
  EXPECT_FLOAT_EQ(pose->x(), -3);
  // A good command still drives r0.
  ASSERT_TRUE(client.send(f_.vel(attack::kPosition0, 0.5f, 0, 0)));
  ++seq;
  client.ask(f_.sim_step(seq, 10), seq, kReplyMs);
  pose = pose_of("r0");
  ASSERT_TRUE(pose);
  EXPECT_GT(pose->x(), 0.1f);
  EXPECT_TRUE(std::isfinite(pose->x()));
  EXPECT_TRUE(sim_.running());
}

TEST_F(SimProcess, AHugeStepRunsInSlicesWhileAnotherClientIsAnswered) {
  start();
  WirePeer stepper, other;
  ASSERT_TRUE(stepper.connect(port_) && other.connect(port_));
  uint32_t seq = 0;
  ++seq;
  const auto before = steps(other.ask(f_.sim_request(seq, wire::SimulationReqSub::GetClock), seq, kReplyMs));
  ASSERT_TRUE(before);
  // A small step: acked once all its steps ran, as before.
  ++seq;
  EXPECT_EQ(steps(stepper.ask(f_.sim_step(seq, 500), seq, kReplyMs)), *before + 500);
  // Over the limit: refused.
  ++seq;
  EXPECT_EQ(attack::reply_kind(stepper.ask(f_.sim_step(seq, 1000001), seq, kReplyMs)), wire::Kind::Nack);
  // The largest: while it runs, the other client is answered, and what it
  // is told shows the step under way.
  const uint64_t start_steps = *before + 500;
  const uint32_t big = ++seq;
  ASSERT_TRUE(stepper.send(f_.sim_step(big, 1000000)));
  bool seen_under_way = false;
  for (int i = 0; i < 200 && !seen_under_way; ++i) {
    ++seq;
    const auto now = steps(other.ask(f_.sim_request(seq, wire::SimulationReqSub::GetClock), seq, kReplyMs));
    ASSERT_TRUE(now) << "the other client was not answered";
    ASSERT_LT(*now, start_steps + 1000000) << "the step ended before the other client was answered";
    seen_under_way = *now > start_steps;
  }
  EXPECT_TRUE(seen_under_way);
  // Meanwhile the other client may also drive a robot.
  ++seq;
  EXPECT_EQ(attack::reply_kind(other.ask(f_.sim_get_pose(seq, "r1"), seq, kReplyMs)), wire::Kind::Ack);
}

TEST_F(SimProcess, SteppingPastTheQuitTimeEndsTheRunAndSaysSo) {
  start(2.0);  // 20 steps
  WirePeer stepper;
  ASSERT_TRUE(stepper.connect(port_));
  ASSERT_TRUE(stepper.send(f_.sim_step(1, 15)));
  EXPECT_EQ(steps(stepper.wait_reply(1, kReplyMs)), 15u);
  // 100 more: the run ends at its quit time, after 5 of them.
  const auto reply = stepper.ask(f_.sim_step(2, 100), 2, kReplyMs);
  const wire::Message* m = reply ? attack::message(*reply) : nullptr;
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->header()->kind(), wire::Kind::Nack);
  ASSERT_NE(m->body_as_Error(), nullptr);
  const std::string why = m->body_as_Error()->text()->str();
  EXPECT_NE(why.find("stopped after 5 of 100 steps"), std::string::npos) << why;
  EXPECT_NE(why.find("quit time (2 s)"), std::string::npos) << why;
  EXPECT_EQ(sim_.wait_exit(kReplyMs), 0) << sim_.err();
  EXPECT_NE(sim_.err().find("quit time 2 s reached after 20 steps: the run ends"), std::string::npos)
      << sim_.err();
}

// Without --secure (tests/security/secure_serve_test.cc), serving beyond
// loopback lets any machine that reaches the port drive every robot, so it
// must be asked for, and the log keeps saying it was.
TEST_F(SimProcess, ListeningBeyondLoopbackNeedsInsecureAndTheLogSaysSo) {
  testing::ProgramResult refused = testing::run_to_end(
      {kBin + "troupe-sim", write_world(0), "--port", "0", "--no-view", "--listen", "0.0.0.0"}, kReplyMs);
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("troupe-sim: serving 0.0.0.0:0 in plain TCP would let any machine"),
            std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find("--insecure"), std::string::npos) << refused.err;

  start(0, {"--listen", "0.0.0.0", "--insecure"});
  EXPECT_TRUE(sim_.wait_for("insecure: troupe-sim on 0.0.0.0:" + std::to_string(port_) + " serves plain TCP",
                            true, kReplyMs))
      << sim_.err();
  testing::ProgramResult ls = troupe({"ls", host_});
  EXPECT_EQ(ls.status, 0) << ls.err;
}

// A robot's number on the wire is 16 bits: a served world of 65,536 robots
// is refused with the reason and the way out, and the same world runs
// unserved (--no-serve), every robot stepped to the last.
TEST_F(SimProcess, MoreRobotsThanTheWireAddressesRunOnlyUnserved) {
  constexpr int kSide = 256;  // 65,536 robots, 0.5 m apart
  std::string text = "resolution 0.05\ninterval_sim 100\ndefine bot position ( size [0.2 0.2] )\n";
  for (int k = 0; k < kSide * kSide; ++k) {
    text += "bot ( name \"b" + std::to_string(k) + "\" pose [" + std::to_string(0.5 * (k % kSide)) + " " +
            std::to_string(0.5 * (k / kSide)) + " 0 0] )\n";
  }
  dir_ = testing::make_temp_dir("troupe-sim-process-");
  ASSERT_FALSE(dir_.empty());
  const std::string world = dir_ + "/many.world", log = dir_ + "/many.csv";
  std::ofstream(world) << text;

  testing::ProgramResult served = testing::run_to_end(
      {kBin + "troupe-sim", world, "--port", "0", "--no-view", "--quit-time", "0.1"}, 120000);
  EXPECT_EQ(served.status, 1);
  EXPECT_NE(served.err.find("more than 65535 robots cannot be addressed"), std::string::npos) << served.err;
  EXPECT_NE(served.err.find("--no-serve"), std::string::npos) << served.err;
  EXPECT_EQ(served.out.find("listening on"), std::string::npos) << served.out;

  testing::ProgramResult unserved = testing::run_to_end(
      {kBin + "troupe-sim", world, "--no-serve", "--quit-time", "0.1", "--log", log}, 120000);
  ASSERT_EQ(unserved.status, 0) << unserved.err;
  std::ifstream in(log);
  std::string line, last;
  size_t lines = 0;
  while (std::getline(in, line)) {
    ++lines;
    last = line;
  }
  // The header, then every robot's pose after the one step.
  EXPECT_EQ(lines, 1u + size_t(kSide) * kSide);
  EXPECT_NE(last.find(",b65535,"), std::string::npos) << last;
}

}  // namespace
}  // namespace troupe::sim
