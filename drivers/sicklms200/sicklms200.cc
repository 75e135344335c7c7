#include "drivers/sicklms200/sicklms200.h"

#include <algorithm>
#include <cmath>

#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/node_config.h"

namespace troupe::drivers::sicklms200 {
namespace {

constexpr double kCentidegreeToRad = 3.14159265358979323846 / 18000.0;
// Power-up speed first, then the speeds a driver may have left it at.
constexpr uint32_t kProbeOrder[] = {9600, 38400, 500000, 19200};

const char* state_name(SickLms200::State s) {
  switch (s) {
    case SickLms200::State::Closed:
      return "closed";
    case SickLms200::State::Connect:
      return "entering configuration mode";
    case SickLms200::State::SwitchBaud:
      return "switching baud";
    case SickLms200::State::Variant:
      return "selecting the variant";
    case SickLms200::State::ReadConfig:
      return "reading the configuration";
    case SickLms200::State::WriteConfig:
      return "writing the configuration";
    case SickLms200::State::Start:
      return "starting continuous output";
    case SickLms200::State::Streaming:
      return "streaming";
  }
  return "?";
}

bool valid_variant(uint16_t width, uint16_t res) {
  if (width == 180) return res == 50 || res == 100;
  if (width == 100) return res == 25 || res == 50 || res == 100;
  return false;
}

}  // namespace

SickLms200::SickLms200() : session_(*this) {}

bool SickLms200::setup(Node& node, const DriverSetup& setup, std::string& error) {
  name_ = setup.name;
  if (setup.provides.size() != 1 ||
      node.address(setup.provides[0]).iface() != uint16_t(wire::Interface::Ranger)) {
    error = "sicklms200 provides exactly one ranger device";
    return false;
  }
  ranger_ = setup.provides[0];
  OptionsView<Options> opt(setup);
  if (opt->port() == nullptr || opt->port()->size() == 0) {
    error = "option \"port\" is missing: the serial device the scanner is on, e.g. \"/dev/ttyUSB0\"";
    return false;
  }
  Mode unused{};
  if (!mode_for_baud(opt->baud(), unused)) {
    error = "option \"baud\": the scanner runs at 9600, 19200, 38400 or 500000 bit/s, not " +
            std::to_string(opt->baud());
    return false;
  }
  if (!valid_variant(opt->scan_width_deg(), opt->resolution_cdeg())) {
    error = "options \"scan_width_deg\" " + std::to_string(opt->scan_width_deg()) +
            " and \"resolution_cdeg\" " + std::to_string(opt->resolution_cdeg()) +
            ": the scanner offers 180 degrees at 100 or 50, and 100 degrees at 100, 50 or 25";
    return false;
  }
  if (opt->reply_timeout_ms() == 0 || opt->reply_attempts() == 0 || opt->scan_timeout_ms() < 200) {
    error = "options \"reply_timeout_ms\" and \"reply_attempts\" must be > 0 and \"scan_timeout_ms\" >= 200";
    return false;
  }
  target_baud_ = opt->baud();
  width_deg_ = opt->scan_width_deg();
  resolution_cdeg_ = opt->resolution_cdeg();
  expected_count_ = uint16_t(width_deg_ * 100 / resolution_cdeg_ + 1);
  pose_x_ = opt->pose_x();
  pose_y_ = opt->pose_y();
  pose_yaw_ = opt->pose_yaw();
  reply_timeout_us_ = opt->reply_timeout_ms() * 1000ull;
  reply_attempts_ = opt->reply_attempts();
  scan_timeout_us_ = opt->scan_timeout_ms() * 1000ull;
  // A scanner not there yet is no reason to refuse to start: the node
  // serves its other devices and the session keeps trying the port.
  serial::SerialSession::Options so;
  so.name = name_;
  so.port = opt->port()->str();
  so.bauds = kProbeOrder;
  so.reopen_min_us = opt->reopen_min_ms() * 1000ull;
  so.reopen_max_us = opt->reopen_max_ms() * 1000ull;
  return session_.start(node.loop(), so, error);
}

void SickLms200::on_session_open() {
  log_info("%s: looking for the scanner on %s", name_.c_str(), session_.port().c_str());
  probe(0);
}

void SickLms200::probe(size_t index) {
  probe_index_ = index;
  if (!session_.probe_baud(index)) return;
  scanner_.reset();
  ask(State::Connect, enter_config(), reply_code(Request::ModeChange));
}

void SickLms200::ask(State state, const Telegram& request, uint8_t reply) {
  state_ = state;
  pending_ = request;
  expect_ = reply;
  attempts_ = 1;
  session_.arm(reply_timeout_us_);
  session_.send(request.view());
}

void SickLms200::on_session_bytes(std::span<const uint8_t> bytes) {
  scan_telegrams(scanner_, bytes, [this](std::span<const uint8_t> body) { handle(body); });
}

void SickLms200::handle(std::span<const uint8_t> body) {
  Reply reply;
  if (state_ == State::Closed || !split_reply(body, reply)) return;
  if (reply.code == kScanReply && state_ == State::Streaming) {
    const char* why = nullptr;
    if (!parse_scan(reply.data, scan_, &why)) {
      log_debug("%s: scan dropped: %s", name_.c_str(), why);
      return;
    }
    if (scan_.count != expected_count_ || scan_.units != Units::Millimetres) {
      // Not the scans configured: someone else reconfigured the scanner,
      // or it restarted with its stored settings. Configure it again.
      log_warn("%s: scan of %u values in units %u, expected %u in millimetres; configuring again",
               name_.c_str(), unsigned(scan_.count), unsigned(scan_.units), unsigned(expected_count_));
      return probe(probe_index_);
    }
    last_scan_us_ = node_->loop().now_us();
    return publish(scan_);
  }
  if (reply.code != expect_ || state_ == State::Streaming) return;  // e.g. scans still streaming in
  on_reply(reply);
}

void SickLms200::on_reply(const Reply& reply) {
  auto refused = [&](const char* what) {
    log_error("%s: the scanner refused %s (reply 0x%02x, data %u bytes)", name_.c_str(), what,
              unsigned(reply.code), unsigned(reply.data.size()));
    session_.lose("configuration refused", session_.reopen_max_us());
  };
  bool ok = !reply.data.empty() && reply.data[0] == 0;  // mode change: 0 is success
  switch (state_) {
    case State::Connect: {
      if (!ok) return refused("configuration mode (wrong password?)");
      // The speed that answered is tried first next time.
      session_.prefer(probe_index_);
      probe_index_ = 0;
      if (session_.baud() == target_baud_)
        return ask(State::Variant, variant(width_deg_, resolution_cdeg_), reply_code(Request::Variant));
      Telegram t;
      baud_change(target_baud_, t);
      return ask(State::SwitchBaud, t, reply_code(Request::ModeChange));
    }
    case State::SwitchBaud: {
      if (!ok) return refused("the baud change");
      // The scanner answered at the old speed and now listens at the new.
      if (!session_.set_baud(target_baud_)) return;
      scanner_.reset();
      // Its new speed is where a reconnect should look first.
      session_.prefer_baud(target_baud_);
      return ask(State::Variant, variant(width_deg_, resolution_cdeg_), reply_code(Request::Variant));
    }
    case State::Variant:
      if (reply.data.empty() || reply.data[0] != 1) return refused("the scan variant");
      return ask(State::ReadConfig, simple(Request::ReadConfig), reply_code(Request::ReadConfig));
    case State::ReadConfig:
      if (reply.data.size() <= kConfigUnits) return refused("to tell its configuration");
      config_size_ = std::min(reply.data.size(), kConfigBytes);
      std::copy_n(reply.data.begin(), config_size_, config_);
      if (config_[kConfigUnits] == uint8_t(Units::Millimetres)) {
        return ask(State::Start, mode_change(Mode::Continuous), reply_code(Request::ModeChange));
      }
      config_[kConfigUnits] = uint8_t(Units::Millimetres);
      return ask(State::WriteConfig, write_config({config_, config_size_}), reply_code(Request::WriteConfig));
    case State::WriteConfig:
      if (reply.data.empty() || reply.data[0] != 1) return refused("millimetre units");
      return ask(State::Start, mode_change(Mode::Continuous), reply_code(Request::ModeChange));
    case State::Start:
      if (!ok) return refused("continuous output");
      log_info("%s: scanner on %s streams %u degrees at %.2f degree steps, %u baud", name_.c_str(),
               session_.port().c_str(), unsigned(width_deg_), resolution_cdeg_ / 100.0, unsigned(session_.baud()));
      state_ = State::Streaming;
      session_.connected();
      last_scan_us_ = node_->loop().now_us();
      return;
    case State::Closed:
    case State::Streaming:
      return;
  }
}

void SickLms200::on_timeout() {
  // Telegrams held behind a corrupted length are still good: look at them
  // before asking again.
  expire_telegrams(scanner_, [this](std::span<const uint8_t> body) { handle(body); });
  if (state_ == State::Streaming || state_ == State::Closed) return;
  if (!session_.expired()) return;  // a reply came and moved us on
  if (attempts_ < reply_attempts_) {
    ++attempts_;
    session_.arm(reply_timeout_us_);
    session_.send(pending_.view());
    return;
  }
  if (state_ == State::Connect) {
    if (probe_index_ + 1 < session_.bauds().size()) {
      log_debug("%s: no answer at %u baud", name_.c_str(), unsigned(session_.bauds()[probe_index_]));
      return probe(probe_index_ + 1);
    }
    return session_.lose("no scanner answers on " + session_.port() + " at " + session_.bauds_text() + " baud");
  }
  log_warn("%s: no reply while %s; starting over", name_.c_str(), state_name(state_));
  probe(0);
}

void SickLms200::on_session_down() {
  state_ = State::Closed;
}

void SickLms200::on_session_tick(uint64_t now) {
  switch (state_) {
    case State::Closed:
      return;
    case State::Streaming:
      if (now - last_scan_us_ > scan_timeout_us_) {
        log_warn("%s: no valid scan for %u ms; configuring the scanner again", name_.c_str(),
                 unsigned((now - last_scan_us_) / 1000));
        probe(0);
      }
      return;
    default:
      if (session_.expired()) on_timeout();
      return;
  }
}

void SickLms200::publish(const Scan& scan) {
  auto& b = node_->begin();
  auto ranges = b.CreateVector(scan.ranges, scan.count);
  wire::RangerScanBuilder out(b);
  out.add_ranges(ranges);
  out.add_scale(0.001f);
  out.add_min_angle(float(-width_deg_ * 50 * kCentidegreeToRad));
  out.add_angular_res(float(resolution_cdeg_ * kCentidegreeToRad));
  out.add_max_range(kNoReturn / 1000.0f);
  node_->publish(ranger_, uint8_t(wire::RangerDataSub::Scan), wire::Body::RangerScan, out.Finish().Union());
}

void SickLms200::on_request(DeviceId device, const wire::Message& req, RequestToken token) {
  using Sub = wire::RangerReqSub;
  switch (Sub(req.header()->subtype())) {
    case Sub::Geometry: {
      auto& b = node_->begin();
      wire::Pose3d pose(pose_x_, pose_y_, 0, 0, 0, pose_yaw_);
      wire::Vec3 size(0.155f, 0.155f, 0.185f);  // the LMS200 housing, m
      auto body = wire::CreateRangerGeometry(b, &pose, &size);
      return node_->ack(token, wire::Body::RangerGeometry, body.Union());
    }
    case Sub::GetConfig: {
      auto& b = node_->begin();
      double half = width_deg_ * 50 * kCentidegreeToRad;
      // Continuous output sends scans as fast as the line carries them, up
      // to the scanner's 75 Hz.
      double telegram_bytes = kFrameBytes + 4.0 + 2.0 * expected_count_;
      double rate = std::min(75.0, (session_.is_open() ? session_.baud() : target_baud_) / 10.0 / telegram_bytes);
      auto body =
          wire::CreateRangerConfig(b, float(-half), float(half), float(resolution_cdeg_ * kCentidegreeToRad),
                                   0, kNoReturn / 1000.0f, 0.001f, float(rate));
      return node_->ack(token, wire::Body::RangerConfig, body.Union());
    }
    default:
      break;
  }
  Driver::on_request(device, req, token);
}

void SickLms200::shutdown() {
  // Leave the scanner quiet; it keeps its speed until power-down.
  if (state_ == State::Streaming) session_.send(mode_change(Mode::StopContinuous).view());
  session_.stop();
  state_ = State::Closed;
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"sicklms200", []() -> Driver* { return new SickLms200; }};

}  // namespace troupe::drivers::sicklms200
