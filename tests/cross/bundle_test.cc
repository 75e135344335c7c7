// The bundles a board build packs (cpack): unpacked into a fresh folder,
// they hold troupe-node, the board's compiled node config and a systemd unit
// naming both; the node starts from there under qemu-user with the bundled
// config and a host client lists its devices.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>

#include "tests/cross/qemu_node.h"
#include "wire/client/client.h"

namespace troupe::cross {
namespace {

bool exists(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0;
}

// The value after `key=` on the unit's line starting with `key=`.
std::string unit_value(const std::string& unit, const std::string& key) {
  size_t at = unit.find("\n" + key + "=");
  if (at == std::string::npos) return "";
  at += key.size() + 2;
  return unit.substr(at, unit.find('\n', at) - at);
}

struct Bundle {
  const char* build;
  const char* kind;  // "tar.gz" or "deb"
  size_t devices;
  // Another of the bundle's configs to start with, run by the ODrive
  // emulator: the default one needs a CAN bus this machine lacks.
  const char* emulated_config = nullptr;
};

class BundleTest : public ::testing::TestWithParam<Bundle> {
 protected:
  void TearDown() override {
    std::string ignored;
    if (!dir_.empty()) run("rm -rf " + quote(dir_), ignored);
  }
  std::string dir_;
};

TEST_P(BundleTest, StartsFromItsUnpackedFolder) {
  const Bundle& p = GetParam();
  CrossBuild b;
  if (std::string why; !load_cross_build(p.build, b, why)) {
    GTEST_SKIP() << why;
  }
  std::string package = b.path("troupe-node-" + b.board + "-0.1.0-" + b.deb_arch + "." + p.kind);
  ASSERT_TRUE(exists(package)) << package;
  dir_ = make_temp_dir("bundle-" + b.name);
  std::string out;
  if (std::string(p.kind) == "deb") {
    ASSERT_EQ(run("dpkg-deb -x " + quote(package) + " " + quote(dir_) + " 2>&1", out), 0) << out;
    ASSERT_EQ(run("dpkg-deb -f " + quote(package) + " Package Architecture Depends 2>&1", out), 0) << out;
    EXPECT_NE(out.find("Package: troupe-node-" + b.board), std::string::npos) << out;
    EXPECT_NE(out.find("Architecture: " + b.deb_arch), std::string::npos) << out;
    // A static node needs no library (package_test checks the versions).
    EXPECT_EQ(out.find("libc6") != std::string::npos, !b.is_static) << out;
  } else {
    ASSERT_EQ(run("tar -xzf " + quote(package) + " -C " + quote(dir_) + " 2>&1", out), 0) << out;
  }

  // The unit names the binary and the config where the bundle puts them.
  std::string unit = read_text(dir_ + "/usr/lib/systemd/system/troupe-node.service");
  ASSERT_FALSE(unit.empty()) << "no systemd unit in " << package;
  std::string exec = unit_value(unit, "ExecStart");
  std::string binary = exec.substr(0, exec.find(' '));
  std::string config = unit_value(unit, "Environment");
  ASSERT_EQ(config.rfind("TROUPE_NODE_CONFIG=", 0), 0u) << unit;
  config = config.substr(config.find('=') + 1);
  EXPECT_EQ(binary, "/usr/bin/troupe-node");
  EXPECT_NE(exec.find("${TROUPE_NODE_CONFIG}"), std::string::npos) << exec;
  EXPECT_NE(unit.find("WantedBy=multi-user.target"), std::string::npos);
  // Retried after a failure (late hardware), but not when it cannot start at
  // all: exec failures (203), the loader's refusal (127), usage (2) and a
  // config to fix (78).
  EXPECT_EQ(unit_value(unit, "Restart"), "on-failure");
  std::string no_retry = " " + unit_value(unit, "RestartPreventExitStatus") + " ";
  for (const char* status : {" 2 ", " 78 ", " 127 ", " 203 "}) {
    EXPECT_NE(no_retry.find(status), std::string::npos) << "RestartPreventExitStatus lacks" << status << "\n" << unit;
  }
  EXPECT_EQ(no_retry.find(" 1 "), std::string::npos) << "exit 1 (a device not there yet) must be retried";
  ASSERT_TRUE(exists(dir_ + binary)) << binary;
  ASSERT_TRUE(exists(dir_ + config)) << config;

  // systemd reads the unit without a complaint (with the binary's path
  // moved to where the bundle was unpacked: verify checks it exists). A
  // misspelt or unknown setting only draws a warning, so the output must be
  // empty, not just the exit status 0. (Package systemd; run.sh installs it.)
  const bool have_systemd_analyze = run("command -v systemd-analyze", out) == 0;
  if (have_systemd_analyze) {
    std::string copy = dir_ + "/troupe-node.service";
    FILE* f = fopen(copy.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::string moved = unit;
    moved.replace(moved.find(binary), binary.size(), dir_ + binary);
    fputs(moved.c_str(), f);
    fclose(f);
    EXPECT_EQ(run("systemd-analyze verify " + quote(copy) + " 2>&1", out), 0) << out;
    EXPECT_EQ(out, "");
  }

  // Secure sessions: where the node has them, the unit hands it the key
  // the postinst makes, at one path throughout, and the node makes such a
  // key itself; where it lacks them, neither asks for a key and the node
  // says what it lacks. (tests/security/bundle_keys_test.cc runs the
  // postinst and the unit's command line on the host.)
  const std::string credential = unit_value(unit, "LoadCredential");
  const bool secure = !credential.empty();
  std::string key_path;
  std::string keygen_out;
  const std::string scratch_key = dir_ + "/scratch.key";
  const int keygen = run(qemu_command(b, dir_ + binary, {"--keygen", scratch_key}) + " 2>&1", keygen_out);
  if (secure) {
    ASSERT_EQ(credential.rfind("node.key:", 0), 0u) << unit;
    key_path = credential.substr(credential.find(':') + 1);
    EXPECT_EQ(unit_value(unit, "AssertPathExists"), key_path) << unit;
    EXPECT_NE(exec.find(" --set key=%d/node.key "), std::string::npos) << exec;
    EXPECT_EQ(keygen, 0) << keygen_out;
    struct stat st {};
    ASSERT_EQ(stat(scratch_key.c_str(), &st), 0) << keygen_out;
    EXPECT_EQ(st.st_mode & 07777, 0600u);
  } else {
    EXPECT_EQ(exec.find("key="), std::string::npos) << exec;
    EXPECT_EQ(keygen, 1) << keygen_out;
    EXPECT_NE(keygen_out.find("is built without secure sessions"), std::string::npos) << keygen_out;
    EXPECT_FALSE(exists(scratch_key));
  }
  if (std::string(p.kind) == "deb") {
    ASSERT_EQ(run("dpkg-deb -e " + quote(package) + " " + quote(dir_ + "/DEBIAN") + " 2>&1", out), 0) << out;
    EXPECT_NE(read_text(dir_ + "/DEBIAN/postinst").find("\nkey=\"" + key_path + "\""), std::string::npos)
        << "the postinst must make the key the unit hands over (" << key_path << ")";
  }

  // The bundled binary is stripped: no symbol table left.
  ASSERT_EQ(run(quote(b.readelf) + " -S " + quote(dir_ + binary), out), 0);
  EXPECT_EQ(out.find(".symtab"), std::string::npos);

  QemuNode node;
  QemuNode::Extras extras;
  if (p.emulated_config != nullptr) {
    config = config.substr(0, config.rfind('/') + 1) + p.emulated_config;
    ASSERT_TRUE(exists(dir_ + config)) << config;
    extras.wrapper = {TROUPE_ODRIVE_EMU, "--status-ms", "0", "--"};
  }
  std::string error;
  ASSERT_TRUE(node.start(b, dir_ + binary, dir_ + config, error, extras)) << error;
  client::Client::Options options;
  options.reconnect = false;
  client::Client c("127.0.0.1", node.port(), options);
  ASSERT_TRUE(c.connect()) << c.error();
  EXPECT_EQ(c.node_name(), b.board);
  std::vector<client::DeviceEntry> devices;
  ASSERT_TRUE(c.device_list(devices)) << c.error();
  EXPECT_EQ(devices.size(), p.devices);
  EXPECT_EQ(node.stop(), 0) << node.log();
  if (!have_systemd_analyze) {
    GTEST_SKIP() << "systemd-analyze is not installed (apt-get install systemd): the unit was not verified";
  }
}

INSTANTIATE_TEST_SUITE_P(Boards, BundleTest,
                         ::testing::Values(Bundle{"core-armhf", "deb", 0}, Bundle{"core-armhf", "tar.gz", 0},
                                           Bundle{"ppc-node-armhf", "deb", 1},
                                           Bundle{"ppc-node-powerpc", "tar.gz", 1},
                                           Bundle{"diffbot-can-arm64", "deb", 2, "diffbot-can-emulated.bin"},
                                           Bundle{"ppc-node-arm64-static", "deb", 1}),
                         [](const auto& param_info) {
                           std::string name =
                               std::string(param_info.param.build) + "_" + param_info.param.kind;
                           for (char& c : name) {
                             if (c == '-' || c == '.') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace troupe::cross
