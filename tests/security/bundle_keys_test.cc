// A robot's node deployed from a board bundle, secured as the README's
// deploy steps say ("Deploying to a robot board"), with the host's programs
// and the bundle's own files as this build makes them (build/bundle/: the
// systemd unit and the .deb's postinst):
//  - `troupe-node --keygen`, which the postinst runs (a board has no
//    `troupe` command);
//  - the postinst against a scratch root ($DPKG_ROOT, as dpkg runs scripts
//    outside a chroot): the key made once, root's only, kept on upgrade;
//  - a node started with the unit's own command line (its key handed over
//    as systemd's LoadCredential does) and a config compiled on the desktop
//    that lists the clients and their rights: the listed clients get their
//    rights, any other key and plain TCP are refused.
// The same bundle cross-built and run under qemu is tests/cross's.
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/child_process.h"

namespace {

using troupe::testing::ChildProcess;
using troupe::testing::ProgramResult;
using troupe::testing::read_text;

const std::string kBin = std::string(TROUPE_BINARY_DIR) + "/bin";
const std::string kBundle = std::string(TROUPE_BINARY_DIR) + "/bundle";
// Hang guard for each program run, ms.
constexpr int kRunMs = 30'000;

ProgramResult run(const std::vector<std::string>& argv) { return troupe::testing::run_to_end(argv, kRunMs); }

struct stat stat_of(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st;
}

// The value of the unit's line `key=...` ("" when it has none).
std::string unit_value(const std::string& unit, const std::string& key) {
  size_t at = unit.find("\n" + key + "=");
  if (at == std::string::npos) return "";
  at += key.size() + 2;
  return unit.substr(at, unit.find('\n', at) - at);
}

// Every occurrence of `from` in `text` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// The second word of a .pub file: its 64 hex digits.
std::string public_hex(const std::string& pub_path) {
  std::vector<std::string> w = words(read_text(pub_path));
  return w.size() >= 2 ? w[1] : "";
}

class BundleKeys : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = troupe::testing::make_temp_dir("troupe-bundle-keys-");
    ASSERT_FALSE(dir_.empty());
    unit_ = read_text(kBundle + "/troupe-node.service");
    ASSERT_FALSE(unit_.empty()) << "no " << kBundle << "/troupe-node.service";
    // This build has secure sessions (the host's always has): its unit
    // hands the node a key, where the postinst makes it.
    const std::string credential = unit_value(unit_, "LoadCredential");
    ASSERT_EQ(credential.rfind("node.key:", 0), 0u) << unit_;
    key_ = credential.substr(credential.find(':') + 1);
    EXPECT_EQ(unit_value(unit_, "AssertPathExists"), key_) << "the unit must not start without the key";
    exec_ = unit_value(unit_, "ExecStart");
    ASSERT_NE(exec_.find(" --set key=%d/node.key "), std::string::npos) << exec_;
  }
  void TearDown() override {
    if (node_.running()) {
      EXPECT_EQ(node_.stop(), 0) << node_.err();
    }
    if (!dir_.empty()) troupe::testing::remove_tree(dir_);
  }

  // A scratch robot: `dir_`/root with the node binary where the bundle
  // puts it (the unit's ExecStart names it).
  std::string make_root() {
    const std::string root = dir_ + "/root";
    const std::string binary = exec_.substr(0, exec_.find(' '));
    const std::string bin_dir = root + binary.substr(0, binary.rfind('/'));
    EXPECT_EQ(run({"mkdir", "-p", bin_dir}).status, 0);
    EXPECT_EQ(::symlink((kBin + "/troupe-node").c_str(), (root + binary).c_str()), 0) << root + binary;
    return root;
  }
  // The postinst as dpkg runs it outside a chroot: `configure` and the
  // version configured before ("" on a first install).
  ProgramResult postinst(const std::string& root, const std::string& previous) {
    std::vector<std::string> argv = {"env", "DPKG_ROOT=" + root, "sh", kBundle + "/deb/postinst", "configure"};
    if (!previous.empty()) argv.push_back(previous);
    return run(argv);
  }

  std::string dir_, unit_, key_, exec_;
  ChildProcess node_;
};

TEST_F(BundleKeys, NodeKeygenWritesAPrivatePairNamedAfterTheHostAndNeverOverwrites) {
  const std::string key = dir_ + "/node.key";
  ProgramResult made = run({kBin + "/troupe-node", "--keygen", key});
  ASSERT_EQ(made.status, 0) << made.err;
  EXPECT_EQ(stat_of(key).st_mode & 07777, 0600u);
  EXPECT_EQ(stat_of(key + ".pub").st_mode & 07777, 0644u);
  const std::string hex = public_hex(key + ".pub");
  EXPECT_EQ(hex.size(), 64u);
  EXPECT_NE(made.out.find(key + ".pub: public key " + hex), std::string::npos) << made.out;
  char host[256] = {};
  ASSERT_EQ(::gethostname(host, sizeof host - 1), 0);
  EXPECT_EQ(words(read_text(key + ".pub")).back(), host) << "the .pub names the robot it came from";

  const std::string secret = read_text(key);
  ProgramResult again = run({kBin + "/troupe-node", "--keygen", key});
  EXPECT_EQ(again.status, 1);
  EXPECT_NE(again.err.find(key + ": exists; not overwritten"), std::string::npos) << again.err;
  EXPECT_EQ(read_text(key), secret);
  EXPECT_EQ(public_hex(key + ".pub"), hex);
  // A .pub left alone is not overwritten either.
  ASSERT_EQ(::unlink(key.c_str()), 0);
  EXPECT_EQ(run({kBin + "/troupe-node", "--keygen", key}).status, 1);
  EXPECT_EQ(public_hex(key + ".pub"), hex);

  ProgramResult extra = run({kBin + "/troupe-node", "--keygen", key, "--port", "7000"});
  EXPECT_EQ(extra.status, 2);
  EXPECT_NE(extra.err.find("--keygen FILE takes no other argument"), std::string::npos) << extra.err;
}

TEST_F(BundleKeys, PostinstMakesTheKeyOnceRootsOnlyAndShowsItsPublicHalf) {
  const std::string root = make_root();
  ProgramResult first = postinst(root, "");
  ASSERT_EQ(first.status, 0) << first.out << first.err;
  const struct stat st = stat_of(root + key_);
  EXPECT_EQ(st.st_mode & 07777, 0600u);
  EXPECT_EQ(st.st_uid, ::geteuid()) << "the key stays its maker's (root under dpkg): systemd copies it for the service";
  const std::string hex = public_hex(root + key_ + ".pub");
  ASSERT_EQ(hex.size(), 64u);
  EXPECT_NE(first.out.find("made this node's key, " + key_), std::string::npos) << first.out;
  EXPECT_NE(first.out.find("public key is " + hex), std::string::npos) << first.out;
  EXPECT_NE(first.out.find("'HOST:6665 " + hex + "' >> ~/.config/troupe/known_nodes"), std::string::npos)
      << first.out;

  // An upgrade (or reinstalling) keeps the robot's identity: the desktops
  // that trust it go on trusting it.
  const std::string secret = read_text(root + key_);
  ProgramResult upgrade = postinst(root, "0.1.0");
  ASSERT_EQ(upgrade.status, 0) << upgrade.out << upgrade.err;
  EXPECT_EQ(read_text(root + key_), secret);
  EXPECT_EQ(stat_of(root + key_).st_mode & 07777, 0600u);
  EXPECT_EQ(upgrade.out.find("made this node's key"), std::string::npos) << upgrade.out;
  EXPECT_NE(upgrade.out.find("public key is " + hex), std::string::npos) << upgrade.out;

  // A lost .pub does not fail the upgrade, nor replace the key.
  ASSERT_EQ(::unlink((root + key_ + ".pub").c_str()), 0);
  ProgramResult lost = postinst(root, "0.1.0");
  EXPECT_EQ(lost.status, 0) << lost.out << lost.err;
  EXPECT_NE(lost.out.find(key_ + ".pub is missing"), std::string::npos) << lost.out;
  EXPECT_EQ(read_text(root + key_), secret);
}

// The README's steps, as a user follows them, with a kinematic base for the
// robot's devices (the host build's driver) and 127.0.0.1 as the robot.
class DeployedNode : public BundleKeys {
 protected:
  void SetUp() override {
    BundleKeys::SetUp();
    if (HasFatalFailure()) return;
    // Install, on the robot: the postinst makes the node's key.
    root_ = make_root();
    ProgramResult installed = postinst(root_, "");
    ASSERT_EQ(installed.status, 0) << installed.err;
    etc_ = root_ + key_.substr(0, key_.rfind('/'));
    // On the desktop: its keys (the stranger's is listed nowhere).
    desktop_ = dir_ + "/desktop";
    ASSERT_EQ(::mkdir(desktop_.c_str(), 0700), 0);
    for (const char* name : {"laptop", "monitor", "stranger"}) {
      ProgramResult k = run({kBin + "/troupe", "keygen", desktop_ + "/" + name});
      ASSERT_EQ(k.status, 0) << k.err;
    }
  }

  // Authorize, on the desktop: the robot's config with its clients, compiled
  // for the board; then copied with the clients' .pub files next to it.
  void authorize(const std::string& clients) {
    port_ = troupe::testing::free_port();
    std::ofstream(desktop_ + "/my-robot.json")
        << R"({ "name": "my-robot", "listen": "0.0.0.0", "port": )" << port_ << R"(, "clients": )" << clients
        << R"(, "drivers": [ { "driver_type": "kinematic", "driver": { "rate_hz": 20 },
                            "provides": ["position2d:0"] } ] })";
    ProgramResult compiled = run({kBin + "/troupe", "config", "compile", desktop_ + "/my-robot.json", "--board",
                                  "host", "-o", desktop_ + "/my-robot.bin"});
    ASSERT_EQ(compiled.status, 0) << compiled.err;
    for (const char* file : {"my-robot.bin", "laptop.pub", "monitor.pub"}) {
      ASSERT_EQ(run({"install", "-m", "644", desktop_ + "/" + file, etc_ + "/"}).status, 0) << file;
    }
  }

  // Starts the node with the unit's command line: TROUPE_NODE_CONFIG set
  // to `config` in /etc/default/troupe-node, the key in a credentials
  // folder as systemd's LoadCredential leaves it (a copy, mode 0400, %d).
  void start_service(const std::string& config) {
    const std::string credentials = dir_ + "/credentials";
    ASSERT_EQ(::mkdir(credentials.c_str(), 0700), 0);
    ASSERT_EQ(run({"install", "-m", "400", root_ + key_, credentials + "/node.key"}).status, 0);
    std::string line = replaced(exec_, "${TROUPE_NODE_CONFIG}", config);
    line = replaced(line, "%d", credentials);
    line = replaced(line, "$TROUPE_NODE_ARGS", "");
    std::vector<std::string> argv = words(line);
    argv[0] = root_ + argv[0];
    std::string error;
    ASSERT_TRUE(node_.start(argv, dir_, "troupe-node", error)) << error;
  }

  // `troupe ARGS...` on the desktop as `identity` ("": plain TCP), the
  // node's key taken from the known-nodes file.
  ProgramResult troupe(std::vector<std::string> args, const std::string& identity) {
    args.insert(args.begin(), kBin + "/troupe");
    if (!identity.empty()) args.insert(args.end(), {"--identity", desktop_ + "/" + identity});
    args.insert(args.begin(), {"env", "XDG_CONFIG_HOME=" + desktop_ + "/config"});
    return run(args);
  }
  // Trust the node, on the desktop: its line in the known-nodes file, with
  // the key the postinst printed.
  void trust_node() {
    ASSERT_EQ(run({"mkdir", "-p", desktop_ + "/config/troupe"}).status, 0);
    std::ofstream(desktop_ + "/config/troupe/known_nodes") << host() << " " << public_hex(root_ + key_ + ".pub")
                                                           << "\n";
  }
  std::string host() const { return "127.0.0.1:" + std::to_string(port_); }
  bool logged(const std::string& text) { return node_.wait_for(text, true, kRunMs); }

  std::string root_, etc_, desktop_;
  uint16_t port_ = 0;
};

TEST_F(DeployedNode, ServesTheClientsItsConfigNamesWithTheirRightsAndNoOneElse) {
  authorize(R"([ { "key": "laptop.pub", "read": ["*"], "command": ["position2d:*"] },
                 { "key": "monitor.pub", "read": ["*"] } ])");
  start_service(etc_ + "/my-robot.bin");
  ASSERT_TRUE(logged("serving 1 devices on 0.0.0.0:" + std::to_string(port_))) << node_.err();
  EXPECT_EQ(node_.err().find("insecure"), std::string::npos) << node_.err();
  trust_node();

  ProgramResult ls = troupe({"ls", host()}, "laptop");
  EXPECT_EQ(ls.status, 0) << ls.err;
  EXPECT_EQ(ls.out, "position2d:0\tkinematic\n");
  ProgramResult drive = troupe({"cmd", host(), "position2d:0", "vel", "0.2", "0", "0"}, "laptop");
  EXPECT_EQ(drive.status, 0) << drive.err;

  // The monitoring laptop reads, and may not drive.
  ProgramResult watch = troupe({"echo", host(), "position2d:0", "--count", "1"}, "monitor");
  EXPECT_EQ(watch.status, 0) << watch.err;
  EXPECT_NE(watch.out.find("pose="), std::string::npos) << watch.out;
  ProgramResult forbidden = troupe({"cmd", host(), "position2d:0", "vel", "0.2", "0", "0"}, "monitor");
  EXPECT_NE(forbidden.status, 0);
  EXPECT_NE(forbidden.err.find("may not command position2d:0"), std::string::npos) << forbidden.err;

  // A key the config does not list, and plain TCP, get nothing of it.
  ProgramResult stranger = troupe({"ls", host()}, "stranger");
  EXPECT_NE(stranger.status, 0);
  EXPECT_EQ(stranger.out, "");
  EXPECT_TRUE(logged("is not among the node's clients")) << node_.err();
  ProgramResult plain = troupe({"ls", host()}, "");
  EXPECT_NE(plain.status, 0);
  EXPECT_EQ(plain.out, "");
  EXPECT_TRUE(logged("did not open a secure session")) << node_.err();
  EXPECT_TRUE(node_.running());
}

TEST_F(DeployedNode, AShippedConfigListingNoClientsDoesNotStart) {
  // Before any client is authorized the service runs the bundle's own
  // config, which lists none: the node says what is missing instead of
  // serving a network it would refuse everyone on.
  start_service(std::string(TROUPE_SOURCE_DIR) + "/examples/nodes/kinematic.json");
  EXPECT_EQ(node_.wait_exit(kRunMs), 78) << "a config to fix: the unit does not retry it";
  EXPECT_NE(node_.err().find("\"key\" without \"clients\""), std::string::npos) << node_.err();
}

}  // namespace
