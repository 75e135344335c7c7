// What a viewer needs beyond the robots' own devices: the robots' list and
// ground-truth poses on simulation:0, and the static obstacles as map:0 (the
// same Info/Tile requests a node's mapfile driver answers, so one viewer
// draws both).
#include <algorithm>
#include <cmath>

#include "host-sim/sim/static_map.h"
#include "host-sim/troupe_sim/sim_server.h"

namespace troupe::sim {

using wire::ErrorCode;

namespace {
// As mapfile's limit: 512 x 512 cells are 64 KiB packed, well inside a frame.
constexpr uint64_t kMaxTileCells = 512 * 512;
}  // namespace

flatbuffers::Offset<wire::SimModelList> SimServer::models(flatbuffers::FlatBufferBuilder& b) {
  std::vector<flatbuffers::Offset<wire::SimModelInfo>> models;
  models.reserve(world_.robot_count());
  for (RobotId r = 0; r < world_.robot_count(); ++r) {
    const RobotDesc& desc = world_.desc().robots[r];
    models.push_back(wire::CreateSimModelInfo(b, b.CreateString(desc.name), uint16_t(r), float(desc.size.x),
                                              float(desc.size.y), desc.look.color));
  }
  return wire::CreateSimModelList(b, b.CreateVector(models));
}

void SimServer::publish_poses(const Device& d) {
  scratch_poses_.clear();
  for (RobotId r = 0; r < world_.robot_count(); ++r) {
    const Pose& p = world_.state(r).pose;
    scratch_poses_.emplace_back(float(p.x), float(p.y), float(p.a));
  }
  auto& b = node_->begin();
  auto poses = b.CreateVectorOfStructs(scratch_poses_);
  auto body = wire::CreateSimPoses(b, uint64_t(std::llround(world_.time() * 1e6)), poses);
  node_->publish(d.id, uint8_t(wire::SimulationDataSub::Poses), wire::Body::SimPoses, body.Union());
}

void SimServer::map_request(const Device& d, const wire::Message& req, RequestToken token) {
  const StaticMap& map = world_.map();
  const uint32_t w = uint32_t(std::max(map.width(), 0));
  const uint32_t h = uint32_t(std::max(map.height(), 0));
  switch (wire::MapReqSub(req.header()->subtype())) {
    case wire::MapReqSub::Info: {
      auto& b = node_->begin();
      wire::Pose2d origin(float(map.origin().x), float(map.origin().y), 0.0f);
      auto body = wire::CreateMapInfo(b, w, h, float(map.resolution()), &origin);
      return node_->ack(token, wire::Body::MapInfo, body.Union());
    }
    case wire::MapReqSub::Tile: {
      const wire::MapTileRequest* t = req.body_as_MapTileRequest();
      if (t == nullptr)
        return node_->nack(token, ErrorCode::BadArgument, "a tile request needs a MapTileRequest");
      if (t->width() == 0 || t->height() == 0 || uint64_t(t->col()) + t->width() > w ||
          uint64_t(t->row()) + t->height() > h) {
        return node_->nack(token, ErrorCode::BadArgument,
                           "tile " + std::to_string(t->width()) + "x" + std::to_string(t->height()) +
                               " at (" + std::to_string(t->col()) + ", " + std::to_string(t->row()) +
                               ") is not inside the " + std::to_string(w) + "x" + std::to_string(h) + " map");
      }
      if (uint64_t(t->width()) * t->height() > kMaxTileCells) {
        return node_->nack(token, ErrorCode::BadArgument,
                           "a tile has at most " + std::to_string(kMaxTileCells) + " cells");
      }
      // Two bits a cell, cell i in bits 2*(i%4) of byte i/4 (map.fbs).
      const size_t cells = size_t(t->width()) * t->height();
      scratch_cells_.assign((cells + 3) / 4, 0);
      size_t i = 0;
      for (uint32_t y = 0; y < t->height(); ++y) {
        for (uint32_t x = 0; x < t->width(); ++x, ++i) {
          const bool occupied = map.code(int(t->col() + x), int(t->row() + y)) <= StaticMap::kFreeBase;
          if (occupied) scratch_cells_[i / 4] |= uint8_t(uint8_t(wire::Cell::Occupied) << (2 * (i % 4)));
        }
      }
      auto& b = node_->begin();
      auto body =
          wire::CreateMapTile(b, t->col(), t->row(), t->width(), t->height(), b.CreateVector(scratch_cells_));
      return node_->ack(token, wire::Body::MapTile, body.Union());
    }
  }
  Driver::on_request(d.id, req, token);
}

}  // namespace troupe::sim
