// An installed Troupe (`cmake --install` into INSTALL_PREFIX, the set-up
// step install.prefix) used as a user uses it: the troupe commands, an
// outside C++ program built against the client library with find_package
// and with pkg-config and run against the installed troupe-node, the Python
// client; and the host .deb, unpacked and run.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/help_checks.h"
#include "tests/support/child_process.h"
#include "wire/client/client.h"

namespace troupe::testing {
namespace {

const std::string kPrefix = INSTALL_PREFIX;
const std::string kScratch = std::string(TROUPE_BINARY_DIR) + "/tests/install";

bool exists(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0;
}

std::string quote(const std::string& text) { return "'" + text + "'"; }

/// A shell command run to its end (10 minutes at most: building is slow
/// under the sanitizers), stdout and stderr together.
ProgramResult sh(const std::string& command) { return run_to_end({"/bin/sh", "-c", command + " 2>&1"}, 600000); }

/// troupe-node of the tree at `root` serving its bundled kinematic config
/// on a free port; stopped when the test ends.
class InstalledNode {
 public:
  bool start(const std::string& root, std::string& error) {
    port_ = free_port();
    if (!node_.start({root + "/bin/troupe-node", root + "/share/troupe/nodes/kinematic.json", "--port",
                      std::to_string(port_)},
                     kScratch, "node", error)) {
      return false;
    }
    if (!wait_for_listener(port_, 30)) {
      error = "troupe-node did not listen: " + node_.err();
      return false;
    }
    return true;
  }
  uint16_t port() const { return port_; }
  int stop() { return node_.stop(); }

 private:
  ChildProcess node_;
  uint16_t port_ = 0;
};

TEST(Install, ThePrefixHoldsToolsDataLibraryAndPythonPackage) {
  for (const char* part :
       {"bin/troupe", "bin/troupe-node", "bin/troupe-sim", "bin/troupe-record", "bin/troupe-view",
        "bin/troupe-emulate-p2os", "bin/troupe-emulate-sick", "bin/troupe-emulate-odrive",
        "share/troupe/schemas/message.fbs", "share/troupe/schemas/position2d.fbs",
        "share/troupe/viewer/index.html", "share/troupe/nodes/kinematic.json",
        "include/troupe/wire/client/proxies.h", "include/troupe/wire/schemas/message_generated.h",
        "lib/libtroupe_client.a", "lib/libtroupe_wire.a", "lib/cmake/Troupe/TroupeConfig.cmake",
        "lib/pkgconfig/troupe-client.pc", "lib/python3/dist-packages/troupe/__init__.py",
        "lib/python3/dist-packages/troupe/message.bfbs"}) {
    EXPECT_TRUE(exists(kPrefix + "/" + part)) << part;
  }
  // The examples' programs are for trying in the tree, not installed.
  EXPECT_FALSE(exists(kPrefix + "/bin/swarm-clients"));
}

TEST(Install, EveryListedCommandRunsFromTheInstalledTree) {
  expect_every_listed_command_has_help(kPrefix + "/bin/troupe");
}

TEST(Install, AProgramBuiltWithFindPackageDrivesTheInstalledNode) {
  const std::string build = kScratch + "/consumer-cmake";
  remove_tree(build);
  ProgramResult configure = sh(std::string(CMAKE_COMMAND) + " -G Ninja -S " + TROUPE_SOURCE_DIR +
                               "/tests/install/consumer -B " + build + " -DCMAKE_MAKE_PROGRAM=" + MAKE_PROGRAM +
                               " -DCMAKE_CXX_COMPILER=" + CXX_COMPILER + " -DCMAKE_PREFIX_PATH=" + kPrefix);
  ASSERT_EQ(configure.status, 0) << configure.out;
  ProgramResult built = sh(std::string(CMAKE_COMMAND) + " --build " + build);
  ASSERT_EQ(built.status, 0) << built.out;
  // The headers came from the prefix, not from the source tree.
  ProgramResult deps = sh(std::string(MAKE_PROGRAM) + " -C " + build + " -t deps");
  EXPECT_NE(deps.out.find(kPrefix + "/include/troupe/wire/client/proxies.h"), std::string::npos) << deps.out;
  EXPECT_EQ(deps.out.find(std::string(TROUPE_SOURCE_DIR) + "/wire/"), std::string::npos) << deps.out;

  InstalledNode node;
  std::string error;
  ASSERT_TRUE(node.start(kPrefix, error)) << error;
  ProgramResult run = run_to_end({build + "/consumer", "127.0.0.1", std::to_string(node.port())}, 60000);
  EXPECT_EQ(run.status, 0) << run.out << run.err;
  EXPECT_EQ(run.out.rfind("devices=1 moved_m=", 0), 0u) << run.out;
  EXPECT_EQ(node.stop(), 0);
}

TEST(Install, AProgramBuiltWithPkgConfigDrivesTheInstalledNode) {
  const std::string program = kScratch + "/consumer-pkg-config";
  ProgramResult built =
      sh("PKG_CONFIG_PATH=" + quote(kPrefix + "/lib/pkgconfig") + " && export PKG_CONFIG_PATH && " +
         CXX_COMPILER + " " + TROUPE_SOURCE_DIR + "/tests/install/consumer/main.cc -o " + program + " $(" +
         PKG_CONFIG + " --cflags --libs troupe-client)");
  ASSERT_EQ(built.status, 0) << built.out;
  InstalledNode node;
  std::string error;
  ASSERT_TRUE(node.start(kPrefix, error)) << error;
  ProgramResult run = run_to_end({program, "127.0.0.1", std::to_string(node.port())}, 60000);
  EXPECT_EQ(run.status, 0) << run.out << run.err;
  EXPECT_EQ(run.out.rfind("devices=1 moved_m=", 0), 0u) << run.out;
  EXPECT_EQ(node.stop(), 0);
}

TEST(Install, ThePythonClientRunsFromTheInstalledTree) {
  if (std::string(PYTHON).empty()) GTEST_SKIP() << "no python3 with the flatbuffers module (python3-flatbuffers)";
  InstalledNode node;
  std::string error;
  ASSERT_TRUE(node.start(kPrefix, error)) << error;
  const std::string site = kPrefix + "/lib/python3/dist-packages";
  ProgramResult run = sh("cd / && PYTHONPATH=" + quote(site) + " " + PYTHON + " " + TROUPE_SOURCE_DIR +
                         "/tests/install/client_check.py 127.0.0.1 " + std::to_string(node.port()));
  EXPECT_EQ(run.status, 0) << run.out;
  EXPECT_EQ(run.out.rfind(site + "/troupe/__init__.py\n", 0), 0u) << run.out;
  EXPECT_NE(run.out.find("devices=1 x="), std::string::npos) << run.out;
  EXPECT_EQ(node.stop(), 0);
}

/// The value of `field` in dpkg-deb -f output ("Field: value").
std::string field(const std::string& fields, const std::string& name) {
  size_t at = ("\n" + fields).find("\n" + name + ": ");
  if (at == std::string::npos) return "";
  at += name.size() + 2;
  return fields.substr(at, fields.find('\n', at) - at);
}

TEST(Install, TheHostPackageHoldsTheToolsAndRunsUnpacked) {
  const std::string out = kScratch + "/package";
  remove_tree(out);
  ProgramResult packed = sh(std::string(CPACK_COMMAND) + " -G DEB -B " + out + " --config " + TROUPE_BINARY_DIR +
                            "/CPackConfig.cmake");
  ASSERT_EQ(packed.status, 0) << packed.out;
  ProgramResult found = sh("ls " + out + "/*.deb");
  ASSERT_EQ(found.status, 0) << found.out;
  const std::string deb = found.out.substr(0, found.out.find('\n'));
  ProgramResult fields = sh("dpkg-deb -f " + deb);
  ASSERT_EQ(fields.status, 0) << fields.out;
  EXPECT_EQ(field(fields.out, "Package"), "troupe") << fields.out;
  EXPECT_EQ(field(fields.out, "Provides"), "troupe-node") << fields.out;
  const std::string depends = ", " + field(fields.out, "Depends") + ",";

  const std::string root = kScratch + "/package-root";
  remove_tree(root);
  ProgramResult unpacked = sh("dpkg-deb -x " + deb + " " + root);
  ASSERT_EQ(unpacked.status, 0) << unpacked.out;
  for (const char* part : {"usr/bin/troupe", "usr/bin/troupe-sim", "usr/share/troupe/schemas/message.fbs",
                           "usr/lib/cmake/Troupe/TroupeConfig.cmake",
                           "usr/lib/python3/dist-packages/troupe/__init__.py"}) {
    EXPECT_TRUE(exists(root + "/" + part)) << part;
  }
  // No service on a desktop: the robot boards' bundles carry that.
  EXPECT_FALSE(exists(root + "/usr/lib/systemd/system/troupe-node.service"));

  // Every library a program loads comes from a package the .deb depends on.
  ProgramResult libs = sh("ldd " + root + "/usr/bin/* | awk '/=> \\//{print $3}' | sort -u");
  ASSERT_EQ(libs.status, 0) << libs.out;
  std::istringstream lines(libs.out);
  for (std::string lib; std::getline(lines, lib);) {
    // A sanitized build's runtime is not something the package promises.
    if (lib.find("/libasan.") != std::string::npos || lib.find("/libubsan.") != std::string::npos) continue;
    // With /usr merged, ldd may name /lib/... for a file dpkg knows as /usr/lib/..., or the other way.
    std::string other = lib.rfind("/usr/", 0) == 0 ? lib.substr(4) : "/usr" + lib;
    ProgramResult owner = sh("(dpkg -S " + quote(lib) + " || dpkg -S " + quote(other) +
                             ") 2>/dev/null | head -n 1 | cut -d: -f1");
    std::string package = owner.out.substr(0, owner.out.find('\n'));
    EXPECT_FALSE(package.empty()) << "no package owns " << lib;
    EXPECT_NE(depends.find(" " + package + ","), std::string::npos) << lib << " is from " << package
                                                                    << ", not in Depends:" << depends;
  }

  // The unpacked tools work: the node serves, troupe lists its devices.
  InstalledNode node;
  std::string error;
  ASSERT_TRUE(node.start(root + "/usr", error)) << error;
  TroupeRun ls = run_troupe(root + "/usr/bin/troupe", "ls 127.0.0.1:" + std::to_string(node.port()));
  EXPECT_EQ(ls.rc, 0) << ls.err;
  EXPECT_EQ(ls.out.rfind("position2d:0\t", 0), 0u) << ls.out;
  EXPECT_EQ(node.stop(), 0);
}

}  // namespace
}  // namespace troupe::testing
