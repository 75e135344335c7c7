#include "runtime/event_loop.h"

#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "runtime/clock.h"
#include "runtime/log.h"

namespace troupe {
namespace {

constexpr int kMaxEventsPerWait = 64;

TimerId make_id(uint32_t slot, uint32_t generation) {
  return (uint64_t{generation} << 32) | (uint64_t{slot} + 1);
}

bool later(const auto& a, const auto& b) { return a.deadline_us > b.deadline_us; }

}  // namespace

EventLoop::EventLoop(size_t max_timers) : timers_(max_timers) {
  epoll_fd_ = epoll_create1(EPOLL_CLOEXEC);
  if (epoll_fd_ < 0) log_error("epoll_create1: errno %d", errno);
  free_slots_.reserve(max_timers);
  for (size_t i = max_timers; i > 0; --i) free_slots_.push_back(uint32_t(i - 1));
  // Cancelled entries stay in the heap until they surface, so it gets room
  // for twice the timers; compaction handles the rest.
  heap_.reserve(2 * max_timers + 1);
}

EventLoop::~EventLoop() {
  if (epoll_fd_ >= 0) close(epoll_fd_);
}

bool EventLoop::watch(int fd, uint32_t events, FdHandler* handler) {
  if (fd < 0) return false;
  epoll_event ev{};
  ev.events = events;
  ev.data.fd = fd;
  if (epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, fd, &ev) != 0) {
    log_error("epoll_ctl(ADD, fd %d): errno %d", fd, errno);
    return false;
  }
  if (size_t(fd) >= handlers_.size()) handlers_.resize(size_t(fd) + 1, nullptr);
  handlers_[size_t(fd)] = handler;
  return true;
}

bool EventLoop::modify(int fd, uint32_t events) {
  epoll_event ev{};
  ev.events = events;
  ev.data.fd = fd;
  return epoll_ctl(epoll_fd_, EPOLL_CTL_MOD, fd, &ev) == 0;
}

void EventLoop::unwatch(int fd) {
  if (fd < 0 || size_t(fd) >= handlers_.size()) return;
  epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
  handlers_[size_t(fd)] = nullptr;
}

uint64_t EventLoop::now_us() const { return monotonic_us(); }

void EventLoop::push_heap_entry(HeapEntry e) {
  if (heap_.size() == heap_.capacity()) {
    // Drop entries of cancelled or re-armed timers before growing.
    std::erase_if(heap_, [this](const HeapEntry& h) {
      const Timer& t = timers_[h.slot];
      return !t.armed || t.generation != h.generation || t.deadline_us != h.deadline_us;
    });
    std::make_heap(heap_.begin(), heap_.end(), later<HeapEntry, HeapEntry>);
  }
  heap_.push_back(e);
  std::push_heap(heap_.begin(), heap_.end(), later<HeapEntry, HeapEntry>);
}

EventLoop::HeapEntry EventLoop::pop_heap_entry() {
  std::pop_heap(heap_.begin(), heap_.end(), later<HeapEntry, HeapEntry>);
  HeapEntry e = heap_.back();
  heap_.pop_back();
  return e;
}

TimerId EventLoop::start_timer(uint64_t delay_us, uint64_t period_us, TimerHandler* handler) {
  if (free_slots_.empty()) {
    log_error("timer queue full (%zu timers)", timers_.size());
    return 0;
  }
  uint32_t slot = free_slots_.back();
  free_slots_.pop_back();
  Timer& t = timers_[slot];
  t.deadline_us = now_us() + delay_us;
  t.period_us = period_us;
  t.handler = handler;
  t.armed = true;
  push_heap_entry({t.deadline_us, slot, t.generation});
  return make_id(slot, t.generation);
}

void EventLoop::cancel_timer(TimerId id) {
  if (id == 0) return;
  uint32_t slot = uint32_t(id & 0xFFFFFFFFu) - 1;
  uint32_t generation = uint32_t(id >> 32);
  if (slot >= timers_.size()) return;
  Timer& t = timers_[slot];
  if (!t.armed || t.generation != generation) return;
  t.armed = false;
  ++t.generation;
  free_slots_.push_back(slot);
}

int64_t EventLoop::next_timer_wait_us() const {
  if (heap_.empty()) return -1;
  uint64_t now = now_us();
  uint64_t first = heap_.front().deadline_us;
  return first > now ? int64_t(first - now) : 0;
}

void EventLoop::run_timers() {
  uint64_t now = now_us();
  while (!heap_.empty() && heap_.front().deadline_us <= now) {
    HeapEntry e = pop_heap_entry();
    Timer& t = timers_[e.slot];
    if (!t.armed || t.generation != e.generation || t.deadline_us != e.deadline_us) continue;
    TimerId id = make_id(e.slot, t.generation);
    TimerHandler* handler = t.handler;
    if (t.period_us > 0) {
      // Keep the phase: the next deadline follows the last one, not `now`,
      // unless we fell more than a period behind.
      t.deadline_us += t.period_us;
      if (t.deadline_us <= now) t.deadline_us = now + t.period_us;
      push_heap_entry({t.deadline_us, e.slot, t.generation});
    } else {
      t.armed = false;
      ++t.generation;
      free_slots_.push_back(e.slot);
    }
    handler->on_timer(id);
  }
}

int EventLoop::wait(epoll_event* events, int max_events, int64_t wait_us) {
  // epoll_pwait2 waits to the microsecond; epoll_wait only to the
  // millisecond, which makes a 1 kHz timer fire late and skip ticks. Kernels
  // before 5.11 (and some qemu-user versions) lack the former.
  if (have_pwait2_) {
    timespec ts{time_t(wait_us / 1000000), long(wait_us % 1000000) * 1000};
    int n = epoll_pwait2(epoll_fd_, events, max_events, wait_us < 0 ? nullptr : &ts, nullptr);
    if (n >= 0 || errno != ENOSYS) return n;
    have_pwait2_ = false;
  }
  // Round up so a timer 300 us away does not spin with a 0 ms timeout.
  int timeout_ms = wait_us < 0 ? -1 : int((wait_us + 999) / 1000);
  return epoll_wait(epoll_fd_, events, max_events, timeout_ms);
}

void EventLoop::run_once(int64_t max_wait_us) {
  int64_t wait_us = next_timer_wait_us();
  if (max_wait_us >= 0 && (wait_us < 0 || wait_us > max_wait_us)) wait_us = max_wait_us;
  if (stopped_) wait_us = 0;
  epoll_event events[kMaxEventsPerWait];
  int n = wait(events, kMaxEventsPerWait, wait_us);
  if (n < 0 && errno != EINTR) log_error("epoll_wait: errno %d", errno);
  for (int i = 0; i < n; ++i) {
    int fd = events[i].data.fd;
    // A handler earlier in this batch may have unwatched this fd.
    if (size_t(fd) < handlers_.size() && handlers_[size_t(fd)] != nullptr) {
      handlers_[size_t(fd)]->on_fd(fd, events[i].events);
    }
  }
  run_timers();
}

}  // namespace troupe
