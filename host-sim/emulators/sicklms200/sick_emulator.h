// A SICK LMS200 laser scanner, behaving like the scanner, not like any
// driver:
//  - it powers up at 9600 baud in monitor mode, silent; a reset request
//    (0x10) is acknowledged (0x91), then the scanner is deaf for its
//    start-up time and announces itself with the power-on message (0x90,
//    its type string) at 9600 baud;
//  - requests in telegrams with a CRC are answered with an ACK byte and a
//    reply telegram; a telegram failing its CRC, or a request it does not
//    know, with a NACK byte;
//  - mode changes: configuration mode (with the password), baud changes
//    (9600, 19200, 38400, 500000; it switches once its reply has left),
//    continuous output, mean values over 2..250 scans, and back to monitor
//    mode;
//  - the status block (0x31 -> 0xB1: version strings, operating mode,
//    measuring mode, scan angle, resolution, units), the error list (0x32
//    -> 0xB2, empty), the type (0x3A), the variant (0x3B: 180 degrees at 1
//    or 0.5, 100 degrees at 1, 0.5 or 0.25) and the configuration block
//    (0x74/0x77; units cm, mm, dm; writable only in configuration mode)
//    are kept, as in its EEPROM, across power cycles and resets;
//  - in continuous mode it sends a scan whenever the line is free, at most
//    75 a second, bytes paced as a UART paces them at its baud.
// The line (pty), its faults and baud are SerialEmulator's.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "drivers/sicklms200/sick_protocol.h"
#include "host-sim/emulators/serial_line/laser_world.h"
#include "host-sim/emulators/serial_line/serial_emulator.h"

namespace troupe::emulators {

/// What the scanner sees (serial_line/laser_world.h).
using SickWorld = LaserWorld;

class SickEmulator final : public SerialEmulator {
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
    /// Software version in the status block, 7 characters.
    std::string version = "V02.10 ";
    /// From a reset to the power-on message, us.
    uint64_t startup_us = 2'000'000;
    /// Seed of the fault generators.
    uint64_t seed = 1;
  };

  /// The operating modes, as the status block reports them.
  enum class Mode : uint8_t {
    Installation = 0x00,
    Continuous = 0x24,
    Monitor = 0x25,
    MeanValues = 0x26,
    Starting = 0xFF,  // deaf after a reset, until the power-on message
  };

  /// `world` may be null for the default; it must outlive the emulator.
  explicit SickEmulator(Config config, SickWorld* world = nullptr);

  /// Reads and answers requests, sends what the line has room for.
  void step(uint64_t now_us) override;
  uint32_t line_baud() const override { return baud_; }
  /// Power-up again: 9600 baud, monitor mode; variant and units are kept.
  void power_cycle();

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
  void on_heard(std::span<const uint8_t> bytes) override;
  bool holds_partial() const override { return scanner_.partial(); }
  void on_stale_partial() override;
  void on_reappear() override { scanner_.reset(); }
  void emit(std::span<const uint8_t> bytes) override { queue(bytes); }

  void obey(std::span<const uint8_t> body);
  void mode_change(std::span<const uint8_t> data);
  void send_status();
  void reply(uint8_t code, std::span<const uint8_t> data);
  void send_byte(uint8_t b);
  void queue(std::span<const uint8_t> bytes);
  void send_scan();
  void drain(uint64_t now_us);

  Config config_;
  SickWorld default_world_;
  SickWorld* world_;
  drivers::sicklms200::TelegramScanner scanner_{drivers::sicklms200::kHostAddress};

  Mode mode_ = Mode::Monitor;
  uint32_t baud_;
  uint32_t pending_baud_ = 0;  // switched to once the queue has drained
  uint16_t width_deg_, resolution_cdeg_;
  uint8_t config_block_[drivers::sicklms200::kConfigBytes] = {};
  uint8_t mean_samples_ = 0;
  uint64_t now_us_ = 0, ready_at_us_ = 0;

  // Bytes waiting for the line, and the line's pace.
  static constexpr size_t kQueueBytes = 8192;
  uint8_t queue_[kQueueBytes];
  size_t queue_head_ = 0, queue_size_ = 0;
  double credit_bytes_ = 0;
  uint64_t last_step_us_ = 0, next_scan_us_ = 0;
  bool started_ = false;

  uint16_t last_scan_[drivers::sicklms200::kMaxScanValues] = {};
  size_t last_count_ = 0;
  uint32_t scans_sent_ = 0, nacks_sent_ = 0;
};

}  // namespace troupe::emulators
