#include "host-sim/emulators/p2os/pioneer_emulator.h"

#include <algorithm>
#include <cmath>

#include "drivers/p2os/p2os_config_packet.h"
#include "runtime/log.h"

namespace troupe::emulators {

using drivers::p2os::Command;
using drivers::p2os::Packet;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
// Heading counts per turn: the firmware sends 0..4095.
constexpr int kHeadingCounts = 4096;
// A partial packet is dropped after this long without a byte, us. At 9600
// baud bytes come every millisecond.
constexpr uint64_t kPacketGapUs = 50'000;
// HOSTBAUD's argument indexes these, bit/s.
constexpr uint32_t kHostBauds[] = {9600, 19200, 38400, 57600, 115200};

}  // namespace

PioneerEmulator::PioneerEmulator(Config config, PioneerWorld* world)
    : SerialEmulator(config.seed, config.check_baud),
      config_(std::move(config)),
      world_(world ? world : &default_world_),
      baud_(config_.baud) {
  robot_ = drivers::p2os::find_robot(config_.model);
  if (robot_ == nullptr) robot_ = drivers::p2os::find_robot("p3dx-sh");
  motion_.half_track = 1.0 / robot_->diff_conv / 1000.0;
  motion_.wheel_max = robot_->max_speed;
  reset_limits();
}

void PioneerEmulator::reset_limits() {
  motion_.limits.trans_vel_max = robot_->max_speed;
  motion_.limits.trans_accel = motion_.limits.trans_decel = config_.accel;
  motion_.limits.rot_vel_max = robot_->max_turn_rate;
  motion_.limits.rot_accel = motion_.limits.rot_decel = config_.rot_accel_deg * kDegToRad;
}

void PioneerEmulator::set_sim_laser(LaserWorld* laser) {
  sim_laser_.attach(laser);
}

void PioneerEmulator::power_cycle() {
  close_session();
  motion_.halt();
  reset_odometry();
  baud_ = config_.baud;
  bump_stall_ = 0;
  polling_size_ = 0;
  reset_limits();
}

void PioneerEmulator::on_heard(std::span<const uint8_t> bytes) {
  drivers::p2os::scan_packets(scanner_, bytes, [this](std::span<const uint8_t> p) { receive(p); });
}

void PioneerEmulator::on_stale_partial() {
  drivers::p2os::expire_packets(scanner_, [this](std::span<const uint8_t> p) { receive(p); });
}

void PioneerEmulator::step(uint64_t now_us) {
  if (!started_) {
    started_ = true;
    last_step_us_ = last_packet_us_ = now_us;
  }
  now_us_ = now_us;
  listen(now_us, kPacketGapUs);
  double dt = double(now_us - last_step_us_) * 1e-6;
  last_step_us_ = now_us;
  if (session_ == Session::Open && now_us - last_packet_us_ > config_.watchdog_us &&
      (motion_.target_left() != 0 || motion_.target_right() != 0 || motion_.left() != 0 || motion_.right() != 0)) {
    // Nobody is talking to the robot: it stops rather than run away.
    motion_.stop();
    watchdog_tripped_ = true;
  }
  move(dt);
  if (session_ == Session::Open && now_us >= next_sip_us_) {
    send_sip();
    next_sip_us_ += config_.sip_period_us;
    if (next_sip_us_ <= now_us) next_sip_us_ = now_us + config_.sip_period_us;
  }
}

void PioneerEmulator::receive(std::span<const uint8_t> p) {
  last_packet_us_ = now_us_;
  const uint8_t cmd = p[0];
  const bool bare = p.size() == 1;
  const uint8_t sync0[1] = {0}, sync1[1] = {1};
  switch (session_) {
    case Session::WaitSync0:
      if (bare && cmd == 0) {
        reply(sync0);
        session_ = Session::WaitSync1;
      }
      return;
    case Session::WaitSync1:
      if (bare && cmd == 1) {
        reply(sync1);
        session_ = Session::WaitSync2;
      } else if (bare && cmd == 0) {
        reply(sync0);  // a repeated SYNC0: answer it again
      } else {
        session_ = Session::WaitSync0;
      }
      return;
    case Session::WaitSync2:
      if (bare && cmd == 2) {
        uint8_t id[drivers::p2os::kMaxPayloadBytes];
        size_t n = 0;
        id[n++] = 2;
        for (const std::string* s : {&config_.name, &config_.robot_class, &config_.model}) {
          size_t len = std::min(s->size(), size_t(60));
          std::copy_n(s->data(), len, id + n);
          n += len;
          id[n++] = 0;
        }
        reply({id, n});
        session_ = Session::Ready;
      } else if (bare && cmd == 0) {
        reply(sync0);
        session_ = Session::WaitSync1;
      } else {
        session_ = Session::WaitSync0;
      }
      return;
    case Session::Ready:
      if (cmd == uint8_t(Command::Open)) {
        session_ = Session::Open;
        motors_enabled_ = false;
        sonar_enabled_ = true;
        next_sip_us_ = now_us_;
      } else if (bare && cmd == 0) {
        reply(sync0);
        session_ = Session::WaitSync1;
      } else if (cmd == uint8_t(Command::Close)) {
        session_ = Session::WaitSync0;
      }
      return;
    case Session::Open:
      return obey(p);
  }
}

void PioneerEmulator::obey(std::span<const uint8_t> p) {
  if (sim_laser_.obey(p)) return;
  drivers::p2os::CommandArg arg = drivers::p2os::parse_arg(p);
  const int value = arg.present ? arg.value : 0;
  const double heading = pose_.a;
  // Motion commands move only a robot whose motors are on.
  // A motion command counts when it carries its argument; it clears a
  // tripped watchdog.
  auto accepted = [&] {
    watchdog_tripped_ = false;
    return arg.present;
  };
  switch (Command(p[0])) {
    case Command::Pulse:
      return;  // feeds the watchdog, as every packet does
    case Command::Open:
      return;  // already open
    case Command::Close:
      return close_session();
    case Command::Enable:
      motors_enabled_ = value != 0;
      if (!motors_enabled_) motion_.halt();
      return;
    case Command::Sonar:
      sonar_enabled_ = value != 0;
      return;
    case Command::Polling: {
      // A string of transducer numbers, 1-based, in firing order.
      if (p.size() < 3 || p[1] != uint8_t(drivers::p2os::ArgType::String)) return;
      size_t n = std::min<size_t>({p[2], p.size() - 3, PioneerSenses::kMaxSonar});
      polling_size_ = 0;
      for (size_t i = 0; i < n; ++i) {
        if (p[3 + i] >= 1 && p[3 + i] <= robot_->sonar_count) polling_[polling_size_++] = uint8_t(p[3 + i] - 1);
      }
      next_sonar_ = 0;
      return;
    }
    case Command::SetO:
      reset_odometry();
      if (motion_.rot_mode() == PioneerMotion::Rot::Heading) motion_.set_heading(0);
      return;
    case Command::SetV:
      if (arg.present) motion_.limits.trans_vel_max = std::min(std::abs(value) / 1000.0, double(robot_->max_speed));
      return;
    case Command::SetRv:
      if (arg.present) motion_.limits.rot_vel_max = std::min(std::abs(value) * kDegToRad, double(robot_->max_turn_rate));
      return;
    case Command::SetA:
      // A positive argument sets the acceleration, a negative one the
      // deceleration; 0 keeps the value in force.
      if (value > 0) motion_.limits.trans_accel = value / 1000.0;
      if (value < 0) motion_.limits.trans_decel = -value / 1000.0;
      return;
    case Command::SetRA:
      if (value > 0) motion_.limits.rot_accel = value * kDegToRad;
      if (value < 0) motion_.limits.rot_decel = -value * kDegToRad;
      return;
    case Command::Vel:
      if (accepted()) motion_.set_velocity(value / 1000.0);
      return;
    case Command::RVel:
    case Command::Rotate:
      if (accepted()) motion_.set_turn_rate(value * kDegToRad);
      return;
    case Command::Move:
      if (!accepted()) return;
      motion_.move(value / 1000.0);
      updated_at_ = pose_;  // what was driven before counts for nothing
      return;
    case Command::Head:
      if (accepted()) motion_.set_heading(value * kDegToRad);
      return;
    case Command::DHead:
      if (accepted()) motion_.set_heading(heading + value * kDegToRad);
      return;
    case Command::DcHead:
      if (accepted()) motion_.set_heading(motion_.heading_setpoint(heading) + value * kDegToRad);
      return;
    case Command::Vel2: {
      if (!accepted()) return;
      // The argument's two bytes are signed wheel speeds: right low, left high.
      const double div = robot_->vel2_divisor / 1000.0;
      return motion_.set_wheels(int8_t(arg.hi) * div, int8_t(arg.lo) * div);
    }
    case Command::Stop:
      return motion_.stop();
    case Command::EStop:
      return motion_.halt();
    case Command::BumpStall:
      bump_stall_ = uint8_t(std::clamp(value, 0, 3));
      return;
    case Command::Config:
      return send_config();
    case Command::HostBaud:
      // The reply-less switch: the next byte comes at the new speed.
      if (value >= 0 && value < int(std::size(kHostBauds))) baud_ = kHostBauds[value];
      return;
    default:
      return unmodelled(p[0]);
  }
}

void PioneerEmulator::unmodelled(uint8_t command) {
  ++unmodelled_;
  if (unmodelled_logged_[command]) return;
  unmodelled_logged_[command] = true;
  log_warn("p2os emulator %s: command %s (%u) is not modelled; ignored", config_.name.c_str(),
           drivers::p2os::command_name(command), unsigned(command));
}

void PioneerEmulator::close_session() {
  session_ = Session::WaitSync0;
  motors_enabled_ = false;
  sonar_enabled_ = false;
  motion_.halt();
}

void PioneerEmulator::move(double dt) {
  if (dt <= 0) return;
  const bool driving = session_ == Session::Open && motors_enabled_;
  if (!driving) motion_.halt();
  waited_s_ += dt;
  const double moved_s = world_->observe(waited_s_, pose_);
  if (moved_s <= 0) return;
  waited_s_ = 0;
  // A MOVE counts the distance the wheels really covered.
  double travelled = std::hypot(pose_.x - updated_at_.x, pose_.y - updated_at_.y);
  if (motion_.v() < 0) travelled = -travelled;
  motion_.update(moved_s, pose_.a, travelled);
  updated_at_ = pose_;
  double track_m = 2 * motion_.half_track;
  stalled_ = world_->move(motion_.left(), motion_.right(), track_m, moved_s, pose_);
  const bool bumped = ((bump_stall_ & 1) && senses_.front_bumpers) || ((bump_stall_ & 2) && senses_.rear_bumpers);
  if (stalled_ || bumped) {
    stalled_ = true;
    motion_.halt();
  }
}

void PioneerEmulator::reset_odometry() {
  pose_ = updated_at_ = {};
}

void PioneerEmulator::reply(std::span<const uint8_t> payload) {
  Packet packet;
  if (drivers::p2os::make_packet(payload, packet)) send_packet(packet);
}

void PioneerEmulator::send_packet(const Packet& packet) {
  uint8_t out[drivers::p2os::kMaxPacketBytes];
  size_t n = through_faults(packet.view(), out);
  garble_if_mismatched({out, n});
  write_line({out, n});
}

void PioneerEmulator::send_sip() {
  world_->sense(pose_, *robot_, senses_);
  drivers::p2os::Sip sip;
  bool moving = std::fabs(left_mps()) > 1e-4 || std::fabs(right_mps()) > 1e-4;
  sip.type = moving ? 0x33 : 0x32;
  // Counters are the pose in robot units; x and y keep 15 bits and wrap.
  sip.x = uint16_t(std::lround(pose_.x * 1000.0 / robot_->dist_conv) & 0x7FFF);
  sip.y = uint16_t(std::lround(pose_.y * 1000.0 / robot_->dist_conv) & 0x7FFF);
  double a = std::fmod(pose_.a, 2 * kPi);
  if (a < 0) a += 2 * kPi;
  sip.heading = int16_t(std::lround(a / robot_->angle_conv) % kHeadingCounts);
  sip.left_vel = int16_t(std::lround(left_mps() * 1000.0 / robot_->vel_conv));
  sip.right_vel = int16_t(std::lround(right_mps() * 1000.0 / robot_->vel_conv));
  sip.battery = uint8_t(std::clamp(std::lround(senses_.battery_v * 10.0), 0L, 255L));
  sip.left_stall = sip.right_stall = stalled_;
  sip.front_bumpers = senses_.front_bumpers & 0x7F;
  sip.rear_bumpers = senses_.rear_bumpers & 0x7F;
  // The heading setpoint, in heading counts.
  double set = std::fmod(motion_.heading_setpoint(pose_.a), 2 * kPi);
  if (set < 0) set += 2 * kPi;
  sip.control = uint16_t(std::lround(set / robot_->angle_conv) % kHeadingCounts);
  sip.flags = motors_enabled_ ? 1 : 0;
  if (sonar_enabled_ && robot_->sonar_count > 0) {
    size_t ring = polling_size_ > 0 ? polling_size_ : robot_->sonar_count;
    int n = std::clamp(config_.sonars_per_sip, 0, int(ring));
    for (int k = 0; k < n; ++k) {
      size_t i = polling_size_ > 0 ? polling_[next_sonar_] : next_sonar_;
      next_sonar_ = (next_sonar_ + 1) % ring;
      double mm = std::min(double(senses_.sonar_m[i]), double(robot_->sonar_max_range)) * 1000.0;
      sip.sonar[k] = {uint8_t(i), uint16_t(std::lround(std::max(mm, 0.0) / robot_->range_conv))};
    }
    sip.sonar_count = uint8_t(n);
  }
  sip.timer = uint16_t(now_us_ / 1000);
  uint8_t payload[drivers::p2os::kMaxPayloadBytes];
  size_t size = drivers::p2os::write_sip(sip, payload);
  Packet packet;
  if (size > 0 && drivers::p2os::make_packet({payload, size}, packet)) {
    send_packet(packet);
    ++sips_sent_;
  }
  if (sim_laser_.mode() != 0) {
    sim_laser_.scan(int(std::lround(pose_.x * 1000)), int(std::lround(pose_.y * 1000)),
                    int(std::lround(std::remainder(pose_.a, 2 * kPi) / kDegToRad)), moving,
                    [this](const Packet& p) { send_packet(p); });
  }
}

void PioneerEmulator::send_config() {
  auto deg = [](double rad) { return int(std::lround(rad / kDegToRad)); };
  auto mm = [](double m) { return int(std::lround(m * 1000)); };
  const MotionLimits& l = motion_.limits;
  drivers::p2os::ConfigPacket c;
  c.robot_class = config_.robot_class;
  c.subclass = config_.model;
  c.name = config_.name;
  c.rot_vel_top = deg(robot_->max_turn_rate);
  c.trans_vel_top = mm(robot_->max_speed);
  c.rot_accel_top = deg(std::max(l.rot_accel, l.rot_decel));
  c.trans_accel_top = mm(std::max(l.trans_accel, l.trans_decel));
  c.sip_cycle_ms = int(config_.sip_period_us / 1000);
  c.host_baud_index = int(std::find(std::begin(kHostBauds), std::end(kHostBauds), baud_) - std::begin(kHostBauds));
  c.front_sonar = c.rear_sonar = robot_->sonar_count > 0;
  c.watchdog_ms = int(config_.watchdog_us / 1000);
  c.rot_vel_max = deg(l.rot_vel_max);
  c.trans_vel_max = mm(l.trans_vel_max);
  c.rot_accel = deg(l.rot_accel);
  c.rot_decel = deg(l.rot_decel);
  c.trans_accel = mm(l.trans_accel);
  c.trans_decel = mm(l.trans_decel);
  Packet packet;
  if (drivers::p2os::write_config_packet(c, packet)) send_packet(packet);
}

}  // namespace troupe::emulators
