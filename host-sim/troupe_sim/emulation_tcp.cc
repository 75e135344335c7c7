#include "host-sim/troupe_sim/emulation_tcp.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "runtime/log.h"

namespace troupe::sim {
namespace {

// A non-blocking listening socket on host:port (IPv4 or IPv6 literal);
// -1 with `error`.
int listen_on(const std::string& host, uint16_t port, uint16_t& bound, std::string& error) {
  sockaddr_storage addr{};
  socklen_t len = 0;
  auto* v4 = reinterpret_cast<sockaddr_in*>(&addr);
  auto* v6 = reinterpret_cast<sockaddr_in6*>(&addr);
  if (inet_pton(AF_INET, host.c_str(), &v4->sin_addr) == 1) {
    v4->sin_family = AF_INET;
    v4->sin_port = htons(port);
    len = sizeof *v4;
  } else if (inet_pton(AF_INET6, host.c_str(), &v6->sin6_addr) == 1) {
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(port);
    len = sizeof *v6;
  } else {
    error = "not an address: " + host;
    return -1;
  }
  int fd = socket(addr.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&addr), len) != 0 || ::listen(fd, 4) != 0) {
    error = "cannot listen on " + host + ":" + std::to_string(port) + ": " + strerror(errno);
    if (fd >= 0) ::close(fd);
    return -1;
  }
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  bound = ntohs(addr.ss_family == AF_INET ? v4->sin_port : v6->sin6_port);
  return fd;
}

}  // namespace

P2osTcp::~P2osTcp() {
  for (Robot& r : robots_) {
    drop(r);
    if (r.listen_fd >= 0) ::close(r.listen_fd);
  }
}

bool P2osTcp::open(World& world, const std::string& listen, int base_port, std::string& error) {
  // ARIA resolves its -remoteHost to IPv4 only (gethostbyname), so the
  // default "localhost" listen serves the Pioneers on 127.0.0.1.
  listen_ = listen == "localhost" ? "127.0.0.1" : listen;
  robots_.resize(world.robot_count());
  for (RobotId id = 0; id < world.robot_count(); ++id) {
    Robot& r = robots_[id];
    r.id = id;
    r.name = world.robot(id).name;
    uint16_t want = base_port == 0 ? 0 : uint16_t(base_port + int(id));
    if (base_port != 0 && base_port + int(id) > 65535) {
      error = "--p2os-tcp: robot " + r.name + " would need port " + std::to_string(base_port + int(id));
      return false;
    }
    r.listen_fd = listen_on(listen_, want, r.port, error);
    if (r.listen_fd < 0) {
      error = "--p2os-tcp: robot " + r.name + ": " + error;
      return false;
    }
    r.body = std::make_unique<SimPioneerBody>(world, id);
    emulators::PioneerEmulator::Config config;
    config.name = r.name;
    config.check_baud = false;
    r.pioneer = std::make_unique<emulators::PioneerEmulator>(config, r.body.get());
    if (std::optional<uint32_t> laser = find_laser(world, id)) {
      r.laser = std::make_unique<SimLaser>(world, *laser);
      r.pioneer->set_sim_laser(r.laser.get());
    }
  }
  return true;
}

void P2osTcp::accept(Robot& r) {
  int fd = ::accept4(r.listen_fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
  if (fd < 0) return;
  if (r.client_fd >= 0) {
    // One client a robot, as MobileSim: a second is turned away.
    ::close(fd);
    return;
  }
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  r.client_fd = fd;
  r.pioneer->power_cycle();
  r.pioneer->attach_stream(fd);
  log_info("robot %s: a P2OS client connected on port %u", r.name.c_str(), unsigned(r.port));
}

void P2osTcp::drop(Robot& r) {
  if (r.client_fd < 0) return;
  r.pioneer->attach_stream(-1);
  r.pioneer->power_cycle();
  ::close(r.client_fd);
  r.client_fd = -1;
  log_info("robot %s: the P2OS client on port %u left", r.name.c_str(), unsigned(r.port));
}

void P2osTcp::step(uint64_t now_us) {
  for (Robot& r : robots_) {
    accept(r);
    if (r.client_fd < 0) continue;
    r.pioneer->step(now_us);
    if (!r.pioneer->stream_closed()) continue;
    drop(r);
    r.pioneer->step(now_us);  // the robot stops in the world too
  }
}

size_t P2osTcp::clients() const {
  size_t n = 0;
  for (const Robot& r : robots_) n += r.client_fd >= 0 ? 1 : 0;
  return n;
}

std::string P2osTcp::info() const {
  std::string text;
  for (const Robot& r : robots_) text += r.name + " p2os-tcp " + listen_ + ":" + std::to_string(r.port) + "\n";
  return text;
}

}  // namespace troupe::sim
