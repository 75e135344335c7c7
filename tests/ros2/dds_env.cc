#include "tests/ros2/dds_env.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/file.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

namespace troupe::testing::ros2 {

namespace {

// RTPS's well-known ports (DDSI-RTPS 9.6.1.1): port base 7400, domain gain
// 250, participant gain 2; unicast discovery at offset 10, user data at 11.
int unicast_port(int domain, int participant, int offset) {
  return 7400 + 250 * domain + offset + 2 * participant;
}

bool udp_port_free(int port) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return false;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(uint16_t(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  close(fd);
  return ok;
}

}  // namespace

DdsDomain::DdsDomain() {
  const std::string dir = std::string(TROUPE_BINARY_DIR) + "/tests/ros2/domains";
  mkdir(dir.c_str(), 0755);
  const int start = int(getpid() % 200);
  for (int k = 0; k < 200; ++k) {
    const int d = 1 + (start + k) % 200;
    const std::string path = dir + "/" + std::to_string(d) + ".lock";
    const int fd = open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    if (fd < 0) continue;
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      close(fd);
      continue;
    }
    bool free = true;
    for (int p = 0; p < 10 && free; ++p) {
      free = udp_port_free(unicast_port(d, p, 10)) && udp_port_free(unicast_port(d, p, 11));
    }
    if (!free) {
      close(fd);
      continue;
    }
    id_ = d;
    lock_fd_ = fd;
    return;
  }
}

DdsDomain::~DdsDomain() {
  if (lock_fd_ >= 0) close(lock_fd_);
}

std::string cyclone_loopback_config() {
  return "<CycloneDDS><Domain id=\"any\">"
         "<General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
         "<AllowMulticast>false</AllowMulticast></General>"
         "<Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>20</"
         "MaxAutoParticipantIndex>"
         "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
         "</Domain></CycloneDDS>";
}

}  // namespace troupe::testing::ros2
