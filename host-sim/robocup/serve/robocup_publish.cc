// The data messages of the served RoboCup devices.
#include <algorithm>
#include <cmath>

#include "host-sim/robocup/serve/robocup_server.h"

#include "host-sim/robocup/api/fiducial_key.h"
#include "host-sim/sim_control/kicker_state.h"

namespace troupe::robocup {
namespace {

uint64_t to_us(double seconds) {
  return uint64_t(std::llround(std::max(0.0, seconds) * 1e6));
}

}  // namespace

void RobocupServer::publish() {
  for (Device& d : devices_) {
    // Game and kicker change rarely: they are published even unread, so a
    // reader gets the current state when it opens the device.
    if (d.kind == Kind::Simulation) publish_game(d);
    if (d.kind == Kind::Kicker) publish_kicker(d);
    if (!node_->has_readers(d.id)) continue;
    switch (d.kind) {
      case Kind::Position:
        publish_position(d);
        break;
      case Kind::Kicker:
        break;
      case Kind::Fiducial:
        publish_fiducials(d);
        break;
      case Kind::Ranger:
        publish_ranges(d);
        break;
      case Kind::Simulation:
        publish_clock(d);
        publish_poses(d);
        break;
    }
  }
}

void RobocupServer::publish_position(Device& d) {
  if (d.reading < 0) return;  // no odometry sensor: nothing to report
  const SensorReading& r = sim_.readings(d.robot)[size_t(d.reading)];
  if (!r.valid || r.time_s <= d.published_s) return;
  d.published_s = r.time_s;
  auto& b = node_->begin();
  wire::Pose2d pose(float(r.odometry.x), float(r.odometry.y), float(r.odometry.a));
  wire::Pose2d vel(float(r.velocity.vx), float(r.velocity.vy), float(r.velocity.w));
  auto body = wire::CreatePosition2dState(b, &pose, &vel, false);
  node_->publish(d.id, uint8_t(wire::Position2dDataSub::State), wire::Body::Position2dState, body.Union(),
                 to_us(r.time_s));
}

void RobocupServer::publish_kicker(Device& d) {
  const std::string state = sim_.kicker_state(d.robot);
  const auto& states = sim_.spec().robots[size_t(d.robot)].spec.kicker.states;
  int index = 0;
  for (size_t i = 0; i < states.size(); ++i) {
    if (states[i].name == state) index = int(i);
  }
  if (index == d.kicker_state) return;
  d.kicker_state = index;
  // The first state is the rest state, ready to kick; any other is a kick
  // in progress (or its recovery).
  sim::publish_kicker_state(*node_, d.id, index == 0);
}

void RobocupServer::publish_fiducials(Device& d) {
  const SensorReading& r = sim_.readings(d.robot)[size_t(d.reading)];
  if (!r.valid || r.time_s <= d.published_s) return;
  d.published_s = r.time_s;
  scratch_fiducials_.clear();
  scratch_kinds_.clear();
  for (const Detection& det : r.detections) {
    const std::optional<FiducialKey> key = fiducial_key(det.kind, det.id);
    if (!key) continue;
    scratch_fiducials_.emplace_back(key->id, float(det.x), float(det.y), float(det.yaw));
    scratch_kinds_.push_back(key->kind);
  }
  auto& b = node_->begin();
  auto fiducials = b.CreateVectorOfStructs(scratch_fiducials_);
  auto kinds = b.CreateVector(scratch_kinds_);
  auto body = wire::CreateFiducialList(b, fiducials, kinds);
  node_->publish(d.id, uint8_t(wire::FiducialDataSub::Detections), wire::Body::FiducialList, body.Union(),
                 to_us(r.time_s));
}

void RobocupServer::publish_ranges(Device& d) {
  const SensorReading& r = sim_.readings(d.robot)[size_t(d.reading)];
  if (!r.valid || r.time_s <= d.published_s) return;
  d.published_s = r.time_s;
  // Millimetres unless the sensor reaches beyond what 16 bits of them hold.
  const double scale = r.max_range <= 65.535 ? 0.001 : r.max_range / 65535.0;
  scratch_ranges_.resize(r.ranges.size());
  for (size_t i = 0; i < r.ranges.size(); ++i) {
    scratch_ranges_[i] = uint16_t(std::clamp(std::lround(r.ranges[i] / scale), 0L, 65535L));
  }
  auto& b = node_->begin();
  auto ranges = b.CreateVector(scratch_ranges_);
  auto body = wire::CreateRangerScan(b, ranges, float(scale), float(r.angle_min), float(r.angle_step),
                                     float(r.max_range));
  node_->publish(d.id, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, body.Union(),
                 to_us(r.time_s));
}

void RobocupServer::publish_clock(const Device& d) {
  auto& b = node_->begin();
  auto body =
      wire::CreateSimClock(b, to_us(sim_.time_s()), uint64_t(std::llround(sim_.time_s() / sim_.cycle_s())),
                           control_.paused, float(control_.speed), float(control_.real_time_factor));
  node_->publish(d.id, uint8_t(wire::SimulationDataSub::Clock), wire::Body::SimClock, body.Union());
}

flatbuffers::Offset<wire::SimGame> RobocupServer::build_game(flatbuffers::FlatBufferBuilder& b) {
  const std::vector<RefereeEvent>& history = sim_.history();
  std::string last;
  uint64_t last_us = 0;
  if (!history.empty()) {
    const RefereeEvent& e = history.back();
    last = event_name(e.kind);
    if (e.kind == RefereeEventKind::Goal) last += std::string(" ") + team_name(e.team);
    last_us = to_us(e.time_s);
  }
  const Score s = sim_.score();
  return wire::CreateSimGame(b, uint16_t(std::clamp(s.blue, 0, 65535)),
                             uint16_t(std::clamp(s.yellow, 0, 65535)), wire::GamePhase(sim_.phase()),
                             uint32_t(history.size()), b.CreateString(last), last_us);
}

void RobocupServer::publish_game(const Device& d) {
  if (sim_.score() == game_score_ && sim_.phase() == game_phase_ && sim_.history().size() == game_events_)
    return;
  game_score_ = sim_.score();
  game_phase_ = sim_.phase();
  game_events_ = sim_.history().size();
  auto& b = node_->begin();
  auto body = build_game(b);
  node_->publish(d.id, uint8_t(wire::SimulationDataSub::Game), wire::Body::SimGame, body.Union());
}

}  // namespace troupe::robocup
