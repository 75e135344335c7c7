// Reading a rendered camera image in tests: one pixel's colour and depth.
#pragma once

#include <cstdint>

#include "host-sim/sim/world.h"

namespace troupe::sim::test {

/// Renders camera `index` now (wanted, sensors refreshed) and returns it.
inline CameraView render(World& w, uint32_t index = 0) {
  w.set_wanted({SensorKind::Camera, index}, true);
  w.refresh_sensors();
  return w.camera(index);
}

/// Pixel (u, row) as 0x00RRGGBB.
inline uint32_t pixel(const CameraView& v, int u, int row) {
  const uint8_t* p = v.rgb.data() + (size_t(row) * size_t(v.width) + size_t(u)) * 3;
  return uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2];
}

/// Pixel (u, row)'s distance along its ray, m.
inline float depth(const CameraView& v, int u, int row) {
  return v.depth[size_t(row) * size_t(v.width) + size_t(u)];
}

}  // namespace troupe::sim::test
