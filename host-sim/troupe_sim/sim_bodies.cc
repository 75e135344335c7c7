#include "host-sim/troupe_sim/sim_bodies.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace troupe::sim {
namespace {

constexpr float kNoReturn = std::numeric_limits<float>::infinity();

}  // namespace

std::optional<uint32_t> find_sonar_ring(const World& world, RobotId robot) {
  const IndexRange& r = world.robot(robot).rangers;
  for (uint32_t i = r.first; i < r.first + r.count; ++i) {
    if (world.ranger_desc(i).transducers.size() > 1) return i;
  }
  return std::nullopt;
}

std::optional<uint32_t> find_laser(const World& world, RobotId robot) {
  const IndexRange& r = world.robot(robot).rangers;
  for (uint32_t i = r.first; i < r.first + r.count; ++i) {
    const RangerDesc& d = world.ranger_desc(i);
    if (d.transducers.size() == 1 && d.transducers[0].samples > 1) return i;
  }
  return std::nullopt;
}

SimPioneerBody::SimPioneerBody(World& world, RobotId robot)
    : world_(world), robot_(robot), sonar_(find_sonar_ring(world, robot)) {
  if (sonar_) world_.set_wanted({SensorKind::Ranger, *sonar_}, true);
  const IndexRange& bumpers = world_.robot(robot).bumpers;
  if (bumpers.count > 0) {
    bumper_ = bumpers.first;
    world_.set_wanted({SensorKind::Bumper, *bumper_}, true);
  }
}

double SimPioneerBody::observe(double, emulators::PioneerPose& pose) {
  if (reported_ && (pose.x != reported_->x || pose.y != reported_->y || pose.a != reported_->a)) {
    world_.set_odometry(robot_, {pose.x, pose.y, pose.a});
  }
  const RobotState& s = world_.state(robot_);
  pose = {s.odometry.x, s.odometry.y, s.odometry.a};
  reported_ = pose;
  const double now_s = world_.time();
  if (!observed_s_ || now_s < *observed_s_) {
    observed_s_ = now_s;  // the first look, or the world was reset
    return 0;
  }
  const double moved_s = now_s - *observed_s_;
  observed_s_ = now_s;
  return moved_s;
}

bool SimPioneerBody::move(double left, double right, double track, double, emulators::PioneerPose&) {
  // The world integrates the motion at its own step; the emulator only sets
  // the wheels. A command is sent when the wheels change, so a client of
  // troupe-sim's own position2d device may still drive a robot at rest.
  const double v = 0.5 * (left + right), w = (right - left) / track;
  if (!commanded_ || v != command_v_ || w != command_w_) {
    world_.command(robot_, Command::velocity(v, 0, w));
    command_v_ = v;
    command_w_ = w;
    commanded_ = true;
  }
  return world_.state(robot_).stalled;
}

void SimPioneerBody::sense(const emulators::PioneerPose&, const drivers::p2os::RobotParams&,
                           emulators::PioneerSenses& senses) {
  std::fill(std::begin(senses.sonar_m), std::end(senses.sonar_m), kNoReturn);
  if (sonar_) {
    RangerView view = world_.ranger(*sonar_);
    const size_t n = std::min<size_t>(view.ranges.size(), emulators::PioneerSenses::kMaxSonar);
    if (view.step != UINT64_MAX) std::copy_n(view.ranges.begin(), n, senses.sonar_m);
  }
  if (world_.robot(robot_).has_power) {
    PowerView p = world_.power(robot_);
    const double charge = p.capacity > 0 ? std::clamp(p.joules / p.capacity, 0.0, 1.0) : 1.0;
    senses.battery_v = float(kEmptyV + charge * (kFullV - kEmptyV));
  }
  if (bumper_) {
    // The Pioneer's front ring has seven segments: the first seven of the
    // simulated bumper's.
    senses.front_bumpers = uint8_t(world_.bumper(*bumper_).pressed & 0x7F);
  }
}

SimLaser::SimLaser(World& world, uint32_t laser) : world_(world), laser_(laser) {
  world_.set_wanted({SensorKind::Ranger, laser_}, true);
}

void SimLaser::measure(double first, double step, std::span<float> ranges) {
  std::fill(ranges.begin(), ranges.end(), kNoReturn);
  const TransducerDesc& t = world_.ranger_desc(laser_).transducers.at(0);
  RangerView view = world_.ranger(laser_);
  if (view.step == UINT64_MAX || t.samples < 2 || view.ranges.size() < size_t(t.samples)) return;
  // The simulated beams lie from -fov/2 to +fov/2, the first and last on
  // the edges (Stage's layout), right to left as the scanner's are.
  const double spacing = t.fov / double(t.samples - 1);
  for (size_t i = 0; i < ranges.size(); ++i) {
    const double bearing = first + double(i) * step;
    const double j = std::round((bearing + 0.5 * t.fov) / spacing);
    if (j < 0 || j >= double(t.samples)) continue;
    const float r = view.ranges[size_t(j)];
    // A beam that reached its range_max hit nothing.
    if (r < float(t.range_max) - 1e-4f) ranges[i] = r;
  }
}

}  // namespace troupe::sim
