// Proxies of world knowledge: localize, map, simulation.
#include <algorithm>

#include "wire/client/proxies.h"

namespace troupe::client {

using wire::Interface;

LocalizeProxy::LocalizeProxy(Client& client, uint16_t index, uint16_t robot)
    : Proxy(client, address_of(Interface::Localize, index, robot)) {
  attach();
}

void LocalizeProxy::update(const wire::Message& msg) {
  const wire::LocalizeState* s = msg.body_as_LocalizeState();
  if (s == nullptr) return;
  copy_structs(s->hypotheses(), hypotheses_);
  lost_ = s->lost();
}

bool LocalizeProxy::set_pose(float x, float y, float a, float sx, float sy, float sa) {
  auto& b = client().begin();
  wire::Pose2d mean(x, y, a);
  wire::Cov2d cov(sx * sx, 0, 0, sy * sy, 0, sa * sa);
  auto body = wire::CreateLocalizeSetPose(b, &mean, &cov);
  return request(uint8_t(wire::LocalizeReqSub::SetPose), wire::Body::LocalizeSetPose, body.Union()).ok();
}

bool LocalizeProxy::global() {
  return request(uint8_t(wire::LocalizeReqSub::Global)).ok();
}

MapProxy::MapProxy(Client& client, uint16_t index, uint16_t robot)
    : Proxy(client, address_of(Interface::Map, index, robot)) {
  attach(wire::Access::Write);  // requests only: maps do not stream data
}

bool MapProxy::fetch(GridMap& out, uint32_t tile) {
  Reply info = request(uint8_t(wire::MapReqSub::Info));
  const wire::MapInfo* mi = info.ok() ? info.message()->body_as_MapInfo() : nullptr;
  if (mi == nullptr) return false;
  out.width = mi->width();
  out.height = mi->height();
  out.resolution = mi->resolution();
  if (mi->origin()) out.origin = {mi->origin()->x(), mi->origin()->y(), mi->origin()->a()};
  out.cells.assign(size_t(out.width) * out.height, uint8_t(wire::Cell::Unknown));
  tile = std::max<uint32_t>(tile, 1);
  for (uint32_t row = 0; row < out.height; row += tile) {
    for (uint32_t col = 0; col < out.width; col += tile) {
      uint32_t w = std::min(tile, out.width - col), h = std::min(tile, out.height - row);
      auto& b = client().begin();
      auto body = wire::CreateMapTileRequest(b, col, row, w, h);
      Reply r = request(uint8_t(wire::MapReqSub::Tile), wire::Body::MapTileRequest, body.Union(), 5000);
      const wire::MapTile* t = r.ok() ? r.message()->body_as_MapTile() : nullptr;
      if (t == nullptr || t->cells() == nullptr || t->width() != w || t->height() != h ||
          t->cells()->size() < (size_t(w) * h + 3) / 4) {
        return false;
      }
      for (uint32_t i = 0; i < w * h; ++i) {
        uint8_t v = (t->cells()->Get(i / 4) >> (2 * (i % 4))) & 3u;
        out.cells[size_t(row + i / w) * out.width + col + i % w] = v;
      }
    }
  }
  return true;
}

SimulationProxy::SimulationProxy(Client& client, uint16_t index)
    : Proxy(client, address_of(Interface::Simulation, index, 0)) {
  attach();
}

void SimulationProxy::update(const wire::Message& msg) {
  if (const wire::SimClock* c = msg.body_as_SimClock()) {
    sim_time_us_ = c->sim_time_us();
    steps_ = c->steps();
    paused_ = c->paused();
    rtf_ = c->real_time_factor();
  } else if (const wire::SimGame* g = msg.body_as_SimGame()) {
    read_game(*g);
  }
}

void SimulationProxy::read_game(const wire::SimGame& g) {
  game_.score_blue = g.score_blue();
  game_.score_yellow = g.score_yellow();
  game_.phase = g.phase();
  game_.events = g.events();
  game_.last_event = g.last_event() ? g.last_event()->str() : std::string();
  game_.last_event_time_us = g.last_event_time_us();
}

bool SimulationProxy::get_game(GameState& out) {
  Reply r = request(uint8_t(wire::SimulationReqSub::GetGame));
  const wire::SimGame* g = r.ok() ? r.message()->body_as_SimGame() : nullptr;
  if (g == nullptr) return false;
  read_game(*g);
  out = game_;
  return true;
}

bool SimulationProxy::start_player(const std::string& robot, const std::string& plugin,
                                   const std::vector<std::string>& options) {
  auto& b = client().begin();
  std::vector<flatbuffers::Offset<flatbuffers::String>> texts;
  for (const std::string& o : options) texts.push_back(b.CreateString(o));
  auto r = b.CreateString(robot);
  auto p = b.CreateString(plugin);
  auto body = wire::CreateSimPlayer(b, r, p, b.CreateVector(texts));
  return request(uint8_t(wire::SimulationReqSub::StartPlayer), wire::Body::SimPlayer, body.Union()).ok();
}

bool SimulationProxy::stop_player(const std::string& robot) {
  auto& b = client().begin();
  auto body = wire::CreateSimModel(b, b.CreateString(robot));
  return request(uint8_t(wire::SimulationReqSub::StopPlayer), wire::Body::SimModel, body.Union()).ok();
}

bool SimulationProxy::get_pose(const std::string& model, Pose2& pose, Pose2& velocity) {
  auto& b = client().begin();
  auto body = wire::CreateSimModel(b, b.CreateString(model));
  Reply r = request(uint8_t(wire::SimulationReqSub::GetPose), wire::Body::SimModel, body.Union());
  const wire::SimPose* p = r.ok() ? r.message()->body_as_SimPose() : nullptr;
  if (p == nullptr || p->pose() == nullptr) return false;
  pose = {p->pose()->x(), p->pose()->y(), p->pose()->a()};
  velocity = p->velocity() ? Pose2{p->velocity()->x(), p->velocity()->y(), p->velocity()->a()} : Pose2{};
  return true;
}

bool SimulationProxy::set_pose(const std::string& model, const Pose2& pose, const Pose2& velocity) {
  auto& b = client().begin();
  wire::Pose2d p(pose.x, pose.y, pose.a);
  wire::Pose2d v(velocity.x, velocity.y, velocity.a);
  auto body = wire::CreateSimPose(b, b.CreateString(model), &p, &v);
  return request(uint8_t(wire::SimulationReqSub::SetPose), wire::Body::SimPose, body.Union()).ok();
}

bool SimulationProxy::clock_request(wire::SimulationReqSub sub) {
  Reply r = request(uint8_t(sub));
  if (!r.ok()) return false;
  if (const wire::SimClock* c = r.message()->body_as_SimClock()) {
    sim_time_us_ = c->sim_time_us();
    paused_ = c->paused();
  }
  return true;
}

bool SimulationProxy::pause() {
  return clock_request(wire::SimulationReqSub::Pause);
}
bool SimulationProxy::resume() {
  return clock_request(wire::SimulationReqSub::Resume);
}
bool SimulationProxy::reset() {
  return clock_request(wire::SimulationReqSub::Reset);
}

bool SimulationProxy::step(uint32_t steps) {
  auto& b = client().begin();
  auto body = wire::CreateSimStep(b, steps);
  Reply r = request(uint8_t(wire::SimulationReqSub::Step), wire::Body::SimStep, body.Union(), 60000);
  if (!r.ok()) return false;
  if (const wire::SimClock* c = r.message()->body_as_SimClock()) sim_time_us_ = c->sim_time_us();
  return true;
}

bool SimulationProxy::set_speed(float speed) {
  auto& b = client().begin();
  auto body = wire::CreateSimSpeed(b, speed);
  return request(uint8_t(wire::SimulationReqSub::SetSpeed), wire::Body::SimSpeed, body.Union()).ok();
}

bool SimulationProxy::get_pose(const std::string& model, Pose2& pose) {
  auto& b = client().begin();
  auto body = wire::CreateSimModel(b, b.CreateString(model));
  Reply r = request(uint8_t(wire::SimulationReqSub::GetPose), wire::Body::SimModel, body.Union());
  const wire::SimPose* p = r.ok() ? r.message()->body_as_SimPose() : nullptr;
  if (p == nullptr || p->pose() == nullptr) return false;
  pose = {p->pose()->x(), p->pose()->y(), p->pose()->a()};
  return true;
}

bool SimulationProxy::set_pose(const std::string& model, const Pose2& pose) {
  auto& b = client().begin();
  wire::Pose2d p(pose.x, pose.y, pose.a);
  auto body = wire::CreateSimPose(b, b.CreateString(model), &p);
  return request(uint8_t(wire::SimulationReqSub::SetPose), wire::Body::SimPose, body.Union()).ok();
}

}  // namespace troupe::client
