// mapfile: serves an occupancy map read from a PNG through the map
// interface, for localizers (mcl) and viewers.
//
// Provides: map (exactly one).
// Requests: Info (size, resolution, origin), Tile (a block of cells, two
// bits each; at most kMaxTileCells cells, so a reply always fits a frame).
#pragma once

#include "drivers/common_desktop/occupancy_grid.h"
#include "runtime/driver.h"
#include "runtime/node_config.h"

namespace troupe::drivers::mapfile {

/// The largest tile served: 512 x 512 cells, 64 KiB packed.
inline constexpr uint64_t kMaxTileCells = 512 * 512;

class MapFile : public Driver {
 public:
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;

  const desktop::OccupancyGrid& grid() const { return grid_; }

 private:
  DeviceId device_ = kNoDevice;
  desktop::OccupancyGrid grid_;
  std::vector<uint8_t> packed_;
};

}  // namespace troupe::drivers::mapfile
