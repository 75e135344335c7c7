// The device end of an emulated serial port: a pseudo-terminal whose slave
// side a driver opens like any serial device (libserial accepts it) and
// whose master side the emulator reads and writes without blocking.
//
// A pty carries bytes at any speed; the baud the driver set on its end is
// still visible here (host_baud()), so an emulator can behave like a UART
// at another speed and garble what it hears and says.
//
// Optionally a symbolic link names the port: the device can then vanish
// (close(): master closed, link removed, the driver's reads fail) and come
// back under the same name (open() again: a new pty, the link re-pointed),
// as a USB serial adapter does when it is pulled and plugged in.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace troupe::emulators {

class PtyPort {
 public:
  PtyPort() = default;
  ~PtyPort() { close(); }
  PtyPort(const PtyPort&) = delete;
  PtyPort& operator=(const PtyPort&) = delete;

  /// Creates a raw pseudo-terminal. With a non-empty `link`, a symbolic link
  /// of that name points at its slave (replacing an older link there). False
  /// with `error` when the system refuses.
  bool open(const std::string& link, std::string& error);
  /// The device vanishes: the master closes (the driver's end hangs up) and
  /// the link is removed.
  void close();

  bool is_open() const { return master_ >= 0; }
  /// The master descriptor, for a caller's poll loop; -1 when closed.
  int fd() const { return master_; }
  /// "/dev/pts/N".
  const std::string& slave_path() const { return slave_path_; }
  /// What a driver opens: the link if there is one, else the slave path.
  const std::string& path() const { return link_.empty() ? slave_path_ : link_; }

  /// Bytes the driver wrote, without blocking; 0 when there are none (or
  /// nobody has the other end open).
  size_t read(std::span<uint8_t> out);
  /// Writes without blocking; returns the bytes taken. What is not taken
  /// is lost, as bytes sent to a port nobody reads are.
  size_t write(std::span<const uint8_t> bytes);
  /// The speed the driver set on its end, bit/s; 0 when unknown.
  uint32_t host_baud() const;

 private:
  int master_ = -1;
  std::string slave_path_;
  std::string link_;
};

}  // namespace troupe::emulators
