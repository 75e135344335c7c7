#include "drivers/mapfile/mapfile.h"

#include <string>

#include "runtime/log.h"
#include "runtime/node.h"

namespace troupe::drivers::mapfile {

bool MapFile::setup(Node& node, const DriverSetup& setup, std::string& error) {
  if (setup.provides.size() != 1 ||
      node.address(setup.provides[0]).iface() != uint16_t(wire::Interface::Map)) {
    error = "mapfile provides exactly one map device";
    return false;
  }
  device_ = setup.provides[0];
  OptionsView<Options> opt(setup);
  if (opt->file() == nullptr || opt->file()->size() == 0) {
    error = "option \"file\" (the PNG map) is missing";
    return false;
  }
  desktop::PngMapOptions png;
  png.resolution = opt->resolution();
  png.origin = {opt->origin_x(), opt->origin_y(), opt->origin_a()};
  png.negate = opt->negate();
  png.occupied_thresh = opt->occupied_thresh();
  png.free_thresh = opt->free_thresh();
  if (!desktop::load_png_map(opt->file()->str(), png, grid_, error)) return false;
  size_t counts[3] = {0, 0, 0};
  for (uint8_t c : grid_.cells()) ++counts[c];
  log_info("%s: %ux%u cells of %.3f m (%zu free, %zu occupied, %zu unknown)", setup.name.c_str(),
           grid_.width(), grid_.height(), grid_.resolution(), counts[0], counts[1], counts[2]);
  return true;
}

void MapFile::on_request(DeviceId device, const wire::Message& req, RequestToken token) {
  switch (wire::MapReqSub(req.header()->subtype())) {
    case wire::MapReqSub::Info: {
      auto& b = node_->begin();
      const desktop::Pose2& o = grid_.origin();
      wire::Pose2d origin(float(o.x), float(o.y), float(o.a));
      auto body = wire::CreateMapInfo(b, grid_.width(), grid_.height(), float(grid_.resolution()), &origin);
      return node_->ack(token, wire::Body::MapInfo, body.Union());
    }
    case wire::MapReqSub::Tile: {
      const wire::MapTileRequest* t = req.body_as_MapTileRequest();
      if (t == nullptr)
        return node_->nack(token, wire::ErrorCode::BadArgument, "a tile request needs a MapTileRequest");
      if (t->width() == 0 || t->height() == 0 || uint64_t(t->col()) + t->width() > grid_.width() ||
          uint64_t(t->row()) + t->height() > grid_.height()) {
        std::string why = "tile " + std::to_string(t->width()) + "x" + std::to_string(t->height()) + " at (" +
                          std::to_string(t->col()) + ", " + std::to_string(t->row()) +
                          ") is not inside the " + std::to_string(grid_.width()) + "x" +
                          std::to_string(grid_.height()) + " map";
        return node_->nack(token, wire::ErrorCode::BadArgument, why);
      }
      if (uint64_t(t->width()) * t->height() > kMaxTileCells) {
        return node_->nack(token, wire::ErrorCode::BadArgument,
                           "a tile has at most " + std::to_string(kMaxTileCells) + " cells");
      }
      grid_.pack(t->col(), t->row(), t->width(), t->height(), packed_);
      auto& b = node_->begin();
      auto cells = b.CreateVector(packed_);
      auto body = wire::CreateMapTile(b, t->col(), t->row(), t->width(), t->height(), cells);
      return node_->ack(token, wire::Body::MapTile, body.Union());
    }
  }
  Driver::on_request(device, req, token);
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"mapfile", []() -> Driver* { return new MapFile; }};

}  // namespace troupe::drivers::mapfile
