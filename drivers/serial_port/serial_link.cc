#include "drivers/serial_port/serial_link.h"

#include <fcntl.h>
#include <libserial/SerialPort.h>
#include <sys/epoll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "runtime/log.h"

namespace troupe::serial {
namespace {

// Reads per readiness event, so a device that floods the line cannot keep
// the loop from its other descriptors.
constexpr int kReadsPerEvent = 4;
constexpr size_t kReadChunk = 512;

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

bool is_supported_baud(uint32_t baud) {
  LibSerial::BaudRate unused{};
  return to_libserial(baud, unused);
}

SerialLink::SerialLink(Listener& listener) : listener_(listener) {}

SerialLink::~SerialLink() {
  close();
}

bool SerialLink::open(const std::string& path, uint32_t baud, std::string& error) {
  close();
  LibSerial::BaudRate rate{};
  if (loop_ == nullptr) {
    error = path + ": no event loop attached";
    return false;
  }
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
  auto port = std::make_unique<LibSerial::SerialPort>();
  try {
    port->Open(path);
    port->SetBaudRate(rate);
    port->SetCharacterSize(LibSerial::CharacterSize::CHAR_SIZE_8);
    port->SetParity(LibSerial::Parity::PARITY_NONE);
    port->SetStopBits(LibSerial::StopBits::STOP_BITS_1);
    port->SetFlowControl(LibSerial::FlowControl::FLOW_CONTROL_NONE);
    port->SetVMin(0);
    port->SetVTime(0);
    port->FlushIOBuffers();
  } catch (const std::exception& e) {
    error = path + ": " + e.what();
    if (port->IsOpen()) {
      try {
        port->Close();
      } catch (const std::exception&) {
        (void)port.release();  // see close(): its destructor would throw
      }
    }
    return false;
  }
  int fd = port->GetFileDescriptor();
  // The loop must never block on this descriptor, whatever libserial chose.
  int flags = fcntl(fd, F_GETFL, 0);
  if (flags < 0 || fcntl(fd, F_SETFL, flags | O_NONBLOCK) != 0 || !loop_->watch(fd, EPOLLIN, this)) {
    error = path + ": cannot make the port non-blocking or watch it";
    port_ = std::move(port);
    fd_ = fd;
    close();
    return false;
  }
  port_ = std::move(port);
  fd_ = fd;
  ++session_;
  path_ = path;
  baud_ = baud;
  queue_head_ = queue_size_ = 0;
  writing_ = false;
  return true;
}

bool SerialLink::set_baud(uint32_t baud, std::string& error) {
  LibSerial::BaudRate rate{};
  if (!is_open()) {
    error = "the port is closed";
    return false;
  }
  if (!to_libserial(baud, rate)) {
    error = path_ + ": " + baud_error(baud);
    return false;
  }
  try {
    port_->SetBaudRate(rate);
    port_->FlushOutputBuffer();
  } catch (const std::exception& e) {
    error = path_ + ": cannot set " + std::to_string(baud) + " baud: " + e.what();
    return false;
  }
  baud_ = baud;
  queue_head_ = queue_size_ = 0;
  want_write(false);
  return true;
}

void SerialLink::discard_input() {
  if (is_open()) tcflush(fd_, TCIFLUSH);
}

bool SerialLink::send(std::span<const uint8_t> bytes) {
  if (!is_open()) return false;
  if (queue_head_ > 0 && queue_size_ + bytes.size() > kQueueBytes) {
    memmove(queue_, queue_ + queue_head_, queue_size_ - queue_head_);
    queue_size_ -= queue_head_;
    queue_head_ = 0;
  }
  if (queue_size_ + bytes.size() > kQueueBytes) return false;
  memcpy(queue_ + queue_size_, bytes.data(), bytes.size());
  queue_size_ += bytes.size();
  if (!writing_) flush();
  return true;
}

void SerialLink::flush() {
  while (queue_head_ < queue_size_) {
    ssize_t n = ::write(fd_, queue_ + queue_head_, queue_size_ - queue_head_);
    if (n > 0) {
      queue_head_ += size_t(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return want_write(true);
    return fail(std::string("write failed: ") + (n < 0 ? strerror(errno) : "nothing written"));
  }
  queue_head_ = queue_size_ = 0;
  want_write(false);
}

void SerialLink::want_write(bool on) {
  if (!is_open() || writing_ == on) return;
  writing_ = on;
  loop_->modify(fd_, EPOLLIN | (on ? uint32_t(EPOLLOUT) : 0u));
}

void SerialLink::on_fd(int fd, uint32_t events) {
  if (fd != fd_) return;
  if (events & EPOLLOUT) {
    flush();
    if (!is_open()) return;
  }
  if (!(events & (EPOLLIN | EPOLLHUP | EPOLLERR))) return;
  const uint32_t session = session_;
  for (int i = 0; i < kReadsPerEvent; ++i) {
    uint8_t chunk[kReadChunk];
    ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n > 0) {
      listener_.on_serial_bytes({chunk, size_t(n)});
      // The listener may have closed or reopened the link meanwhile; these
      // events were about the old descriptor.
      if (session_ != session || size_t(n) < sizeof chunk) return;
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      // Readable yet empty with a hang-up flag: the other end is gone.
      if (events & (EPOLLHUP | EPOLLERR)) fail("the device hung up");
      return;
    }
    // 0 is end of file: a terminal whose other end went away.
    return fail(n == 0 ? std::string("the device hung up") : std::string("read failed: ") + strerror(errno));
  }
}

void SerialLink::fail(const std::string& why) {
  close();
  lost_why_ = why;
  lost_timer_ = loop_->start_timer(0, 0, this);
}

void SerialLink::on_timer(TimerId id) {
  if (id != lost_timer_) return;
  lost_timer_ = 0;
  listener_.on_serial_lost(lost_why_);
}

void SerialLink::close() {
  if (lost_timer_ != 0) {
    loop_->cancel_timer(lost_timer_);
    lost_timer_ = 0;
  }
  if (fd_ < 0) return;
  loop_->unwatch(fd_);
  int fd = fd_;
  fd_ = -1;
  baud_ = 0;
  writing_ = false;
  queue_head_ = queue_size_ = 0;
  try {
    port_->Close();
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
      port_->Close();
      port_.reset();
      return;
    } catch (const std::exception&) {
    }
  } else if (spare >= 0) {
    ::close(spare);
  }
  // Last resort: close the descriptor ourselves and never destroy the
  // object (its destructor would throw from noexcept). A few hundred bytes
  // per vanished device.
  ::close(fd);
  (void)port_.release();
  log_warn("%s: closed by hand after libserial refused to close it", path_.c_str());
}

}  // namespace troupe::serial
