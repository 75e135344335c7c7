#include "wire/record/recorder.h"

#include <poll.h>
#include <sys/time.h>

#include <algorithm>
#include <cerrno>

#include "wire/address.h"
#include "wire/clock.h"
#include "wire/log.h"

namespace troupe::record {
namespace {

using wire::monotonic_us;

uint64_t unix_us() {
  timeval tv{};
  gettimeofday(&tv, nullptr);
  return uint64_t(tv.tv_sec) * 1000000u + uint64_t(tv.tv_usec);
}

std::string nack_text(const wire::Message& msg) {
  const wire::Error* e = msg.body_as_Error();
  if (e == nullptr) return "refused";
  return e->text() ? e->text()->str() : std::string(wire::EnumNameErrorCode(e->code()));
}

wire::ConnectionOptions connection_options(const RecordOptions& o) {
  wire::ConnectionOptions c;
  c.name = "troupe-record";
  c.target = o.host + ":" + std::to_string(o.port);
  c.backoff_min_us = uint64_t(o.reconnect_min_ms) * 1000u;
  c.backoff_max_us = uint64_t(std::max(o.reconnect_max_ms, o.reconnect_min_ms)) * 1000u;
  c.connect_timeout_us = uint64_t(o.timeout_ms) * 1000u;
  // A node with nothing to send is told apart from a dead one.
  c.keepalive_us = 2'000'000;
  c.keepalive_timeout_us = 6'000'000;
  c.sync_clock = false;
  return c;
}

}  // namespace

Recorder::Recorder(RecordOptions options)
    : options_(std::move(options)),
      link_(options_.host, options_.port, connection_options(options_), options_.resolver,
            options_.transport.get()) {}

double Recorder::elapsed_s() const {
  return start_us_ ? double(monotonic_us() - start_us_) * 1e-6 : 0.0;
}

bool Recorder::done() const {
  if (options_.max_frames > 0 && frames_ >= options_.max_frames) return true;
  return options_.duration_s > 0 && elapsed_s() >= options_.duration_s;
}

template <class Until>
bool Recorder::wait_for(Until until, int timeout_ms, const char* what, std::string& error) {
  uint64_t deadline = monotonic_us() + uint64_t(timeout_ms) * 1000u;
  for (;;) {
    for (wire::Event e = link_.next_event(); e.kind != wire::EventKind::None; e = link_.next_event()) {
      if (e.kind == wire::EventKind::Down) {
        error = std::string(e.text);
        return false;
      }
      if (until(e)) return true;
    }
    uint64_t now = monotonic_us();
    if (now >= deadline) {
      error = std::string(what) + " from " + options_.host + " within the timeout";
      return false;
    }
    link_.wait(int((deadline - now + 999) / 1000));
  }
}

bool Recorder::start(std::string& error) {
  link_.start();
  auto hello = [&](const wire::Event& e) {
    if (e.kind != wire::EventKind::Up) return false;
    hello_.assign(e.frame.begin(), e.frame.end());
    return true;
  };
  // The connect timeout of the connection bounds this wait; the margin only
  // covers a resolver that blocks.
  if (!wait_for(hello, options_.timeout_ms * 2, "no Hello", error)) return false;
  wire::Connection& conn = link_.connection();
  uint32_t list_seq = conn.next_seq();
  wire::MessageWriter w;
  link_.send(w.empty(wire::make_header({}, wire::Kind::DeviceList, 0, list_seq, monotonic_us())));
  auto list = [&](const wire::Event& e) {
    if (e.kind != wire::EventKind::Frame) return false;
    const wire::Header& h = *e.message->header();
    if (h.kind() != wire::Kind::DeviceList || h.seq() != list_seq || e.message->body_as_DeviceList() == nullptr) {
      return false;
    }
    device_list_.assign(e.frame.begin(), e.frame.end());
    return true;
  };
  if (!wait_for(list, options_.timeout_ms, "no device list", error)) return false;
  if (!resolve(error)) return false;

  // The log names only the recorded devices, with the node's robot and
  // driver names, so that play serves exactly these.
  const wire::DeviceList* devices = wire::trusted_message(device_list_)->body_as_DeviceList();
  auto& b = w.start();
  std::vector<flatbuffers::Offset<wire::DeviceInfo>> infos;
  for (const Device& d : devices_) {
    // resolve() found every device in the list, so the list is not empty.
    for (const wire::DeviceInfo* info : *devices->devices()) {
      if (info->addr() == nullptr || !(*info->addr() == d.addr)) continue;
      infos.push_back(wire::CreateDeviceInfo(
          b, &d.addr, b.CreateString(info->robot_name() ? info->robot_name()->str() : ""),
          b.CreateString(info->driver() ? info->driver()->str() : "")));
      break;
    }
  }
  auto body = wire::CreateDeviceList(b, b.CreateVector(infos));
  auto recorded = w.finish(wire::make_header({}, wire::Kind::DeviceList, 0, 0, monotonic_us()),
                           wire::Body::DeviceList, body.Union());

  if (!writer_.open(options_.output, unix_us(), error)) return false;
  start_us_ = monotonic_us();
  if (!writer_.write(0, hello_, error) || !writer_.write(0, recorded, error)) return false;
  // Asked before the Open: a node refuses requests from a client that
  // opened the device read-only.
  send_camera_requests();
  std::string write_error;
  auto answered = [&](const wire::Event& e) {
    if (e.kind == wire::EventKind::Frame && !handle(e.frame, *e.message, write_error)) return true;
    return !camera_replies_pending();
  };
  if (camera_replies_pending() &&
      !wait_for(answered, options_.timeout_ms, "no reply to a camera's Geometry or GetConfig", error)) {
    return false;
  }
  if (!write_error.empty()) {
    error = write_error;
    return false;
  }
  send_opens();
  auto opened = [&](const wire::Event& e) {
    if (e.kind == wire::EventKind::Frame && !handle(e.frame, *e.message, write_error)) return true;
    return !open_error_.empty() ||
           std::all_of(devices_.begin(), devices_.end(), [](const Device& d) { return d.acked; });
  };
  if (!wait_for(opened, options_.timeout_ms, "no reply to Open", error)) return false;
  if (!write_error.empty() || !open_error_.empty()) {
    error = write_error.empty() ? open_error_ : write_error;
    return false;
  }
  return writer_.flush(error);
}

bool Recorder::resolve(std::string& error) {
  const wire::DeviceList* list = wire::trusted_message(device_list_)->body_as_DeviceList();
  std::vector<std::string> available;
  if (list->devices() != nullptr) {
    for (const wire::DeviceInfo* info : *list->devices()) {
      if (info->addr() == nullptr) continue;
      available.push_back(
          wire::format_address(*info->addr(), info->robot_name() ? info->robot_name()->str() : ""));
    }
  }
  auto has = [&](const wire::Address& a) {
    if (list->devices() == nullptr) return false;
    for (const wire::DeviceInfo* info : *list->devices()) {
      if (info->addr() != nullptr && *info->addr() == a) return true;
    }
    return false;
  };
  for (const std::string& spec : options_.devices) {
    wire::DeviceSpec parsed;
    if (!wire::parse_device(spec, parsed, error)) return false;
    int robot = wire::robot_number(parsed.robot);
    if (robot < 0 && list->devices() != nullptr) {
      for (const wire::DeviceInfo* info : *list->devices()) {
        if (info->addr() != nullptr && info->robot_name() && info->robot_name()->str() == parsed.robot) {
          robot = info->addr()->robot();
          break;
        }
      }
    }
    wire::Address addr(uint16_t(std::max(robot, 0)), uint16_t(parsed.iface), parsed.index);
    if (robot < 0 || !has(addr)) {
      std::string names;
      for (const std::string& a : available) names += (names.empty() ? "" : ", ") + a;
      error = "no such device " + spec + " on " + options_.host +
              " (it has: " + (names.empty() ? "none" : names) + ")";
      return false;
    }
    bool duplicate =
        std::any_of(devices_.begin(), devices_.end(), [&](const Device& d) { return d.addr == addr; });
    if (!duplicate) devices_.push_back({addr, spec});
  }
  return true;
}

void Recorder::send_opens() {
  wire::MessageWriter w;
  for (Device& d : devices_) {
    d.open_seq = link_.connection().next_seq();
    auto& b = w.start();
    auto open = wire::CreateOpen(b, wire::Access::Read, wire::Delivery::Push, options_.image_compression);
    link_.send(w.finish(wire::make_header(d.addr, wire::Kind::Open, 0, d.open_seq, monotonic_us()),
                        wire::Body::Open, open.Union()));
  }
}

void Recorder::send_camera_requests() {
  wire::MessageWriter w;
  for (Device& d : devices_) {
    if (d.addr.iface() != uint16_t(wire::Interface::Camera)) continue;
    d.geometry_seq = link_.connection().next_seq();
    link_.send(w.empty(wire::make_header(d.addr, wire::Kind::Request, uint8_t(wire::CameraReqSub::Geometry),
                                         d.geometry_seq, monotonic_us())));
    d.config_seq = link_.connection().next_seq();
    link_.send(w.empty(wire::make_header(d.addr, wire::Kind::Request, uint8_t(wire::CameraReqSub::GetConfig),
                                         d.config_seq, monotonic_us())));
  }
}

bool Recorder::camera_replies_pending() const {
  return std::any_of(devices_.begin(), devices_.end(),
                     [](const Device& d) { return d.geometry_seq != 0 || d.config_seq != 0; });
}

bool Recorder::handle(std::span<const uint8_t> frame, const wire::Message& msg, std::string& error) {
  const wire::Header& h = *msg.header();
  if (h.kind() == wire::Kind::Data) {
    bool wanted =
        std::any_of(devices_.begin(), devices_.end(), [&](const Device& d) { return d.addr == h.addr(); });
    if (!wanted || done()) return true;
    if (!writer_.write(monotonic_us() - start_us_, frame, error)) return false;
    ++frames_;
  } else if (h.kind() == wire::Kind::Ack || h.kind() == wire::Kind::Nack) {
    for (Device& d : devices_) {
      if (d.open_seq == h.seq()) {
        d.acked = true;
        if (h.kind() == wire::Kind::Nack) open_error_ = "cannot open " + d.name + ": " + nack_text(msg);
      } else if (h.seq() != 0 && (d.geometry_seq == h.seq() || d.config_seq == h.seq())) {
        (d.geometry_seq == h.seq() ? d.geometry_seq : d.config_seq) = 0;
        // A camera that does not answer is still recorded; play then
        // refuses that request as a node without the answer would.
        if (h.kind() == wire::Kind::Nack) {
          log_warn("%s did not answer %s (%s); play will refuse it", d.name.c_str(),
                   wire::EnumNameCameraReqSub(wire::CameraReqSub(h.subtype())), nack_text(msg).c_str());
        } else if (!writer_.write(monotonic_us() - start_us_, frame, error)) {
          return false;
        }
      }
    }
  }
  return true;
}

bool Recorder::run(int stop_fd, std::string& error) {
  uint64_t deadline_us = options_.duration_s > 0 ? start_us_ + uint64_t(options_.duration_s * 1e6) : 0;
  while (!done()) {
    for (wire::Event e = link_.next_event(); e.kind != wire::EventKind::None && !done(); e = link_.next_event()) {
      if (e.kind == wire::EventKind::Frame) {
        if (!handle(e.frame, *e.message, error)) return false;
      } else if (e.kind == wire::EventKind::Down) {
        // The first failure says what happened; the attempts after it only
        // say why they failed, at debug level.
        if (!lost_) log_warn("%.*s; reconnecting", int(e.text.size()), e.text.data());
        if (lost_) log_debug("%.*s", int(e.text.size()), e.text.data());
        lost_ = true;
      } else if (e.kind == wire::EventKind::Up) {
        lost_ = false;
        send_opens();
        log_info("reconnected to %s; recording again", options_.host.c_str());
      }
    }
    if (!writer_.flush(error)) return false;
    if (done()) break;
    pollfd fds[1 + wire::kMaxAttemptsInFlight];
    int n = link_.poll_fds(fds, int(wire::kMaxAttemptsInFlight));
    fds[n] = {stop_fd, POLLIN, 0};
    int wait = link_.next_timeout_ms();
    if (wait < 0 || wait > 1000) wait = 1000;
    if (deadline_us != 0) {
      uint64_t now = monotonic_us();
      wait = now >= deadline_us ? 0 : std::min<int>(wait, int((deadline_us - now + 999) / 1000));
    }
    if (poll(fds, nfds_t(n + (stop_fd >= 0 ? 1 : 0)), wait) < 0 && errno != EINTR) break;
    if (stop_fd >= 0 && (fds[n].revents & POLLIN)) break;
    link_.process(fds, n);
    if (deadline_us != 0 && monotonic_us() >= deadline_us) break;
  }
  return writer_.close(error);
}

}  // namespace troupe::record
