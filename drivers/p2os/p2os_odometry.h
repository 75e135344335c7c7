// Odometry from SIP counters. The robot integrates its own pose, but sends
// x and y as 15-bit counters that wrap, and a heading counter; this turns
// them into an unbounded pose in metres and radians:
//  - position: wrap-aware deltas of the counters (the shorter way round the
//    15-bit circle) times DistConvFactor, accumulated. A delta over 100 mm
//    in one SIP is not motion at any speed the driver commands: it is a
//    corrupted SIP whose checksum still matched (two bit flips can cancel
//    in P2OS's 16-bit sum) and is rejected, the last good counters kept so
//    the next good SIP loses nothing. Counters that stay far away for
//    kJumpsToRebase SIPs were reset behind our back: they become the
//    reference, without motion;
//  - heading: the counter times AngleConvFactor.
// Clients may move the frame (SetOdometry) and reset it (ResetOdometry: the
// driver also sends SETO, and the robot's counters restart near zero).
#pragma once

#include <cstdint>

#include "drivers/p2os/p2os_protocol.h"
#include "drivers/p2os/p2os_robot.h"
#include "wire/geometry.h"

namespace troupe::drivers::p2os {

/// A planar pose: m, m, rad.
using Pose = geometry::Pose2;

/// Shortest signed difference `to - from` on a circle of `modulus` counts.
int wrap_delta(uint32_t from, uint32_t to, uint32_t modulus);

class Odometry {
 public:
  /// Position jumps larger than this between two SIPs are rejected, mm.
  static constexpr double kMaxJumpMm = 100.0;
  /// SIPs to wait for the robot to act on SETO before giving up.
  static constexpr int kResetWaitSips = 10;
  /// Jumps in a row after which the counters are taken as the reference.
  static constexpr int kJumpsToRebase = 3;

  enum class Update : uint8_t {
    First,         // first SIP since restart(): counters remembered, no motion
    Moved,         // integrated
    JumpRejected,  // a position jump over kMaxJumpMm was not integrated
    JumpAccepted,  // the counters jumped kJumpsToRebase times: a new reference
    Rebased,       // the robot's counters restarted after SETO
    ResetIgnored,  // the robot never showed its counters restarting
  };

  explicit Odometry(const RobotParams& params) : params_(&params) {}

  void set_params(const RobotParams& params) { params_ = &params; }
  /// A new session with the robot: the next SIP only sets the reference,
  /// so motion while disconnected is neither added nor mistaken for a jump.
  void restart() { have_reference_ = false; }
  Update update(const Sip& sip);

  /// The reported pose, m, m, rad (heading in (-pi, pi]).
  Pose pose() const;
  /// Makes the current pose read `p` from now on (SetOdometry).
  void set_pose(const Pose& p);
  /// Makes the current pose read zero, and watches for the robot's counters
  /// to restart after the SETO the driver sends.
  void reset();
  bool reset_pending() const { return reset_wait_ > 0; }

 private:
  Pose robot_pose() const;  // robot's own frame: accumulated position, heading counter

  const RobotParams* params_;
  bool have_reference_ = false;
  uint16_t last_x_ = 0, last_y_ = 0;
  double robot_x_mm_ = 0, robot_y_mm_ = 0;
  double robot_a_ = 0;
  Pose frame_;  // reported = frame_ composed with the robot's pose
  int reset_wait_ = 0;
  int jumps_in_row_ = 0;
};

}  // namespace troupe::drivers::p2os
