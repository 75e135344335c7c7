// A SICK LMS200 laser scanner on a pseudo-terminal, behaving like the
// scanner, not like any driver:
//  - it powers up at 9600 baud in monitor mode, silent;
//  - requests in telegrams with a CRC are answered with an ACK byte and a
//    reply telegram; a telegram failing its CRC, or a request it does not
//    know, with a NACK byte;
//  - mode changes: configuration mode (with the password), baud changes
//    (9600, 38400, 500000; it switches once its reply has left), continuous
//    output and back to monitor mode;
//  - the variant (180 degrees at 1 or 0.5, 100 degrees at 1, 0.5 or 0.25)
//    and the configuration block (units: cm, mm, dm; writable only in
//    configuration mode) are kept, as in its EEPROM, across power cycles;
//  - in continuous mode it sends a scan whenever the line is free, at most
//    75 a second: it sends at its baud, bytes paced as a UART paces them;
//  - at another baud than the driver's end of the pty, each side hears
//    only garbage.
// Faults (LineFaults) corrupt what it sends and hears; it can vanish, come
// back, fall silent and restart.
//
// Time is the caller's: step(now_us) does everything due by `now_us`.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "drivers/sicklms200/sick_protocol.h"
#include "host-sim/emulators/serial_line/line_faults.h"
#include "host-sim/emulators/serial_line/pty_port.h"
#include "host-sim/emulators/serial_line/room.h"

namespace troupe::emulators {

/// What the scanner sees. The default is the scanner at (x, y, a) in
/// `room`; troupe-sim derives from it to measure its own world.
class SickWorld {
 public:
  virtual ~SickWorld() = default;
  /// Fills `ranges_m[i]` with the range along beam i, whose bearing in the
  /// scanner's frame is first_rad + i * step_rad, m. Anything beyond the
  /// scanner's reach reads as no return.
  virtual void measure(double first_rad, double step_rad, std::span<float> ranges_m);

  /// A corridor: 20 m long, so the beams along it see nothing.
  Room room{10.0, 3.0};
  /// The scanner's pose in the room: m, m, rad.
  double x = 0, y = 0, a = 0;
};

class SickEmulator {
 public:
  using Units = drivers::sicklms200::Units;

  struct Config {
    /// The speed it powers up at, bit/s.
    uint32_t power_up_baud = 9600;
    /// Garble both directions while the driver's end is at another baud.
    bool check_baud = true;
    /// Stored variant and units (the factory setting is centimetres).
    uint16_t width_deg = 180, resolution_cdeg = 100;
    Units units = Units::Centimetres;
    /// Most scans per second it sends.
    double max_scan_rate_hz = 75;
    std::string type = "LMS200;30106";
    /// Seed of the fault generators.
    uint64_t seed = 1;
  };

  enum class Mode : uint8_t { Monitor, Installation, Continuous };

  /// `world` may be null for the default; it must outlive the emulator.
  explicit SickEmulator(Config config, SickWorld* world = nullptr);

  bool open(const std::string& link, std::string& error);
  const std::string& path() const { return port_.path(); }
  PtyPort& port() { return port_; }

  /// Reads and answers requests, sends what the line has room for.
  void step(uint64_t now_us);

  // ---- Faults ----
  /// Faults on what the scanner sends (each telegram passes through them).
  LineFaults& faults() { return faults_; }
  /// Faults on what it hears (each chunk read).
  LineFaults& inbound_faults() { return inbound_faults_; }
  void inject_noise(size_t bytes);
  void vanish();
  /// The port comes back; the scanner kept running (and streaming).
  bool reappear(std::string& error);
  /// Power-up again: 9600 baud, monitor mode; variant and units are kept.
  void power_cycle();
  void set_mute(bool mute) { mute_ = mute; }

  // ---- State, for tests and simulators ----
  Mode mode() const { return mode_; }
  uint32_t baud() const { return baud_; }
  Units units() const { return Units(config_block_[drivers::sicklms200::kConfigUnits]); }
  uint16_t width_deg() const { return width_deg_; }
  uint16_t resolution_cdeg() const { return resolution_cdeg_; }
  uint32_t scans_sent() const { return scans_sent_; }
  uint32_t nacks_sent() const { return nacks_sent_; }
  /// The ranges of the last scan sent, in its units.
  std::span<const uint16_t> last_scan() const { return {last_scan_, last_count_}; }

 private:
  void obey(std::span<const uint8_t> body);
  void mode_change(std::span<const uint8_t> data);
  void reply(uint8_t code, std::span<const uint8_t> data);
  void send_byte(uint8_t b);
  void queue(std::span<const uint8_t> bytes);
  void send_scan();
  void drain(uint64_t now_us);
  bool baud_mismatch() const;

  Config config_;
  SickWorld default_world_;
  SickWorld* world_;
  PtyPort port_;
  std::string link_;
  LineFaults faults_, inbound_faults_;
  drivers::sicklms200::TelegramScanner scanner_{drivers::sicklms200::kHostAddress};

  Mode mode_ = Mode::Monitor;
  uint32_t baud_;
  uint32_t pending_baud_ = 0;  // switched to once the queue has drained
  uint16_t width_deg_, resolution_cdeg_;
  uint8_t config_block_[drivers::sicklms200::kConfigBytes] = {};
  bool mute_ = false;

  // Bytes waiting for the line, and the line's pace.
  static constexpr size_t kQueueBytes = 8192;
  uint8_t queue_[kQueueBytes];
  size_t queue_head_ = 0, queue_size_ = 0;
  double credit_bytes_ = 0;
  uint64_t last_step_us_ = 0, last_byte_us_ = 0, next_scan_us_ = 0;
  bool started_ = false;

  uint16_t last_scan_[drivers::sicklms200::kMaxScanValues] = {};
  size_t last_count_ = 0;
  uint32_t scans_sent_ = 0, nacks_sent_ = 0;
};

}  // namespace troupe::emulators
