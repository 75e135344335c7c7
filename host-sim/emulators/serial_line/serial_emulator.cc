#include "host-sim/emulators/serial_line/serial_emulator.h"

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace troupe::emulators {

SerialEmulator::SerialEmulator(uint64_t seed, bool check_baud)
    : check_baud_(check_baud), faults_(seed), inbound_faults_(seed + 1) {}

bool SerialEmulator::open(const std::string& link, std::string& error) {
  link_ = link;
  return port_.open(link, error);
}

void SerialEmulator::attach_stream(int fd) {
  stream_fd_ = fd;
  stream_closed_ = false;
  on_reappear();
}

bool SerialEmulator::reappear(std::string& error) {
  on_reappear();
  return port_.open(link_, error);
}

bool SerialEmulator::baud_mismatch() const {
  if (!check_baud_ || stream_fd_ >= 0) return false;
  uint32_t host = port_.host_baud();
  return host != 0 && host != line_baud();
}

void SerialEmulator::garble_if_mismatched(std::span<uint8_t> bytes) {
  if (baud_mismatch()) faults_.mangle(bytes);
}

size_t SerialEmulator::read_line(std::span<uint8_t> out) {
  if (stream_fd_ < 0) return port_.read(out);
  for (;;) {
    ssize_t n = ::read(stream_fd_, out.data(), out.size());
    if (n > 0) return size_t(n);
    if (n < 0 && errno == EINTR) continue;
    if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) stream_closed_ = true;
    return 0;
  }
}

size_t SerialEmulator::write_line(std::span<const uint8_t> bytes) {
  if (mute_ || bytes.empty()) return 0;
  if (stream_fd_ < 0) return port_.write(bytes);
  if (stream_closed_) return 0;
  for (;;) {
    ssize_t n = ::send(stream_fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    if (n >= 0) return size_t(n);
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) stream_closed_ = true;
    return 0;
  }
}

void SerialEmulator::listen(uint64_t now_us, uint64_t gap_us) {
  if (!started_) {
    started_ = true;
    last_byte_us_ = now_us;
  }
  uint8_t buf[256], heard[256];
  bool heard_any = false;
  for (size_t n; (n = read_line(buf)) > 0; heard_any = true) {
    std::span<uint8_t> bytes(heard, inbound_faults_.apply({buf, n}, heard));
    garble_if_mismatched(bytes);
    on_heard(bytes);
  }
  if (heard_any) {
    last_byte_us_ = now_us;
  } else if (holds_partial() && now_us - last_byte_us_ > gap_us) {
    on_stale_partial();
  }
}

void SerialEmulator::inject_noise(size_t bytes) {
  uint8_t out[256];
  while (bytes > 0 && has_line()) {
    size_t n = std::min(bytes, sizeof out);
    faults_.noise({out, n});
    emit({out, n});
    bytes -= n;
  }
}

}  // namespace troupe::emulators
