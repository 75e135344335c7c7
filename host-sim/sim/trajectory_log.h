// The trajectory log (--log FILE.csv): one line per robot per step,
// "time,robot,x,y,a" in s, name, m, m, rad. Printed with fixed precision so
// two runs with the same world and seed give byte-identical files.
#pragma once

#include <cstdio>
#include <span>
#include <string>

#include "host-sim/sim/world.h"

namespace troupe::sim {

class TrajectoryLog {
 public:
  TrajectoryLog() = default;
  ~TrajectoryLog();
  TrajectoryLog(const TrajectoryLog&) = delete;
  TrajectoryLog& operator=(const TrajectoryLog&) = delete;

  /// Opens (truncates) `path` and writes the header. False with `error`.
  bool open(const std::string& path, std::string& error);
  /// Appends every robot's ground-truth pose at the world's current time.
  void record(const World& world);
  /// The same with the poses given, one per robot in robot order (world
  /// frame: m, m, rad): a divided world's, gathered from its processes.
  void record(const World& world, std::span<const Pose> poses);
  /// Flushes and closes; false when a write failed (disk full).
  bool close();

  /// The lines record() would write, for tests and in-memory use.
  static std::string format(const World& world);
  static std::string format(const World& world, std::span<const Pose> poses);

 private:
  void write(const std::string& lines);

  FILE* file_ = nullptr;
  bool failed_ = false;
};

}  // namespace troupe::sim
