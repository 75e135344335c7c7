// The Pioneer emulator as a P2OS client sees it, through its pty, on the
// emulator's own clock (step() is given the time, so "every 100 ms" and
// "after 2 s" are checked exactly, not timed).
#include "host-sim/emulators/p2os/pioneer_emulator.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <vector>

#include "tests/device_harness/device_harness.h"
#include "tests/device_harness/raw_port.h"

namespace troupe::emulators {
namespace {

using drivers::p2os::Command;
using drivers::p2os::Packet;
using Bytes = std::vector<uint8_t>;

constexpr uint64_t kMs = 1000;

// The client's end of the pty, speaking P2OS packets.
class RawPort : public testing::RawPort {
 public:
  using testing::RawPort::RawPort;
  void write(std::span<const uint8_t> bytes) { ASSERT_TRUE(testing::RawPort::write(bytes)); }
  void send(const Packet& p) { write(p.view()); }
  // Every packet that has arrived, as payloads.
  std::vector<Bytes> packets() {
    std::vector<Bytes> out;
    Bytes bytes = read_all();
    drivers::p2os::scan_packets(scanner_, bytes,
                                [&](std::span<const uint8_t> p) { out.emplace_back(p.begin(), p.end()); });
    return out;
  }

 private:
  drivers::p2os::PacketScanner scanner_;
};

class PioneerEmulatorTest : public ::testing::Test {
 protected:
  void start(PioneerEmulator::Config config = {}, PioneerWorld* world = nullptr) {
    robot_ = std::make_unique<PioneerEmulator>(config, world);
    std::string error;
    ASSERT_TRUE(robot_->open(dir_.file("pioneer"), error)) << error;
    port_ = std::make_unique<RawPort>(robot_->path(), B9600);
    ASSERT_TRUE(port_->ok());
    step(0);
  }
  // Advances the emulator's clock by `dt_us` in 10 ms steps.
  void step(uint64_t dt_us) {
    uint64_t end = now_ + dt_us;
    do {
      now_ = std::min(end, now_ + 10 * kMs);
      robot_->step(now_);
    } while (now_ < end);
  }
  // SYNC0..2 and OPEN, as a tidy client does it.
  void open_session() {
    for (Command c : {Command::Sync0, Command::Sync1, Command::Sync2}) {
      port_->send(drivers::p2os::command(c));
      step(10 * kMs);
    }
    port_->packets();  // the handshake replies
    port_->send(drivers::p2os::command(Command::Open));
    step(0);
    ASSERT_EQ(robot_->session(), PioneerEmulator::Session::Open);
  }
  std::vector<drivers::p2os::Sip> sips() {
    std::vector<drivers::p2os::Sip> out;
    for (const Bytes& p : port_->packets()) {
      drivers::p2os::Sip s;
      if (drivers::p2os::parse_sip(p, s, nullptr)) out.push_back(s);
    }
    return out;
  }

  testing::TempDir dir_;
  std::unique_ptr<PioneerEmulator> robot_;
  std::unique_ptr<RawPort> port_;
  uint64_t now_ = 1'000'000;
};

TEST_F(PioneerEmulatorTest, HandshakeCopesWithAnUntidyClient) {
  start();
  // A modem wake-up string and a CLOSE sent at another baud: neither frames.
  const uint8_t wake[] = {'W', 'M', 'S', '2', '\r'};
  port_->write(wake);
  port_->set_speed(B19200);
  port_->send(drivers::p2os::command(Command::Close));
  step(10 * kMs);
  port_->set_speed(B9600);
  EXPECT_TRUE(port_->packets().empty());
  // SYNC0 twice (the first reply "lost"), then on.
  port_->send(drivers::p2os::command(Command::Sync0));
  step(10 * kMs);
  port_->send(drivers::p2os::command(Command::Sync0));
  step(10 * kMs);
  std::vector<Bytes> replies = port_->packets();
  ASSERT_EQ(replies.size(), 2u);
  EXPECT_EQ(replies[0], (Bytes{0}));
  EXPECT_EQ(replies[1], (Bytes{0}));
  port_->send(drivers::p2os::command(Command::Sync1));
  step(10 * kMs);
  port_->send(drivers::p2os::command(Command::Sync2));
  step(10 * kMs);
  replies = port_->packets();
  ASSERT_EQ(replies.size(), 2u);
  EXPECT_EQ(replies[0], (Bytes{1}));
  drivers::p2os::RobotIdentity id;
  ASSERT_TRUE(drivers::p2os::parse_sync2(replies[1], id));
  EXPECT_STREQ(id.name, "Troupe");
  EXPECT_STREQ(id.robot_class, "Pioneer");
  EXPECT_STREQ(id.subclass, "p3dx-sh");
  EXPECT_EQ(robot_->session(), PioneerEmulator::Session::Ready);
}

TEST_F(PioneerEmulatorTest, AnOutOfOrderSyncStartsOverSilently) {
  start();
  port_->send(drivers::p2os::command(Command::Sync0));
  step(10 * kMs);
  port_->send(drivers::p2os::command(Command::Sync2));  // SYNC1 skipped
  step(10 * kMs);
  EXPECT_EQ(port_->packets().size(), 1u);  // only the SYNC0 echo
  EXPECT_EQ(robot_->session(), PioneerEmulator::Session::WaitSync0);
}

TEST_F(PioneerEmulatorTest, SendsASipEveryHundredMilliseconds) {
  start();
  open_session();
  EXPECT_EQ(robot_->sips_sent(), 1u);  // the first at once
  step(1000 * kMs);
  EXPECT_EQ(robot_->sips_sent(), 11u);
  std::vector<drivers::p2os::Sip> got = sips();
  ASSERT_EQ(got.size(), 11u);
  EXPECT_EQ(got.back().type, 0x32);      // stopped
  EXPECT_EQ(got.back().battery, 125);    // 12.5 V
  EXPECT_EQ(got.back().sonar_count, 4);  // the ring fires by default once open
}

TEST_F(PioneerEmulatorTest, MotorsMoveOnlyWhenEnabled) {
  start();
  open_session();
  port_->send(drivers::p2os::vel2(10, 10));  // 200 mm/s each wheel
  step(500 * kMs);
  EXPECT_EQ(robot_->left_mps(), 0);
  port_->send(drivers::p2os::command_int(Command::Enable, 1));
  step(100 * kMs);
  port_->send(drivers::p2os::vel2(10, 10));
  step(500 * kMs);
  EXPECT_NEAR(robot_->left_mps(), 0.2, 1e-9);
  EXPECT_NEAR(robot_->right_mps(), 0.2, 1e-9);
  EXPECT_GT(robot_->pose().x, 0.05);
  std::vector<drivers::p2os::Sip> got = sips();
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back().type, 0x33);  // moving
  EXPECT_EQ(got.back().left_vel, 200);
}

TEST_F(PioneerEmulatorTest, WatchdogStopsTheMotorsWhenNothingArrives) {
  start();
  open_session();
  port_->send(drivers::p2os::command_int(Command::Enable, 1));
  port_->send(drivers::p2os::command_int(Command::Vel, 300));
  step(1000 * kMs);
  EXPECT_NEAR(robot_->left_mps(), 0.3, 1e-9);
  // Pulses keep it going past the watchdog time...
  for (int i = 0; i < 3; ++i) {
    port_->send(drivers::p2os::command(Command::Pulse));
    step(1000 * kMs);
  }
  EXPECT_FALSE(robot_->watchdog_tripped());
  EXPECT_NEAR(robot_->left_mps(), 0.3, 1e-9);
  // ...silence does not (a second of it has passed already).
  step(900 * kMs);
  EXPECT_FALSE(robot_->watchdog_tripped());
  step(200 * kMs);
  EXPECT_TRUE(robot_->watchdog_tripped());
  EXPECT_EQ(robot_->target_left_mps(), 0);
  step(1000 * kMs);
  EXPECT_EQ(robot_->left_mps(), 0);
}

TEST_F(PioneerEmulatorTest, AtAnotherBaudEachSideHearsOnlyGarbage) {
  PioneerEmulator::Config config;
  config.baud = 38400;
  start(config);
  port_->send(drivers::p2os::command(Command::Sync0));
  step(10 * kMs);
  EXPECT_TRUE(port_->packets().empty());
  EXPECT_EQ(robot_->session(), PioneerEmulator::Session::WaitSync0);
  port_->set_speed(B38400);
  port_->send(drivers::p2os::command(Command::Sync0));
  step(10 * kMs);
  EXPECT_EQ(port_->packets().size(), 1u);
}

class FixedRanges : public PioneerWorld {
 public:
  void sense(const PioneerPose&, const drivers::p2os::RobotParams& robot, PioneerSenses& s) override {
    for (size_t i = 0; i < robot.sonar_count; ++i) s.sonar_m[i] = 0.5f + 0.25f * float(i);
    s.battery_v = 11.8f;
    s.front_bumpers = 0x03;
  }
};

TEST_F(PioneerEmulatorTest, SonarReadingsGoRoundTheRing) {
  FixedRanges world;
  start({}, &world);
  open_session();
  step(300 * kMs);
  std::vector<drivers::p2os::Sip> got = sips();
  ASSERT_EQ(got.size(), 4u);
  int expected = 0;
  for (const auto& s : got) {
    ASSERT_EQ(s.sonar_count, 4);
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(s.sonar[k].index, expected % 16);
      // Ranges beyond the sonar's 5 m read as 5 m.
      EXPECT_EQ(s.sonar[k].range, std::min(5000, 500 + 250 * (expected % 16)));
      ++expected;
    }
    EXPECT_EQ(s.battery, 118);
    EXPECT_EQ(s.front_bumpers, 0x03);
  }
  port_->send(drivers::p2os::command_int(Command::Sonar, 0));
  step(100 * kMs);
  got = sips();
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back().sonar_count, 0);
}

TEST_F(PioneerEmulatorTest, SetoRestartsTheCounters) {
  start();
  open_session();
  robot_->set_pose({1.234, -0.5, 1.0});
  step(100 * kMs);
  std::vector<drivers::p2os::Sip> got = sips();
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back().x, 1234);
  EXPECT_EQ(got.back().y, uint16_t(-500 & 0x7FFF));
  EXPECT_EQ(got.back().heading, std::lround(1.0 / 0.001534));
  port_->send(drivers::p2os::command(Command::SetO));
  step(100 * kMs);
  got = sips();
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back().x, 0);
  EXPECT_EQ(got.back().heading, 0);
}

TEST_F(PioneerEmulatorTest, VanishesAndComesBackUnderTheSameName) {
  start();
  open_session();
  robot_->vanish();
  EXPECT_NE(access(dir_.file("pioneer").c_str(), F_OK), 0);
  // The client's end hangs up: a read sees end of file.
  uint8_t byte = 0;
  EXPECT_EQ(port_->read_once(&byte, 1), 0);
  std::string error;
  ASSERT_TRUE(robot_->reappear(error)) << error;
  char target[128] = {};
  ASSERT_GT(readlink(dir_.file("pioneer").c_str(), target, sizeof target - 1), 0);
  EXPECT_EQ(std::string(target), robot_->port().slave_path());
  // The robot kept its session: the port, opened again, hears SIPs at once.
  port_ = std::make_unique<RawPort>(robot_->path(), B9600);
  step(200 * kMs);
  EXPECT_EQ(robot_->session(), PioneerEmulator::Session::Open);
  EXPECT_FALSE(sips().empty());
}

}  // namespace
}  // namespace troupe::emulators
