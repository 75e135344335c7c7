// Fetches a whole occupancy grid from a map device of the same node, tile by
// tile, through driver-to-driver requests (Node::request): the same Info and
// Tile requests a client sends, so the map may come from mapfile or from any
// driver serving the map interface.
#pragma once

#include <functional>

#include "drivers/common_desktop/occupancy_grid.h"
#include "runtime/driver.h"

namespace troupe::drivers::mcl {

class MapFetch {
 public:
  /// Tile side requested, cells.
  static constexpr uint32_t kTileCells = 256;

  /// Starts (or restarts) fetching from `map_device` on behalf of `owner`;
  /// false when the request could not be sent.
  bool start(Node& node, Driver& owner, DeviceId map_device);
  /// Feed every on_reply() of the owner for the map device. Returns true
  /// when this reply completed the grid; on a Nack, failed() turns true and
  /// `error` says why.
  bool on_reply(const wire::Message& reply, std::string& error);

  bool busy() const { return busy_; }
  desktop::OccupancyGrid& grid() { return grid_; }

 private:
  bool request_next();

  Node* node_ = nullptr;
  Driver* owner_ = nullptr;
  DeviceId device_ = kNoDevice;
  desktop::OccupancyGrid grid_;
  uint32_t next_col_ = 0, next_row_ = 0;
  uint32_t seq_ = 0;
  bool busy_ = false;
};

}  // namespace troupe::drivers::mcl
