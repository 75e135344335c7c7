// DDS for tests and benchmarks that run the bridge: a domain of their own
// (tests run side by side, and a shared domain would mix their topics), and
// discovery by unicast on loopback (this machine's loopback has no
// multicast, and a test must not reach beyond the host).
#pragma once

#include <string>

namespace troupe::testing::ros2 {

/// A DDS domain held by this process: no other test holding one (a lock
/// file in the build tree) and no program using its ports now. Released
/// when the object goes.
class DdsDomain {
 public:
  DdsDomain();
  ~DdsDomain();
  DdsDomain(const DdsDomain&) = delete;
  DdsDomain& operator=(const DdsDomain&) = delete;

  /// 1..200; -1 when none was free.
  int id() const { return id_; }

 private:
  int id_ = -1;
  int lock_fd_ = -1;
};

/// CYCLONEDDS_URI for programs on Cyclone DDS (the bridge): loopback only,
/// no multicast, peers found at the well-known ports of 127.0.0.1.
std::string cyclone_loopback_config();

}  // namespace troupe::testing::ros2
