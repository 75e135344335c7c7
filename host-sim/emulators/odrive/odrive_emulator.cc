#include "host-sim/emulators/odrive/odrive_emulator.h"

#include <sys/epoll.h>

#include <cstring>

#include "drivers/odrive_can/can_io.h"
#include "runtime/log.h"

namespace troupe::emulators::odrive {

namespace cs = troupe::cansimple;

namespace {
constexpr int kFramesPerEvent = 64;
}

OdriveEmulator::OdriveEmulator(EventLoop& loop, int fd, EmulatorOptions options)
    : loop_(loop), fd_(fd), options_(std::move(options)), rng_(options_.seed) {
  slots_.reserve(options_.axes.size());
  for (const AxisConfig& c : options_.axes) slots_.push_back(Slot{Axis(c)});
}

OdriveEmulator::~OdriveEmulator() {
  stop();
}

bool OdriveEmulator::start(std::string& error) {
  for (size_t i = 0; i < slots_.size(); ++i) {
    for (size_t k = 0; k < i; ++k) {
      if (slots_[i].axis.node_id() == slots_[k].axis.node_id()) {
        error = "two emulated axes share node id " + std::to_string(slots_[i].axis.node_id());
        return false;
      }
    }
    if (slots_[i].axis.node_id() > cs::kMaxNodeId) {
      error = "node id " + std::to_string(slots_[i].axis.node_id()) + " is over 63";
      return false;
    }
  }
  if (!cs::make_nonblocking(fd_, error)) return false;
  if (!loop_.watch(fd_, EPOLLIN, this)) {
    error = "cannot watch descriptor " + std::to_string(fd_);
    return false;
  }
  uint64_t now = loop_.now_us();
  for (Slot& s : slots_) s.axis.step(now);
  estimates_timer_ = loop_.start_timer(options_.estimates_period_us, options_.estimates_period_us, this);
  // A heartbeat period that is a whole number of estimate periods rides on
  // the estimates' tick, as one firmware clock would send them: a loaded host
  // that skips a tick then skips both, and the two streams keep their ratio.
  const uint64_t e = options_.estimates_period_us, h = options_.heartbeat_period_us;
  heartbeat_every_ = (e > 0 && h >= e && h % e == 0) ? uint32_t(h / e) : 0;
  if (heartbeat_every_ == 0) heartbeat_timer_ = loop_.start_timer(h, h, this);
  if (estimates_timer_ == 0 || (heartbeat_every_ == 0 && heartbeat_timer_ == 0)) {
    error = "no timer left in the loop";
    return false;
  }
  return true;
}

void OdriveEmulator::stop() {
  if (estimates_timer_) loop_.cancel_timer(estimates_timer_);
  if (heartbeat_timer_) loop_.cancel_timer(heartbeat_timer_);
  estimates_timer_ = heartbeat_timer_ = 0;
  if (fd_ >= 0) loop_.unwatch(fd_);
  fd_ = -1;
}

OdriveEmulator::Slot* OdriveEmulator::find(uint8_t node_id) {
  for (Slot& s : slots_) {
    if (s.axis.node_id() == node_id) return &s;
  }
  return nullptr;
}

Axis* OdriveEmulator::axis(uint8_t node_id) {
  Slot* s = find(node_id);
  return s ? &s->axis : nullptr;
}

void OdriveEmulator::set_silent(uint8_t node_id, bool silent) {
  if (Slot* s = find(node_id)) s->silent = silent;
}

bool OdriveEmulator::drop() {
  return drop_p_ > 0 && std::uniform_real_distribution<double>(0, 1)(rng_) < drop_p_;
}

void OdriveEmulator::send(const can_frame& f) {
  if (fd_ < 0) return;
  if (drop()) {
    counters_.dropped_out++;
    return;
  }
  int err = 0;
  switch (cs::write_frame(fd_, f, err)) {
    case cs::IoResult::Frame:
      counters_.frames_out++;
      return;
    case cs::IoResult::Closed:
      log_warn("odrive emulator: write: %s: the bus is gone", strerror(err));
      stop();
      return;
    default:
      counters_.dropped_out++;
      return;  // full queue, or the kernel refused a malformed frame
  }
}

void OdriveEmulator::on_fd(int fd, uint32_t events) {
  if (fd != fd_) return;
  const uint64_t now = loop_.now_us();
  for (int i = 0; i < kFramesPerEvent && fd_ >= 0; ++i) {
    can_frame f;
    int err = 0;
    switch (cs::read_frame(fd_, f, err)) {
      case cs::IoResult::Frame:
        break;
      case cs::IoResult::WouldBlock:
        if (events & (EPOLLHUP | EPOLLERR)) stop();
        return;
      case cs::IoResult::Down:  // the interface went down; frames flow again once it is up
        return;
      case cs::IoResult::Closed:
        log_info("odrive emulator: the bus closed%s%s", err ? ": " : "", err ? strerror(err) : "");
        stop();
        return;
      default:
        counters_.short_reads++;
        continue;
    }
    counters_.frames_in++;
    if (f.can_id & (CAN_EFF_FLAG | CAN_ERR_FLAG)) continue;  // ODrive listens to standard ids only
    if (drop()) {
      counters_.dropped_in++;
      continue;
    }
    Slot* s = find(cs::node_of(f.can_id));
    if (s == nullptr || s->silent) continue;
    can_frame reply;
    s->axis.step(now);  // state at the moment the frame arrives
    if (s->axis.handle(f, now, reply)) send(reply);
  }
}

void OdriveEmulator::update_bus() {
  float amps = 0;
  for (const Slot& s : slots_) amps += s.axis.bus_amps();
  for (Slot& s : slots_) {
    const AxisConfig& c = options_.axes[size_t(&s - slots_.data())];
    s.axis.set_bus(c.supply_volts - c.supply_ohms * amps, amps);
  }
}

void OdriveEmulator::on_timer(TimerId id) {
  const uint64_t now = loop_.now_us();
  if (id == estimates_timer_) {
    for (Slot& s : slots_) s.axis.step(now);
    update_bus();
    for (Slot& s : slots_) {
      if (!s.silent) send(s.axis.encoder_estimates());
    }
    if (heartbeat_every_ != 0 && ++ticks_ % heartbeat_every_ == 0) {
      for (Slot& s : slots_) {
        if (!s.silent) send(s.axis.heartbeat());
      }
    }
  } else if (id == heartbeat_timer_) {
    for (Slot& s : slots_) {
      if (!s.silent) send(s.axis.heartbeat());
    }
  }
}

void OdriveEmulator::send_garbage(uint8_t node_id, int count) {
  for (int i = 0; i < count; ++i) {
    can_frame f;
    std::memset(&f, 0, sizeof f);
    switch (i % 5) {
      case 0:  // a heartbeat cut short
        f = find(node_id) ? find(node_id)->axis.heartbeat() : cs::heartbeat_frame(node_id, {});
        f.len = uint8_t(i % 4);
        break;
      case 1:  // encoder estimates cut short, with a wild position
        f = cs::encoder_estimates_frame(node_id, {1e9f, 0});
        f.len = 6;
        break;
      case 2:  // a length no classic CAN frame has
        f.can_id = cs::make_id(node_id, cs::Cmd::GetEncoderEstimates);
        f.len = 15;
        break;
      case 3:  // an extended id that would alias the node's heartbeat
        f.can_id = cs::make_id(node_id, cs::Cmd::Heartbeat) | CAN_EFF_FLAG;
        f.len = 8;
        break;
      case 4:                           // a controller error frame
        f.can_id = CAN_ERR_FLAG | 0x4;  // CAN_ERR_CRTL
        f.len = 8;
        break;
    }
    for (int k = 0; k < f.len && k < CAN_MAX_DLEN; ++k) f.data[k] = f.data[k] ? f.data[k] : uint8_t(rng_());
    send(f);
  }
}

}  // namespace troupe::emulators::odrive
