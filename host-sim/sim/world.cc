#include "host-sim/sim/world.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "host-sim/sim/engine.h"
#include "host-sim/sim/journal.h"
#include "host-sim/sim/loader.h"

namespace troupe::sim {

World::World(const WorldDesc& desc, Random random) : e_(std::make_unique<Engine>(desc, random)) {}
World::~World() = default;

std::unique_ptr<World> World::load(const std::string& path, uint64_t seed, world::Diagnostics& diags) {
  WorldDesc desc;
  if (!load_world_file(path, desc, diags)) return nullptr;
  return std::make_unique<World>(desc, Random(seed));
}

void Engine::update_sensors(PhaseLaps& laps) {
  // A kind no robot carries costs no clock reading (a RoboCup world has
  // none of them unless its robots carry Stage sensors).
  if (!rangers.empty()) {
    update_rangers();
    laps.lap(ph_rangers);
  }
  if (!blobfinders.empty()) {
    update_blobfinders();
    laps.lap(ph_blobfinders);
  }
  if (!fiducials.empty()) {
    update_fiducials();
    laps.lap(ph_fiducials);
  }
  if (!bumpers.empty()) {
    update_bumpers();
    laps.lap(ph_bumpers);
  }
  if (!cameras.empty()) {
    update_cameras();
    laps.lap(ph_cameras);
  }
}

void World::step() {
  e_->step(*this, nullptr);
}

void World::step(StepExchange& exchange) {
  e_->step(*this, &exchange);
}

void Engine::step(World& world, World::StepExchange* exchange) {
  Engine& e = *this;
  PhaseLaps laps(e.profile);
  e.control();
  laps.lap(e.ph_control);
  // The motion model is chosen once per phase, never per robot.
  if (e.rigid) {
    e.rigid_integrate();
  } else {
    e.integrate();
  }
  laps.lap(e.ph_integrate);
  if (exchange) exchange->proposed(world);
  e.broadphase();
  laps.lap(e.ph_broadphase);
  if (e.rigid) {
    e.rigid_collide();
  } else {
    e.collide();
  }
  laps.lap(e.ph_collide);
  if (!e.grippers.empty()) {
    e.update_grippers();
    laps.lap(e.ph_grippers);
  }
  e.odometry();
  e.publish_states();
  laps.lap(e.ph_odometry);
  ++e.steps;
  // From the step count, so the clock does not drift by summing.
  e.time = double(e.steps) * e.desc.interval_sim;
  if (exchange) {
    exchange->moved(world);
    e.publish_states();
  }
  e.update_sensors(laps);
  e.changed_since_step = false;
  e.profile.count_step();
}

void World::refresh_sensors() {
  e_->broadphase();
  PhaseLaps laps(e_->profile);
  e_->update_sensors(laps);
}

bool World::changed_since_step() const {
  return e_->changed_since_step;
}

void World::refresh_new_sensors() {
  Engine& e = *e_;
  e.new_sensors_only = !e.changed_since_step;
  refresh_sensors();
  e.new_sensors_only = false;
}

void World::reset() {
  Engine& e = *e_;
  for (GripperState& g : e.grippers) {
    g.closed = g.want_closed = e.desc.robots[g.robot].grippers[g.robot_gripper].closed;
    if (g.holding) e.bodies[g.held].obstacle = e.desc.robots[g.held].look.obstacle;
    g.holding = false;
  }
  for (RobotId i = 0; i < e.bodies.size(); ++i) e.start_robot(i);
  for (std::vector<std::byte>& m : e.controller_memory) std::fill(m.begin(), m.end(), std::byte{0});
  if (e.rigid) {
    for (RobotId i = 0; i < e.bodies.size(); ++i) e.sync_rigid(i);
  }
  e.steps = 0;
  e.time = 0;
  e.changed_since_step = true;
  e.publish_states();
  e.broadphase();
}

// std::vector's allocator takes its bytes from operator new.
static_assert(__STDCPP_DEFAULT_NEW_ALIGNMENT__ >= alignof(std::max_align_t),
              "controller memory must be aligned for any scalar type");

void World::set_controller_memory_size(RobotId id, size_t bytes) {
  Engine& e = *e_;
  if (id >= e.bodies.size()) throw std::out_of_range("no robot " + std::to_string(id));
  if (e.controller_memory.size() < e.bodies.size()) e.controller_memory.resize(e.bodies.size());
  e.controller_memory[id].assign(bytes, std::byte{0});
}

std::span<std::byte> World::controller_memory(RobotId id) {
  Engine& e = *e_;
  if (id >= e.bodies.size()) throw std::out_of_range("no robot " + std::to_string(id));
  if (id >= e.controller_memory.size()) return {};
  return e.controller_memory[id];
}

std::span<const std::byte> World::controller_memory(RobotId id) const {
  return const_cast<World*>(this)->controller_memory(id);
}

double World::time() const {
  return e_->time;
}
uint64_t World::steps() const {
  return e_->steps;
}
double World::interval() const {
  return e_->desc.interval_sim;
}
const WorldDesc& World::desc() const {
  return e_->desc;
}

size_t World::robot_count() const {
  return e_->bodies.size();
}
const RobotInfo& World::robot(RobotId id) const {
  return e_->info.at(id);
}

std::optional<RobotId> World::find_robot(std::string_view name) const {
  for (RobotId i = 0; i < e_->info.size(); ++i) {
    if (e_->info[i].name == name) return i;
  }
  return std::nullopt;
}

const RobotState& World::state(RobotId id) const {
  return e_->states.at(id);
}

bool finite_pose(const Pose& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.a);
}

bool World::set_pose(RobotId id, const Pose& pose) {
  Engine& e = *e_;
  Body& b = e.bodies.at(id);
  if (!finite_pose(pose) || std::abs(pose.x) > kMaxCoordinate || std::abs(pose.y) > kMaxCoordinate)
    return false;
  b.pose = {pose.x, pose.y, wrap_angle(pose.a)};
  b.proposed = b.pose;
  b.moved = false;
  b.stalled = false;
  if (e.kinematics[id].localization == Localization::Gps)
    e.odom[id].estimate = relative(e.odom[id].origin, b.pose);
  if (e.rigid) e.sync_rigid(id);
  e.changed_since_step = true;
  e.publish_states();
  e.broadphase();
  if (e.journal) journal_pose(*e.journal, Input::Teleport, id, pose);
  return true;
}

bool World::command(RobotId id, const Command& cmd) {
  Body& b = e_->bodies.at(id);
  if (!finite_pose(cmd.value)) return false;
  b.cmd = cmd;
  if (e_->journal) journal_pose(*e_->journal, cmd.mode == CommandMode::Goto ? Input::Goto : Input::Velocity, id, cmd.value);
  return true;
}

bool World::set_odometry(RobotId id, const Pose& pose) {
  Engine& e = *e_;
  Odometry& o = e.odom.at(id);
  if (!finite_pose(pose)) return false;
  o.estimate = pose;
  // The odometry frame that puts the robot at `pose`.
  const Pose& p = e.bodies[id].pose;
  const double a = wrap_angle(p.a - pose.a);
  const double c = std::cos(a), s = std::sin(a);
  o.origin = {p.x - (c * pose.x - s * pose.y), p.y - (s * pose.x + c * pose.y), a};
  e.publish_states();
  if (e.journal) journal_pose(*e.journal, Input::Odometry, id, pose);
  return true;
}

PowerView World::power(RobotId id) const {
  const PowerState& p = e_->power.at(id);
  return {p.joules, p.capacity, p.watts};
}

void World::set_wanted(SensorRef s, bool wanted) {
  Engine& e = *e_;
  if (e.journal && this->wanted(s) != wanted) journal_wanted(*e.journal, s, wanted);
  switch (s.kind) {
    case SensorKind::Ranger:
      e.rangers.at(s.index).wanted = wanted;
      break;
    case SensorKind::Blobfinder:
      e.blobfinders.at(s.index).wanted = wanted;
      break;
    case SensorKind::Fiducial:
      e.fiducials.at(s.index).wanted = wanted;
      break;
    case SensorKind::Bumper:
      e.bumpers.at(s.index).wanted = wanted;
      break;
    case SensorKind::Camera:
      e.cameras.at(s.index).wanted = wanted;
      break;
  }
}

bool World::wanted(SensorRef s) const {
  switch (s.kind) {
    case SensorKind::Ranger:
      return e_->rangers.at(s.index).wanted;
    case SensorKind::Blobfinder:
      return e_->blobfinders.at(s.index).wanted;
    case SensorKind::Fiducial:
      return e_->fiducials.at(s.index).wanted;
    case SensorKind::Bumper:
      return e_->bumpers.at(s.index).wanted;
    case SensorKind::Camera:
      return e_->cameras.at(s.index).wanted;
  }
  return false;
}

RobotId World::owner(SensorRef s) const {
  switch (s.kind) {
    case SensorKind::Ranger:
      return e_->rangers.at(s.index).robot;
    case SensorKind::Blobfinder:
      return e_->blobfinders.at(s.index).robot;
    case SensorKind::Fiducial:
      return e_->fiducials.at(s.index).robot;
    case SensorKind::Bumper:
      return e_->bumpers.at(s.index).robot;
    case SensorKind::Camera:
      return e_->cameras.at(s.index).robot;
  }
  throw std::out_of_range("sensor kind");
}

const RangerDesc& World::ranger_desc(uint32_t index) const {
  RobotId r = e_->rangers.at(index).robot;
  return e_->desc.robots[r].rangers[index - e_->info[r].rangers.first];
}

RangerView World::ranger(uint32_t index) const {
  const RangerState& rs = e_->rangers.at(index);
  return {{e_->ranges.data() + rs.beam_first, rs.beam_count},
          {e_->intensities.data() + rs.beam_first, rs.beam_count},
          rs.step};
}

std::vector<Pose> World::ranger_beams(uint32_t index) const {
  const Engine& e = *e_;
  const RangerState& rs = e.rangers.at(index);
  std::vector<Pose> out;
  for (uint32_t t = rs.transducer_first; t < rs.transducer_first + rs.transducer_count; ++t) {
    const Transducer& td = e.transducers[t];
    const Pose org = compose(e.bodies[rs.robot].pose, td.pose);
    for (uint32_t s = 0; s < td.samples; ++s)
      out.push_back({org.x, org.y, wrap_angle(org.a + td.start + td.incr * s)});
  }
  return out;
}

const BlobfinderDesc& World::blobfinder_desc(uint32_t index) const {
  RobotId r = e_->blobfinders.at(index).robot;
  return e_->desc.robots[r].blobfinders[index - e_->info[r].blobfinders.first];
}

BlobView World::blobfinder(uint32_t index) const {
  const BlobState& s = e_->blobfinders.at(index);
  const BlobfinderDesc& d = blobfinder_desc(index);
  return {s.blobs, d.width, d.height, s.step};
}

const FiducialDesc& World::fiducial_desc(uint32_t index) const {
  RobotId r = e_->fiducials.at(index).robot;
  return e_->desc.robots[r].fiducials[index - e_->info[r].fiducials.first];
}

FiducialView World::fiducial(uint32_t index) const {
  const FiducialState& s = e_->fiducials.at(index);
  return {s.readings, s.step};
}

const BumperDesc& World::bumper_desc(uint32_t index) const {
  RobotId r = e_->bumpers.at(index).robot;
  return e_->desc.robots[r].bumpers[index - e_->info[r].bumpers.first];
}

BumperView World::bumper(uint32_t index) const {
  const BumperState& s = e_->bumpers.at(index);
  return {s.pressed, uint32_t(bumper_desc(index).segments.size()), s.step};
}

std::vector<std::vector<Vec2>> World::outline(RobotId id) const {
  std::vector<Vec2> v;
  std::vector<PolyRef> p;
  e_->outline(id, e_->bodies.at(id).pose, v, p);
  std::vector<std::vector<Vec2>> out;
  for (const PolyRef& r : p) out.emplace_back(v.begin() + r.first, v.begin() + r.first + r.count);
  return out;
}

robocup::World* World::rigid() {
  return e_->rigid_world();
}

robocup::BodyId World::rigid_body(RobotId id) const {
  return e_->rigid_body(id);
}

robocup::BodyId World::rigid_static_body(size_t index) const {
  return e_->rigid_static_body(index);
}

void World::rigid_moved() {
  if (!e_->rigid) return;
  e_->rigid_moved();
  e_->changed_since_step = true;
}

const StaticMap& World::map() const {
  return e_->map;
}
const Profile& World::profile() const {
  return e_->profile;
}
Profile& World::profile() {
  return e_->profile;
}
const Random& World::random() const {
  return e_->random;
}

void World::set_raycast_per_cell(bool on) {
  e_->map.set_per_cell(on);
}

void World::set_ranger_robots(RangerRobots how) {
  e_->ranger_robots = how;
}

size_t World::memory_bytes() const {
  const Engine& e = *e_;
  return e.map.memory_bytes() + e.hash.memory_bytes() + e.robot_layer.memory_bytes() +
         e.bodies.capacity() * sizeof(Body) + e.verts.capacity() * sizeof(Vec2) + e.ranges.capacity() * 8 +
         e.transducers.capacity() * sizeof(Transducer);
}

const CameraDesc& World::camera_desc(uint32_t index) const {
  RobotId r = e_->cameras.at(index).robot;
  return e_->desc.robots[r].cameras[index - e_->info[r].cameras.first];
}

CameraView World::camera(uint32_t index) const {
  const CameraState& s = e_->cameras.at(index);
  return {s.width, s.height, s.rgb, s.depth, s.step};
}

bool World::set_camera_size(uint32_t index, int width, int height) {
  if (width < 1 || height < 1 || width > kMaxCameraSide || height > kMaxCameraSide) return false;
  RobotId r = e_->cameras.at(index).robot;
  CameraDesc& d = e_->desc.robots[r].cameras[index - e_->info[r].cameras.first];
  d.width = width;
  d.height = height;
  e_->changed_since_step = true;
  if (e_->journal) journal_camera_size(*e_->journal, index, width, height);
  return true;
}

size_t World::gripper_count() const {
  return e_->grippers.size();
}

RobotId World::gripper_owner(uint32_t index) const {
  return e_->grippers.at(index).robot;
}

GripperView World::gripper(uint32_t index) const {
  const GripperState& g = e_->grippers.at(index);
  return {g.closed, g.holding, g.held};
}

void World::set_gripper(uint32_t index, bool closed) {
  e_->grippers.at(index).want_closed = closed;
  if (e_->journal) journal_gripper(*e_->journal, index, closed);
}

}  // namespace troupe::sim
