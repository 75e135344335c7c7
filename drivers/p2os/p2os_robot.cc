#include "drivers/p2os/p2os_robot.h"

#include <strings.h>

namespace troupe::drivers::p2os {
namespace {

constexpr float kDegToRad = 3.14159265358979f / 180.0f;

constexpr SonarPose sonar(float x_mm, float y_mm, float a_deg) {
  return {x_mm / 1000.0f, y_mm / 1000.0f, a_deg * kDegToRad};
}

// The Pioneer 2/3-DX ring: eight front transducers, then eight rear ones,
// counter-clockwise from the left side (protocols.md).
constexpr SonarPose kDxRing[16] = {
    sonar(69, 136, 90),     sonar(114, 119, 50),     sonar(148, 78, 30),     sonar(166, 27, 10),
    sonar(166, -27, -10),   sonar(148, -78, -30),    sonar(114, -119, -50),  sonar(69, -136, -90),
    sonar(-157, -136, -90), sonar(-203, -119, -130), sonar(-237, -78, -150), sonar(-255, -27, -170),
    sonar(-255, 27, 170),   sonar(-237, 78, 150),    sonar(-203, 119, 130),  sonar(-157, 136, 90),
};

// Footprint 0.511 x 0.400 m; the sonar reads up to 5 m.
constexpr RobotParams kRobots[] = {
    {"p3dx-sh", 0.001534, 1.0, 1.0, 1.0, 0.0056, 20, 2.2f, 500 * kDegToRad, 0.511f, 0.400f, 5.0f, 16,
     kDxRing},
    {"p3dx", 0.001534, 0.485, 1.0, 1.0, 0.0056, 20, 2.2f, 500 * kDegToRad, 0.511f, 0.400f, 5.0f, 16, kDxRing},
};

}  // namespace

const RobotParams* find_robot(std::string_view subclass) {
  for (const RobotParams& r : kRobots) {
    std::string_view name(r.subclass);
    if (name.size() == subclass.size() && strncasecmp(name.data(), subclass.data(), name.size()) == 0)
      return &r;
  }
  return nullptr;
}

std::string known_robots() {
  std::string names;
  for (const RobotParams& r : kRobots) {
    if (!names.empty()) names += ", ";
    names += r.subclass;
  }
  return names;
}

}  // namespace troupe::drivers::p2os
