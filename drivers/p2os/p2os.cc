#include "drivers/p2os/p2os.h"

#include <algorithm>
#include <cstring>

#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/node_config.h"

namespace troupe::drivers::p2os {
namespace {

// The state machine's clock: timeouts are checked this often, us.
constexpr uint64_t kTickUs = 50'000;
// After CLOSE for a confused handshake, packets still in flight are let go
// by for this long before SYNC0 starts again, us.
constexpr uint64_t kSettleUs = 150'000;
constexpr uint32_t kProbeOrder[] = {9600, 38400, 19200, 115200, 57600};

const char* state_name(P2os::State s) {
  switch (s) {
    case P2os::State::Closed:
      return "closed";
    case P2os::State::Sync0:
      return "SYNC0";
    case P2os::State::Sync1:
      return "SYNC1";
    case P2os::State::Sync2:
      return "SYNC2";
    case P2os::State::Running:
      return "running";
  }
  return "?";
}

}  // namespace

P2os::P2os() : link_(*this), odometry_(*find_robot("p3dx-sh")) {}

bool P2os::setup(Node& node, const DriverSetup& setup, std::string& error) {
  name_ = setup.name;
  for (DeviceId id : setup.provides) {
    auto iface = wire::Interface(node.address(id).iface());
    DeviceId* slot = iface == wire::Interface::Position2d ? &position_
                     : iface == wire::Interface::Ranger   ? &ranger_
                     : iface == wire::Interface::Power    ? &power_
                     : iface == wire::Interface::Bumper   ? &bumper_
                                                          : nullptr;
    if (slot == nullptr) {
      error = "p2os provides position2d, ranger, power and bumper, not " +
              std::string(wire::interface_name(uint16_t(iface)));
      return false;
    }
    if (*slot != kNoDevice) {
      error = "p2os provides one " + std::string(wire::interface_name(uint16_t(iface))) + " device, not two";
      return false;
    }
    *slot = id;
  }
  OptionsView<Options> opt(setup);
  if (opt->port() == nullptr || opt->port()->size() == 0) {
    error = "option \"port\" is missing: the serial device the robot is on, e.g. \"/dev/ttyS0\"";
    return false;
  }
  port_ = opt->port()->str();
  if (opt->baud() != 0) {
    if (!serial::is_supported_baud(opt->baud())) {
      error = "option \"baud\": " + std::to_string(opt->baud()) +
              " is not a baud the robot speaks (9600, 19200, 38400, 57600, 115200; 0 probes them)";
      return false;
    }
    bauds_[0] = opt->baud();
    baud_count_ = 1;
  } else {
    std::copy(std::begin(kProbeOrder), std::end(kProbeOrder), bauds_);
    baud_count_ = std::size(kProbeOrder);
  }
  if (opt->model() && opt->model()->size() > 0) {
    forced_model_ = find_robot(opt->model()->string_view());
    if (forced_model_ == nullptr) {
      error = "option \"model\": unknown robot '" + opt->model()->str() + "' (known: " + known_robots() + ")";
      return false;
    }
  }
  if (opt->pulse_ms() < 50 || opt->pulse_ms() > 1500) {
    error = "option \"pulse_ms\" must be in [50, 1500] ms: the robot's watchdog fires after about 2 s";
    return false;
  }
  if (opt->sync_timeout_ms() == 0 || opt->sync_attempts() == 0 || opt->sip_timeout_ms() < 200) {
    error = "options \"sync_timeout_ms\" and \"sync_attempts\" must be > 0 and \"sip_timeout_ms\" >= 200";
    return false;
  }
  if (opt->reopen_min_ms() == 0 || opt->reopen_max_ms() < opt->reopen_min_ms()) {
    error = "options \"reopen_min_ms\" must be > 0 and \"reopen_max_ms\" at least as large";
    return false;
  }
  if (opt->max_speed() < 0 || opt->max_turn_rate() < 0) {
    error = "options \"max_speed\" and \"max_turn_rate\" must be >= 0";
    return false;
  }
  sonar_on_ = opt->sonar();
  motors_on_ = opt->motors_on();
  use_vel2_ = opt->use_vel2();
  max_speed_opt_ = opt->max_speed();
  max_turn_opt_ = opt->max_turn_rate();
  pulse_us_ = opt->pulse_ms() * 1000ull;
  command_timeout_us_ = opt->command_timeout_ms() * 1000ull;
  sync_timeout_us_ = opt->sync_timeout_ms() * 1000ull;
  sync_attempts_ = opt->sync_attempts();
  sip_timeout_us_ = opt->sip_timeout_ms() * 1000ull;
  reopen_min_us_ = opt->reopen_min_ms() * 1000ull;
  reopen_max_us_ = opt->reopen_max_ms() * 1000ull;
  backoff_us_ = reopen_min_us_;

  link_.attach(node.loop());
  tick_ = node.loop().start_timer(kTickUs, kTickUs, this);
  if (tick_ == 0) {
    error = "no timer left";
    return false;
  }
  // A robot that is not there yet is no reason to refuse to start: the
  // node serves its other devices and keeps trying this port.
  try_open();
  return true;
}

void P2os::send(const Packet& packet) {
  if (!link_.send(packet.view())) log_debug("%s: output queue full; a packet was dropped", name_.c_str());
}

void P2os::try_open() {
  std::string error;
  if (!link_.open(port_, bauds_[0], error)) {
    uint64_t now = node_->loop().now_us();
    reopen_at_us_ = now + backoff_us_;
    // The first failure is worth a warning; repeats of the same only at
    // debug level, or a missing robot fills the log.
    if (!open_failed_logged_) {
      log_warn("%s: %s; trying again every %u ms or less", name_.c_str(), error.c_str(),
               unsigned(reopen_max_us_ / 1000));
      open_failed_logged_ = true;
    } else {
      log_debug("%s: %s", name_.c_str(), error.c_str());
    }
    backoff_us_ = std::min(backoff_us_ * 2, reopen_max_us_);
    state_ = State::Closed;
    return report_down();
  }
  log_info("%s: opened %s; looking for a robot", name_.c_str(), port_.c_str());
  open_failed_logged_ = false;
  start_baud(0);
}

void P2os::start_baud(size_t index) {
  baud_index_ = index;
  std::string error;
  if (link_.baud() != bauds_[index] && !link_.set_baud(bauds_[index], error)) {
    return lose(error, backoff_us_);
  }
  link_.discard_input();
  scanner_.reset();
  attempts_ = 0;
  settling_ = false;
  state_ = State::Sync0;
  send_sync();
}

void P2os::send_sync() {
  ++attempts_;
  Command c = state_ == State::Sync0   ? Command::Sync0
              : state_ == State::Sync1 ? Command::Sync1
                                       : Command::Sync2;
  send(command(c));
  deadline_us_ = node_->loop().now_us() + sync_timeout_us_;
}

void P2os::on_sync_timeout() {
  if (settling_) {
    // In-flight packets have had their time: start over cleanly.
    link_.discard_input();
    scanner_.reset();
    settling_ = false;
    attempts_ = 0;
    state_ = State::Sync0;
    return send_sync();
  }
  if (state_ != State::Sync0) return confused("no reply to a SYNC packet");
  if (attempts_ < sync_attempts_) return send_sync();
  if (baud_index_ + 1 < baud_count_) {
    log_debug("%s: no answer at %u baud", name_.c_str(), unsigned(bauds_[baud_index_]));
    return start_baud(baud_index_ + 1);
  }
  std::string tried;
  for (size_t i = 0; i < baud_count_; ++i) tried += (i ? ", " : "") + std::to_string(bauds_[i]);
  lose("no robot answers on " + port_ + " at " + tried + " baud", backoff_us_);
}

void P2os::confused(const char* what) {
  // Something else is talking (a session left open by an earlier client
  // streams SIPs): close it once, let its packets drain, then sync again.
  log_debug("%s: %s during %s; sending CLOSE and starting over", name_.c_str(), what, state_name(state_));
  send(command(Command::Close));
  settling_ = true;
  state_ = State::Sync0;
  deadline_us_ = node_->loop().now_us() + kSettleUs;
}

void P2os::on_serial_bytes(std::span<const uint8_t> bytes) {
  scan_packets(scanner_, bytes, [this](std::span<const uint8_t> payload) { handle_packet(payload); });
}

void P2os::handle_packet(std::span<const uint8_t> payload) {
  if (settling_) return;
  switch (state_) {
    case State::Closed:
      return;
    case State::Sync0:
      if (payload.size() == 1 && payload[0] == uint8_t(Command::Sync0)) {
        state_ = State::Sync1;
        attempts_ = 0;
        return send_sync();
      }
      return confused("an unexpected packet");
    case State::Sync1:
      if (payload.size() == 1 && payload[0] == uint8_t(Command::Sync1)) {
        state_ = State::Sync2;
        attempts_ = 0;
        return send_sync();
      }
      // A repeated SYNC0 echo (our retry crossed the reply) is no confusion.
      if (payload.size() == 1 && payload[0] == uint8_t(Command::Sync0)) return;
      return confused("an unexpected packet");
    case State::Sync2:
      if (payload[0] == uint8_t(Command::Sync2)) return identify(payload);
      if (payload.size() == 1 && payload[0] == uint8_t(Command::Sync1)) return;
      return confused("an unexpected packet");
    case State::Running:
      if (is_standard_sip(payload[0])) return handle_sip(payload);
      return;  // other server packets (config, encoders) are not used
  }
}

void P2os::identify(std::span<const uint8_t> payload) {
  RobotIdentity id;
  if (!parse_sync2(payload, id)) return confused("a malformed SYNC2 reply");
  const RobotParams* params = forced_model_ ? forced_model_ : find_robot(id.subclass);
  if (params == nullptr) {
    log_error(
        "%s: robot '%s' on %s is a %s/%s, whose parameters are unknown (known: %s); set the \"model\" "
        "option to drive it",
        name_.c_str(), id.name, port_.c_str(), id.robot_class, id.subclass, known_robots().c_str());
    send(command(Command::Close));
    return lose("unknown robot model", reopen_max_us_);
  }
  if (robot_ != params) {
    robot_ = params;
    odometry_.set_params(*params);
  }
  log_info("%s: connected to %s (%s %s) on %s at %u baud", name_.c_str(), id.name, id.robot_class,
           id.subclass, port_.c_str(), unsigned(bauds_[baud_index_]));
  enter_running();
}

void P2os::enter_running() {
  // The baud that worked is tried first next time.
  std::rotate(bauds_, bauds_ + baud_index_, bauds_ + baud_index_ + 1);
  baud_index_ = 0;
  backoff_us_ = reopen_min_us_;
  max_speed_ = max_speed_opt_ > 0 ? std::min(max_speed_opt_, robot_->max_speed) : robot_->max_speed;
  max_turn_ = max_turn_opt_ > 0 ? std::min(max_turn_opt_, robot_->max_turn_rate) : robot_->max_turn_rate;
  send(command(Command::Open));
  send(command(Command::Pulse));
  send(command_int(Command::Sonar, sonar_on_ ? 1 : 0));
  send(command_int(Command::Enable, motors_on_ ? 1 : 0));
  uint64_t now = node_->loop().now_us();
  state_ = State::Running;
  connected_ = true;
  reported_down_ = false;
  last_sip_us_ = now;
  sonar_seen_ = 0;
  odometry_.restart();
  if (target_v_ != 0 || target_w_ != 0) {
    send_velocity();
  } else {
    next_keepalive_us_ = now + pulse_us_;
  }
}

void P2os::lose(const std::string& why, uint64_t delay_us) {
  link_.close();
  state_ = State::Closed;
  connected_ = false;
  settling_ = false;
  reopen_at_us_ = node_->loop().now_us() + delay_us;
  backoff_us_ = std::min(std::max(delay_us, reopen_min_us_) * 2, reopen_max_us_);
  log_warn("%s: %s; reopening %s in %u ms", name_.c_str(), why.c_str(), port_.c_str(),
           unsigned(delay_us / 1000));
  report_down();
}

void P2os::report_down() {
  // Clients learn of it as a stall: the base is not under control.
  if (reported_down_) return;
  reported_down_ = true;
  publish_position();
}

void P2os::on_serial_lost(const std::string& why) {
  lose(port_ + ": " + why, backoff_us_);
}

void P2os::on_timer(TimerId id) {
  if (id != tick_) return;
  uint64_t now = node_->loop().now_us();
  switch (state_) {
    case State::Closed:
      if (now >= reopen_at_us_) try_open();
      return;
    case State::Sync0:
    case State::Sync1:
    case State::Sync2:
      if (now >= deadline_us_) on_sync_timeout();
      return;
    case State::Running:
      if (now - last_sip_us_ > sip_timeout_us_) {
        log_warn("%s: no SIP from the robot for %u ms; reconnecting", name_.c_str(),
                 unsigned((now - last_sip_us_) / 1000));
        connected_ = false;
        report_down();
        return confused("silence");
      }
      if (command_timeout_us_ > 0 && (target_v_ != 0 || target_w_ != 0) &&
          now - last_command_us_ > command_timeout_us_) {
        log_info("%s: no velocity command for %u ms; stopping", name_.c_str(),
                 unsigned(command_timeout_us_ / 1000));
        target_v_ = target_w_ = 0;
        send_velocity();
      }
      if (now >= next_keepalive_us_) keep_alive();
      return;
  }
}

void P2os::shutdown() {
  if (tick_ != 0) node_->loop().cancel_timer(tick_);
  tick_ = 0;
  if (state_ == State::Running) {
    // Stop and end the session; the robot's watchdog is the backstop
    // should these bytes not reach it.
    send(command(Command::Stop));
    send(command_int(Command::Enable, 0));
    send(command(Command::Close));
  }
  link_.close();
  state_ = State::Closed;
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"p2os", []() -> Driver* { return new P2os; }};

}  // namespace troupe::drivers::p2os
