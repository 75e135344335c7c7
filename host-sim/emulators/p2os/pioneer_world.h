// What the emulated Pioneer's surroundings tell it: how its wheels move it
// and what its sonar, battery and bumpers read. The default is an ideal
// differential drive in an empty 6 x 6 m room with a full battery; tests and
// troupe-sim derive from PioneerWorld to put the robot somewhere else.
#pragma once

#include <cstdint>

#include "drivers/p2os/p2os_robot.h"
#include "host-sim/emulators/serial_line/room.h"

namespace troupe::emulators {

/// The robot's odometric pose: m, m, rad.
struct PioneerPose {
  double x = 0, y = 0, a = 0;
};

/// What the robot's sensors read, once per SIP.
struct PioneerSenses {
  static constexpr int kMaxSonar = 32;
  /// Range each transducer sees, m; beyond the sonar's reach means no echo.
  float sonar_m[kMaxSonar] = {};
  /// Battery, V.
  float battery_v = 12.5f;
  /// Bit i: bumper i of the front / rear ring pressed (0..6).
  uint8_t front_bumpers = 0, rear_bumpers = 0;
};

class PioneerWorld {
 public:
  virtual ~PioneerWorld() = default;
  /// Moves the robot `dt_s` seconds with its wheels at `left_mps` and
  /// `right_mps` (m/s) on a track `track_m` wide, updating its odometric
  /// `pose`. Returns true when the wheels are blocked (the robot reports a
  /// stall). The default rolls freely along the exact arc.
  virtual bool move(double left_mps, double right_mps, double track_m, double dt_s, PioneerPose& pose);
  /// Called before each motion update with the `waited_s` seconds since
  /// the last update that ran; returns the seconds of motion to update for,
  /// 0 to wait. A world that moves the robot by itself at a coarser step
  /// (a simulator) returns 0 between its steps and, once it stepped, the
  /// time it moved the robot, with `pose` the odometry it reached: the
  /// firmware's heading and distance controllers must act on fresh
  /// feedback once per step, or they overrun their target and hunt round
  /// it. The default world moves the robot in move(), at the emulator's
  /// own pace: it returns `waited_s` and leaves `pose` alone.
  virtual double observe(double waited_s, PioneerPose& pose);
  /// Fills what the sensors read with the robot at `pose`. The default
  /// measures the sonar ranges in `room`.
  virtual void sense(const PioneerPose& pose, const drivers::p2os::RobotParams& robot, PioneerSenses& senses);

  Room room;
};

}  // namespace troupe::emulators
