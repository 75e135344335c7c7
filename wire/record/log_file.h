// Troupe log files: what `troupe record` writes and `troupe play` serves.
// The layout (all integers little-endian; README.md has the full story):
//
//   file header, 24 bytes:
//     0   8  magic "\x89TROUPE\n"
//     8   2  format version (kLogVersion)
//     10  2  header size in bytes; records start there
//     12  4  flags, 0
//     16  8  wall-clock time the recording started, us since the Unix epoch
//   then records, each:
//     0   4  N: bytes of the frame
//     4   4  CRC-32 (IEEE) of the receive time and the frame bytes
//     8   8  receive time, us since the recording started (recorder's
//            monotonic clock)
//     16  N  one wire frame exactly as received, its own length prefix
//            included: the node's Hello, a DeviceList naming the recorded
//            devices, then their Data.
//
// A reader stops at the first record that is cut short or fails its check
// and reports that record's byte offset; everything before it stays usable.
#pragma once

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "wire/frame.h"

namespace troupe::record {

inline constexpr uint8_t kLogMagic[8] = {0x89, 'T', 'R', 'O', 'U', 'P', 'E', '\n'};
inline constexpr uint16_t kLogVersion = 1;
inline constexpr uint32_t kLogHeaderBytes = 24;
inline constexpr uint32_t kRecordHeaderBytes = 16;

/// CRC-32 as zlib and PNG compute it (reflected polynomial 0xEDB88320),
/// continued from `crc` (0 to start).
uint32_t crc32(std::span<const uint8_t> bytes, uint32_t crc = 0);

struct LogHeader {
  uint16_t version = kLogVersion;
  /// When the recording started: us since the Unix epoch.
  uint64_t start_unix_us = 0;
};

/// Appends records to a new log file.
class LogWriter {
 public:
  LogWriter() = default;
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  /// Creates (or truncates) `path` and writes the file header.
  bool open(const std::string& path, uint64_t start_unix_us, std::string& error);
  /// Appends one frame received at `time_us` (us since the recording started).
  bool write(uint64_t time_us, std::span<const uint8_t> frame, std::string& error);
  /// Pushes buffered records to the kernel, so a crash loses at most what
  /// came after the last flush.
  bool flush(std::string& error);
  bool close(std::string& error);
  /// Bytes written so far, file header included.
  uint64_t bytes() const { return bytes_; }

 private:
  FILE* file_ = nullptr;
  std::string path_;
  uint64_t bytes_ = 0;
};

/// One record as read back.
struct LogRecord {
  /// Byte offset of the record in the file.
  uint64_t offset = 0;
  /// Receive time, us since the recording started.
  uint64_t time_us = 0;
  /// The frame; valid until the next call to LogReader::next().
  std::span<const uint8_t> frame;
  /// The verified message inside `frame`.
  const wire::Message* message = nullptr;
};

/// Reads records in order, checking each one: length within the limit and
/// within the file, CRC, and the frame through the wire verifier.
class LogReader {
 public:
  explicit LogReader(wire::Limits limits = {});
  ~LogReader();
  LogReader(const LogReader&) = delete;
  LogReader& operator=(const LogReader&) = delete;

  /// Opens `path` and checks its header; on failure `error` names the file
  /// and the byte offset.
  bool open(const std::string& path, std::string& error);
  /// The next record. False at the end of the file, or at a record that is
  /// truncated or corrupt: problem() then says which and where.
  bool next(LogRecord& out);
  /// Empty when the file ended cleanly, else "FILE: byte N: what".
  const std::string& problem() const { return problem_; }
  /// Offset of the first byte not yet read as part of a good record.
  uint64_t offset() const { return offset_; }
  const LogHeader& header() const { return header_; }
  /// Goes back to the first record.
  bool rewind();

 private:
  bool fail(uint64_t at, const std::string& what);

  wire::Limits limits_;
  FILE* file_ = nullptr;
  std::string path_;
  LogHeader header_;
  uint32_t header_bytes_ = kLogHeaderBytes;
  uint64_t file_bytes_ = 0;
  uint64_t offset_ = 0;
  std::vector<uint8_t> frame_;
  std::string problem_;
};

/// The longest pause between two Data records that play keeps by default,
/// us (`troupe play --max-gap`). A recorder's reconnect backoff is 2 s at
/// most; a longer gap is a node that was down a while, or a bad time.
inline constexpr uint64_t kDefaultMaxGapUs = 60'000'000;

/// Where the record times jump: play does not keep that pause.
struct TimeJump {
  /// Byte offset of the Data record after the jump.
  uint64_t offset = 0;
  /// Receive times of the Data records before and after it, us since the
  /// recording started.
  uint64_t from_us = 0, to_us = 0;
};

/// Turns the receive times of a file's Data records, in file order, into
/// play times: us after the first Data record, at speed 1. Pauses are kept
/// as recorded, except jumps: a time before the previous record's (a clock
/// stepped back, or a bad time) and a gap longer than `max_gap_us` (a bad
/// time could say 2^40 us, twelve days). After a jump the record plays at
/// once, and the pace goes on from there.
class PlayClock {
 public:
  explicit PlayClock(uint64_t max_gap_us = kDefaultMaxGapUs) : max_gap_us_(max_gap_us) {}
  /// The play time of the next Data record, received at `record_us`;
  /// `jumped` says whether the pause before it was dropped.
  uint64_t next(uint64_t record_us, bool& jumped);
  /// Back to the first record.
  void restart() { started_ = false; }

 private:
  uint64_t max_gap_us_;
  bool started_ = false;
  uint64_t last_record_us_ = 0;
  uint64_t play_us_ = 0;
};

/// What a whole file holds, read once before playing it.
struct LogSummary {
  uint64_t records = 0;
  uint64_t data_records = 0;
  /// Receive times of the first and last Data record, us since the start.
  uint64_t first_data_us = 0, last_data_us = 0;
  /// How long playing the Data records takes at speed 1 (PlayClock), us.
  uint64_t play_us = 0;
  /// Jumps in the record times (PlayClock), the first kMaxJumpsListed of
  /// them; jump_count counts them all.
  static constexpr size_t kMaxJumpsListed = 20;
  std::vector<TimeJump> jumps;
  uint64_t jump_count = 0;
  /// The recorded devices (the last DeviceList record), as a frame.
  std::vector<uint8_t> device_list;
  /// The node's name from its Hello record.
  std::string node_name;
  /// Bytes of good records from the start of the file: playing stops there.
  uint64_t valid_bytes = 0;
  /// Empty for a clean file, else what is wrong and where (LogReader::problem()).
  std::string problem;
};

/// Reads the whole file. False only when it cannot be opened or its header
/// is bad (`error`); a bad record later is reported in `out.problem`.
/// `max_gap_us` is the PlayClock's.
bool summarize_log(const std::string& path, LogSummary& out, std::string& error,
                   uint64_t max_gap_us = kDefaultMaxGapUs);

}  // namespace troupe::record
