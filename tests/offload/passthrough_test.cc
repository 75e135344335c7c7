// The passthrough driver between real troupe-node processes over loopback
// TCP: a "robot" node with the kinematic driver, a "desktop" node serving its
// device under another address, and a client on the desktop. The robot is
// killed and restarted; a remote that never answers must not stall the
// desktop.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <functional>
#include <string>

#include "tests/support/child_process.h"
#include "wire/client/proxies.h"

namespace troupe::testing {
namespace {

using client::Client;
using client::Position2dProxy;
using client::Reply;

const std::string kNode = std::string(TROUPE_BINARY_DIR) + "/bin/troupe-node";
constexpr double kDeadlineS = 30;  // bounds a failing test only

// Spins the client until `done` or the deadline.
bool spin_until(Client& c, const std::function<bool()>& done, double timeout_s = kDeadlineS) {
  auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    c.spin_once(20);
  }
  return true;
}

std::string robot_config() {
  return R"({ "name": "robot", "drivers": [ { "driver_type": "kinematic",
    "driver": { "max_speed": 1.0, "max_accel": 2.0, "rate_hz": 20 }, "provides": ["position2d:0"] } ] })";
}

// A desktop forwarding `remote` of `host`:`port` as `local`, with a status
// device opaque:0.
std::string passthrough_config(const std::string& name, uint16_t port, const std::string& remote,
                               const std::string& local, const std::string& extra = "",
                               const std::string& host = "127.0.0.1") {
  return R"({ "name": ")" + name + R"(", "drivers": [ { "driver_type": "passthrough",
    "driver": { "host": ")" + host + R"(", "port": )" +
         std::to_string(port) + R"(, "remote": [")" + remote + R"("],
                "backoff_min": 0.05, "backoff_max": 0.5)" +
         extra + R"( },
    "provides": [")" +
         local + R"(", "opaque:0"] } ] })";
}

class Passthrough : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = make_temp_dir("troupe-passthrough-");
    ASSERT_FALSE(dir_.empty());
  }
  void TearDown() override {
    for (ChildProcess* p : {&robot_, &desktop_, &middle_}) p->stop();
    if (HasFailure()) {
      for (const char* log : {"robot.log", "middle.log", "desktop.log"}) {
        std::string text = read_text(dir_ + "/" + log);
        if (!text.empty()) std::fprintf(stderr, "---- %s\n%s", log, text.c_str());
      }
    }
    remove_tree(dir_);
  }

  // Starts troupe-node with `json` on `port` and waits until it listens
  // (on 127.0.0.1; with `listen` given, on that address, and no waiting).
  void start_node(ChildProcess& p, const std::string& name, const std::string& json, uint16_t port,
                  const std::string& listen = "") {
    std::string path = dir_ + "/" + name + ".json";
    FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(json.c_str(), f);
    std::fclose(f);
    std::string error;
    std::vector<std::string> args = {kNode, path, "--port", std::to_string(port), "--log-level", "debug"};
    if (!listen.empty()) args.insert(args.end(), {"--listen", listen});
    ASSERT_TRUE(p.start_logged(args, dir_ + "/" + name + ".log", error)) << error;
    if (listen.empty()) {
      ASSERT_TRUE(wait_for_listener(port, kDeadlineS)) << name << " does not listen on " << port;
    }
  }

  // Connects `c` and follows the status device's text into status_.
  void watch_status(Client& c) {
    ASSERT_TRUE(c.connect(5000)) << c.error();
    c.add_data_handler([this](const wire::Message& m) {
      const wire::OpaqueBytes* o = m.body_as_OpaqueBytes();
      if (o != nullptr && o->bytes() != nullptr) status_.assign(o->bytes()->begin(), o->bytes()->end());
    });
    ASSERT_TRUE(c.open(kStatus)) << c.error();
  }
  bool status_has(const std::string& s) const { return status_.find(s) != std::string::npos; }

  const wire::Address kStatus{0, uint16_t(wire::Interface::Opaque), 0};
  std::string dir_;
  std::string status_;
  ChildProcess robot_, middle_, desktop_;
  uint16_t robot_port_ = free_port();
  uint16_t desktop_port_ = free_port();
};

TEST_F(Passthrough, ForwardsDataCommandsAndRequestsUnderTheLocalAddress) {
  start_node(robot_, "robot", robot_config(), robot_port_);
  start_node(desktop_, "desktop", passthrough_config("desktop", robot_port_, "position2d:0", "position2d:3"),
             desktop_port_);
  Client c("127.0.0.1", desktop_port_);
  watch_status(c);
  ASSERT_TRUE(spin_until(c, [&] { return status_has("\"state\":\"connected\""); })) << status_;

  // Remap: the desktop lists position2d:3, not the robot's address.
  std::vector<client::DeviceEntry> list;
  ASSERT_TRUE(c.device_list(list));
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].addr, client::address_of(wire::Interface::Position2d, 3));
  EXPECT_EQ(list[0].driver, "passthrough");

  Position2dProxy pos(c, 3);
  ASSERT_TRUE(pos.is_open()) << c.error();
  ASSERT_TRUE(spin_until(c, [&] { return pos.samples() >= 3; })) << "no data through the passthrough";
  EXPECT_NEAR(pos.x(), 0.0, 1e-6);

  // Commands reach the robot's kinematic driver: the pose read back moves.
  ASSERT_TRUE(pos.set_velocity(0.5f, 0, 0));
  ASSERT_TRUE(spin_until(c, [&] { return pos.x() > 0.2f; })) << "x stayed at " << pos.x();
  ASSERT_TRUE(pos.set_velocity(0, 0, 0));

  // A request and its reply body come back, addressed from the local device.
  Reply r = c.request(pos.address(), uint8_t(wire::Position2dReqSub::Geometry));
  ASSERT_TRUE(r.ok()) << r.text;
  EXPECT_EQ(r.message()->header()->addr(), pos.address());
  ASSERT_NE(r.message()->body_as_Position2dGeometry(), nullptr);

  // SetOdometry with its body reaches the robot: the pose jumps there.
  ASSERT_TRUE(pos.set_odometry(5.0f, -2.0f, 1.0f)) << c.error();
  ASSERT_TRUE(spin_until(c, [&] { return std::abs(pos.y() + 2.0f) < 0.05f; })) << pos.x() << " " << pos.y();

  // The robot's refusal comes back as it was.
  r = c.request(pos.address(), 77);
  EXPECT_EQ(r.status, Reply::Status::Nack);
  EXPECT_EQ(r.code, wire::ErrorCode::Unsupported) << r.text;
}

TEST_F(Passthrough, ReconnectsWhenTheRemoteIsRestartedAndClientsStayConnected) {
  start_node(robot_, "robot", robot_config(), robot_port_);
  start_node(desktop_, "desktop", passthrough_config("desktop", robot_port_, "position2d:0", "position2d:0"),
             desktop_port_);
  Client c("127.0.0.1", desktop_port_);
  watch_status(c);
  Position2dProxy pos(c, 0);
  ASSERT_TRUE(spin_until(c, [&] { return pos.samples() >= 3; }));

  robot_.kill_hard();
  ASSERT_TRUE(spin_until(c, [&] { return status_has("\"state\":\"reconnecting\""); })) << status_;
  // While the robot is gone, requests fail at once with the reason.
  Reply r = c.request(pos.address(), uint8_t(wire::Position2dReqSub::Geometry));
  EXPECT_EQ(r.status, Reply::Status::Nack);
  EXPECT_EQ(r.code, wire::ErrorCode::DeviceFailed);
  EXPECT_NE(r.text.find("not connected"), std::string::npos) << r.text;

  start_node(robot_, "robot", robot_config(), robot_port_);
  ASSERT_TRUE(spin_until(c, [&] { return status_has("\"connections\":2"); })) << status_;
  uint64_t before = pos.samples();
  ASSERT_TRUE(spin_until(c, [&] { return pos.samples() >= before + 3; })) << "data did not resume";
  ASSERT_TRUE(pos.set_velocity(0.5f, 0, 0));
  ASSERT_TRUE(spin_until(c, [&] { return pos.x() > 0.2f; }));
  EXPECT_TRUE(c.connected());
  EXPECT_EQ(c.connections(), 1u) << "the client had to reconnect";
}

TEST_F(Passthrough, ChainsThroughASecondPassthrough) {
  uint16_t middle_port = free_port();
  start_node(robot_, "robot", robot_config(), robot_port_);
  start_node(middle_, "middle", passthrough_config("middle", robot_port_, "position2d:0", "position2d:1"),
             middle_port);
  start_node(desktop_, "desktop", passthrough_config("desktop", middle_port, "position2d:1", "position2d:2"),
             desktop_port_);
  Client c("127.0.0.1", desktop_port_);
  ASSERT_TRUE(c.connect(5000)) << c.error();
  Position2dProxy pos(c, 2);
  ASSERT_TRUE(spin_until(c, [&] { return pos.samples() >= 3; }));
  ASSERT_TRUE(pos.set_velocity(0, 0, 0.5f));
  ASSERT_TRUE(spin_until(c, [&] { return pos.a() > 0.3f; })) << "a stayed at " << pos.a();
  Reply r = c.request(pos.address(), uint8_t(wire::Position2dReqSub::Geometry));
  ASSERT_TRUE(r.ok()) << r.text;
  EXPECT_NE(r.message()->body_as_Position2dGeometry(), nullptr);
}

TEST_F(Passthrough, ReachesARemoteOnIpv6AndOneByLocalhost) {
  // The robot listens on ::1 only: the desktop names it by address; a second
  // desktop names it `localhost`, which the hosts file may give as ::1 or
  // 127.0.0.1 or both: every address is tried, so ::1 is found either way
  // when the hosts file has it, and the robot is on both loopbacks below.
  start_node(robot_, "robot", robot_config(), robot_port_, "::1");
  start_node(desktop_, "desktop",
             passthrough_config("desktop", robot_port_, "position2d:0", "position2d:0", "", "::1"), desktop_port_);
  Client c("127.0.0.1", desktop_port_);
  watch_status(c);
  ASSERT_TRUE(spin_until(c, [&] { return status_has("\"state\":\"connected\""); })) << status_;
  EXPECT_TRUE(status_has("\"remote\":\"[::1]:" + std::to_string(robot_port_) + "\"")) << status_;
  Position2dProxy pos(c, 0);
  ASSERT_TRUE(spin_until(c, [&] { return pos.samples() >= 2; })) << "no data from the IPv6 robot";

  uint16_t middle_port = free_port();
  robot_.stop();
  start_node(robot_, "robot", robot_config(), robot_port_, "localhost");
  start_node(middle_, "middle",
             passthrough_config("middle", robot_port_, "position2d:0", "position2d:0", "", "localhost"),
             middle_port);
  Client m("127.0.0.1", middle_port);
  ASSERT_TRUE(m.connect(5000)) << m.error();
  Position2dProxy via_localhost(m, 0);
  ASSERT_TRUE(spin_until(m, [&] { return via_localhost.samples() >= 2; })) << "no data through localhost";
}

TEST_F(Passthrough, ARemoteThatNeverAnswersDoesNotStallTheNode) {
  // Accepts TCP connections (the kernel does, from the backlog) and never
  // says a word.
  int mute = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(robot_port_);
  ASSERT_EQ(bind(mute, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  ASSERT_EQ(listen(mute, 16), 0);
  start_node(desktop_, "desktop",
             passthrough_config("desktop", robot_port_, "position2d:0", "position2d:0",
                                R"(, "connect_timeout": 0.3)"),
             desktop_port_);
  Client c("127.0.0.1", desktop_port_);
  watch_status(c);
  ASSERT_TRUE(spin_until(c, [&] { return status_has("no handshake"); })) << status_;
  // The desktop's loop keeps serving: round trips and requests are answered.
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(c.sync()) << c.error();
  Reply r = c.request(client::address_of(wire::Interface::Position2d, 0),
                      uint8_t(wire::Position2dReqSub::Geometry));
  EXPECT_EQ(r.status, Reply::Status::Nack);
  EXPECT_EQ(r.code, wire::ErrorCode::DeviceFailed);
  close(mute);
}

TEST_F(Passthrough, RefusesAHostNameAndAMismatchedRemote) {
  std::string log = dir_ + "/bad.log";
  std::string bad = dir_ + "/bad.json";
  auto run = [&](const std::string& json) {
    FILE* f = std::fopen(bad.c_str(), "w");
    std::fputs(json.c_str(), f);
    std::fclose(f);
    std::string cmd =
        "'" + kNode + "' '" + bad + "' --port " + std::to_string(free_port()) + " > '" + log + "' 2>&1";
    return std::system(cmd.c_str());
  };
  std::string json = passthrough_config("bad", 6665, "position2d:0", "position2d:0");
  json.replace(json.find("127.0.0.1"), 9, "robot.example");
  EXPECT_NE(run(json), 0);
  EXPECT_NE(read_text(log).find("not a numeric address"), std::string::npos) << read_text(log);

  EXPECT_NE(run(passthrough_config("bad", 6665, "ranger:0", "position2d:0")), 0);
  EXPECT_NE(read_text(log).find("remote[0] is a ranger but provides[0] a position2d"), std::string::npos)
      << read_text(log);
}

}  // namespace
}  // namespace troupe::testing
