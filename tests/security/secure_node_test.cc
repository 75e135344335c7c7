// Secure sessions end to end, as a user sets them up: `troupe keygen` for the
// node and its clients, a real troupe-node whose config names its key and
// its clients, and the troupe CLI (the C++ client library) as the client,
// each a separate process on loopback.
#include <sys/stat.h>

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "tests/support/child_process.h"
#include "tests/support/secure_node.h"

namespace {

using troupe::testing::ChildProcess;

const std::string kBin = std::string(TROUPE_BINARY_DIR) + "/bin";
// Hang guard for each CLI run (a bound on a failing test), ms.
constexpr int kRunMs = 30'000;

struct Result {
  int rc = -1;
  std::string out, err;
};

Result run(const std::vector<std::string>& argv) {
  auto r = troupe::testing::run_to_end(argv, kRunMs);
  return {r.status, r.out, r.err};
}

mode_t mode_of(const std::string& path) {
  struct stat st {};
  ::stat(path.c_str(), &st);
  return st.st_mode & 07777;
}

class SecureNode : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(rig_.make_keys({"laptop", "stranger", "monitor", "operator"}, error)) << error;
    ASSERT_TRUE(rig_.start(clients(), drivers(), error)) << error;
    dir_ = rig_.dir();
    host_ = rig_.host();
  }
  virtual std::string clients() const { return R"([{ "key": "laptop.pub" }])"; }
  virtual std::string drivers() const {
    return R"([ { "driver_type": "kinematic", "driver": { "rate_hz": 20 }, "provides": ["position2d:0"] } ])";
  }
  void TearDown() override {
    if (node_.running()) {
      EXPECT_EQ(node_.stop(), 0) << node_.err();
    }
  }
  // `troupe ARGS... HOST` as `identity` with `node_key` ("" leaves the flag out).
  Result troupe(std::vector<std::string> args, const std::string& identity, const std::string& node_key) {
    args.insert(args.begin(), kBin + "/troupe");
    if (!identity.empty()) args.insert(args.end(), {"--identity", dir_ + "/" + identity});
    if (!node_key.empty()) args.insert(args.end(), {"--node-key", dir_ + "/" + node_key});
    return run(args);
  }
  // The node's log has `text` (it logs a refusal as it closes the connection).
  bool logged(const std::string& text) { return node_.wait_for(text, true, kRunMs); }
  // `r` got nothing of the node, the node logged `node_says`, and it still
  // serves its known client.
  void expect_refused(const Result& r, const std::string& node_says) {
    EXPECT_NE(r.rc, 0);
    EXPECT_EQ(r.out, "") << "nothing of the node may reach a refused client";
    EXPECT_TRUE(logged(node_says)) << node_.err();
    Result known = troupe({"ls", host_}, "laptop", "node.pub");
    EXPECT_EQ(known.rc, 0) << known.err;
    EXPECT_EQ(known.out, "position2d:0\tkinematic\n");
  }

  troupe::testing::SecureNodeProcess rig_;
  ChildProcess& node_ = rig_.node();
  std::string dir_, host_;
};

TEST_F(SecureNode, KeygenWritesAPrivateSecretAndRefusesToOverwrite) {
  EXPECT_EQ(mode_of(dir_ + "/laptop"), 0600u);
  EXPECT_EQ(mode_of(dir_ + "/laptop.pub"), 0644u);
  Result again = run({kBin + "/troupe", "keygen", dir_ + "/laptop"});
  EXPECT_NE(again.rc, 0);
  EXPECT_NE(again.err.find("exists; not overwritten"), std::string::npos) << again.err;
}

TEST_F(SecureNode, KnownClientReadsADevice) {
  Result r = troupe({"echo", host_, "position2d:0", "--count", "3"}, "laptop", "node.pub");
  ASSERT_EQ(r.rc, 0) << r.err;
  size_t lines = 0;
  for (char ch : r.out) lines += ch == '\n';
  EXPECT_EQ(lines, 3u) << r.out;
  EXPECT_NE(r.out.find("pose="), std::string::npos) << r.out;
  EXPECT_TRUE(logged("secure session with key ")) << node_.err();
}

TEST_F(SecureNode, UnknownClientKeyIsRefused) {
  Result r = troupe({"ls", host_}, "stranger", "node.pub");
  EXPECT_NE(r.err.find("during the secure handshake"), std::string::npos) << r.err;
  expect_refused(r, "is not among the node's clients");
}

TEST_F(SecureNode, ClientHoldingAnotherNodeKeyIsRefused) {
  expect_refused(troupe({"ls", host_}, "laptop", "stranger.pub"), "does not hold this node's public key");
}

TEST_F(SecureNode, PlainClientIsRefused) {
  expect_refused(troupe({"ls", host_}, "", ""), "did not open a secure session");
}

TEST_F(SecureNode, TheKnownNodesFileNamesTheNodesKey) {
  // The CLI's known-nodes file: $XDG_CONFIG_HOME/troupe/known_nodes.
  const std::string config_home = dir_ + "/config";
  ASSERT_EQ(::mkdir(config_home.c_str(), 0700), 0);
  ASSERT_EQ(::mkdir((config_home + "/troupe").c_str(), 0700), 0);
  ASSERT_EQ(::setenv("XDG_CONFIG_HOME", config_home.c_str(), 1), 0);
  Result unknown = troupe({"ls", host_}, "laptop", "");
  EXPECT_NE(unknown.rc, 0);
  EXPECT_NE(unknown.err.find("no key known for " + host_), std::string::npos) << unknown.err;

  const std::string key = rig_.node_key_hex();
  std::ofstream(config_home + "/troupe/known_nodes") << "# nodes this laptop talks to\nother:6665 " << key << "\n"
                                                      << host_ << " " << key << "\n";
  Result known = troupe({"ls", host_}, "laptop", "");
  ::unsetenv("XDG_CONFIG_HOME");
  EXPECT_EQ(known.rc, 0) << known.err;
  EXPECT_EQ(known.out, "position2d:0\tkinematic\n");
}

TEST_F(SecureNode, SecretKeyOthersCanReadIsRefused) {
  ASSERT_EQ(::chmod((dir_ + "/laptop").c_str(), 0644), 0);
  Result r = troupe({"ls", host_}, "laptop", "node.pub");
  EXPECT_NE(r.rc, 0);
  EXPECT_NE(r.err.find("chmod 600"), std::string::npos) << r.err;
}

TEST_F(SecureNode, KeyWithoutClientsDoesNotStart) {
  const std::string config = dir_ + "/lonely.json";
  std::ofstream(config) << R"({ "listen": "127.0.0.1", "port": 0, "key": "node",
  "drivers": [ { "driver_type": "kinematic", "provides": ["position2d:0"] } ] })";
  Result r = run({kBin + "/troupe-node", config});
  EXPECT_EQ(r.rc, 78);
  EXPECT_NE(r.err.find("\"key\" without \"clients\""), std::string::npos) << r.err;
}

// Secure by default: a node that would serve plain TCP beyond loopback
// does not start unless told --insecure, and then says so in its log; one
// with its key and clients serves any address quietly.
TEST_F(SecureNode, PlainTcpBeyondLoopbackMustBeAskedForAndIsLogged) {
  const std::string plain = dir_ + "/plain.json";
  std::ofstream(plain) << R"({ "listen": "0.0.0.0", "port": 0,
  "drivers": [ { "driver_type": "kinematic", "provides": ["position2d:0"] } ] })";
  Result refused = run({kBin + "/troupe-node", plain});
  EXPECT_EQ(refused.rc, 2);
  EXPECT_NE(refused.err.find("troupe-node: serving 0.0.0.0:0 in plain TCP would let any machine"), std::string::npos)
      << refused.err;

  const uint16_t port = troupe::testing::free_port();
  ChildProcess open_node;
  std::string error;
  ASSERT_TRUE(open_node.start({kBin + "/troupe-node", plain, "--port", std::to_string(port), "--insecure"}, dir_,
                              "plain-node", error))
      << error;
  EXPECT_TRUE(open_node.wait_for("insecure: troupe-node on 0.0.0.0:" + std::to_string(port) + " serves plain TCP",
                                 true, kRunMs))
      << open_node.err();
  Result ls = run({kBin + "/troupe", "ls", "127.0.0.1:" + std::to_string(port)});
  EXPECT_EQ(ls.rc, 0) << ls.err;
  EXPECT_EQ(open_node.stop(), 0);

  // With its key and clients it needs no flag, and warns of nothing.
  const std::string keyed = dir_ + "/keyed.json";
  std::ofstream(keyed) << R"({ "listen": "0.0.0.0", "port": 0, "key": "node", "clients": [{ "key": "laptop.pub" }],
  "drivers": [ { "driver_type": "kinematic", "provides": ["position2d:0"] } ] })";
  ChildProcess secure;
  ASSERT_TRUE(secure.start({kBin + "/troupe-node", keyed}, dir_, "keyed-node", error)) << error;
  EXPECT_TRUE(secure.wait_for("serving 1 devices on 0.0.0.0:", true, kRunMs)) << secure.err();
  EXPECT_EQ(secure.err().find("insecure"), std::string::npos) << secure.err();
  EXPECT_EQ(secure.stop(), 0);
}

// Rights by device pattern: a monitoring laptop reads everything and
// commands nothing; the operator's station reads everything and commands
// the base it drives, not the other one; the laptop, listed without rights,
// may do everything. Each refusal is a Nack Forbidden that leaves the
// connection (and the node) serving.
class SecureRights : public SecureNode {
 protected:
  std::string clients() const override {
    return R"([ { "key": "laptop.pub" },
                { "key": "monitor.pub", "read": ["*"] },
                { "key": "operator.pub", "read": ["*"], "command": ["position2d:0"] } ])";
  }
  std::string drivers() const override {
    return R"([ { "driver_type": "kinematic", "name": "base", "provides": ["position2d:0"] },
                { "driver_type": "kinematic", "name": "arm", "provides": ["position2d:1"] } ])";
  }
  Result cmd(const std::string& who, const std::string& device) {
    return troupe({"cmd", host_, device, "vel", "0.2", "0", "0"}, who, "node.pub");
  }
  Result get(const std::string& who, const std::string& device) {
    return troupe({"req", host_, device, "geometry"}, who, "node.pub");
  }
};

TEST_F(SecureRights, AReadOnlyClientReadsButItsCommandsAndRequestsAreForbidden) {
  Result read = troupe({"echo", host_, "position2d:1", "--count", "1"}, "monitor", "node.pub");
  EXPECT_EQ(read.rc, 0) << read.err;
  EXPECT_NE(read.out.find("pose="), std::string::npos) << read.out;
  Result c = cmd("monitor", "position2d:0");
  EXPECT_NE(c.rc, 0);
  EXPECT_NE(c.err.find("may not command position2d:0"), std::string::npos) << c.err;
  Result g = get("monitor", "position2d:0");
  EXPECT_NE(g.rc, 0);
  EXPECT_NE(g.err.find("may not request position2d:0"), std::string::npos) << g.err;
  // Nothing moved: the base still stands where it started.
  Result pose = troupe({"echo", host_, "position2d:0", "--count", "1"}, "laptop", "node.pub");
  EXPECT_NE(pose.out.find("pose=0.000,0.000,0.000 vel=0.000,0.000,0.000"), std::string::npos) << pose.out;
}

TEST_F(SecureRights, AnOperatorCommandsOnlyTheDevicesItsPatternsName) {
  EXPECT_EQ(cmd("operator", "position2d:0").rc, 0);
  Result other = cmd("operator", "position2d:1");
  EXPECT_NE(other.rc, 0);
  EXPECT_NE(other.err.find("may not command position2d:1"), std::string::npos) << other.err;
  Result g = get("operator", "position2d:0");
  EXPECT_NE(g.rc, 0) << "no request right was given";
  // A client listed without rights holds them all.
  EXPECT_EQ(cmd("laptop", "position2d:1").rc, 0);
  Result geometry = get("laptop", "position2d:1");
  EXPECT_EQ(geometry.rc, 0) << geometry.err;
}

TEST_F(SecureRights, ABadPatternStopsTheNodeAtStartNamingIt) {
  const std::string config = dir_ + "/bad.json";
  std::ofstream(config) << R"({ "listen": "127.0.0.1", "port": 0, "key": "node",
  "clients": [ { "key": "laptop.pub", "command": ["position2d:0", "wheels:*"] } ],
  "drivers": [ { "driver_type": "kinematic", "provides": ["position2d:0"] } ] })";
  Result r = run({kBin + "/troupe-node", config});
  EXPECT_EQ(r.rc, 78);
  EXPECT_NE(r.err.find("clients[0]: command: device pattern 'wheels:*': unknown interface 'wheels'"),
            std::string::npos)
      << r.err;
}

}  // namespace
