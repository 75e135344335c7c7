#include "drivers/p2os/p2os.h"

#include <algorithm>
#include <cstring>

#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/node_config.h"

namespace troupe::drivers::p2os {
namespace {

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

P2os::P2os() : session_(*this), odometry_(*find_robot("p3dx-sh")) {}

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

  // A robot that is not there yet is no reason to refuse to start: the
  // node serves its other devices and the session keeps trying the port.
  serial::SerialSession::Options so;
  so.name = name_;
  so.port = opt->port()->str();
  so.bauds = {bauds_, baud_count_};
  so.reopen_min_us = opt->reopen_min_ms() * 1000ull;
  so.reopen_max_us = opt->reopen_max_ms() * 1000ull;
  return session_.start(node.loop(), so, error);
}

void P2os::send(const Packet& packet) {
  session_.send(packet.view());
}

void P2os::on_session_open() {
  log_info("%s: looking for a robot on %s", name_.c_str(), session_.port().c_str());
  start_baud(0);
}

void P2os::start_baud(size_t index) {
  baud_index_ = index;
  if (!session_.probe_baud(index)) return;
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
  session_.arm(sync_timeout_us_);
}

void P2os::on_sync_timeout() {
  if (settling_) {
    // In-flight packets have had their time: start over cleanly.
    session_.link().discard_input();
    scanner_.reset();
    settling_ = false;
    attempts_ = 0;
    state_ = State::Sync0;
    return send_sync();
  }
  if (state_ != State::Sync0) return confused("no reply to a SYNC packet");
  if (attempts_ < sync_attempts_) return send_sync();
  if (baud_index_ + 1 < session_.bauds().size()) {
    log_debug("%s: no answer at %u baud", name_.c_str(), unsigned(session_.bauds()[baud_index_]));
    return start_baud(baud_index_ + 1);
  }
  session_.lose("no robot answers on " + session_.port() + " at " + session_.bauds_text() + " baud");
}

void P2os::confused(const char* what) {
  // Something else is talking (a session left open by an earlier client
  // streams SIPs): close it once, let its packets drain, then sync again.
  log_debug("%s: %s during %s; sending CLOSE and starting over", name_.c_str(), what, state_name(state_));
  send(command(Command::Close));
  settling_ = true;
  state_ = State::Sync0;
  session_.arm(kSettleUs);
}

void P2os::on_session_bytes(std::span<const uint8_t> bytes) {
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
        name_.c_str(), id.name, session_.port().c_str(), id.robot_class, id.subclass, known_robots().c_str());
    send(command(Command::Close));
    return session_.lose("unknown robot model", session_.reopen_max_us());
  }
  if (robot_ != params) {
    robot_ = params;
    odometry_.set_params(*params);
  }
  log_info("%s: connected to %s (%s %s) on %s at %u baud", name_.c_str(), id.name, id.robot_class,
           id.subclass, session_.port().c_str(), unsigned(session_.baud()));
  enter_running();
}

void P2os::enter_running() {
  // The baud that worked is tried first next time.
  session_.prefer(baud_index_);
  baud_index_ = 0;
  session_.connected();
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

void P2os::on_session_down() {
  state_ = State::Closed;
  connected_ = false;
  settling_ = false;
  report_down();
}

void P2os::report_down() {
  // Clients learn of it as a stall: the base is not under control.
  if (reported_down_) return;
  reported_down_ = true;
  publish_position();
}

void P2os::on_session_tick(uint64_t now) {
  switch (state_) {
    case State::Closed:
      return;
    case State::Sync0:
    case State::Sync1:
    case State::Sync2:
      if (session_.expired()) on_sync_timeout();
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
  if (state_ == State::Running) {
    // Stop and end the session; the robot's watchdog is the backstop
    // should these bytes not reach it.
    send(command(Command::Stop));
    send(command_int(Command::Enable, 0));
    send(command(Command::Close));
  }
  session_.stop();
  state_ = State::Closed;
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"p2os", []() -> Driver* { return new P2os; }};

}  // namespace troupe::drivers::p2os
