// What every serial-line device emulator is apart from its protocol: a line
// to its driver (a pseudo-terminal, or a connected stream socket for
// simulators that serve the device over TCP, as MobileSim does), the faults
// that line suffers in both directions, a UART's view of baud (at another
// speed than the driver's end, each side hears only garbage), vanishing and
// coming back, and falling silent.
//
// A device derives from it, says what it makes of the bytes it hears
// (on_heard) and steps itself: step(now_us) calls listen(now_us) first.
// Time is the caller's; nothing here reads a clock or blocks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "host-sim/emulators/serial_line/line_faults.h"
#include "host-sim/emulators/serial_line/pty_port.h"

namespace troupe::emulators {

class SerialEmulator {
 public:
  /// `seed` seeds the fault generators; `check_baud` garbles both
  /// directions while the driver's end of the pty is at another baud.
  SerialEmulator(uint64_t seed, bool check_baud);
  virtual ~SerialEmulator() = default;
  SerialEmulator(const SerialEmulator&) = delete;
  SerialEmulator& operator=(const SerialEmulator&) = delete;

  /// Creates the pty (see PtyPort::open for `link`).
  bool open(const std::string& link, std::string& error);
  /// Talks over `fd`, a connected non-blocking stream socket the caller
  /// owns, instead of the pty (a TCP line has no baud); -1 goes back to the
  /// pty. Clears stream_closed().
  void attach_stream(int fd);
  /// The attached stream reached its end or failed (the client went away).
  bool stream_closed() const { return stream_closed_; }

  /// What a driver opens.
  const std::string& path() const { return port_.path(); }
  PtyPort& port() { return port_; }

  /// Does everything due by `now_us` (us, the caller's clock).
  virtual void step(uint64_t now_us) = 0;
  /// The speed the device talks at, bit/s.
  virtual uint32_t line_baud() const = 0;

  // ---- Faults ----
  /// Faults on what the device sends.
  LineFaults& faults() { return faults_; }
  /// Faults on what it hears (each chunk read).
  LineFaults& inbound_faults() { return inbound_faults_; }
  /// Sends `bytes` of noise.
  void inject_noise(size_t bytes);
  /// The port vanishes (pty closed, link removed).
  void vanish() { port_.close(); }
  /// The port comes back under the same name; the device kept running.
  bool reappear(std::string& error);
  /// The device stops talking (true) or resumes (false); it still listens.
  void set_mute(bool mute) { mute_ = mute; }

 protected:
  /// Reads what arrived by `now_us`, passes it through the inbound faults
  /// and the UART's view of baud to on_heard(). A frame whose bytes stopped
  /// coming for `gap_us` is given up (on_stale_partial), as the device's
  /// receiver forgets it, so a corrupted length cannot hold commands back.
  void listen(uint64_t now_us, uint64_t gap_us);
  virtual void on_heard(std::span<const uint8_t> bytes) = 0;
  /// True while a frame is partly received.
  virtual bool holds_partial() const = 0;
  virtual void on_stale_partial() = 0;
  /// The port came back: forget half-heard frames.
  virtual void on_reappear() = 0;
  /// Sends bytes the way the device does (now, or queued behind others).
  virtual void emit(std::span<const uint8_t> bytes) = 0;

  /// Passes a frame through the outbound faults into `out` (room for
  /// in.size() bytes); returns its size.
  size_t through_faults(std::span<const uint8_t> in, std::span<uint8_t> out) { return faults_.apply(in, out); }
  /// Garbles `bytes` in place when the driver's end is at another baud.
  void garble_if_mismatched(std::span<uint8_t> bytes);
  /// Writes to the line now; nothing while mute or without a line. Returns
  /// the bytes taken (what the line does not take is lost).
  size_t write_line(std::span<const uint8_t> bytes);
  bool has_line() const { return stream_fd_ >= 0 || port_.is_open(); }

 private:
  size_t read_line(std::span<uint8_t> out);
  bool baud_mismatch() const;

  PtyPort port_;
  std::string link_;
  int stream_fd_ = -1;
  bool stream_closed_ = false;
  bool check_baud_;
  bool mute_ = false;
  LineFaults faults_, inbound_faults_;
  uint64_t last_byte_us_ = 0;
  bool started_ = false;
};

}  // namespace troupe::emulators
