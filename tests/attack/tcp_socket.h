// One loopback TCP connection with deadlines, for the attack suite's peers
// (wire_peer.h, web_peer.h): connect, write all, read some, close with FIN
// or RST. Never blocks past a deadline; SIGPIPE never fires.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>

namespace troupe::attack {

using Deadline = std::chrono::steady_clock::time_point;
/// The time `ms` from now.
Deadline deadline_in(int ms);
/// Milliseconds left until `d`, 0 once it passed.
int ms_left(Deadline d);

class TcpSocket {
 public:
  TcpSocket() = default;
  ~TcpSocket() { close(); }
  TcpSocket(TcpSocket&& other) noexcept;
  TcpSocket& operator=(TcpSocket&& other) noexcept;
  TcpSocket(const TcpSocket&) = delete;
  TcpSocket& operator=(const TcpSocket&) = delete;

  /// Connects to 127.0.0.1:`port`, waiting at most `timeout_ms`.
  bool connect(uint16_t port, int timeout_ms = 5000);
  /// Asks the kernel for a small receive buffer (a slow reader's), bytes.
  void shrink_receive_buffer(int bytes);
  /// Writes every byte, waiting up to `timeout_ms` for room. False when the
  /// other side closed or reset the connection, or it stayed full.
  bool send(std::span<const uint8_t> bytes, int timeout_ms = 5000);
  /// Writes what fits now, without waiting. False once the connection broke.
  bool send_now(std::span<const uint8_t> bytes);
  /// Reads what has arrived, waiting up to `timeout_ms` for something:
  /// bytes read, 0 when the other side closed (closed() then), -1 when the
  /// time ran out.
  long recv_some(std::span<uint8_t> into, int timeout_ms);
  /// The other side closed or reset the connection.
  bool closed() const { return closed_; }
  bool open() const { return fd_ >= 0; }
  /// Sends FIN but keeps reading: "that was all".
  void shutdown_write();
  /// Closes with FIN.
  void close();
  /// Closes with RST (SO_LINGER 0): gone without a goodbye.
  void reset();

 private:
  int fd_ = -1;
  bool closed_ = false;
};

}  // namespace troupe::attack
