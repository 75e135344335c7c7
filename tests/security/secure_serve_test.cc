// troupe-sim and troupe play serving secure sessions, as a user sets them
// up: `troupe keygen` for the server and its clients, a --secure file with
// the server's key and its clients (the node config's "key" and "clients"),
// the real programs listening on every address (0.0.0.0, where plain TCP
// would need --insecure) and the troupe CLI as the client, each a separate
// process.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "tests/support/child_process.h"
#include "tests/support/secure_node.h"

namespace troupe::testing {
namespace {

const std::string kBin = std::string(TROUPE_BINARY_DIR) + "/bin/";
constexpr int kRunMs = 30'000;  // bounds a failing run only

// One robot, r0, at the origin facing +x with nothing in its way, stepped
// every 100 ms.
const char kWorld[] =
    "resolution 0.05\ninterval_sim 100\n"
    "define bot position ( size [0.4 0.3] )\n"
    "bot ( name \"r0\" pose [0 0 0 0] )\n";

// The laptop may do everything, the monitor only read; "stranger" is
// nobody's client.
const char kKeys[] = R"({ "key": "node", "clients": [ { "key": "laptop.pub" },
                                                      { "key": "monitor.pub", "read": ["*"] } ] })";

size_t lines_of(const std::string& text) {
  size_t n = 0;
  for (char ch : text) n += ch == '\n';
  return n;
}

class SecureServe : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(keys_.make_keys({"laptop", "monitor", "stranger"}, error)) << error;
    std::ofstream(keys_.path("keys.json")) << kKeys;
    std::ofstream(keys_.path("room.world")) << kWorld;
  }
  void TearDown() override {
    for (ChildProcess* p : {&sim_, &player_}) {
      if (p->running()) p->kill_hard();
    }
  }
  // troupe-sim on 0.0.0.0 with `more`, `world` the room unless named;
  // true once it prints its port.
  void start_sim(const std::vector<std::string>& more, std::string world = "") {
    if (world.empty()) world = keys_.path("room.world");
    std::vector<std::string> argv = {kBin + "troupe-sim", world,      "--port", "0",
                                     "--no-view",         "--listen", "0.0.0.0"};
    argv.insert(argv.end(), more.begin(), more.end());
    std::string error;
    ASSERT_TRUE(sim_.start(argv, keys_.dir(), "sim", error)) << error;
    ASSERT_TRUE(sim_.wait_for("listening on ", false, kRunMs)) << sim_.err();
    const std::string out = sim_.out();
    const std::string at = out.substr(out.find("listening on ") + 13);
    host_ = "127.0.0.1:" + std::to_string(std::atoi(at.c_str() + at.find(':') + 1));
  }
  // `troupe ARGS...` as `identity` holding the server's key ("": plain).
  ProgramResult troupe(std::vector<std::string> args, const std::string& identity) {
    args.insert(args.begin(), kBin + "troupe");
    if (!identity.empty()) {
      for (const std::string& a : secure_args(keys_, identity, "node.pub")) args.push_back(a);
    }
    return run_to_end(args, kRunMs);
  }

  SecureNodeProcess keys_;  // its keys and folder; its troupe-node is not started
  ChildProcess sim_, player_;
  std::string host_;
};

TEST_F(SecureServe, SimServesAKnownClientBeyondLoopbackWhichReadsAndDrivesARobot) {
  start_sim({"--secure", keys_.path("keys.json")});
  EXPECT_TRUE(
      sim_.wait_for("secure sessions only; this simulator's key is " + keys_.node_key_hex(), true, kRunMs))
      << sim_.err();
  EXPECT_EQ(sim_.err().find("insecure"), std::string::npos) << sim_.err();

  ProgramResult ls = troupe({"ls", host_}, "laptop");
  ASSERT_EQ(ls.status, 0) << ls.err;
  EXPECT_NE(ls.out.find("r0/position2d:0\ttroupe-sim\n"), std::string::npos) << ls.out;
  EXPECT_TRUE(sim_.wait_for("secure session with key ", true, kRunMs)) << sim_.err();

  ProgramResult still = troupe({"echo", host_, "r0/position2d:0", "--count", "2"}, "laptop");
  ASSERT_EQ(still.status, 0) << still.err;
  EXPECT_EQ(lines_of(still.out), 2u) << still.out;
  EXPECT_NE(still.out.find("pose=0.000,0.000,0.000"), std::string::npos) << still.out;

  ProgramResult cmd = troupe({"cmd", host_, "r0/position2d:0", "vel", "0.5", "0", "0"}, "laptop");
  ASSERT_EQ(cmd.status, 0) << cmd.err;
  // Driven forward at 0.5 m/s, r0 leaves the origin within these steps.
  ProgramResult moving = troupe({"echo", host_, "r0/position2d:0", "--count", "20"}, "laptop");
  ASSERT_EQ(moving.status, 0) << moving.err;
  const std::string last = moving.out.substr(moving.out.rfind("pose="));
  EXPECT_EQ(last.find("pose=0.000,"), std::string::npos) << moving.out;
}

TEST_F(SecureServe, SimRefusesAnUnknownKeyAndAPlainClient) {
  start_sim({"--secure", keys_.path("keys.json")});
  ProgramResult stranger = troupe({"ls", host_}, "stranger");
  EXPECT_NE(stranger.status, 0);
  EXPECT_EQ(stranger.out, "") << "nothing of the simulator may reach a refused client";
  EXPECT_NE(stranger.err.find("during the secure handshake"), std::string::npos) << stranger.err;
  EXPECT_TRUE(sim_.wait_for("is not among the node's clients", true, kRunMs)) << sim_.err();

  ProgramResult plain = troupe({"ls", host_}, "");
  EXPECT_NE(plain.status, 0);
  EXPECT_EQ(plain.out, "");
  EXPECT_TRUE(sim_.wait_for("did not open a secure session", true, kRunMs)) << sim_.err();
  // The known client is still served.
  EXPECT_EQ(troupe({"ls", host_}, "laptop").status, 0);
}

TEST_F(SecureServe, SimAnswersAReadOnlyClientsCommandWithForbidden) {
  start_sim({"--secure", keys_.path("keys.json")});
  ProgramResult read = troupe({"echo", host_, "r0/position2d:0", "--count", "1"}, "monitor");
  EXPECT_EQ(read.status, 0) << read.err;
  EXPECT_NE(read.out.find("pose="), std::string::npos) << read.out;
  ProgramResult cmd = troupe({"cmd", host_, "r0/position2d:0", "vel", "0.5", "0", "0"}, "monitor");
  EXPECT_NE(cmd.status, 0);
  EXPECT_NE(cmd.err.find("may not command r0/position2d:0"), std::string::npos) << cmd.err;
  ProgramResult pause = troupe({"req", host_, "simulation:0", "pause"}, "monitor");
  EXPECT_NE(pause.status, 0);
  EXPECT_NE(pause.err.find("may not request simulation:0"), std::string::npos) << pause.err;
  // Nothing moved: r0 still stands at the origin.
  ProgramResult pose = troupe({"echo", host_, "r0/position2d:0", "--count", "5"}, "laptop");
  EXPECT_NE(pose.out.rfind("pose=0.000,0.000,0.000 vel=0.000,0.000,0.000"), std::string::npos) << pose.out;
  EXPECT_EQ(pose.out.find("vel=0.500"), std::string::npos) << pose.out;
}

// A RoboCup match is served by another loop (host-sim/robocup/serve); its
// node runs the same sessions.
TEST_F(SecureServe, ARoboCupMatchServesKnownKeysOnly) {
  start_sim({"--secure", keys_.path("keys.json")},
            std::string(TROUPE_SOURCE_DIR) + "/examples/robocup/match.world");
  ProgramResult ls = troupe({"ls", host_}, "laptop");
  ASSERT_EQ(ls.status, 0) << ls.err;
  EXPECT_NE(ls.out.find("blue0/position2d:0"), std::string::npos) << ls.out;
  ProgramResult stranger = troupe({"ls", host_}, "stranger");
  EXPECT_NE(stranger.status, 0);
  EXPECT_EQ(stranger.out, "");
  EXPECT_TRUE(sim_.wait_for("is not among the node's clients", true, kRunMs)) << sim_.err();
}

TEST_F(SecureServe, ABadSecureFileStopsTheSimAtStartNamingTheMistake) {
  struct Case {
    const char* json;
    const char* says;
  };
  const Case cases[] = {
      {R"({ "key": "node", "port": 7000, "clients": [ { "key": "laptop.pub" } ] })",
       "\"port\": this file holds only \"key\" and \"clients\""},
      {R"({ "clients": [ { "key": "laptop.pub" } ] })", "no \"key\""},
      {R"({ "key": "node" })", "\"key\" without \"clients\""},
      {R"({ "key": "node", "clients": [ { "key": "nobody.pub" } ] })", "clients[0]: "},
      {R"({ "key": "node", "clients": [ { "key": "laptop.pub", "read": ["wheels:*"] } ] })",
       "clients[0]: read: device pattern 'wheels:*'"},
      {R"({ "key": "node", "clients": [ { "key": "laptop.pub" } )", "bad.json:"},
  };
  for (const Case& c : cases) {
    std::ofstream(keys_.path("bad.json")) << c.json;
    ProgramResult r = run_to_end({kBin + "troupe-sim", keys_.path("room.world"), "--port", "0", "--no-view",
                                  "--secure", keys_.path("bad.json")},
                                 kRunMs);
    EXPECT_EQ(r.status, 2) << c.json;
    EXPECT_NE(r.err.find("troupe-sim: --secure " + keys_.path("bad.json")), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.json << "\n" << r.err;
  }
  ProgramResult both = run_to_end(
      {kBin + "troupe-sim", keys_.path("room.world"), "--secure", keys_.path("keys.json"), "--insecure"},
      kRunMs);
  EXPECT_EQ(both.status, 2);
  EXPECT_NE(both.err.find("--secure excludes --insecure"), std::string::npos) << both.err;
}

// troupe record takes a log from the secure simulator; troupe play serves
// it again, secure, beyond loopback: a client reads every recorded sample,
// an unknown key is refused, and without keys it does not start there.
TEST_F(SecureServe, PlayServesARecordedLogToKnownKeysOnly) {
  start_sim({"--secure", keys_.path("keys.json")});
  const std::string log = keys_.path("run.trl");
  ProgramResult rec = troupe({"record", host_, "r0/position2d:0", "-o", log, "--count", "5"}, "laptop");
  ASSERT_EQ(rec.status, 0) << rec.err;
  sim_.kill_hard();

  ProgramResult plain =
      run_to_end({kBin + "troupe", "play", log, "--listen", "0.0.0.0", "--port", "0"}, kRunMs);
  EXPECT_EQ(plain.status, 2);
  EXPECT_NE(plain.err.find("troupe play: serving 0.0.0.0:0 in plain TCP would let any machine"),
            std::string::npos)
      << plain.err;

  const uint16_t port = free_port();
  host_ = "127.0.0.1:" + std::to_string(port);
  std::string error;
  // --wait holds the samples until the device has a reader.
  ASSERT_TRUE(player_.start({kBin + "troupe", "play", log, "--listen", "0.0.0.0", "--port",
                             std::to_string(port), "--wait", "--secure", keys_.path("keys.json")},
                            keys_.dir(), "player", error))
      << error;
  ASSERT_TRUE(wait_for_listener(port, 10)) << player_.err();
  EXPECT_EQ(player_.err().find("insecure"), std::string::npos) << player_.err();

  ProgramResult stranger = troupe({"ls", host_}, "stranger");
  EXPECT_NE(stranger.status, 0);
  EXPECT_EQ(stranger.out, "");
  EXPECT_TRUE(player_.wait_for("is not among the node's clients", true, kRunMs)) << player_.err();

  ProgramResult read = troupe({"echo", host_, "r0/position2d:0", "--count", "5"}, "monitor");
  ASSERT_EQ(read.status, 0) << read.err;
  EXPECT_EQ(lines_of(read.out), 5u) << read.out;
  EXPECT_NE(read.out.find("pose=0.000,0.000,0.000"), std::string::npos) << read.out;
  EXPECT_TRUE(player_.wait_for("secure session with key ", true, kRunMs)) << player_.err();
}

}  // namespace
}  // namespace troupe::testing
