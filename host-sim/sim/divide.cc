// A world divided between processes (host-sim/mpi): which robots this
// process steps, its ghosts' motion, and a robot's running state as bytes
// for the process it migrates to. The bytes are the engine's own values,
// copied whole, so a migrated robot carries on bit for bit; both processes
// loaded the same world, so nothing about the robot's make-up travels.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "host-sim/sim/bytes.h"
#include "host-sim/sim/engine.h"
#include "host-sim/sim/journal.h"

namespace troupe::sim {
namespace {

using bytes::get;
using bytes::get_vector;
using bytes::put;
using bytes::put_vector;

// A sensor's bookkeeping, the same for every kind.
template <class State>
void put_common(std::vector<std::byte>& out, const State& st) {
  put(out, uint8_t(st.wanted));
  put(out, st.step);
}

template <class State>
bool get_common(std::span<const std::byte>& in, State& st) {
  uint8_t wanted = 0;
  if (!get(in, wanted) || !get(in, st.step)) return false;
  st.wanted = wanted != 0;
  return true;
}

// Robot frame offset of a sensor, m: what its reach adds to its range.
double offset(const Pose& p) {
  return std::hypot(p.x, p.y);
}

}  // namespace

void World::set_residence(RobotId id, Residence residence) {
  Engine& e = *e_;
  if (id >= e.bodies.size()) throw std::out_of_range("no robot " + std::to_string(id));
  if (e.residence.empty()) e.residence.assign(e.bodies.size(), Engine::kOwned);
  e.residence[id] = uint8_t(residence);
}

World::Residence World::residence(RobotId id) const {
  const Engine& e = *e_;
  if (id >= e.bodies.size()) throw std::out_of_range("no robot " + std::to_string(id));
  return e.residence.empty() ? Residence::Owned : Residence(e.residence[id]);
}

bool World::divisible(std::string& why) const {
  const Engine& e = *e_;
  if (e.rigid) {
    why = "a rigid world (physics \"rigid\") moves every body in one physics world";
    return false;
  }
  if (!e.grippers.empty()) {
    why = "grippers carry pucks, which would have to travel with their robots";
    return false;
  }
  return true;
}

double World::interaction_reach() const {
  const Engine& e = *e_;
  const double dt = e.desc.interval_sim;
  double sense = 0, radius = 0, move = 0;
  for (RobotId i = 0; i < e.bodies.size(); ++i) {
    const RobotDesc& r = e.desc.robots[i];
    radius = std::max(radius, e.bodies[i].radius);
    const Kinematics& k = e.kinematics[i];
    auto most = [](const Range& v) { return std::max(std::fabs(v.min), std::fabs(v.max)); };
    // A car's speed is its x; its steering angle moves no centre.
    const double speed = k.drive == Drive::Omni ? std::hypot(most(k.velocity[0]), most(k.velocity[1]))
                                                : most(k.velocity[0]);
    // A start velocity beyond the bounds is kept until the robot is told
    // otherwise.
    const Pose& v0 = r.initial_velocity;
    move = std::max(move, std::max(speed, std::hypot(v0.x, v0.y)) * dt);
    for (uint32_t k2 = 0; k2 < e.info[i].rangers.count; ++k2)
      sense = std::max(sense, e.rangers[e.info[i].rangers.first + k2].reach);
    for (const BlobfinderDesc& d : r.blobfinders) sense = std::max(sense, offset(d.pose) + d.range);
    for (const FiducialDesc& d : r.fiducials) sense = std::max(sense, offset(d.pose) + d.range_max);
    for (const CameraDesc& d : r.cameras)
      sense = std::max(sense, offset(d.pose) + std::max(d.far, d.mirror_range));
    for (const BumperDesc& d : r.bumpers) {
      for (const BumperSegment& s : d.segments)
        sense = std::max(sense, offset(compose(d.pose, s.pose)) + s.length);
    }
  }
  // The sensing robot may have moved before it senses, and the sensed one
  // too; collisions test both robots' moves. Every term counts once more,
  // for a robot that has left its region and not yet migrated.
  return sense + 2 * radius + 3 * move;
}

World::GhostMotion World::ghost_motion(RobotId id) const {
  const Body& b = e_->bodies.at(id);
  return {b.pose, b.proposed, b.moved};
}

void World::set_ghost_motion(RobotId id, const GhostMotion& motion) {
  Body& b = e_->bodies.at(id);
  b.pose = motion.pose;
  b.proposed = motion.proposed;
  b.moved = motion.moved;
}

void World::save_robot(RobotId id, std::vector<std::byte>& out) const {
  const Engine& e = *e_;
  if (id >= e.bodies.size()) throw std::out_of_range("no robot " + std::to_string(id));
  put(out, e.bodies[id]);
  put(out, e.odom[id]);
  put(out, e.power[id]);
  const RobotInfo& info = e.info[id];
  for (uint32_t k = info.rangers.first; k < info.rangers.first + info.rangers.count; ++k) {
    const RangerState& rs = e.rangers[k];
    put_common(out, rs);
    put(out, rs.robots_near);
    const size_t at = out.size(), bytes = rs.beam_count * sizeof(float);
    out.resize(at + 2 * bytes);
    std::memcpy(out.data() + at, e.ranges.data() + rs.beam_first, bytes);
    std::memcpy(out.data() + at + bytes, e.intensities.data() + rs.beam_first, bytes);
  }
  for (uint32_t k = info.blobfinders.first; k < info.blobfinders.first + info.blobfinders.count; ++k) {
    put_common(out, e.blobfinders[k]);
    put_vector(out, e.blobfinders[k].blobs);
  }
  for (uint32_t k = info.fiducials.first; k < info.fiducials.first + info.fiducials.count; ++k) {
    put_common(out, e.fiducials[k]);
    put_vector(out, e.fiducials[k].readings);
  }
  for (uint32_t k = info.bumpers.first; k < info.bumpers.first + info.bumpers.count; ++k) {
    put_common(out, e.bumpers[k]);
    put(out, e.bumpers[k].pressed);
  }
  for (uint32_t k = info.cameras.first; k < info.cameras.first + info.cameras.count; ++k) {
    const CameraState& c = e.cameras[k];
    put_common(out, c);
    put(out, int32_t(c.width));
    put(out, int32_t(c.height));
    put_vector(out, c.rgb);
    put_vector(out, c.depth);
  }
  put_vector(out, id < e.controller_memory.size() ? e.controller_memory[id] : std::vector<std::byte>{});
}

bool World::restore_robot(RobotId id, std::span<const std::byte>& in) {
  Engine& e = *e_;
  if (id >= e.bodies.size()) return false;
  // Read whole into copies first: a short or foreign record changes nothing.
  Body body;
  Odometry odom;
  PowerState power;
  if (!get(in, body) || !get(in, odom) || !get(in, power)) return false;
  const RobotInfo& info = e.info[id];
  std::vector<RangerState> rangers;
  std::vector<float> beams;
  for (uint32_t k = info.rangers.first; k < info.rangers.first + info.rangers.count; ++k) {
    RangerState rs = e.rangers[k];
    if (!get_common(in, rs) || !get(in, rs.robots_near)) return false;
    const size_t bytes = rs.beam_count * sizeof(float);
    if (in.size() < 2 * bytes) return false;
    const size_t at = beams.size();
    beams.resize(at + 2 * rs.beam_count);
    std::memcpy(beams.data() + at, in.data(), 2 * bytes);
    in = in.subspan(2 * bytes);
    rangers.push_back(rs);
  }
  std::vector<BlobState> blobs;
  for (uint32_t k = info.blobfinders.first; k < info.blobfinders.first + info.blobfinders.count; ++k) {
    BlobState st = e.blobfinders[k];
    if (!get_common(in, st) || !get_vector(in, st.blobs)) return false;
    blobs.push_back(std::move(st));
  }
  std::vector<FiducialState> fiducials;
  for (uint32_t k = info.fiducials.first; k < info.fiducials.first + info.fiducials.count; ++k) {
    FiducialState st = e.fiducials[k];
    if (!get_common(in, st) || !get_vector(in, st.readings)) return false;
    fiducials.push_back(std::move(st));
  }
  std::vector<BumperState> bumpers;
  for (uint32_t k = info.bumpers.first; k < info.bumpers.first + info.bumpers.count; ++k) {
    BumperState st = e.bumpers[k];
    if (!get_common(in, st) || !get(in, st.pressed)) return false;
    bumpers.push_back(st);
  }
  std::vector<CameraState> cameras;
  for (uint32_t k = info.cameras.first; k < info.cameras.first + info.cameras.count; ++k) {
    CameraState st = e.cameras[k];
    int32_t w = 0, h = 0;
    if (!get_common(in, st) || !get(in, w) || !get(in, h) || !get_vector(in, st.rgb) ||
        !get_vector(in, st.depth))
      return false;
    st.width = w;
    st.height = h;
    cameras.push_back(std::move(st));
  }
  std::vector<std::byte> memory;
  if (!get_vector(in, memory)) return false;
  if (memory.size() != controller_memory(id).size()) return false;

  e.bodies[id] = body;
  e.odom[id] = odom;
  e.power[id] = power;
  const float* beam = beams.data();
  for (const RangerState& rs : rangers) {
    e.rangers[info.rangers.first + (&rs - rangers.data())] = rs;
    std::memcpy(e.ranges.data() + rs.beam_first, beam, rs.beam_count * sizeof(float));
    std::memcpy(e.intensities.data() + rs.beam_first, beam + rs.beam_count, rs.beam_count * sizeof(float));
    beam += 2 * rs.beam_count;
  }
  std::move(blobs.begin(), blobs.end(), e.blobfinders.begin() + info.blobfinders.first);
  std::move(fiducials.begin(), fiducials.end(), e.fiducials.begin() + info.fiducials.first);
  std::move(bumpers.begin(), bumpers.end(), e.bumpers.begin() + info.bumpers.first);
  std::move(cameras.begin(), cameras.end(), e.cameras.begin() + info.cameras.first);
  if (!memory.empty()) std::copy(memory.begin(), memory.end(), controller_memory(id).begin());
  e.states[id] = {body.pose, body.vel, odom.estimate, body.stalled, body.disabled};
  return true;
}

void World::set_journal(std::vector<std::byte>* journal) {
  e_->journal = journal;
}

std::vector<std::byte>* World::journal() const {
  return e_->journal;
}

bool World::replay(std::span<const std::byte> in) {
  Engine& e = *e_;
  std::vector<std::byte>* journal = e.journal;
  e.journal = nullptr;  // what is replayed was journaled where it came from
  bool ok = true;
  Input kind{};
  while (ok && !in.empty() && get(in, kind)) {
    RobotId id = 0;
    Pose p;
    uint32_t index = 0;
    uint8_t flag = 0;
    switch (kind) {
      case Input::Velocity:
      case Input::Goto:
      case Input::Teleport:
      case Input::Odometry:
        ok = get(in, id) && get(in, p) && id < e.bodies.size();
        if (!ok) break;
        if (kind == Input::Teleport) {
          set_pose(id, p);
        } else if (kind == Input::Odometry) {
          set_odometry(id, p);
        } else {
          command(id, {kind == Input::Goto ? CommandMode::Goto : CommandMode::Velocity, p});
        }
        break;
      case Input::Wanted: {
        SensorKind sensor{};
        ok = get(in, sensor) && get(in, index) && get(in, flag);
        if (ok) set_wanted({sensor, index}, flag != 0);
        break;
      }
      case Input::Gripper:
        ok = get(in, index) && get(in, flag) && index < e.grippers.size();
        if (ok) set_gripper(index, flag != 0);
        break;
      case Input::CameraSize: {
        int32_t w = 0, h = 0;
        ok = get(in, index) && get(in, w) && get(in, h) && index < e.cameras.size();
        if (ok) set_camera_size(index, w, h);
        break;
      }
      default:
        ok = false;
    }
  }
  e.journal = journal;
  return ok;
}

}  // namespace troupe::sim
