// troupe-sim --p2os-tcp, as an ARIA program written for MobileSim finds it:
// a scripted P2OS client on a real TCP connection (what ARIA's ArRobot and
// ArSimulatedLaser send) handshakes with robot r0 of sitl_room.world, reads
// its configuration, sonar and laser (MobileSim's 0x61 packets), drives it
// with MOVE and HEAD, and the simulator's ground truth shows the robot went
// where it was told.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "drivers/p2os/p2os_protocol.h"
#include "host-sim/emulators/serial_line/room.h"
#include "tests/support/child_process.h"
#include "wire/client/proxies.h"

namespace troupe::sitl {
namespace {

using drivers::p2os::Command;
using drivers::p2os::command;
using drivers::p2os::command_int;
using Bytes = std::vector<uint8_t>;

constexpr double kPi = 3.14159265358979323846;
// Bounds a wait for something that must happen (hangs, not speed).
constexpr int kWaitMs = 60000;
// sitl_room.world: walls' inner faces at +-2.95 m; the laser 0.16 m ahead.
const emulators::Room kRoom{2.95, 2.95};
constexpr double kLaserX = 0.16;

// A P2OS client on TCP: packets out, payloads in.
class P2osTcpClient {
 public:
  ~P2osTcpClient() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool connect(uint16_t port) {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return fd_ >= 0 && ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  void send(const drivers::p2os::Packet& p) { ASSERT_EQ(::send(fd_, p.view().data(), p.size, MSG_NOSIGNAL), ssize_t(p.size)); }
  // Reads for up to `ms`, handing each packet's payload to `on`; stops
  // early when `on` returns true.
  template <typename On>
  bool read(int ms, On&& on) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 20) <= 0) continue;
      uint8_t buf[1024];
      ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) return false;
      bool done = false;
      drivers::p2os::scan_packets(scanner_, std::span<const uint8_t>(buf, size_t(n)),
                                  [&](std::span<const uint8_t> payload) {
                                    if (!done) done = on(Bytes(payload.begin(), payload.end()));
                                  });
      if (done) return true;
    }
    return false;
  }
  // Sends `p` until a packet of `type` answers it.
  Bytes ask(const drivers::p2os::Packet& p, uint8_t type) {
    Bytes reply;
    for (int i = 0; i < 10 && reply.empty(); ++i) {
      send(p);
      read(1000, [&](const Bytes& b) {
        if (b[0] == type) reply = b;
        return !reply.empty();
      });
    }
    return reply;
  }

 private:
  int fd_ = -1;
  drivers::p2os::PacketScanner scanner_;
};

class P2osTcp : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::make_temp_dir("p2os-tcp");
    const uint16_t base = testing::free_port();
    std::string error;
    ASSERT_TRUE(sim_.start({TROUPE_SIM_BIN, std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/sitl_room.world",
                            "--port", "0", "--no-ctrl", "--no-view", "--p2os-tcp=" + std::to_string(base)},
                           dir_, "troupe-sim", error))
        << error;
    ASSERT_TRUE(sim_.wait_for("r0 p2os-tcp 127.0.0.1:" + std::to_string(base), false, kWaitMs)) << logs();
    ASSERT_TRUE(sim_.wait_for("listening on 127.0.0.1:", false, kWaitMs)) << logs();
    const std::string out = sim_.out();
    sim_port_ = uint16_t(std::stoi(out.substr(out.find("listening on 127.0.0.1:") + 23)));
    ASSERT_TRUE(robot_.connect(base)) << "no P2OS server on port " << base;
  }
  void TearDown() override {
    sim_.stop();
    testing::remove_tree(dir_);
  }
  std::string logs() const { return sim_.out() + sim_.err(); }

  void connect_sim() {
    client::Client::Options o;
    o.name = "p2os-tcp-test";
    o.reconnect = false;
    sim_client_ = std::make_unique<client::Client>("127.0.0.1", sim_port_, o);
    ASSERT_TRUE(sim_client_->connect()) << sim_client_->error();
    simulation_ = std::make_unique<client::SimulationProxy>(*sim_client_);
  }
  client::Pose2 truth() {
    client::Pose2 p;
    EXPECT_TRUE(simulation_->get_pose("r0", p)) << sim_client_->error();
    return p;
  }
  // Pulses as ARIA's cycle does until the SIPs say the robot is still
  // (type 0x32) twice in a row.
  void until_still() {
    int still = 0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(kWaitMs);
    while (still < 2 && std::chrono::steady_clock::now() < end) {
      robot_.send(command(Command::Pulse));
      robot_.read(200, [&](const Bytes& b) {
        if (b[0] == 0x32) ++still;
        if (b[0] == 0x33) still = 0;
        return still >= 2;
      });
    }
    ASSERT_GE(still, 2) << "the robot never stopped\n" << logs();
  }

  std::string dir_;
  testing::ChildProcess sim_;
  uint16_t sim_port_ = 0;
  P2osTcpClient robot_;
  std::unique_ptr<client::Client> sim_client_;
  std::unique_ptr<client::SimulationProxy> simulation_;
};

TEST_F(P2osTcp, AriaDrivesTheSimulatedRobotAndReadsItsSonarAndLaser) {
  // ARIA's handshake.
  ASSERT_EQ(robot_.ask(command(Command::Sync0), 0), Bytes{0});
  ASSERT_EQ(robot_.ask(command(Command::Sync1), 1), Bytes{1});
  Bytes id = robot_.ask(command(Command::Sync2), 2);
  ASSERT_GT(id.size(), 3u);
  EXPECT_STREQ(reinterpret_cast<const char*>(id.data() + 1), "r0");
  robot_.send(command_int(Command::Open, 1));
  ASSERT_FALSE(robot_.ask(command_int(Command::Config, 1), 0x20).empty()) << logs();
  robot_.send(command_int(Command::Enable, 1));
  robot_.send(command_int(Command::SetV, 400));
  robot_.send(command_int(Command::SetRv, 60));
  // ArSimulatedLaser: field of view, step x 100, then on with extended packets.
  robot_.send(command_int(Command(36), -90));
  robot_.send(command_int(Command(37), 90));
  robot_.send(command_int(Command(38), 100));
  robot_.send(command_int(Command(35), 2));

  // A whole scan arrives in 0x61 packets, and sonar readings in the SIPs.
  std::map<int, uint16_t> laser;  // reading index -> range, mm
  std::map<int, uint16_t> sonar;  // transducer -> range, mm
  int total = 0;
  ASSERT_TRUE(robot_.read(kWaitMs, [&](const Bytes& b) {
    if (b[0] == 0x61) {
      total = b[1] | (b[2] << 8);
      int first = b[3] | (b[4] << 8), n = b[5];
      for (int i = 0; i < n; ++i) laser[first + i] = uint16_t(b[6 + 5 * i] | (b[7 + 5 * i] << 8));
    } else if ((b[0] == 0x32 || b[0] == 0x33) && b.size() > 20) {
      for (int i = 0; i < b[19]; ++i) sonar[b[20 + 3 * i]] = uint16_t(b[21 + 3 * i] | (b[22 + 3 * i] << 8));
    }
    return total > 0 && int(laser.size()) == total && sonar.size() == 16;
  })) << "laser readings " << laser.size() << " of " << total << ", sonar " << sonar.size() << "\n"
      << logs();
  EXPECT_EQ(total, 181);

  connect_sim();
  ASSERT_FALSE(HasFatalFailure());
  const client::Pose2 start = truth();
  // The laser's middle beam reads the east wall from the true pose.
  EXPECT_NEAR(laser[90] / 1000.0, kRoom.range(start.x + kLaserX, start.y, start.a), 0.05);
  // The front sonar (transducers 3 and 4, +-10 degrees) sees it too.
  EXPECT_GT(sonar[3], 1000);

  // MOVE 500 mm, then HEAD 90 degrees: the ground truth follows.
  robot_.send(command_int(Command::Move, 500));
  until_still();
  const client::Pose2 moved = truth();
  EXPECT_NEAR(moved.x - start.x, 0.5, 0.03) << logs();
  EXPECT_NEAR(moved.y, start.y, 0.03);
  robot_.send(command_int(Command::Head, 90));
  until_still();
  const client::Pose2 turned = truth();
  EXPECT_NEAR(std::remainder(turned.a - start.a, 2 * kPi), kPi / 2, 0.05) << logs();
  EXPECT_NEAR(turned.x, moved.x, 0.03);
}

}  // namespace
}  // namespace troupe::sitl
