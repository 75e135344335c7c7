// The cross builds the tests run: one board built for one target by the
// set-up step (build_target.sh) under <host build>/cross/<name>, described
// by the board.json that build writes.
#pragma once

#include <string>
#include <vector>

namespace troupe::cross {

struct CrossBuild {
  std::string name;  // "core-armhf": the folder under <host build>/cross
  std::string dir;
  std::string board;
  std::vector<std::string> drivers;
  std::string triple;         // arm-linux-gnueabihf
  std::string deb_arch;       // armhf
  std::string qemu;           // qemu-arm
  std::string loader_prefix;  // /usr/arm-linux-gnueabihf (qemu -L)
  std::string sysroot_lib;    // target libraries of the drivers, or ""
  std::string node;           // troupe-node, unstripped
  bool is_static = false;     // linked fully statically (TROUPE_STATIC)
  std::string strip, nm, size, readelf;

  /// A file of the build, by its path inside the build folder.
  std::string path(const std::string& relative) const { return dir + "/" + relative; }
};

/// Loads the facts of cross build `name`. False with `why` when the build
/// is absent (its set-up step was skipped: no cross compiler) or qemu-user
/// is missing; tests then skip with `why`.
bool load_cross_build(const std::string& name, CrossBuild& out, std::string& why);

/// Runs a shell command; returns its exit status (-1 when it could not run)
/// and its standard output in `out`.
int run(const std::string& command, std::string& out);

/// Quotes `text` for the shell.
std::string quote(const std::string& text);

/// A fresh empty folder under the host build's cross/ folder.
std::string make_temp_dir(const std::string& tag);

std::string read_text(const std::string& path);

/// A cross build's name as a gtest parameter name: "core-armhf" -> "core_armhf".
std::string test_name_of(std::string build_name);

}  // namespace troupe::cross
