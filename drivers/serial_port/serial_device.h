// The port itself: opening it raw 8N1 without flow control at a baud,
// changing the baud, flushing, closing. SerialLink (serial_link.h) does the
// reading and writing on its descriptor.
//
// Two implementations of this one class, one linked into each program:
//  - serial_device_libserial.cc: libserial's SerialPort, the default;
//  - serial_device_termios.cc: termios directly, for programs linked with
//    -static, since Debian ships libserial as a shared library only. Such a
//    program sets the target property TROUPE_STATIC_LINK (see CMakeLists.txt).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace troupe::serial {

/// True for the bauds the serial drivers use: 9600, 19200, 38400, 57600,
/// 115200, 230400, 500000 (bit/s).
bool is_supported_baud(uint32_t baud);

class SerialDevice {
 public:
  SerialDevice();
  ~SerialDevice();
  SerialDevice(const SerialDevice&) = delete;
  SerialDevice& operator=(const SerialDevice&) = delete;

  /// Opens `path` for exclusive use, raw 8N1, no flow control, `baud`
  /// bit/s, non-blocking, with both queues flushed. False with `error`
  /// naming the path and the reason.
  bool open(const std::string& path, uint32_t baud, std::string& error);
  /// Changes the line speed, bit/s; bytes not yet sent are dropped.
  bool set_baud(uint32_t baud, std::string& error);
  /// Drops bytes received and not yet read.
  void discard_input();
  /// Restores the settings found at open() and closes; safe when the
  /// device has vanished, and when closed.
  void close();
  /// The descriptor, -1 when closed.
  int fd() const { return fd_; }
  /// What close() could not do cleanly, for a log line; empty when fine.
  const std::string& close_note() const { return close_note_; }

 private:
  struct Port;  // the implementation's state
  std::unique_ptr<Port> port_;
  int fd_ = -1;
  std::string path_;
  std::string close_note_;
};

}  // namespace troupe::serial
