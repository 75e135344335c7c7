// The client's end of an emulator's pty, opened the plain way (no driver):
// for tests that speak to an emulator byte by byte.
#pragma once

#include <termios.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace troupe::testing {

class RawPort {
 public:
  /// Opens `path` raw at `speed` (a termios B-constant), non-blocking.
  RawPort(const std::string& path, speed_t speed);
  ~RawPort();
  RawPort(const RawPort&) = delete;
  RawPort& operator=(const RawPort&) = delete;

  bool ok() const { return fd_ >= 0; }
  void set_speed(speed_t speed);
  /// Writes all of `bytes`; false when the port refused them.
  bool write(std::span<const uint8_t> bytes);
  /// Every byte that has arrived.
  std::vector<uint8_t> read_all();
  /// One read(2): bytes read, 0 at end of file, -1 when none (or an error).
  long read_once(uint8_t* buf, size_t n);

 private:
  int fd_ = -1;
};

}  // namespace troupe::testing
