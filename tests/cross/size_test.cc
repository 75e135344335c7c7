// The size budget and the contents of board builds, read from the binaries
// the cross builds made: the armhf core within 64 KiB stripped, linked
// against the target's shared libc/libstdc++, and every board's symbol
// table holding the code of its own drivers and of no other.
#include <dirent.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <set>
#include <sstream>

#include "tests/cross/cross_build.h"

namespace troupe::cross {
namespace {

constexpr long kCoreBudgetBytes = 64 * 1024;

struct Sizes {
  long file_bytes = 0;  // the stripped file
  long text = 0, data = 0, bss = 0;
};

// Strips a copy of the node and measures it: file size, and the Berkeley
// text/data/bss that `size` reports.
Sizes stripped_sizes(const CrossBuild& b, std::string& error) {
  Sizes s;
  std::string dir = make_temp_dir("size-" + b.name);
  std::string stripped = dir + "/troupe-node";
  std::string out;
  if (run(quote(b.strip) + " -o " + quote(stripped) + " " + quote(b.node), out) != 0) {
    error = "strip failed for " + b.node;
    return s;
  }
  struct stat st {};
  stat(stripped.c_str(), &st);
  s.file_bytes = long(st.st_size);
  run(quote(b.size) + " -B " + quote(stripped), out);
  std::istringstream lines(out);
  std::string header;
  std::getline(lines, header);
  lines >> s.text >> s.data >> s.bss;
  run("rm -rf " + quote(dir), out);
  return s;
}

// Driver namespaces found in the unstripped symbol table:
// "troupe::drivers::<name>::...".
std::set<std::string> driver_namespaces(const CrossBuild& b) {
  std::string out;
  run(quote(b.nm) + " -C " + quote(b.node), out);
  std::set<std::string> found;
  const std::string prefix = "troupe::drivers::";
  for (size_t at = out.find(prefix); at != std::string::npos; at = out.find(prefix, at + 1)) {
    size_t begin = at + prefix.size();
    size_t end = out.find("::", begin);
    if (end != std::string::npos) found.insert(out.substr(begin, end - begin));
  }
  return found;
}

std::set<std::string> all_driver_folders() {
  std::set<std::string> names;
  std::string root = std::string(TROUPE_SOURCE_DIR) + "/drivers";
  DIR* d = opendir(root.c_str());
  while (dirent* e = d ? readdir(d) : nullptr) {
    std::string name = e->d_name;
    struct stat st {};
    if (name[0] != '.' && stat((root + "/" + name + "/" + name + ".fbs").c_str(), &st) == 0)
      names.insert(name);
  }
  if (d) closedir(d);
  return names;
}

TEST(CoreSize, ArmhfCoreIsWithin64KiBStripped) {
  CrossBuild b;
  if (std::string why; !load_cross_build("core-armhf", b, why)) {
    GTEST_SKIP() << why;
  }
  ASSERT_EQ(b.board, "core");
  ASSERT_TRUE(b.drivers.empty());
  std::string error;
  Sizes s = stripped_sizes(b, error);
  ASSERT_EQ(error, "");
  printf("armhf core, stripped: file %ld bytes, text %ld + data %ld = %ld bytes (budget %ld)\n", s.file_bytes,
         s.text, s.data, s.text + s.data, kCoreBudgetBytes);
  EXPECT_GT(s.text, 0);
  EXPECT_LE(s.text + s.data, kCoreBudgetBytes);
  EXPECT_LE(s.file_bytes, kCoreBudgetBytes);
}

TEST(CoreSize, ArmhfCoreLinksTheTargetsSharedLibraries) {
  CrossBuild b;
  if (std::string why; !load_cross_build("core-armhf", b, why)) {
    GTEST_SKIP() << why;
  }
  std::string dynamic, headers;
  ASSERT_EQ(run(quote(b.readelf) + " -d " + quote(b.node), dynamic), 0);
  ASSERT_EQ(run(quote(b.readelf) + " -lW " + quote(b.node), headers), 0);
  // Small because libc and libstdc++ are the board's, not inside the node.
  EXPECT_NE(dynamic.find("Shared library: [libc.so.6]"), std::string::npos) << dynamic;
  EXPECT_NE(dynamic.find("Shared library: [libstdc++.so.6]"), std::string::npos) << dynamic;
  EXPECT_NE(headers.find("Requesting program interpreter: /lib/ld-linux-armhf.so.3"), std::string::npos)
      << headers;
}

TEST(BoardContents, CoreHoldsNoDriverCode) {
  CrossBuild b;
  if (std::string why; !load_cross_build("core-armhf", b, why)) {
    GTEST_SKIP() << why;
  }
  // Drivers exist that the core could have picked up; it holds none.
  ASSERT_FALSE(all_driver_folders().empty());
  std::set<std::string> found = driver_namespaces(b);
  EXPECT_TRUE(found.empty()) << "driver code in the core: " << ::testing::PrintToString(found);
}

TEST(BoardContents, BoardHoldsExactlyItsDrivers) {
  CrossBuild b;
  if (std::string why; !load_cross_build("ppc-node-powerpc", b, why)) {
    GTEST_SKIP() << why;
  }
  std::set<std::string> listed(b.drivers.begin(), b.drivers.end());
  ASSERT_TRUE(listed.count("kinematic")) << "boards/ppc-node lists kinematic";
  EXPECT_EQ(driver_namespaces(b), listed);
  std::string symbols;
  run(quote(b.nm) + " -C " + quote(b.node), symbols);
  EXPECT_NE(symbols.find("troupe::drivers::kinematic::kEntry"), std::string::npos);
  EXPECT_NE(symbols.find("troupe::drivers::kinematic::Kinematic::on_command"), std::string::npos);
}

TEST(BoardContents, PowerpcNodeIsBigEndianPowerpc) {
  CrossBuild b;
  if (std::string why; !load_cross_build("ppc-node-powerpc", b, why)) {
    GTEST_SKIP() << why;
  }
  std::string header;
  ASSERT_EQ(run(quote(b.readelf) + " -h " + quote(b.node), header), 0);
  EXPECT_NE(header.find("big endian"), std::string::npos) << header;
  EXPECT_NE(header.find("PowerPC"), std::string::npos) << header;
}

}  // namespace
}  // namespace troupe::cross
