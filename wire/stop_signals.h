// SIGINT and SIGTERM as a readable descriptor (signalfd), so that programs
// stop from inside their single loop like any other event: drivers shut
// down, files are finished, nothing runs in a signal handler.
#pragma once

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

}  // namespace troupe
