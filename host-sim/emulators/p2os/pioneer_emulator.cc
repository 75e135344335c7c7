#include "host-sim/emulators/p2os/pioneer_emulator.h"

#include <algorithm>
#include <cmath>

namespace troupe::emulators {

using drivers::p2os::Command;
using drivers::p2os::Packet;

namespace {

constexpr double kPi = 3.14159265358979323846;
// Heading counts per turn: the firmware sends 0..4095.
constexpr int kHeadingCounts = 4096;
// A partial packet is dropped after this long without a byte, us. At 9600
// baud bytes come every millisecond.
constexpr uint64_t kPacketGapUs = 50'000;

double approach(double current, double target, double max_change) {
  return current + std::clamp(target - current, -max_change, max_change);
}

}  // namespace

PioneerEmulator::PioneerEmulator(Config config, PioneerWorld* world)
    : config_(std::move(config)),
      world_(world ? world : &default_world_),
      faults_(config_.seed),
      inbound_faults_(config_.seed + 1) {
  robot_ = drivers::p2os::find_robot(config_.model);
  if (robot_ == nullptr) robot_ = drivers::p2os::find_robot("p3dx-sh");
}

bool PioneerEmulator::open(const std::string& link, std::string& error) {
  link_ = link;
  return port_.open(link, error);
}

void PioneerEmulator::vanish() {
  port_.close();
}

bool PioneerEmulator::reappear(std::string& error) {
  scanner_.reset();
  return port_.open(link_, error);
}

void PioneerEmulator::power_cycle() {
  close_session();
  left_ = right_ = 0;
  pose_ = {};
}

bool PioneerEmulator::baud_mismatch() const {
  if (!config_.check_baud) return false;
  uint32_t host = port_.host_baud();
  return host != 0 && host != config_.baud;
}

void PioneerEmulator::step(uint64_t now_us) {
  if (!started_) {
    started_ = true;
    last_step_us_ = last_packet_us_ = now_us;
  }
  now_us_ = now_us;
  uint8_t buf[256], heard[256];
  bool heard_any = false;
  for (size_t n; (n = port_.read(buf)) > 0; heard_any = true) {
    std::span<uint8_t> bytes(heard, inbound_faults_.apply({buf, n}, heard));
    if (baud_mismatch()) faults_.mangle(bytes);
    drivers::p2os::scan_packets(scanner_, bytes, [this](std::span<const uint8_t> p) { receive(p); });
  }
  // The firmware's receiver forgets a packet whose bytes stop coming, so a
  // corrupted count cannot hold the next commands back.
  if (heard_any) {
    last_byte_us_ = now_us;
  } else if (scanner_.partial() && now_us - last_byte_us_ > kPacketGapUs) {
    drivers::p2os::expire_packets(scanner_, [this](std::span<const uint8_t> p) { receive(p); });
  }
  double dt = double(now_us - last_step_us_) * 1e-6;
  last_step_us_ = now_us;
  if (session_ == Session::Open && now_us - last_packet_us_ > config_.watchdog_us &&
      (target_left_ != 0 || target_right_ != 0)) {
    // Nobody is talking to the robot: it stops rather than run away.
    set_wheel_targets(0, 0);
    vel_mm_s_ = rvel_deg_s_ = 0;
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
  ++packets_received_;
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
  drivers::p2os::CommandArg arg = drivers::p2os::parse_arg(p);
  const double div = robot_->vel2_divisor;
  switch (Command(p[0])) {
    case Command::Pulse:
      return;  // feeds the watchdog, as every packet does
    case Command::Close:
      return close_session();
    case Command::Enable:
      motors_enabled_ = arg.present && arg.value != 0;
      if (!motors_enabled_) {
        vel_mm_s_ = rvel_deg_s_ = 0;
        set_wheel_targets(0, 0);
      }
      return;
    case Command::SetO:
      pose_ = {};
      return;
    case Command::Vel:
    case Command::RVel: {
      if (!arg.present) return;
      (Command(p[0]) == Command::Vel ? vel_mm_s_ : rvel_deg_s_) = arg.value;
      double turn_mm_s = rvel_deg_s_ * kPi / 180.0 / robot_->diff_conv;
      watchdog_tripped_ = false;
      return set_wheel_targets(vel_mm_s_ - turn_mm_s, vel_mm_s_ + turn_mm_s);
    }
    case Command::Vel2: {
      if (!arg.present) return;
      // The argument's two bytes are signed wheel speeds: right low, left high.
      double right = int8_t(arg.lo) * div, left = int8_t(arg.hi) * div;
      vel_mm_s_ = 0.5 * (left + right);
      rvel_deg_s_ = 0.5 * (right - left) * robot_->diff_conv * 180.0 / kPi;
      watchdog_tripped_ = false;
      return set_wheel_targets(left, right);
    }
    case Command::Sonar:
      sonar_enabled_ = arg.present && arg.value != 0;
      return;
    case Command::Stop:
      vel_mm_s_ = rvel_deg_s_ = 0;
      return set_wheel_targets(0, 0);
    default:
      return;  // SETA, SETV, SETRA, GYRO, ...: accepted, not modelled
  }
}

void PioneerEmulator::set_wheel_targets(double left_mm_s, double right_mm_s) {
  double max = robot_->max_speed;
  target_left_ = std::clamp(left_mm_s / 1000.0, -max, max);
  target_right_ = std::clamp(right_mm_s / 1000.0, -max, max);
}

void PioneerEmulator::close_session() {
  session_ = Session::WaitSync0;
  motors_enabled_ = false;
  sonar_enabled_ = false;
  vel_mm_s_ = rvel_deg_s_ = 0;
  set_wheel_targets(0, 0);
}

void PioneerEmulator::move(double dt) {
  if (dt <= 0) return;
  bool driving = session_ == Session::Open && motors_enabled_;
  double step = config_.accel * dt;
  left_ = approach(left_, driving ? target_left_ : 0, step);
  right_ = approach(right_, driving ? target_right_ : 0, step);
  double track_m = 2.0 / robot_->diff_conv / 1000.0;
  stalled_ = world_->move(left_, right_, track_m, dt, pose_);
  if (stalled_) left_ = right_ = 0;
}

void PioneerEmulator::reply(std::span<const uint8_t> payload) {
  Packet packet;
  if (drivers::p2os::make_packet(payload, packet)) send_packet(packet);
}

void PioneerEmulator::send_packet(const Packet& packet) {
  if (mute_ || !port_.is_open()) return;
  uint8_t out[drivers::p2os::kMaxPacketBytes];
  size_t n = faults_.apply(packet.view(), out);
  if (baud_mismatch()) faults_.mangle({out, n});
  port_.write({out, n});
}

void PioneerEmulator::inject_noise(size_t bytes) {
  uint8_t out[256];
  while (bytes > 0 && port_.is_open()) {
    size_t n = std::min(bytes, sizeof out);
    faults_.noise({out, n});
    port_.write({out, n});
    bytes -= n;
  }
}

void PioneerEmulator::send_sip() {
  world_->sense(pose_, *robot_, senses_);
  drivers::p2os::Sip sip;
  bool moving = std::fabs(left_) > 1e-4 || std::fabs(right_) > 1e-4;
  sip.type = moving ? 0x33 : 0x32;
  // Counters are the pose in robot units; x and y keep 15 bits and wrap.
  sip.x = uint16_t(std::lround(pose_.x * 1000.0 / robot_->dist_conv) & 0x7FFF);
  sip.y = uint16_t(std::lround(pose_.y * 1000.0 / robot_->dist_conv) & 0x7FFF);
  double a = std::fmod(pose_.a, 2 * kPi);
  if (a < 0) a += 2 * kPi;
  sip.heading = int16_t(std::lround(a / robot_->angle_conv) % kHeadingCounts);
  sip.left_vel = int16_t(std::lround(left_ * 1000.0 / robot_->vel_conv));
  sip.right_vel = int16_t(std::lround(right_ * 1000.0 / robot_->vel_conv));
  sip.battery = uint8_t(std::clamp(std::lround(senses_.battery_v * 10.0), 0L, 255L));
  sip.left_stall = sip.right_stall = stalled_;
  sip.front_bumpers = senses_.front_bumpers & 0x7F;
  sip.rear_bumpers = senses_.rear_bumpers & 0x7F;
  sip.flags = motors_enabled_ ? 1 : 0;
  if (sonar_enabled_ && robot_->sonar_count > 0) {
    int n = std::clamp(config_.sonars_per_sip, 0, int(robot_->sonar_count));
    for (int k = 0; k < n; ++k) {
      int i = next_sonar_;
      next_sonar_ = (next_sonar_ + 1) % int(robot_->sonar_count);
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
}

}  // namespace troupe::emulators
