// SIGINT and SIGTERM as a readable descriptor (signalfd), so that programs
// stop from inside their single loop like any other event: drivers shut
// down, files are finished, nothing runs in a signal handler.
#pragma once

#include <cstdint>

#include "runtime/event_loop.h"
#include "runtime/log.h"

namespace troupe {

class StopSignals {
 public:
  /// Blocks SIGINT and SIGTERM for this thread and opens the descriptor.
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// Readable once a signal is pending; -1 when signalfd failed.
  int fd() const { return fd_; }
  /// Consumes a pending signal and returns its name, or nullptr.
  const char* take();

 private:
  int fd_ = -1;
};

/// Calls `stop()` from `loop` when SIGINT or SIGTERM arrives, after logging
/// which one. `Stop` is any callable (a lambda naming what to stop).
template <class Stop>
class StopOnSignal final : public FdHandler {
 public:
  StopOnSignal(EventLoop& loop, Stop stop) : stop_(stop) {
    if (signals_.fd() >= 0) loop.watch(signals_.fd(), 1 /*EPOLLIN*/, this);
  }
  void on_fd(int, uint32_t) override {
    if (const char* name = signals_.take()) {
      log_info("%s: stopping", name);
      stop_();
    }
  }

 private:
  StopSignals signals_;
  Stop stop_;
};

}  // namespace troupe
