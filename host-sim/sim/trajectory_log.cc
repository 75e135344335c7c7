#include "host-sim/sim/trajectory_log.h"

#include <cerrno>
#include <cstring>

namespace troupe::sim {

TrajectoryLog::~TrajectoryLog() {
  close();
}

bool TrajectoryLog::open(const std::string& path, std::string& error) {
  close();
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) {
    error = "cannot write " + path + ": " + std::strerror(errno);
    return false;
  }
  failed_ = std::fputs("time,robot,x,y,a\n", file_) < 0;
  return true;
}

std::string TrajectoryLog::format(const World& world) {
  std::vector<Pose> poses(world.robot_count());
  for (RobotId i = 0; i < world.robot_count(); ++i) poses[i] = world.state(i).pose;
  return format(world, poses);
}

std::string TrajectoryLog::format(const World& world, std::span<const Pose> poses) {
  std::string out;
  char line[256];
  for (RobotId i = 0; i < world.robot_count() && i < poses.size(); ++i) {
    const Pose& p = poses[i];
    std::snprintf(line, sizeof line, "%.3f,%s,%.6f,%.6f,%.6f\n", world.time(), world.robot(i).name.c_str(),
                  p.x, p.y, p.a);
    out += line;
  }
  return out;
}

void TrajectoryLog::record(const World& world) {
  if (file_ == nullptr) return;
  write(format(world));
}

void TrajectoryLog::record(const World& world, std::span<const Pose> poses) {
  if (file_ == nullptr) return;
  write(format(world, poses));
}

void TrajectoryLog::write(const std::string& lines) {
  if (std::fwrite(lines.data(), 1, lines.size(), file_) != lines.size()) failed_ = true;
}

bool TrajectoryLog::close() {
  if (file_ == nullptr) return !failed_;
  if (std::fclose(file_) != 0) failed_ = true;
  file_ = nullptr;
  return !failed_;
}

}  // namespace troupe::sim
