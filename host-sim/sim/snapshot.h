// Headless pictures of a world: the obstacle grid, every robot's outline in
// its colour with a nose, and the beams of the rangers that have data.
#pragma once

#include <string>

#include "host-sim/sim/world.h"
#include "host-sim/world/png_image.h"

namespace troupe::sim {

struct SnapshotOptions {
  /// Pixels per metre; 0 picks one that fits `max_pixels` on the longer side
  /// (or the world file's window scale when it fits).
  double scale = 0;
  int max_pixels = 1600;
  bool beams = true;
};

/// Draws the world as it is now.
world::RgbImage render(const World& world, const SnapshotOptions& options = {});
/// Draws and writes a PNG. False with `error`.
bool write_snapshot(const World& world, const std::string& path, std::string& error,
                    const SnapshotOptions& options = {});

}  // namespace troupe::sim
