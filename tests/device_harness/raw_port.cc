#include "tests/device_harness/raw_port.h"

#include <fcntl.h>
#include <unistd.h>

namespace troupe::testing {

RawPort::RawPort(const std::string& path, speed_t speed) {
  fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ >= 0) set_speed(speed);
}

RawPort::~RawPort() {
  if (fd_ >= 0) ::close(fd_);
}

void RawPort::set_speed(speed_t speed) {
  termios t{};
  tcgetattr(fd_, &t);
  cfmakeraw(&t);
  cfsetispeed(&t, speed);
  cfsetospeed(&t, speed);
  tcsetattr(fd_, TCSANOW, &t);
}

bool RawPort::write(std::span<const uint8_t> bytes) {
  return ::write(fd_, bytes.data(), bytes.size()) == ssize_t(bytes.size());
}

std::vector<uint8_t> RawPort::read_all() {
  std::vector<uint8_t> out;
  uint8_t buf[1024];
  for (ssize_t n; (n = ::read(fd_, buf, sizeof buf)) > 0;) out.insert(out.end(), buf, buf + n);
  return out;
}

long RawPort::read_once(uint8_t* buf, size_t n) {
  return long(::read(fd_, buf, n));
}

}  // namespace troupe::testing
