// What the round-trip benchmarks share: a node serving the kinematic base on
// position2d:0, the request they time (ResetOdometry: answered at once,
// changes nothing that matters), and timed round trips on a blocking socket.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "wire/address.h"
#include "wire/connection/transport.h"

namespace troupe::bench {

/// The kinematic base's address on the benchmark node.
inline const wire::Address kBenchBase(0, uint16_t(wire::Interface::Position2d), 0);

/// Runs a node with the kinematic base on an ephemeral port, reports the port
/// (0 when it cannot start, after printing why) and serves until killed. For
/// spawn_server().
void serve_kinematic_node(const std::function<void(uint16_t)>& report);
/// The same node with each connection through the transport `make_transport`
/// makes (a secure session), for comparing against the plain one.
void serve_kinematic_node_through(const std::function<void(uint16_t)>& report,
                                  const std::function<std::unique_ptr<wire::Transport>()>& make_transport);

/// The ResetOdometry request to kBenchBase, framed, with sequence `seq`.
std::vector<uint8_t> request_frame(uint32_t seq);

/// `count` round trips of request_frame() through the blocking socket `fd`,
/// each reply being the first frame back; microseconds each.
std::vector<double> blocking_round_trips(int fd, int count);

}  // namespace troupe::bench
