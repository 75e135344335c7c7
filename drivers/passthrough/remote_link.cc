#include "drivers/passthrough/remote_link.h"

#include <algorithm>

#include "wire/clock.h"

namespace troupe::drivers::passthrough {

RemoteLink::RemoteLink(EventLoop& loop, LinkListener& listener) : loop_(loop), listener_(listener) {}

RemoteLink::~RemoteLink() {
  stop();
}

bool RemoteLink::start(const LinkOptions& options, std::string& error) {
  if (options.port == 0) {
    error = "port 0 is not a remote node's port";
    return false;
  }
  std::vector<wire::Endpoint> found;
  if (!wire::resolve_numeric(options.host, options.port, found, error)) return false;
  bool v6 = options.host.find(':') != std::string::npos && options.host.front() != '[';
  remote_text_ = (v6 ? "[" + options.host + "]" : options.host) + ":" + std::to_string(options.port);
  wire::ConnectionOptions c;
  c.name = options.client_name;
  c.target = remote_text_;
  c.peer = "remote " + remote_text_;
  c.limits = options.limits;
  c.backoff_min_us = options.backoff_min_us;
  c.backoff_max_us = options.backoff_max_us;
  c.connect_timeout_us = options.connect_timeout_us;
  c.keepalive_us = options.idle_timeout_us / 4;
  c.keepalive_timeout_us = options.idle_timeout_us - options.idle_timeout_us / 4;
  c.max_output_bytes = options.max_queue_bytes;
  c.sync_clock = false;
  transport_ = options.transport;
  link_ = std::make_unique<wire::SocketLink>(options.host, options.port, std::move(c), wire::resolve_numeric,
                                             transport_.get());
  link_->on_close([this](int fd) { forget(fd); });
  link_->start();
  service();
  return true;
}

void RemoteLink::stop() {
  if (!link_) return;
  if (timer_ != 0) loop_.cancel_timer(timer_);
  timer_ = 0;
  timer_at_us_ = wire::kNoDeadline;
  link_->stop();  // forgets each socket as it closes it
}

bool RemoteLink::send(std::span<const uint8_t> frame) {
  if (!up()) return false;
  bool queued = link_->send(frame);
  service();
  return queued;
}

void RemoteLink::close(const std::string& why) {
  link_->close(why);
  service();
}

void RemoteLink::on_fd(int fd, uint32_t events) {
  // epoll's EPOLLIN/OUT/ERR/HUP bits are poll's POLLIN/OUT/ERR/HUP.
  pollfd p{fd, 0, short(events)};
  link_->process(&p, 1);
  service();
}

void RemoteLink::on_timer(TimerId id) {
  if (id != timer_) return;
  timer_ = 0;
  timer_at_us_ = wire::kNoDeadline;
  link_->process(nullptr, 0);
  service();
}

void RemoteLink::service() {
  // A listener may send or close from inside its callback; the outer call
  // then picks up what that caused.
  if (servicing_) {
    again_ = true;
    return;
  }
  servicing_ = true;
  do {
    again_ = false;
    for (wire::Event e = link_->next_event(); e.kind != wire::EventKind::None; e = link_->next_event()) {
      switch (e.kind) {
        case wire::EventKind::Up: listener_.on_link_up(); break;
        case wire::EventKind::Down: listener_.on_link_down(std::string(e.text)); break;
        case wire::EventKind::Frame: listener_.on_remote_frame(*e.message); break;
        case wire::EventKind::Synced:
        case wire::EventKind::None: break;
      }
    }
    bool busy = !idle();
    if (busy_ && !busy && up()) listener_.on_link_writable();
    busy_ = busy;
  } while (again_);
  servicing_ = false;
  sync_watches();
  arm_timer();
}

void RemoteLink::forget(int fd) {
  pollfd* end = watched_ + watched_count_;
  pollfd* it = std::find_if(watched_, end, [&](const pollfd& w) { return w.fd == fd; });
  if (it == end) return;
  loop_.unwatch(fd);
  std::copy(it + 1, end, it);
  --watched_count_;
}

void RemoteLink::sync_watches() {
  // Every closed socket was forgotten before it closed (forget()): what is
  // watched is open, and a number seen again is the same socket.
  pollfd want[wire::kMaxAttemptsInFlight];
  int n = link_->poll_fds(want, int(wire::kMaxAttemptsInFlight));
  for (int i = 0; i < watched_count_; ++i) {
    bool kept = std::any_of(want, want + n, [&](const pollfd& w) { return w.fd == watched_[i].fd; });
    if (!kept) loop_.unwatch(watched_[i].fd);
  }
  for (int i = 0; i < n; ++i) {
    const pollfd* had = std::find_if(watched_, watched_ + watched_count_,
                                     [&](const pollfd& w) { return w.fd == want[i].fd; });
    if (had == watched_ + watched_count_) {
      loop_.watch(want[i].fd, uint32_t(want[i].events), this);
    } else if (had->events != want[i].events) {
      loop_.modify(want[i].fd, uint32_t(want[i].events));
    }
  }
  std::copy(want, want + n, watched_);
  watched_count_ = n;
}

void RemoteLink::arm_timer() {
  uint64_t at = conn().next_deadline_us();
  // Deadlines move later with traffic (the keep-alive's); an armed timer
  // that fires early only finds nothing due and is armed again. Re-arming
  // only for an earlier deadline keeps busy links from churning timers.
  if (at == wire::kNoDeadline || (timer_ != 0 && at >= timer_at_us_)) return;
  if (timer_ != 0) loop_.cancel_timer(timer_);
  uint64_t now = wire::monotonic_us();
  timer_ = loop_.start_timer(at > now ? at - now : 0, 0, this);
  timer_at_us_ = timer_ != 0 ? at : wire::kNoDeadline;
}

}  // namespace troupe::drivers::passthrough
