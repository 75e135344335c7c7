// SerialDevice through libserial's SerialPort (the default backend).
#include <fcntl.h>
#include <libserial/SerialPort.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "drivers/serial_port/serial_device.h"

namespace troupe::serial {
namespace {

bool to_libserial(uint32_t baud, LibSerial::BaudRate& out) {
  using LibSerial::BaudRate;
  switch (baud) {
    case 9600:
      out = BaudRate::BAUD_9600;
      return true;
    case 19200:
      out = BaudRate::BAUD_19200;
      return true;
    case 38400:
      out = BaudRate::BAUD_38400;
      return true;
    case 57600:
      out = BaudRate::BAUD_57600;
      return true;
    case 115200:
      out = BaudRate::BAUD_115200;
      return true;
    case 230400:
      out = BaudRate::BAUD_230400;
      return true;
    case 500000:
      out = BaudRate::BAUD_500000;
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
  LibSerial::SerialPort port;
};

bool is_supported_baud(uint32_t baud) {
  LibSerial::BaudRate unused{};
  return to_libserial(baud, unused);
}

SerialDevice::SerialDevice() = default;
SerialDevice::~SerialDevice() {
  close();
}

bool SerialDevice::open(const std::string& path, uint32_t baud, std::string& error) {
  close();
  LibSerial::BaudRate rate{};
  if (!to_libserial(baud, rate)) {
    error = path + ": " + baud_error(baud);
    return false;
  }
  // libserial reports a missing device as "Bad file descriptor"; ask the
  // file system first so the message says what is wrong.
  if (::access(path.c_str(), R_OK | W_OK) != 0) {
    error = path + ": " + strerror(errno);
    return false;
  }
  port_ = std::make_unique<Port>();
  path_ = path;
  try {
    LibSerial::SerialPort& p = port_->port;
    p.Open(path);
    fd_ = p.GetFileDescriptor();
    p.SetBaudRate(rate);
    p.SetCharacterSize(LibSerial::CharacterSize::CHAR_SIZE_8);
    p.SetParity(LibSerial::Parity::PARITY_NONE);
    p.SetStopBits(LibSerial::StopBits::STOP_BITS_1);
    p.SetFlowControl(LibSerial::FlowControl::FLOW_CONTROL_NONE);
    p.SetVMin(0);
    p.SetVTime(0);
    p.FlushIOBuffers();
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
    close();
    return false;
  }
  // The loop must never block on this descriptor, whatever libserial chose.
  int flags = fcntl(fd_, F_GETFL, 0);
  if (flags < 0 || fcntl(fd_, F_SETFL, flags | O_NONBLOCK) != 0) {
    error = path + ": cannot make the port non-blocking: " + strerror(errno);
    close();
    return false;
  }
  return true;
}

bool SerialDevice::set_baud(uint32_t baud, std::string& error) {
  LibSerial::BaudRate rate{};
  if (!port_ || fd_ < 0) {
    error = "the port is closed";
    return false;
  }
  if (!to_libserial(baud, rate)) {
    error = path_ + ": " + baud_error(baud);
    return false;
  }
  try {
    port_->port.SetBaudRate(rate);
    port_->port.FlushOutputBuffer();
  } catch (const std::exception& e) {
    error = path_ + ": cannot set " + std::to_string(baud) + " baud: " + e.what();
    return false;
  }
  return true;
}

void SerialDevice::discard_input() {
  if (fd_ >= 0) tcflush(fd_, TCIFLUSH);
}

void SerialDevice::close() {
  close_note_.clear();
  if (!port_) return;
  int fd = fd_;
  fd_ = -1;
  if (!port_->port.IsOpen()) {
    port_.reset();
    return;
  }
  try {
    port_->port.Close();
    port_.reset();
    return;
  } catch (const std::exception&) {
  }
  // libserial restores the settings it found before closing, and a vanished
  // device refuses that (EIO), which leaves the descriptor open and makes
  // the object's destructor throw. A fresh terminal put in the descriptor's
  // place takes the settings, so the close can finish.
  int spare = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (spare >= 0 && dup2(spare, fd) == fd) {
    ::close(spare);
    try {
      port_->port.Close();
      port_.reset();
      return;
    } catch (const std::exception&) {
    }
  } else if (spare >= 0) {
    ::close(spare);
  }
  // Last resort: close the descriptor ourselves and never destroy the
  // object (its destructor would throw from noexcept): a few hundred bytes
  // per vanished device.
  ::close(fd);
  (void)port_.release();
  close_note_ = "closed by hand after libserial refused to close it";
}

}  // namespace troupe::serial
