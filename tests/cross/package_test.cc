// The Depends of a board's .deb, computed from troupe-node when CPack packs
// it (boards/deb_depends.cmake): checked against the versions the binary
// needs from each library, and against dpkg itself, which must refuse the
// package on a system whose libc is too old for it and accept it on one
// just recent enough.
//
// dpkg, not apt: apt would need the package lists of a target archive
// (network); dpkg decides from its status file alone. Each check uses a
// scratch root and a scratch dpkg database whose status file lists the
// target's libc6, libstdc++6 and libgcc-s1 at chosen versions (no files:
// only the database says they are there). `dpkg --unpack` puts the package
// in (no script of ours runs: the bundle has no preinst), and
// `dpkg --no-act --configure` says whether its dependencies are satisfied
// without running its postinst.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "tests/cross/cross_build.h"

namespace troupe::cross {
namespace {

std::string package_path(const CrossBuild& b) {
  return b.path("troupe-node-" + b.board + "-0.1.0-" + b.deb_arch + ".deb");
}

// "libc6 (>= 2.35), libstdc++6 (>= 11)" -> {libc6: 2.35, libstdc++6: 11};
// a dependency without a version maps to "".
std::map<std::string, std::string> parse_depends(const std::string& field) {
  std::map<std::string, std::string> out;
  std::istringstream items(field);
  std::string item;
  while (std::getline(items, item, ',')) {
    size_t begin = item.find_first_not_of(' ');
    if (begin == std::string::npos) continue;
    size_t end = item.find_first_of(" (", begin);
    std::string name = item.substr(begin, end - begin);
    size_t ge = item.find(">=");
    std::string floor;
    if (ge != std::string::npos) {
      size_t v = item.find_first_not_of(' ', ge + 2);
      floor = item.substr(v, item.find(')', v) - v);
    }
    out[name] = floor;
  }
  return out;
}

std::string depends_field(const std::string& package) {
  std::string out;
  run("dpkg-deb -f " + quote(package) + " Depends", out);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}

// dpkg's version order.
bool version_at_least(const std::string& a, const std::string& b) {
  std::string out;
  return run("dpkg --compare-versions " + quote(a) + " ge " + quote(b), out) == 0;
}

// The binary's dynamic needs: NEEDED libraries, and per library the
// version tags it needs (readelf's version needs section).
struct Needs {
  std::set<std::string> libraries;
  std::map<std::string, std::set<std::string>> tags;
};

Needs read_needs(const CrossBuild& b) {
  Needs needs;
  std::string out;
  run(quote(b.readelf) + " --wide --dynamic --version-info " + quote(b.node), out);
  std::istringstream lines(out);
  std::string line, file;
  while (std::getline(lines, line)) {
    size_t at = line.find("Shared library: [");
    if (line.find("(NEEDED)") != std::string::npos && at != std::string::npos) {
      at += 17;
      needs.libraries.insert(line.substr(at, line.find(']', at) - at));
    } else if ((at = line.find("File: ")) != std::string::npos) {
      at += 6;
      file = line.substr(at, line.find(' ', at) - at);
    } else if ((at = line.find("Name: ")) != std::string::npos && !file.empty()) {
      at += 6;
      needs.tags[file].insert(line.substr(at, line.find(' ', at) - at));
    }
  }
  return needs;
}

// The Debian version that brought version tag `tag`, from Debian's symbols
// files of `packages` (lines " TAG@TAG VERSION"); "" when none dates it.
std::string debian_date(const std::string& tag, const std::vector<std::string>& packages) {
  for (const std::string& p : packages) {
    std::string path, out;
    if (run("dpkg-query --control-path " + quote(p) + " symbols 2>/dev/null", path) != 0 || path.empty()) continue;
    path.erase(path.find_last_not_of("\n") + 1);
    std::string needle = " " + tag + "@" + tag + " ";
    run("grep -h -F -e " + quote(needle) + " " + quote(path), out);
    if (out.rfind(needle, 0) == 0) return out.substr(needle.size(), out.find_first_of(" \n", needle.size()) - needle.size());
  }
  return "";
}

// "2.35" -> "2.34": a version just below `floor` (its last number less one).
std::string just_below(const std::string& floor) {
  size_t dot = floor.rfind('.');
  int last = std::stoi(floor.substr(dot + 1));
  return floor.substr(0, dot + 1) + std::to_string(last - 1);
}

// A scratch system for dpkg: an empty root and a database that lists
// `installed` (package -> Debian version) for the target architecture.
class FakeSystem {
 public:
  FakeSystem(const CrossBuild& b, const std::map<std::string, std::string>& installed) {
    dir_ = make_temp_dir("dpkg-" + b.name);
    std::string out;
    run("mkdir -p " + quote(dir_ + "/root") + " " + quote(dir_ + "/db/info") + " " + quote(dir_ + "/db/updates"),
        out);
    std::string native;
    run("dpkg --print-architecture", native);
    write(dir_ + "/db/arch", native + b.deb_arch + "\n");
    write(dir_ + "/db/available", "");
    std::string status;
    for (const auto& [name, version] : installed) {
      status += "Package: " + name + "\nStatus: install ok installed\nPriority: optional\nSection: libs\n" +
                "Installed-Size: 1\nMaintainer: Troupe tests <tests@troupe.invalid>\nArchitecture: " +
                b.deb_arch + "\nMulti-Arch: same\nVersion: " + version + "\nDescription: stands in\n\n";
    }
    write(dir_ + "/db/status", status);
  }
  ~FakeSystem() {
    std::string ignored;
    run("rm -rf " + quote(dir_), ignored);
  }

  /// Unpacks `package`, then asks dpkg whether it could configure it.
  /// Returns dpkg's exit status of the second step; `out` gets both outputs.
  int install(const std::string& package, std::string& out) {
    std::string dpkg = "dpkg --root=" + quote(dir_ + "/root") + " --admindir=" + quote(dir_ + "/db") +
                       " --force-not-root ";
    if (int rc = run(dpkg + "--unpack " + quote(package) + " 2>&1", out); rc != 0) return 100 + rc;
    std::string unpacked = out;
    std::string name;
    run("dpkg-deb -f " + quote(package) + " Package", name);
    name.erase(name.find_last_not_of("\n") + 1);
    int rc = run(dpkg + "--no-act --configure " + quote(name) + " 2>&1", out);
    out = unpacked + out;
    return rc;
  }

 private:
  static void write(const std::string& path, const std::string& text) {
    FILE* f = fopen(path.c_str(), "w");
    ASSERT_NE(f, nullptr) << path;
    fputs(text.c_str(), f);
    fclose(f);
  }
  std::string dir_;
};

// The Debian package of each library a dynamic node loads.
const std::map<std::string, std::string> kPackageOf = {
    {"libc.so.6", "libc6"},
    {"libm.so.6", "libc6"},
    {"libstdc++.so.6", "libstdc++6"},
    {"libgcc_s.so.1", "libgcc-s1"},
    // Secure boards (BOARD_SECURE) linked against Debian's shared libsodium.
    {"libsodium.so.23", "libsodium23"}};

std::string build_test_name(const ::testing::TestParamInfo<const char*>& param_info) {
  return test_name_of(param_info.param);
}

class DynamicPackage : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    std::string why;
    if (!load_cross_build(GetParam(), b_, why)) {
      GTEST_SKIP() << why;
    }
    ASSERT_FALSE(b_.is_static);
    depends_ = parse_depends(depends_field(package_path(b_)));
    needs_ = read_needs(b_);
  }
  CrossBuild b_;
  std::map<std::string, std::string> depends_;
  Needs needs_;
};

TEST_P(DynamicPackage, DependsOnWhatTheBinaryNeedsAtTheVersionsItNeeds) {
  ASSERT_FALSE(needs_.libraries.empty()) << b_.node << " loads no library: is it static?";
  for (const std::string& lib : needs_.libraries) {
    ASSERT_TRUE(kPackageOf.count(lib)) << "the node of " << b_.name << " loads " << lib << ", which this test "
                                       << "does not know: add its package to kPackageOf";
    EXPECT_TRUE(depends_.count(kPackageOf.at(lib))) << kPackageOf.at(lib) << " missing from the Depends of "
                                                    << package_path(b_);
  }
  // libc6: the newest GLIBC_x.y the binary needs from any of glibc's
  // libraries, exactly (a higher floor would refuse systems that run it).
  std::string newest_glibc;
  for (const auto& [lib, tags] : needs_.tags) {
    if (!kPackageOf.count(lib) || kPackageOf.at(lib) != "libc6") continue;
    for (const std::string& tag : tags) {
      ASSERT_EQ(tag.rfind("GLIBC_", 0), 0u) << lib << " " << tag;
      std::string v = tag.substr(6);
      if (newest_glibc.empty() || !version_at_least(newest_glibc, v)) newest_glibc = v;
    }
  }
  ASSERT_FALSE(newest_glibc.empty());
  EXPECT_EQ(depends_["libc6"], newest_glibc) << depends_field(package_path(b_));

  // libstdc++6 and libgcc-s1: at least the Debian version that brought each
  // tag (Debian's symbols files date them), and no more than the newest.
  const std::vector<std::pair<std::string, std::vector<std::string>>> dated = {
      {"libstdc++.so.6", {"libstdc++6"}}, {"libgcc_s.so.1", {"libgcc-s1-" + b_.deb_arch + "-cross", "libgcc-s1"}}};
  for (const auto& [lib, symbols] : dated) {
    if (!needs_.libraries.count(lib)) continue;
    const std::string& floor = depends_[kPackageOf.at(lib)];
    ASSERT_FALSE(floor.empty()) << lib << ": " << depends_field(package_path(b_));
    std::string newest;
    for (const std::string& tag : needs_.tags[lib]) {
      std::string date = debian_date(tag, symbols);
      ASSERT_FALSE(date.empty()) << "no Debian symbols file dates " << tag << " of " << lib;
      EXPECT_TRUE(version_at_least(floor, date)) << lib << " " << tag << " came with " << date << ", Depends says "
                                                 << floor;
      if (newest.empty() || !version_at_least(newest, date)) newest = date;
    }
    EXPECT_EQ(floor, newest) << lib;
  }
}

TEST_P(DynamicPackage, DpkgRefusesItWhereLibcIsTooOldAndTakesItWhereLibcSuffices) {
  ASSERT_FALSE(depends_["libc6"].empty()) << depends_field(package_path(b_));
  std::map<std::string, std::string> installed;
  for (const auto& [name, floor] : depends_) installed[name] = (floor.empty() ? "1" : floor) + "-1";

  // One minor release of glibc too old (Debian 11 has 2.31, the binary
  // needs e.g. 2.35): dpkg refuses, naming libc6 and the version it needs.
  std::string too_old = just_below(depends_["libc6"]) + "-1";
  installed["libc6"] = too_old;
  {
    FakeSystem system(b_, installed);
    std::string out;
    EXPECT_NE(system.install(package_path(b_), out), 0) << out;
    EXPECT_NE(out.find("depends on libc6 (>= " + depends_["libc6"] + ")"), std::string::npos) << out;
    EXPECT_NE(out.find("Version of libc6:" + b_.deb_arch + " on system is " + too_old), std::string::npos) << out;
  }
  // Exactly the glibc it needs (Ubuntu 22.04's 2.35 for a node needing
  // 2.35): dpkg would configure it.
  installed["libc6"] = depends_["libc6"] + "-1";
  {
    FakeSystem system(b_, installed);
    std::string out;
    EXPECT_EQ(system.install(package_path(b_), out), 0) << out;
    EXPECT_NE(out.find("Setting up troupe-node-" + b_.board), std::string::npos) << out;
  }
  // Without libstdc++ at all: refused too.
  installed.erase("libstdc++6");
  {
    FakeSystem system(b_, installed);
    std::string out;
    EXPECT_NE(system.install(package_path(b_), out), 0) << out;
    EXPECT_NE(out.find("libstdc++6"), std::string::npos) << out;
  }
}

INSTANTIATE_TEST_SUITE_P(Boards, DynamicPackage,
                         ::testing::Values("core-armhf", "ppc-node-armhf", "diffbot-can-arm64"),
                         build_test_name);

// A static node loads no library: its package depends on nothing and
// installs on a system that has no libc package at all.
class StaticPackage : public ::testing::TestWithParam<const char*> {};

TEST_P(StaticPackage, DependsOnNothingAndInstallsOnAnEmptySystem) {
  CrossBuild b;
  if (std::string why; !load_cross_build(GetParam(), b, why)) {
    GTEST_SKIP() << why;
  }
  ASSERT_TRUE(b.is_static);
  EXPECT_TRUE(read_needs(b).libraries.empty());
  EXPECT_EQ(depends_field(package_path(b)), "");
  FakeSystem system(b, {});
  std::string out;
  EXPECT_EQ(system.install(package_path(b), out), 0) << out;
  EXPECT_NE(out.find("Setting up troupe-node-" + b.board), std::string::npos) << out;
}

INSTANTIATE_TEST_SUITE_P(Boards, StaticPackage, ::testing::Values("ppc-node-armhf-static", "ppc-node-arm64-static"),
                         build_test_name);

}  // namespace
}  // namespace troupe::cross
