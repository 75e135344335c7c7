// Reading a rendered camera image in tests: one pixel's colour and depth.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host-sim/sim/loader.h"
#include "host-sim/sim/world.h"
#include "tests/sim/scenes.h"
#include "tests/sim/temp_dir.h"

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

/// Adds six robots of different colours and heights along a diagonal
/// from (x0, -2) m, for a camera to watch them move.
inline void add_movers(WorldDesc& d, double x0) {
  for (int i = 0; i < 6; ++i) {
    RobotDesc r = robot("r" + std::to_string(i), {x0 + 0.7 * i, -2.0 + 0.8 * i, 0.3 * i});
    r.look.color = 0x00FF00u + uint32_t(i) * 0x20u;
    r.look.height = 0.3 + 0.2 * i;
    d.robots.push_back(r);
  }
}

/// Camera 0's colour and depth bytes after 20 steps (seed 42) with every
/// robot but the first driving in circles.
inline std::vector<uint8_t> camera_bytes_after_steps(const WorldDesc& d) {
  World w(d, Random(42));
  w.set_wanted({SensorKind::Camera, 0}, true);
  for (RobotId r = 1; r < w.robot_count(); ++r) w.command(r, Command::velocity(0.2, 0, 0.3));
  for (int s = 0; s < 20; ++s) w.step();
  const CameraView v = w.camera(0);
  std::vector<uint8_t> bytes(v.rgb.begin(), v.rgb.end());
  const auto* f = reinterpret_cast<const uint8_t*>(v.depth.data());
  bytes.insert(bytes.end(), f, f + v.depth.size() * sizeof(float));
  return bytes;
}

/// Loads a world whose one robot carries a camera with `keys` (on line 2
/// of c.world). True when the load failed with an error at that line;
/// `diags` gets the messages.
inline bool camera_keys_refused_at_their_line(const std::string& keys, std::string& diags) {
  troupe::test::TempDir dir;
  world::Diagnostics d;
  WorldDesc desc;
  const bool loaded =
      load_world_file(dir.write("c.world", "position ( name \"r0\"\n  camera ( " + keys + " ) )\n"), desc, d);
  diags = d.str();
  return !loaded && diags.find("c.world:2") != std::string::npos;
}

}  // namespace troupe::sim::test
