// The replay driver behind `troupe play`: provides the devices named in a
// log file and publishes their recorded Data again, paced by the recorded
// receive times (as PlayClock keeps them: jumps dropped) divided by a speed
// factor, with the original sender timestamps in the headers. It stops at the end of the file or at the
// first bad record (everything before it plays).
//
// Provides: every device of the log's DeviceList record, in its order.
// Commands are ignored; requests are refused as unsupported (a log holds
// data only).
#pragma once

#include <string>
#include <unordered_map>

#include "runtime/driver.h"
#include "wire/record/body_copy.h"
#include "wire/record/log_file.h"

namespace troupe::record {

class ReplayDriver : public Driver {
 public:
  struct Options {
    std::string path;
    /// Multiple of the recorded pace (2: twice as fast). Must be > 0.
    double speed = 1.0;
    /// Start over at the end of the file (or at its first bad record).
    bool loop = false;
    /// Hold the start until every device has a reader, so that a client
    /// connecting after `troupe play` started still sees the first frame.
    bool wait_for_readers = false;
    /// Longer pauses between records are jumps, not kept (PlayClock), us.
    uint64_t max_gap_us = kDefaultMaxGapUs;
  };

  explicit ReplayDriver(Options options);
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_timer(TimerId id) override;
  void shutdown() override;

  /// True once the whole file (without --loop) has been published.
  bool finished() const { return finished_; }
  /// Frames published so far.
  uint64_t published() const { return published_; }
  /// Passes begun (more than one with --loop).
  uint32_t passes() const { return passes_; }

 private:
  void begin_pass();
  /// Publishes every record that is due, then arms the timer for the next.
  void play_due();
  /// Reads up to the next Data record and its play time; false at the end
  /// of the playable part.
  bool read_data();
  void publish(const LogRecord& record);

  Options options_;
  LogReader reader_;
  BodyCopier copier_;
  std::unordered_map<uint64_t, DeviceId> devices_;  // by wire::address_key
  PlayClock clock_;
  LogRecord current_;
  uint64_t current_play_us_ = 0;  // current_'s play time, us after the pass's first record
  bool has_current_ = false;
  uint64_t pass_start_us_ = 0;  // loop clock when the pass began
  uint64_t last_play_us_ = 0;   // play time of the latest record published
  uint64_t pass_frames_ = 0;
  uint64_t jumps_ = 0;
  bool restart_ = false;  // the armed timer starts the next pass
  TimerId timer_ = 0;
  bool waiting_ = false;
  bool finished_ = false;
  bool warned_unknown_ = false;
  uint64_t published_ = 0;
  uint32_t passes_ = 0;
};

}  // namespace troupe::record
