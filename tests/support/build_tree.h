// Where a build tree keeps what tests load: plugins (sim controllers,
// RoboCup players and referees) in lib/troupe, as in an installed tree.
// TROUPE_BINARY_DIR is the build folder, defined for every test and
// benchmark program by its CMakeLists.
#pragma once

#include <string>

namespace troupe::testing {

/// The folder this build puts loadable plugins in (an absolute path). A
/// test program does not sit in bin/, so the loaders' "../lib/troupe beside
/// the program" does not reach them: tests name this folder.
inline const std::string kPluginDir = TROUPE_BINARY_DIR "/lib/troupe";

}  // namespace troupe::testing
