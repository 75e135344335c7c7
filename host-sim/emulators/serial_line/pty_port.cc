#include "host-sim/emulators/serial_line/pty_port.h"

#include <fcntl.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace troupe::emulators {
namespace {

uint32_t speed_to_baud(speed_t s) {
  switch (s) {
    case B1200:
      return 1200;
    case B2400:
      return 2400;
    case B4800:
      return 4800;
    case B9600:
      return 9600;
    case B19200:
      return 19200;
    case B38400:
      return 38400;
    case B57600:
      return 57600;
    case B115200:
      return 115200;
    case B230400:
      return 230400;
    case B460800:
      return 460800;
    case B500000:
      return 500000;
    case B921600:
      return 921600;
    default:
      return 0;
  }
}

}  // namespace

bool PtyPort::open(const std::string& link, std::string& error) {
  close();
  // Raw from the start: a fresh pty echoes and edits lines, which would
  // send a device's output back to it before any driver opens the port.
  termios raw{};
  cfmakeraw(&raw);
  cfsetispeed(&raw, B9600);
  cfsetospeed(&raw, B9600);
  int master = -1, slave = -1;
  char name[128] = {};
  if (openpty(&master, &slave, name, &raw, nullptr) != 0) {
    error = std::string("cannot create a pseudo-terminal: ") + strerror(errno);
    return false;
  }
  // Only the driver holds the slave: when it closes it, its settings go
  // with it, as on a real port.
  ::close(slave);
  int flags = fcntl(master, F_GETFL, 0);
  fcntl(master, F_SETFL, flags | O_NONBLOCK);
  fcntl(master, F_SETFD, FD_CLOEXEC);
  if (!link.empty()) {
    // rename() replaces an older link in one step, so the name never
    // points nowhere while a new pty takes over.
    std::string tmp = link + ".new";
    ::unlink(tmp.c_str());
    if (symlink(name, tmp.c_str()) != 0 || rename(tmp.c_str(), link.c_str()) != 0) {
      error = "cannot link " + link + " to " + name + ": " + strerror(errno);
      ::unlink(tmp.c_str());
      ::close(master);
      return false;
    }
  }
  master_ = master;
  slave_path_ = name;
  link_ = link;
  return true;
}

void PtyPort::close() {
  if (master_ < 0) return;
  if (!link_.empty()) {
    // Remove the link only while it is still ours.
    char target[128] = {};
    ssize_t n = readlink(link_.c_str(), target, sizeof target - 1);
    if (n > 0 && slave_path_ == std::string(target, size_t(n))) ::unlink(link_.c_str());
  }
  ::close(master_);
  master_ = -1;
}

size_t PtyPort::read(std::span<uint8_t> out) {
  if (master_ < 0 || out.empty()) return 0;
  for (;;) {
    ssize_t n = ::read(master_, out.data(), out.size());
    if (n > 0) return size_t(n);
    if (n < 0 && errno == EINTR) continue;
    // EAGAIN: nothing; EIO: the driver's end is not open.
    return 0;
  }
}

size_t PtyPort::write(std::span<const uint8_t> bytes) {
  if (master_ < 0 || bytes.empty()) return 0;
  for (;;) {
    ssize_t n = ::write(master_, bytes.data(), bytes.size());
    if (n >= 0) return size_t(n);
    if (errno == EINTR) continue;
    return 0;
  }
}

uint32_t PtyPort::host_baud() const {
  termios t{};
  // Terminal settings asked of the master are the slave's: the driver's.
  if (master_ < 0 || tcgetattr(master_, &t) != 0) return 0;
  return speed_to_baud(cfgetospeed(&t));
}

}  // namespace troupe::emulators
