// The inputs a world takes from outside (World::set_journal), as records:
// a kind byte, then the input's own values. Private to host-sim/sim.
#pragma once

#include <cstdint>
#include <vector>

#include "host-sim/sim/bytes.h"
#include "host-sim/sim/world.h"

namespace troupe::sim {

enum class Input : uint8_t { Velocity, Goto, Teleport, Odometry, Wanted, Gripper, CameraSize };

inline void journal_pose(std::vector<std::byte>& j, Input kind, RobotId id, const Pose& p) {
  bytes::put(j, kind);
  bytes::put(j, id);
  bytes::put(j, p);
}

inline void journal_wanted(std::vector<std::byte>& j, SensorRef s, bool wanted) {
  bytes::put(j, Input::Wanted);
  bytes::put(j, s.kind);
  bytes::put(j, s.index);
  bytes::put(j, uint8_t(wanted));
}

inline void journal_gripper(std::vector<std::byte>& j, uint32_t index, bool closed) {
  bytes::put(j, Input::Gripper);
  bytes::put(j, index);
  bytes::put(j, uint8_t(closed));
}

inline void journal_camera_size(std::vector<std::byte>& j, uint32_t index, int width, int height) {
  bytes::put(j, Input::CameraSize);
  bytes::put(j, index);
  bytes::put(j, int32_t(width));
  bytes::put(j, int32_t(height));
}

}  // namespace troupe::sim
