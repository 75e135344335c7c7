// The SICK LMS200/291 serial protocol, as bytes: telegrams and their CRC,
// finding telegrams in a noisy byte stream, the requests a driver sends,
// and the scan telegram. No I/O and no allocation; the driver and the
// scanner emulator both speak through this. Facts: protocols.md ("SICK").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace troupe::drivers::sicklms200 {

inline constexpr uint8_t kStx = 0x02;
/// Address byte of host-to-scanner telegrams (scanner 0) and of replies.
inline constexpr uint8_t kHostAddress = 0x00;
inline constexpr uint8_t kReplyAddress = 0x80;
/// A single byte before a reply: the request was understood, or not.
inline constexpr uint8_t kAck = 0x06;
inline constexpr uint8_t kNack = 0x15;
/// Header (STX, address, length) and CRC around a telegram's body.
inline constexpr size_t kFrameBytes = 6;
/// Largest telegram handled, bytes: a 401-value scan is 812.
inline constexpr size_t kMaxTelegramBytes = 1024;
/// Most range values in one scan (100 degrees at 0.25).
inline constexpr size_t kMaxScanValues = 401;
/// Range value meaning "no return" (mm mode: 8.191 m).
inline constexpr uint16_t kNoReturn = 8191;

/// Request codes; a reply carries the request's code + 0x80.
enum class Request : uint8_t {
  Reset = 0x10,       // acknowledged with 0x91; 0x90 follows once restarted
  ModeChange = 0x20,
  OneScan = 0x30,
  Status = 0x31,      // 0xB1: the status block (kStatusBytes)
  Errors = 0x32,      // 0xB2: (type, number) pairs of the errors logged
  Type = 0x3A,
  Variant = 0x3B,
  ReadConfig = 0x74,
  WriteConfig = 0x77,
};
inline constexpr uint8_t reply_code(Request r) {
  return uint8_t(r) | 0x80;
}
inline constexpr uint8_t kScanReply = 0xB0;
/// Mean values (mode 0x26): sample count, then a scan as in 0xB0.
inline constexpr uint8_t kMeanScanReply = 0xB6;
/// Sent unasked once the scanner has (re)started: its type string.
inline constexpr uint8_t kPowerOnReply = 0x90;
/// The answer to a reset request.
inline constexpr uint8_t kResetReply = 0x91;
/// Second byte of a mode change.
enum class Mode : uint8_t {
  Config = 0x00,  // followed by the password "SICK_LMS"
  Baud38400 = 0x40,
  Baud19200 = 0x41,
  Baud9600 = 0x42,
  Baud500000 = 0x48,
  Continuous = 0x24,      // scans without being asked
  StopContinuous = 0x25,  // monitor mode: scans on request only
  MeanValues = 0x26,      // followed by the sample count, 2..250: means streamed
};
/// Units of range values (the configuration's units byte; the top bits of a
/// scan's count).
enum class Units : uint8_t { Centimetres = 0, Millimetres = 1, Decimetres = 2 };

/// The configuration block (0x74 reply data, 0x77 request data), bytes at
/// most: the LMS200 telegram listing gives 32, later firmware (and
/// sicktoolbox) 34; a driver writes back what it read.
inline constexpr size_t kConfigBytes = 34;
/// The status block (0xB1 reply data), bytes.
inline constexpr size_t kStatusBytes = 152;
/// Offset of the units byte in the configuration block.
inline constexpr size_t kConfigUnits = 6;

/// The scanner's CRC-16 over `bytes` (generator 0x8005, SICK's variant).
uint16_t crc16(std::span<const uint8_t> bytes);

/// A whole telegram, built in place.
struct Telegram {
  std::array<uint8_t, kMaxTelegramBytes> bytes{};
  size_t size = 0;
  std::span<const uint8_t> view() const { return {bytes.data(), size}; }
};

/// Frames `body` (request code and data) as a host telegram. False when it
/// does not fit.
bool make_request(std::span<const uint8_t> body, Telegram& out);
/// Frames a reply: code, data, status (the scanner's side).
bool make_reply(uint8_t code, std::span<const uint8_t> data, uint8_t status, Telegram& out);

Telegram mode_change(Mode mode);
/// Mode change to the baud given in bit/s: 9600, 19200, 38400 or 500000.
bool baud_change(uint32_t baud, Telegram& out);
/// The mode the scanner switches to for `baud`; false for other bauds.
bool mode_for_baud(uint32_t baud, Mode& out);
Telegram enter_config();
Telegram variant(uint16_t width_deg, uint16_t resolution_cdeg);
Telegram simple(Request request);
Telegram write_config(std::span<const uint8_t> config);

/// Finds telegrams addressed `address` (kReplyAddress for a driver,
/// kHostAddress for the scanner) in a byte stream: hunts for STX and the
/// address, checks the length and the CRC, drops what does not frame.
/// A telegram failing its CRC is dropped and the hunt resumes one byte
/// after its start. ACK and NACK bytes between telegrams are counted.
class TelegramScanner {
 public:
  explicit TelegramScanner(uint8_t address) : address_(address) {}

  /// Consumes bytes of `in` up to the end of the next good telegram.
  /// Returns the bytes consumed; `body` is set to the telegram's body
  /// (from the code to the last byte before the CRC) when one completed,
  /// valid until the next call.
  size_t feed(std::span<const uint8_t> in, std::span<const uint8_t>& body);
  /// Gives up on a partial telegram whose bytes stopped coming: returns the
  /// next whole telegram held behind it, or false when none is left.
  bool expire(std::span<const uint8_t>& body);
  void reset() { size_ = consume_ = 0; }
  bool partial() const { return size_ > consume_; }

  uint32_t telegrams() const { return telegrams_; }
  uint32_t bad_crcs() const { return bad_crcs_; }
  uint32_t skipped_bytes() const { return skipped_; }
  uint32_t nacks() const { return nacks_; }

 private:
  bool scan(std::span<const uint8_t>& body);
  void drop_front(size_t n);

  uint8_t address_;
  uint8_t buf_[kMaxTelegramBytes];
  size_t size_ = 0;
  size_t consume_ = 0;
  uint32_t telegrams_ = 0, bad_crcs_ = 0, skipped_ = 0, nacks_ = 0;
};

/// Calls `on_body(std::span<const uint8_t>)` for every good telegram in `in`.
template <typename OnBody>
void scan_telegrams(TelegramScanner& scanner, std::span<const uint8_t> in, OnBody&& on_body) {
  for (;;) {
    std::span<const uint8_t> body;
    in = in.subspan(scanner.feed(in, body));
    if (!body.empty()) {
      on_body(body);
    } else if (in.empty()) {
      return;
    }
  }
}

/// expire()s a stalled partial telegram, calling `on_body` for each whole
/// telegram held behind it.
template <typename OnBody>
void expire_telegrams(TelegramScanner& scanner, OnBody&& on_body) {
  for (std::span<const uint8_t> body; scanner.expire(body);) on_body(body);
}

/// A reply telegram's body split up: code, data, status.
struct Reply {
  uint8_t code = 0;
  std::span<const uint8_t> data;
  uint8_t status = 0;
};
/// False when the body is too short to be a reply (code and status).
bool split_reply(std::span<const uint8_t> body, Reply& out);

/// A scan (0xB0 reply data).
struct Scan {
  uint16_t count = 0;
  Units units = Units::Centimetres;
  /// Range of each beam in `units`, flag bits removed.
  uint16_t ranges[kMaxScanValues] = {};
};
/// Parses 0xB0 reply data; false with `why` when the count is impossible
/// or overruns the data.
bool parse_scan(std::span<const uint8_t> data, Scan& out, const char** why);
/// Writes 0xB0 reply data for `count` ranges (the scanner's side); returns
/// its size, 0 when `out` is too small.
size_t write_scan(std::span<const uint16_t> ranges, Units units, std::span<uint8_t> out);

}  // namespace troupe::drivers::sicklms200
