#include "drivers/serial_port/serial_link.h"

#include <fcntl.h>
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

}  // namespace

bool SerialLink::open(const std::string& path, uint32_t baud, std::string& error) {
  close();
  if (loop_ == nullptr) {
    error = path + ": no event loop attached";
    return false;
  }
  if (!device_.open(path, baud, error)) return false;
  if (!loop_->watch(device_.fd(), EPOLLIN, this)) {
    error = path + ": cannot watch the port";
    device_.close();
    return false;
  }
  ++session_;
  path_ = path;
  baud_ = baud;
  queue_head_ = queue_size_ = 0;
  writing_ = false;
  return true;
}

bool SerialLink::set_baud(uint32_t baud, std::string& error) {
  if (!device_.set_baud(baud, error)) return false;
  baud_ = baud;
  queue_head_ = queue_size_ = 0;
  want_write(false);
  return true;
}

void SerialLink::discard_input() {
  device_.discard_input();
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
    ssize_t n = ::write(device_.fd(), queue_ + queue_head_, queue_size_ - queue_head_);
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
  loop_->modify(device_.fd(), EPOLLIN | (on ? uint32_t(EPOLLOUT) : 0u));
}

void SerialLink::on_fd(int fd, uint32_t events) {
  if (fd != device_.fd()) return;
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
  if (!is_open()) return;
  loop_->unwatch(device_.fd());
  baud_ = 0;
  writing_ = false;
  queue_head_ = queue_size_ = 0;
  device_.close();
  if (!device_.close_note().empty()) log_warn("%s: %s", path_.c_str(), device_.close_note().c_str());
}

}  // namespace troupe::serial
