// odrive_can: reading the options, registering the devices and opening the
// bus. The state machine and the frames are in odrive_can.cc.
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "drivers/odrive_can/can_io.h"
#include "drivers/odrive_can/odrive_can.h"
#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/node_config.h"

namespace troupe::drivers::odrive_can {

bool OdriveCan::read_options(const DriverSetup& setup, std::string& error) {
  OptionsView<Options> opt(setup);
  ifname_ = opt->can_interface() ? opt->can_interface()->str() : "can0";
  given_fd_ = opt->descriptor();
  uint8_t left = opt->left_node_id(), right = opt->right_node_id();
  if (left > cansimple::kMaxNodeId || right > cansimple::kMaxNodeId) {
    error = "left_node_id and right_node_id must be 0..63 (CAN Simple has six node bits)";
    return false;
  }
  if (left == right) {
    error = "left_node_id and right_node_id are both " + std::to_string(left) + ": each axis needs its own";
    return false;
  }
  geometry_ = {opt->wheel_radius(), opt->track_width(), opt->invert_left(), opt->invert_right()};
  if (!(geometry_.wheel_radius > 0) || !(geometry_.track_width > 0)) {
    error = "wheel_radius and track_width must be > 0 m";
    return false;
  }
  max_speed_ = opt->max_speed();
  max_turn_rate_ = opt->max_turn_rate();
  max_wheel_turns_s_ = opt->max_wheel_turns_s();
  current_limit_ = opt->current_limit();
  if (!(max_speed_ >= 0) || !(max_turn_rate_ >= 0) || !(max_wheel_turns_s_ > 0) || !(current_limit_ > 0)) {
    error = "max_speed and max_turn_rate must be >= 0, max_wheel_turns_s and current_limit > 0";
    return false;
  }
  if (!(opt->rate_hz() >= 1 && opt->rate_hz() <= 1000)) {
    error = "rate_hz must be in [1, 1000] Hz";
    return false;
  }
  if (!(opt->power_rate_hz() >= 0 && opt->power_rate_hz() <= 100)) {
    error = "power_rate_hz must be in [0, 100] Hz";
    return false;
  }
  if (opt->heartbeat_timeout_ms() == 0 || opt->arm_timeout_ms() == 0 || opt->retry_delay_ms() == 0) {
    error = "heartbeat_timeout_ms, arm_timeout_ms and retry_delay_ms must be > 0";
    return false;
  }
  if (!(opt->position_wrap_turns() >= 0)) {
    error = "position_wrap_turns must be >= 0 turns";
    return false;
  }
  velocity_ramp_ = opt->velocity_ramp();
  estop_on_shutdown_ = opt->estop_on_shutdown();
  period_us_ = uint64_t(1e6 / double(opt->rate_hz()));
  heartbeat_timeout_us_ = uint64_t(opt->heartbeat_timeout_ms()) * 1000u;
  arm_timeout_us_ = uint64_t(opt->arm_timeout_ms()) * 1000u;
  retry_delay_us_ = uint64_t(opt->retry_delay_ms()) * 1000u;
  retry_max_us_ = std::max(retry_delay_us_, uint64_t(opt->retry_max_ms()) * 1000u);
  command_timeout_us_ = uint64_t(opt->command_timeout_ms()) * 1000u;
  power_period_us_ = opt->power_rate_hz() > 0 ? uint64_t(1e6 / double(opt->power_rate_hz())) : 0;
  length_ = opt->length();
  width_ = opt->width();

  const char* sides[2] = {"left", "right"};
  const uint8_t ids[2] = {left, right};
  const bool inverts[2] = {geometry_.invert_left, geometry_.invert_right};
  for (int i = 0; i < 2; ++i) {
    axes_[i].side = sides[i];
    axes_[i].node_id = ids[i];
    axes_[i].invert = inverts[i];
    axes_[i].tracker.configure(opt->position_wrap_turns(), max_wheel_turns_s_);
  }
  return true;
}

bool OdriveCan::setup(Node& node, const DriverSetup& setup, std::string& error) {
  name_ = setup.name;
  for (DeviceId id : setup.provides) {
    auto iface = wire::Interface(node.address(id).iface());
    if (iface == wire::Interface::Position2d && position_ == kNoDevice) {
      position_ = id;
    } else if (iface == wire::Interface::Power && power_ == kNoDevice) {
      power_ = id;
    } else {
      error = "odrive_can provides one position2d and at most one power device, not " +
              std::string(wire::interface_name(uint16_t(iface))) + " or a second of a kind";
      return false;
    }
  }
  if (position_ == kNoDevice) {
    error = "odrive_can must provide a position2d device";
    return false;
  }
  if (!read_options(setup, error)) return false;
  if (!open_bus(error)) return false;
  uint64_t now = node.loop().now_us();
  state_since_us_ = now;
  tick_timer_ = node.loop().start_timer(period_us_, period_us_, this);
  if (power_ != kNoDevice && power_period_us_ > 0) {
    power_timer_ = node.loop().start_timer(power_period_us_, power_period_us_, this);
  }
  if (tick_timer_ == 0 || (power_ != kNoDevice && power_period_us_ > 0 && power_timer_ == 0)) {
    error = "no timer left in the node's loop";
    return false;
  }
  log_info("%s: axes left node %u, right node %u on %s", name_.c_str(), axes_[0].node_id, axes_[1].node_id,
           given_fd_ >= 0 ? ("descriptor " + std::to_string(given_fd_)).c_str() : ifname_.c_str());
  return true;
}

bool OdriveCan::open_bus(std::string& error) {
  if (given_fd_ >= 0) {
    if (!cansimple::make_nonblocking(given_fd_, error)) return false;
    fd_ = given_fd_;
    own_fd_ = false;
  } else {
    const uint8_t ids[2] = {axes_[0].node_id, axes_[1].node_id};
    fd_ = cansimple::open_can_socket(ifname_, ids, error);
    if (fd_ < 0) {
      // The config may be right for a robot whose bus is not up yet.
      if (errno == EAFNOSUPPORT || errno == ENODEV) setup_failure_ = SetupFailure::MissingDevice;
      return false;
    }
    own_fd_ = true;
  }
  if (!node_->loop().watch(fd_, EPOLLIN, this)) {
    error = "cannot watch CAN descriptor " + std::to_string(fd_);
    if (own_fd_) close(fd_);
    fd_ = -1;
    return false;
  }
  return true;
}

}  // namespace troupe::drivers::odrive_can
