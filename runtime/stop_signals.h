// Stopping a node's loop on SIGINT or SIGTERM (the signals as a descriptor:
// wire/stop_signals.h).
#pragma once

#include <cstdint>

#include "runtime/event_loop.h"
#include "runtime/log.h"
#include "wire/stop_signals.h"

namespace troupe {

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
