#include "drivers/odrive_can/can_io.h"

#include <fcntl.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace troupe::cansimple {
namespace {

// Leaves errno as the failed call set it, for the caller to tell why.
bool fail(std::string& error, const std::string& what, int fd = -1) {
  const int why = errno;
  error = what + ": " + strerror(why);
  if (why == ENODEV) error += " (no interface of that name: `ip link` lists them)";
  if (fd >= 0) close(fd);
  errno = why;
  return false;
}

}  // namespace

bool make_nonblocking(int fd, std::string& error) {
  int flags = fcntl(fd, F_GETFL);
  if (flags < 0 || fcntl(fd, F_SETFL, flags | O_NONBLOCK) < 0) {
    return fail(error, "descriptor " + std::to_string(fd));
  }
  return true;
}

int open_can_socket(const std::string& ifname, std::span<const uint8_t> node_ids, std::string& error) {
  if (ifname.empty() || ifname.size() >= IFNAMSIZ) {
    error =
        "CAN interface name '" + ifname + "' must have 1 to " + std::to_string(IFNAMSIZ - 1) + " characters";
    return -1;
  }
  int fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    if (errno == EAFNOSUPPORT) {
      fail(error, "CAN interface '" + ifname + "': this kernel has no CAN support (socket(PF_CAN)");
      error += "); load the can and can-raw modules";
    } else {
      fail(error, "socket(PF_CAN, SOCK_RAW, CAN_RAW)");
    }
    return -1;
  }
  if (!node_ids.empty()) {
    // Id = node << 5 | cmd: matching the top six id bits selects a node. The
    // RTR and EFF bits in the mask keep remote and extended frames out.
    std::vector<can_filter> filters;
    for (uint8_t node : node_ids) {
      filters.push_back({uint32_t(node) << 5, (CAN_SFF_MASK & ~0x1Fu) | CAN_EFF_FLAG | CAN_RTR_FLAG});
    }
    if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, filters.data(),
                   socklen_t(filters.size() * sizeof(can_filter))) < 0) {
      fail(error, "setsockopt(CAN_RAW_FILTER)", fd);
      return -1;
    }
  }
  ifreq ifr{};
  std::memcpy(ifr.ifr_name, ifname.c_str(), ifname.size() + 1);
  if (ioctl(fd, SIOCGIFINDEX, &ifr) < 0) {
    fail(error, "CAN interface '" + ifname + "'", fd);
    return -1;
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) {
    fail(error, "bind to CAN interface '" + ifname + "'", fd);
    return -1;
  }
  return fd;
}

IoResult read_frame(int fd, can_frame& frame, int& errno_out) {
  for (;;) {
    ssize_t n = read(fd, &frame, sizeof frame);
    if (n == ssize_t(sizeof frame)) return IoResult::Frame;
    if (n == 0) {
      errno_out = 0;
      return IoResult::Closed;
    }
    if (n > 0) {
      errno_out = int(n);
      return IoResult::Short;
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return IoResult::WouldBlock;
    errno_out = errno;
    return errno == ENETDOWN ? IoResult::Down : IoResult::Closed;
  }
}

IoResult write_frame(int fd, const can_frame& frame, int& errno_out) {
  for (;;) {
    // send() with MSG_NOSIGNAL: a socketpair whose peer closed must give
    // EPIPE, not kill the process with SIGPIPE. write() for non-sockets.
    ssize_t n = send(fd, &frame, sizeof frame, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && errno == ENOTSOCK) n = write(fd, &frame, sizeof frame);
    if (n == ssize_t(sizeof frame)) return IoResult::Frame;
    if (n >= 0) {
      errno_out = int(n);
      return IoResult::Short;
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS) return IoResult::WouldBlock;
    errno_out = errno;
    if (errno == ENETDOWN) return IoResult::Down;
    return errno == EINVAL ? IoResult::Rejected : IoResult::Closed;
  }
}

}  // namespace troupe::cansimple
