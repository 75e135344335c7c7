// ARIA's connection to a Pioneer, played byte for byte against the
// emulator on a real pseudo-terminal (what ArRobot::asyncConnectHandler and
// its motion commands send, learnt from ARIA's public source): the modem
// wake-up string, SYNC0/1/2, OPEN 1, the configuration request, the switch
// to 38400 baud, the limits, then MOVE, HEAD and DHEAD moves, and CLOSE 1.
// The robot must end where the moves say, under the limits set. The
// emulator runs on its own clock (step()), so profiles are checked exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "drivers/p2os/p2os_protocol.h"
#include "host-sim/emulators/p2os/pioneer_emulator.h"
#include "tests/device_harness/device_harness.h"
#include "tests/device_harness/raw_port.h"

namespace troupe::emulators {
namespace {

using drivers::p2os::Command;
using drivers::p2os::command_int;
using Bytes = std::vector<uint8_t>;

constexpr uint64_t kMs = 1000;
constexpr double kPi = 3.14159265358979323846;

// Packets as ARIA writes them, checksums worked by hand.
const Bytes kSync0 = {0xFA, 0xFB, 0x03, 0x00, 0x00, 0x00};
const Bytes kSync1 = {0xFA, 0xFB, 0x03, 0x01, 0x00, 0x01};
const Bytes kSync2 = {0xFA, 0xFB, 0x03, 0x02, 0x00, 0x02};
const Bytes kOpen1 = {0xFA, 0xFB, 0x06, 0x01, 0x3B, 0x01, 0x00, 0x02, 0x3B};
const Bytes kConfig1 = {0xFA, 0xFB, 0x06, 0x12, 0x3B, 0x01, 0x00, 0x13, 0x3B};
const Bytes kHostBaud38400 = {0xFA, 0xFB, 0x06, 0x32, 0x3B, 0x02, 0x00, 0x34, 0x3B};
const Bytes kClose1 = {0xFA, 0xFB, 0x06, 0x02, 0x3B, 0x01, 0x00, 0x03, 0x3B};

Bytes bytes(const drivers::p2os::Packet& p) {
  return Bytes(p.view().begin(), p.view().end());
}

class AriaClient : public ::testing::Test {
 protected:
  void SetUp() override {
    robot_ = std::make_unique<PioneerEmulator>(PioneerEmulator::Config{});
    std::string error;
    ASSERT_TRUE(robot_->open(dir_.file("pioneer"), error)) << error;
    port_ = std::make_unique<testing::RawPort>(robot_->path(), B9600);
    ASSERT_TRUE(port_->ok());
    robot_->step(0);
  }
  void send(const Bytes& b) { ASSERT_TRUE(port_->write(b)); }
  // Advances the robot's clock by `dt_us` in 10 ms steps, calling
  // `each()` after every step.
  template <typename Each>
  void run(uint64_t dt_us, Each&& each) {
    uint64_t end = now_ + dt_us;
    while (now_ < end) {
      now_ = std::min(end, now_ + 10 * kMs);
      robot_->step(now_);
      each();
    }
  }
  void run(uint64_t dt_us) {
    run(dt_us, [] {});
  }
  // The packets that arrived since the last call, as payloads.
  std::vector<Bytes> packets() {
    std::vector<Bytes> out;
    Bytes in = port_->read_all();
    drivers::p2os::scan_packets(scanner_, in, [&](std::span<const uint8_t> p) { out.emplace_back(p.begin(), p.end()); });
    return out;
  }
  // Sends `b` and returns the first reply whose type is `type`.
  Bytes ask(const Bytes& b, uint8_t type) {
    send(b);
    for (int i = 0; i < 50; ++i) {
      run(10 * kMs);
      for (const Bytes& p : packets())
        if (p[0] == type) return p;
    }
    return {};
  }
  // ARIA's handshake up to a streaming, enabled robot at 38400 baud.
  void connect() {
    send({'W', 'M', 'S', '2', '\r'});
    ASSERT_EQ(ask(kSync0, 0), Bytes{0});
    ASSERT_EQ(ask(kSync1, 1), Bytes{1});
    Bytes id = ask(kSync2, 2);
    ASSERT_GT(id.size(), 3u);
    // Name, class, subclass: NUL-terminated.
    const char* name = reinterpret_cast<const char*>(id.data() + 1);
    const char* cls = name + strlen(name) + 1;
    const char* sub = cls + strlen(cls) + 1;
    EXPECT_STREQ(cls, "Pioneer");
    EXPECT_STREQ(sub, "p3dx-sh");
    send(kOpen1);
    config_ = ask(kConfig1, 0x20);
    ASSERT_FALSE(config_.empty()) << "no configuration packet";
    // ARIA switches to its SwitchToBaudRate when the robot says it can.
    send(kHostBaud38400);
    run(10 * kMs);
    port_->set_speed(B38400);
    packets();
    send(bytes(drivers::p2os::command(Command::Pulse)));
    ASSERT_FALSE(ask(bytes(drivers::p2os::command(Command::Pulse)), 0x32).empty()) << "no SIP at 38400 baud";
    send(bytes(command_int(Command::Enable, 1)));
    send(bytes(command_int(Command::SetV, 400)));
    send(bytes(command_int(Command::SetA, 300)));
    send(bytes(command_int(Command::SetA, -300)));
    send(bytes(command_int(Command::SetRv, 60)));
    send(bytes(command_int(Command::SetRA, 100)));
    run(50 * kMs);
    ASSERT_TRUE(robot_->motors_enabled());
  }
  // Pulses while the robot moves, as ARIA's cycle does, until it rests.
  void until_still(uint64_t max_us) {
    uint64_t end = now_ + max_us;
    do {
      send(bytes(drivers::p2os::command(Command::Pulse)));
      run(100 * kMs, [&] {
        max_v_ = std::max(max_v_, std::fabs(robot_->motion().v()));
        max_w_ = std::max(max_w_, std::fabs(robot_->motion().w()));
        max_dv_ = std::max(max_dv_, std::fabs(robot_->motion().v() - last_v_));
        last_v_ = robot_->motion().v();
      });
    } while (now_ < end && (robot_->motion().v() != 0 || robot_->motion().w() != 0 ||
                            robot_->motion().remaining() != 0));
  }

  testing::TempDir dir_;
  std::unique_ptr<PioneerEmulator> robot_;
  std::unique_ptr<testing::RawPort> port_;
  drivers::p2os::PacketScanner scanner_;
  uint64_t now_ = 0;
  Bytes config_;
  double max_v_ = 0, max_w_ = 0, max_dv_ = 0, last_v_ = 0;
};

TEST_F(AriaClient, HandPackedPacketsAreTheCodecs) {
  EXPECT_EQ(kOpen1, bytes(command_int(Command::Open, 1)));
  EXPECT_EQ(kConfig1, bytes(command_int(Command::Config, 1)));
  EXPECT_EQ(kHostBaud38400, bytes(command_int(Command::HostBaud, 2)));
  EXPECT_EQ(kClose1, bytes(command_int(Command::Close, 1)));
}

TEST_F(AriaClient, ConnectsAndReadsTheConfiguration) {
  connect();
  ASSERT_FALSE(HasFatalFailure());
  // 0x20: class, subclass, serial number, a byte, then the top limits.
  size_t at = 1;
  auto str = [&] {
    std::string s(reinterpret_cast<const char*>(config_.data() + at));
    at += s.size() + 1;
    return s;
  };
  auto i16 = [&] {
    int v = int16_t(config_[at] | (config_[at + 1] << 8));
    at += 2;
    return v;
  };
  EXPECT_EQ(str(), "Pioneer");
  EXPECT_EQ(str(), "p3dx-sh");
  str();
  ++at;
  int rot_top = i16(), trans_top = i16();
  EXPECT_NEAR(rot_top, robot_->robot().max_turn_rate * 180 / kPi, 1);
  EXPECT_NEAR(trans_top, robot_->robot().max_speed * 1000, 1);
  EXPECT_EQ(robot_->line_baud(), 38400u);
}

TEST_F(AriaClient, MoveDrivesTheDistanceUnderTheLimits) {
  connect();
  ASSERT_FALSE(HasFatalFailure());
  send(bytes(command_int(Command::Move, 300)));
  until_still(10'000 * kMs);
  EXPECT_NEAR(robot_->pose().x, 0.3, 0.002);
  EXPECT_NEAR(robot_->pose().y, 0, 0.002);
  EXPECT_LE(max_v_, 0.4 + 1e-9) << "faster than SETV 400";
  EXPECT_LE(max_dv_, 0.3 * 0.01 + 1e-9) << "accelerated beyond SETA 300 in a 10 ms step";
  // The SIP's odometry says the same (x counts are mm on a p3dx-sh).
  packets();
  Bytes sip = ask(bytes(drivers::p2os::command(Command::Pulse)), 0x32);
  ASSERT_GT(sip.size(), 6u);
  EXPECT_NEAR(sip[1] | (sip[2] << 8), 300, 2);
}

TEST_F(AriaClient, HeadAndDheadTurnToTheHeading) {
  connect();
  ASSERT_FALSE(HasFatalFailure());
  send(bytes(command_int(Command::Head, 90)));
  until_still(10'000 * kMs);
  EXPECT_NEAR(robot_->pose().a, kPi / 2, 0.002);
  EXPECT_LE(max_w_, 60 * kPi / 180 + 1e-9) << "faster than SETRV 60";
  send(bytes(command_int(Command::DHead, -45)));
  until_still(10'000 * kMs);
  EXPECT_NEAR(robot_->pose().a, kPi / 4, 0.002);
  // HEAD takes the short way round: from 45 to -90 degrees is a right turn.
  send(bytes(command_int(Command::Head, -90)));
  until_still(10'000 * kMs);
  EXPECT_NEAR(std::remainder(robot_->pose().a, 2 * kPi), -kPi / 2, 0.002);
  EXPECT_NEAR(robot_->pose().x, 0, 0.002);
}

TEST_F(AriaClient, StopAndEstopEndAMove) {
  connect();
  ASSERT_FALSE(HasFatalFailure());
  send(bytes(command_int(Command::Move, 2000)));
  run(1000 * kMs);
  send(bytes(drivers::p2os::command(Command::EStop)));
  run(20 * kMs);
  EXPECT_EQ(robot_->motion().v(), 0);
  EXPECT_LT(robot_->pose().x, 1.0);
}

TEST_F(AriaClient, UnmodelledCommandsAreCountedNotObeyed) {
  connect();
  ASSERT_FALSE(HasFatalFailure());
  send(bytes(command_int(Command::Gyro, 1)));
  send(bytes(command_int(Command::Gyro, 1)));
  send(bytes(command_int(Command::Say, 1)));
  run(50 * kMs);
  EXPECT_EQ(robot_->unmodelled(), 3u);
  // The robot goes on serving.
  packets();
  EXPECT_FALSE(ask(bytes(drivers::p2os::command(Command::Pulse)), 0x32).empty());
  send(kClose1);
  run(20 * kMs);
  EXPECT_EQ(robot_->session(), PioneerEmulator::Session::WaitSync0);
}

}  // namespace
}  // namespace troupe::emulators
