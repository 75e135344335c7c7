// What sensor plugins produce each cycle. One struct for every sensor so
// players (and later the wire) can address readings uniformly: odometry
// fills `odometry`, iconic sensors fill `detections`, range sensors fill
// `ranges`.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "host-sim/robocup/api/world_view.h"

namespace troupe::robocup {

enum class ReadingKind : uint8_t { Odometry = 0, Detections = 1, Ranges = 2 };

/// One object seen, in the sensor's frame (x forward, y left).
struct Detection {
  ObjectKind kind = ObjectKind::Ball;
  int id = -1;
  /// Position in the sensor frame, m: the object's centre (ball, robot,
  /// post, goal mouth) or the nearest point (line).
  double x = 0, y = 0;
  /// Lines: the line's direction relative to the sensor, rad.
  /// Robots: their heading relative to the sensor, rad.
  double yaw = 0;
  /// Robots: the team (0 blue, 1 yellow); -1 otherwise.
  int team = -1;

  /// m and rad (counter-clockwise from the sensor's x axis).
  double range() const { return std::hypot(x, y); }
  double bearing() const { return std::atan2(y, x); }
};

struct SensorReading {
  /// The sensor's instance name on its robot (e.g. "omni") and its plugin
  /// (e.g. "omnivision").
  std::string name, model;
  ReadingKind kind = ReadingKind::Detections;
  /// Simulated time of the measurement, s.
  double time_s = 0;
  /// False until the sensor has measured once.
  bool valid = false;

  /// Odometry: pose in the odometry frame (m, rad) and the robot-frame
  /// velocity (m/s, rad/s).
  Pose2 odometry;
  Twist velocity;

  /// Iconic sensors.
  std::vector<Detection> detections;

  /// Range sensors: beam i points at angle_min + i * angle_step (rad, sensor
  /// frame); ranges in m, max_range where nothing was hit.
  double angle_min = 0, angle_step = 0, max_range = 0;
  std::vector<float> ranges;
};

}  // namespace troupe::robocup
