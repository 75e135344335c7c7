#include "wire/record/recorder.h"

#include <poll.h>
#include <sys/time.h>

#include <algorithm>

#include "runtime/clock.h"
#include "runtime/log.h"
#include "wire/address.h"

namespace troupe::record {
namespace {

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

}  // namespace

Recorder::Recorder(RecordOptions options) : options_(std::move(options)), session_("troupe-record") {}

double Recorder::elapsed_s() const {
  return start_us_ ? double(monotonic_us() - start_us_) * 1e-6 : 0.0;
}

bool Recorder::done() const {
  if (options_.max_frames > 0 && frames_ >= options_.max_frames) return true;
  return options_.duration_s > 0 && elapsed_s() >= options_.duration_s;
}

bool Recorder::start(std::string& error) {
  if (!session_.connect(options_.host, options_.port, options_.timeout_ms, error)) return false;
  uint32_t list_seq = ++seq_;
  if (!session_.send({}, wire::Kind::DeviceList, list_seq, error)) return false;
  uint64_t deadline = monotonic_us() + uint64_t(options_.timeout_ms) * 1000u;
  while (device_list_.empty()) {
    std::span<const uint8_t> frame;
    const wire::Message* msg = nullptr;
    uint64_t now = monotonic_us();
    int wait = now >= deadline ? 0 : int((deadline - now) / 1000);
    Session::Read r = session_.read(wait, frame, msg, error);
    if (r == Session::Read::Timeout) error = "no device list from " + options_.host + " within the timeout";
    if (r != Session::Read::Frame) return false;
    if (msg->header()->kind() == wire::Kind::DeviceList && msg->header()->seq() == list_seq &&
        msg->body_as_DeviceList() != nullptr) {
      device_list_.assign(frame.begin(), frame.end());
    }
  }
  if (!resolve(error)) return false;

  // The log names only the recorded devices, with the node's robot and
  // driver names, so that play serves exactly these.
  const wire::DeviceList* list = wire::trusted_message(device_list_)->body_as_DeviceList();
  wire::MessageWriter w;
  auto& b = w.start();
  std::vector<flatbuffers::Offset<wire::DeviceInfo>> infos;
  for (const Device& d : devices_) {
    // resolve() found every device in the list, so the list is not empty.
    for (const wire::DeviceInfo* info : *list->devices()) {
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
  if (!writer_.write(0, session_.hello_frame(), error) || !writer_.write(0, recorded, error)) return false;
  if (!send_opens(error)) return false;
  deadline = monotonic_us() + uint64_t(options_.timeout_ms) * 1000u;
  while (!std::all_of(devices_.begin(), devices_.end(), [](const Device& d) { return d.acked; })) {
    std::span<const uint8_t> frame;
    const wire::Message* msg = nullptr;
    uint64_t now = monotonic_us();
    Session::Read r = session_.read(now >= deadline ? 0 : int((deadline - now) / 1000), frame, msg, error);
    if (r == Session::Read::Timeout) error = "no reply to Open from " + options_.host + " within the timeout";
    if (r != Session::Read::Frame) return false;
    if (!handle(frame, *msg, error)) return false;
    if (!open_error_.empty()) {
      error = open_error_;
      return false;
    }
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

bool Recorder::send_opens(std::string& error) {
  for (Device& d : devices_) {
    d.open_seq = ++seq_;
    auto& b = session_.begin();
    auto open = wire::CreateOpen(b, wire::Access::Read, wire::Delivery::Push);
    if (!session_.send(d.addr, wire::Kind::Open, d.open_seq, error, wire::Body::Open, open.Union()))
      return false;
  }
  return true;
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
      if (d.open_seq != h.seq()) continue;
      d.acked = true;
      if (h.kind() == wire::Kind::Nack) open_error_ = "cannot open " + d.name + ": " + nack_text(msg);
    }
  }
  return true;
}

bool Recorder::reconnect(int stop_fd, uint64_t deadline_us) {
  uint32_t backoff_ms = options_.reconnect_min_ms;
  for (;;) {
    int wait = int(backoff_ms);
    if (deadline_us != 0) {
      uint64_t now = monotonic_us();
      if (now >= deadline_us) return false;
      wait = std::min<int>(wait, int((deadline_us - now + 999) / 1000));
    }
    pollfd p{stop_fd, POLLIN, 0};
    if (poll(&p, stop_fd >= 0 ? 1 : 0, wait) > 0) return false;
    std::string error;
    if (session_.connect(options_.host, options_.port, options_.timeout_ms, error) && send_opens(error)) {
      ++reconnections_;
      log_info("reconnected to %s; recording again", options_.host.c_str());
      return true;
    }
    log_debug("%s", error.c_str());
    backoff_ms = std::min(backoff_ms * 2, options_.reconnect_max_ms);
  }
}

bool Recorder::run(int stop_fd, std::string& error) {
  uint64_t deadline_us = options_.duration_s > 0 ? start_us_ + uint64_t(options_.duration_s * 1e6) : 0;
  while (!done()) {
    // Drain whatever the session holds, then wait for more or for a stop.
    std::span<const uint8_t> frame;
    const wire::Message* msg = nullptr;
    std::string why;
    Session::Read r;
    while ((r = session_.read(0, frame, msg, why)) == Session::Read::Frame) {
      if (!handle(frame, *msg, error)) return false;
      if (done()) break;
    }
    if (!writer_.flush(error)) return false;
    if (done()) break;
    if (r == Session::Read::Closed) {
      log_warn("%s; reconnecting", why.c_str());
      if (!reconnect(stop_fd, deadline_us)) break;
      continue;
    }
    pollfd fds[2] = {{session_.fd(), POLLIN, 0}, {stop_fd, POLLIN, 0}};
    int wait = 1000;
    if (deadline_us != 0) {
      uint64_t now = monotonic_us();
      wait = now >= deadline_us ? 0 : std::min<int>(wait, int((deadline_us - now + 999) / 1000));
    }
    if (poll(fds, stop_fd >= 0 ? 2 : 1, wait) > 0 && (fds[1].revents & POLLIN)) break;
  }
  return writer_.close(error);
}

}  // namespace troupe::record
