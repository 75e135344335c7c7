#include "drivers/mcl/map_fetch.h"

#include <algorithm>
#include <cmath>

#include "runtime/node.h"

namespace troupe::drivers::mcl {

bool MapFetch::start(Node& node, Driver& owner, DeviceId map_device) {
  node_ = &node;
  owner_ = &owner;
  device_ = map_device;
  busy_ = true;
  node.begin();
  if (!node.request(device_, uint8_t(wire::MapReqSub::Info), ++seq_, wire::Body::NONE, 0, owner_)) {
    busy_ = false;
    return false;
  }
  return true;
}

bool MapFetch::request_next() {
  uint32_t w = std::min(kTileCells, grid_.width() - next_col_);
  uint32_t h = std::min(kTileCells, grid_.height() - next_row_);
  auto& b = node_->begin();
  auto body = wire::CreateMapTileRequest(b, next_col_, next_row_, w, h);
  return node_->request(device_, uint8_t(wire::MapReqSub::Tile), ++seq_, wire::Body::MapTileRequest,
                        body.Union(), owner_);
}

bool MapFetch::on_reply(const wire::Message& reply, std::string& error) {
  if (!busy_ || reply.header()->seq() != seq_) return false;  // stale: an earlier fetch
  if (reply.header()->kind() != wire::Kind::Ack) {
    busy_ = false;
    const wire::Error* e = reply.body_as_Error();
    error = "map request refused: " + std::string(e && e->text() ? e->text()->c_str() : "no reason given");
    return false;
  }
  if (const wire::MapInfo* info = reply.body_as_MapInfo()) {
    if (info->width() == 0 || info->height() == 0 || !(info->resolution() > 0) ||
        uint64_t(info->width()) * info->height() > desktop::kMaxGridCells) {
      busy_ = false;
      error = "map info is unusable: " + std::to_string(info->width()) + "x" +
              std::to_string(info->height()) + " cells of " + std::to_string(info->resolution()) + " m";
      return false;
    }
    desktop::Pose2 origin;
    if (info->origin()) origin = {info->origin()->x(), info->origin()->y(), info->origin()->a()};
    grid_ = desktop::OccupancyGrid(info->width(), info->height(), info->resolution(), origin);
    next_col_ = next_row_ = 0;
  } else if (const wire::MapTile* tile = reply.body_as_MapTile()) {
    if (tile->col() != next_col_ || tile->row() != next_row_ || tile->cells() == nullptr ||
        !grid_.unpack(tile->col(), tile->row(), tile->width(), tile->height(), tile->cells()->data(),
                      tile->cells()->size())) {
      busy_ = false;
      error = "map tile at (" + std::to_string(tile->col()) + ", " + std::to_string(tile->row()) +
              ") does not fit the map or is short";
      return false;
    }
    next_col_ += tile->width();
    if (next_col_ >= grid_.width()) {
      next_col_ = 0;
      next_row_ += tile->height();
    }
    if (next_row_ >= grid_.height()) {
      busy_ = false;
      return true;
    }
  } else {
    busy_ = false;
    error = "map reply without MapInfo or MapTile";
    return false;
  }
  if (!request_next()) {
    busy_ = false;
    error = "no request slot for the next map tile";
  }
  return false;
}

}  // namespace troupe::drivers::mcl
