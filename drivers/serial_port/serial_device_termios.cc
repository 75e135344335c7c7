// SerialDevice through termios directly, for programs linked with -static
// (Debian ships libserial as a shared library only). Same settings as the
// libserial backend: exclusive, raw 8N1, no flow control, non-blocking.
#include <fcntl.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "drivers/serial_port/serial_device.h"

namespace troupe::serial {
namespace {

bool to_speed(uint32_t baud, speed_t& out) {
  switch (baud) {
    case 9600:
      out = B9600;
      return true;
    case 19200:
      out = B19200;
      return true;
    case 38400:
      out = B38400;
      return true;
    case 57600:
      out = B57600;
      return true;
    case 115200:
      out = B115200;
      return true;
    case 230400:
      out = B230400;
      return true;
    case 500000:
      out = B500000;
      return true;
    default:
      return false;
  }
}

std::string baud_error(uint32_t baud) {
  return "unsupported baud " + std::to_string(baud) +
         " (use 9600, 19200, 38400, 57600, 115200, 230400 or 500000)";
}

}  // namespace

struct SerialDevice::Port {
  termios saved{};  // settings found at open, restored at close
};

bool is_supported_baud(uint32_t baud) {
  speed_t unused{};
  return to_speed(baud, unused);
}

SerialDevice::SerialDevice() = default;
SerialDevice::~SerialDevice() {
  close();
}

bool SerialDevice::open(const std::string& path, uint32_t baud, std::string& error) {
  close();
  speed_t speed{};
  if (!to_speed(baud, speed)) {
    error = path + ": " + baud_error(baud);
    return false;
  }
  int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    error = path + ": " + strerror(errno);
    return false;
  }
  auto port = std::make_unique<Port>();
  termios t{};
  if (ioctl(fd, TIOCEXCL) != 0 || tcgetattr(fd, &port->saved) != 0) {
    error = path + ": not a serial port: " + strerror(errno);
    ::close(fd);
    return false;
  }
  t = port->saved;
  cfmakeraw(&t);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_cflag &= ~(CSTOPB | PARENB | CRTSCTS);
  t.c_iflag &= ~(IXON | IXOFF | IXANY);
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (cfsetispeed(&t, speed) != 0 || cfsetospeed(&t, speed) != 0 || tcsetattr(fd, TCSANOW, &t) != 0) {
    error = path + ": cannot configure the port: " + strerror(errno);
    ::close(fd);
    return false;
  }
  tcflush(fd, TCIOFLUSH);
  port_ = std::move(port);
  fd_ = fd;
  path_ = path;
  return true;
}

bool SerialDevice::set_baud(uint32_t baud, std::string& error) {
  speed_t speed{};
  if (fd_ < 0) {
    error = "the port is closed";
    return false;
  }
  if (!to_speed(baud, speed)) {
    error = path_ + ": " + baud_error(baud);
    return false;
  }
  termios t{};
  if (tcgetattr(fd_, &t) != 0 || cfsetispeed(&t, speed) != 0 || cfsetospeed(&t, speed) != 0 ||
      tcsetattr(fd_, TCSANOW, &t) != 0) {
    error = path_ + ": cannot set " + std::to_string(baud) + " baud: " + strerror(errno);
    return false;
  }
  tcflush(fd_, TCOFLUSH);
  return true;
}

void SerialDevice::discard_input() {
  if (fd_ >= 0) tcflush(fd_, TCIFLUSH);
}

void SerialDevice::close() {
  close_note_.clear();
  if (fd_ < 0) return;
  // A vanished device refuses its old settings (EIO); it is closed anyway.
  tcsetattr(fd_, TCSANOW, &port_->saved);
  ::close(fd_);
  fd_ = -1;
  port_.reset();
}

}  // namespace troupe::serial
