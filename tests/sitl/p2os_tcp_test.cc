// troupe-sim --p2os-tcp, as an ARIA program written for MobileSim finds it,
// and as a hundred of them driving a swarm find it:
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

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>
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
  int fd() const { return fd_; }
  void send(const drivers::p2os::Packet& p) { ASSERT_EQ(::send(fd_, p.view().data(), p.size, MSG_NOSIGNAL), ssize_t(p.size)); }
  // One read of what has arrived, each packet's payload handed to `on`
  // until it returns true. False when the connection is gone.
  template <typename On>
  bool take(On&& on, bool& done) {
    uint8_t buf[1024];
    ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) return false;
    drivers::p2os::scan_packets(scanner_, std::span<const uint8_t>(buf, size_t(n)),
                                [&](std::span<const uint8_t> payload) {
                                  if (!done) done = on(Bytes(payload.begin(), payload.end()));
                                });
    return true;
  }
  // Reads for up to `ms`, handing each packet's payload to `on`; stops
  // early when `on` returns true.
  template <typename On>
  bool read(int ms, On&& on) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    bool done = false;
    while (std::chrono::steady_clock::now() < end) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 20) <= 0) continue;
      if (!take(on, done)) return false;
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


// A fleet of P2OS clients, one a robot, served together: what one ARIA
// program a robot does when a hundred of them drive a swarm.
class Fleet {
 public:
  explicit Fleet(size_t n) : robots_(n) {}
  P2osTcpClient& operator[](size_t i) { return robots_[i]; }
  size_t size() const { return robots_.size(); }
  // Sends `p` to every robot until each answers with a packet of `type`
  // (resent each second, as ARIA's connect does); the answers.
  std::vector<Bytes> ask(const drivers::p2os::Packet& p, uint8_t type) {
    std::vector<Bytes> replies(size());
    for (int attempt = 0; attempt < 10; ++attempt) {
      for (size_t i = 0; i < size(); ++i) {
        if (replies[i].empty()) robots_[i].send(p);
      }
      read_all(1000, [&](size_t i, const Bytes& b) {
        if (replies[i].empty() && b[0] == type) replies[i] = b;
        return !replies[i].empty();
      });
      if (std::none_of(replies.begin(), replies.end(), [](const Bytes& r) { return r.empty(); })) break;
    }
    return replies;
  }
  void send_all(const drivers::p2os::Packet& p) {
    for (P2osTcpClient& r : robots_) r.send(p);
  }
  // Reads every robot for up to `ms`, handing robot i's payloads to
  // on(i, payload) until it returns true for that robot; true when it did
  // for every robot.
  template <typename On>
  bool read_all(int ms, On&& on) {
    std::vector<bool> done(size(), false);
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (std::chrono::steady_clock::now() < end) {
      std::vector<pollfd> fds;
      std::vector<size_t> who;
      for (size_t i = 0; i < size(); ++i) {
        if (done[i]) continue;
        fds.push_back({robots_[i].fd(), POLLIN, 0});
        who.push_back(i);
      }
      if (fds.empty()) return true;
      if (poll(fds.data(), fds.size(), 20) <= 0) continue;
      for (size_t k = 0; k < fds.size(); ++k) {
        if (!(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
        const size_t i = who[k];
        bool robot_done = false;
        if (!robots_[i].take([&](const Bytes& b) { return on(i, b); }, robot_done)) return false;
        done[i] = robot_done;
      }
    }
    return std::all_of(done.begin(), done.end(), [](bool d) { return d; });
  }

 private:
  std::vector<P2osTcpClient> robots_;
};

// troupe-sim --p2os-tcp on swarm100.world: a hundred Pioneers, each on its
// own port, each found by its name, turned by its own client and reading
// its own sonar, as a hundred ARIA programs would.
TEST(P2osTcpSwarm, EveryRobotIsAPioneerOnItsOwnPortAndObeysItsOwnClient) {
  const std::string dir = testing::make_temp_dir("p2os-tcp-swarm");
  testing::ChildProcess sim;
  std::string error;
  // Port 0: every robot's port chosen by the kernel, so no range of 100
  // ports need be free.
  ASSERT_TRUE(sim.start({TROUPE_SIM_BIN, std::string(TROUPE_SOURCE_DIR) + "/examples/worlds/swarm100.world", "--port",
                         "0", "--no-ctrl", "--no-view", "--p2os-tcp=0"},
                        dir, "troupe-sim", error))
      << error;
  ASSERT_TRUE(sim.wait_for("listening on 127.0.0.1:", false, kWaitMs)) << sim.err();
  ASSERT_TRUE(sim.wait_for("b99 p2os-tcp 127.0.0.1:", false, kWaitMs)) << sim.out() << sim.err();
  std::vector<std::pair<std::string, uint16_t>> served;  // robot name, its P2OS port
  std::istringstream lines(sim.out());
  for (std::string line; std::getline(lines, line);) {
    const size_t at = line.find(" p2os-tcp 127.0.0.1:");
    if (at != std::string::npos) served.emplace_back(line.substr(0, at), uint16_t(std::stoi(line.substr(at + 20))));
  }
  ASSERT_EQ(served.size(), 100u);
  const std::string out = sim.out();
  const uint16_t sim_port = uint16_t(std::stoi(out.substr(out.find("listening on 127.0.0.1:") + 23)));

  Fleet fleet(served.size());
  for (size_t i = 0; i < served.size(); ++i) ASSERT_TRUE(fleet[i].connect(served[i].second)) << served[i].first;
  for (const Bytes& r : fleet.ask(command(Command::Sync0), 0)) ASSERT_EQ(r, Bytes{0});
  for (const Bytes& r : fleet.ask(command(Command::Sync1), 1)) ASSERT_EQ(r, Bytes{1});
  const std::vector<Bytes> ids = fleet.ask(command(Command::Sync2), 2);
  for (size_t i = 0; i < ids.size(); ++i) {
    ASSERT_GT(ids[i].size(), 3u) << served[i].first;
    EXPECT_STREQ(reinterpret_cast<const char*>(ids[i].data() + 1), served[i].first.c_str());
  }
  fleet.send_all(command_int(Command::Open, 1));
  fleet.send_all(command_int(Command::Enable, 1));

  client::Client::Options o;
  o.name = "p2os-tcp-swarm-test";
  o.reconnect = false;
  client::Client sim_client("127.0.0.1", sim_port, o);
  ASSERT_TRUE(sim_client.connect()) << sim_client.error();
  client::SimulationProxy simulation(sim_client);
  auto heading = [&](const std::string& name) {
    client::Pose2 p;
    EXPECT_TRUE(simulation.get_pose(name, p)) << name << ": " << sim_client.error();
    return p.a;
  };
  std::vector<double> start;
  for (const auto& [name, port] : served) start.push_back(heading(name));

  // Each robot turns a different amount, so that no robot can pass by
  // obeying a neighbour's command.
  for (size_t i = 0; i < fleet.size(); ++i) fleet[i].send(command_int(Command::DHead, 10 + int(i % 8) * 10));
  // Pulsing as ARIA's cycle does (the robots' watchdogs stop a robot whose
  // client goes quiet) until every robot's true heading has turned as far
  // as its client asked and its SIPs say it is still (type 0x32, twice in a
  // row: a controller that hunts round its target never says so); every
  // SIP's sonar readings kept meanwhile.
  auto want = [](size_t i) { return (10 + int(i % 8) * 10) * kPi / 180; };
  auto turned = [&](size_t i) { return std::remainder(heading(served[i].first) - start[i], 2 * kPi); };
  std::vector<std::map<int, int>> sonar(fleet.size());  // transducer -> range, mm
  std::vector<bool> there(fleet.size(), false);
  std::vector<int> still(fleet.size(), 0);  // SIPs in a row that said "still"
  auto settled = [&](size_t i) { return there[i] && still[i] >= 2; };
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(kWaitMs);
  auto all_settled = [&] {
    for (size_t i = 0; i < fleet.size(); ++i) {
      if (!settled(i)) return false;
    }
    return true;
  };
  while (!all_settled() && std::chrono::steady_clock::now() < end) {
    fleet.send_all(command(Command::Pulse));
    fleet.read_all(200, [&](size_t i, const Bytes& b) {
      if ((b[0] == 0x32 || b[0] == 0x33) && b.size() > 20) {
        for (int k = 0; k < b[19]; ++k) sonar[i][b[20 + 3 * k]] = b[21 + 3 * k] | (b[22 + 3 * k] << 8);
        still[i] = b[0] == 0x32 ? still[i] + 1 : 0;
      }
      return false;  // read every robot for the whole 200 ms
    });
    for (size_t i = 0; i < fleet.size(); ++i) {
      if (!there[i]) there[i] = std::fabs(turned(i) - want(i)) < 0.05;
    }
  }
  for (size_t i = 0; i < fleet.size(); ++i) {
    const std::string& name = served[i].first;
    EXPECT_NEAR(turned(i), want(i), 0.05) << name;
    EXPECT_GE(still[i], 2) << name << " never said it stopped";
    // The Pioneer's ring of 16: the swarmbot's eight 1 m sonars fill the
    // first eight, the rest never see an echo.
    ASSERT_EQ(sonar[i].size(), 16u) << name;
    for (const auto& [transducer, mm] : sonar[i]) {
      if (transducer < 8) {
        EXPECT_LE(mm, 1000) << name << " sonar " << transducer;
      } else {
        EXPECT_GT(mm, 1000) << name << " sonar " << transducer;
      }
    }
  }
  sim.stop();
  testing::remove_tree(dir);
}

}  // namespace
}  // namespace troupe::sitl
