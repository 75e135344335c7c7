// The replay driver: provides devices named in a troupe log file (made by
// `troupe record`, wire/record/log_file.h) and publishes their recorded
// Data again, paced by the recorded receive times (as PlayClock keeps them:
// jumps dropped) divided by a speed factor, with the original sender
// timestamps in the headers. It stops at the end of the file or at the
// first bad record (everything before it plays). `troupe play` is a node
// with this driver serving every device of the log; a node config may use
// it too (replay.fbs).
//
// Provides: devices of the log's DeviceList record; frames of devices it
// does not provide are skipped. Commands are ignored. Requests whose reply
// the log holds (a camera's Geometry and GetConfig, which `troupe record`
// asks for) are answered with that reply; others are refused as unsupported.
// An image that lacks pixels it claims (a damaged recording) is skipped
// with a warning naming its byte offset; the rest plays.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "runtime/driver.h"
#include "wire/body_copy.h"
#include "wire/record/log_file.h"

namespace troupe::drivers::replay {

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
    uint64_t max_gap_us = record::kDefaultMaxGapUs;
  };

  /// Options as given (troupe play).
  explicit ReplayDriver(Options options);
  /// Options from the node config, read in setup().
  ReplayDriver() = default;
  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_timer(TimerId id) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void shutdown() override;

  /// True once the whole file (without --loop) has been published.
  bool finished() const { return finished_; }
  /// Frames published so far.
  uint64_t published() const { return published_; }
  /// Passes begun (more than one with --loop).
  uint32_t passes() const { return passes_; }
  /// Images skipped because they lack pixels they claim.
  uint64_t incomplete_images() const { return incomplete_images_; }

 private:
  void begin_pass();
  /// Publishes every record that is due, then arms the timer for the next.
  void play_due();
  /// Reads up to the next Data record and its play time; false at the end
  /// of the playable part.
  bool read_data();
  void publish(const record::LogRecord& record);
  /// Keeps the first Ack of each device and request subtype in the log.
  void read_replies();

  Options options_;
  bool configured_ = false;  // options_ given to the constructor
  record::LogReader reader_;
  const wire::BodyCopier& copier_ = wire::body_copier();
  std::unordered_map<uint64_t, DeviceId> devices_;  // by wire::address_key
  // Recorded Ack frames, by address_key * 256 + request subtype.
  std::unordered_map<uint64_t, std::vector<uint8_t>> replies_;
  record::PlayClock clock_;
  record::LogRecord current_;
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
  uint64_t incomplete_images_ = 0;
  uint32_t passes_ = 0;
};

}  // namespace troupe::drivers::replay
