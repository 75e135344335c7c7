// The node's one loop: epoll over every descriptor (sockets, serial ports,
// CAN sockets) and a fixed-capacity timer queue. Nothing here blocks except
// the wait itself, and nothing allocates after construction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

struct epoll_event;

namespace troupe {

/// Receives readiness of a watched descriptor.
class FdHandler {
 public:
  /// `events`: EPOLLIN, EPOLLOUT, EPOLLERR, EPOLLHUP bits.
  virtual void on_fd(int fd, uint32_t events) = 0;

 protected:
  ~FdHandler() = default;
};

/// A timer: slot index and generation, so a stale id never cancels a newer
/// timer that reuses the slot. 0 is never a valid id.
using TimerId = uint64_t;

class TimerHandler {
 public:
  virtual void on_timer(TimerId id) = 0;

 protected:
  ~TimerHandler() = default;
};

class EventLoop {
 public:
  /// `max_timers`: timers that may be armed at once.
  explicit EventLoop(size_t max_timers = 256);
  ~EventLoop();
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  bool ok() const { return epoll_fd_ >= 0; }

  /// Watches `fd` for `events` (EPOLLIN/EPOLLOUT...). One handler per fd.
  bool watch(int fd, uint32_t events, FdHandler* handler);
  /// Changes the events watched on an fd already watched.
  bool modify(int fd, uint32_t events);
  /// Stops watching; safe from inside a handler, even for another fd of the
  /// same batch (its pending events are dropped).
  void unwatch(int fd);

  /// Arms a timer `delay_us` from now; `period_us` > 0 repeats it. Returns 0
  /// when the queue is full.
  TimerId start_timer(uint64_t delay_us, uint64_t period_us, TimerHandler* handler);
  void cancel_timer(TimerId id);

  /// Waits for events or the next timer (at most `max_wait_us`, forever when
  /// negative) and dispatches them.
  void run_once(int64_t max_wait_us = -1);
  /// Makes run_once() return without waiting until `stop()` is cleared.
  void stop() { stopped_ = true; }
  bool stopped() const { return stopped_; }

  /// The time timers are measured against, us (monotonic).
  uint64_t now_us() const;

 private:
  struct Timer {
    uint64_t deadline_us = 0;
    uint64_t period_us = 0;
    TimerHandler* handler = nullptr;
    uint32_t generation = 0;
    bool armed = false;
  };
  struct HeapEntry {
    uint64_t deadline_us;
    uint32_t slot;
    uint32_t generation;
  };

  int wait(struct epoll_event* events, int max_events, int64_t wait_us);
  void push_heap_entry(HeapEntry e);
  HeapEntry pop_heap_entry();
  void run_timers();
  int64_t next_timer_wait_us() const;

  int epoll_fd_ = -1;
  std::vector<FdHandler*> handlers_;  // indexed by fd
  std::vector<Timer> timers_;
  std::vector<uint32_t> free_slots_;
  std::vector<HeapEntry> heap_;  // min-heap on deadline; cancelled entries linger until popped
  bool stopped_ = false;
  bool have_pwait2_ = true;
};

}  // namespace troupe
