// Who keeps a client slot: the Hello and idle deadlines, readers that have
// stopped reading, and whom a new connection displaces when every slot is
// taken. The rest of the server (sockets, frames, queues) is server.cc.
#include <linux/sockios.h>  // SIOCOUTQ
#include <netinet/in.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/server.h"

namespace troupe {
namespace {

// A connection whose peer has taken none of the bytes waiting for it for
// this long is not reading: when every slot is taken, a new connection may
// have its slot. It is still served until then (a link may be down a while).
constexpr uint64_t kStalledUs = 1'000'000;

bool same_host(const sockaddr_storage& a, const sockaddr_storage& b) {
  if (a.ss_family != b.ss_family) return false;
  if (a.ss_family == AF_INET6) {
    return memcmp(&reinterpret_cast<const sockaddr_in6&>(a).sin6_addr,
                  &reinterpret_cast<const sockaddr_in6&>(b).sin6_addr, sizeof(in6_addr)) == 0;
  }
  return reinterpret_cast<const sockaddr_in&>(a).sin_addr.s_addr ==
         reinterpret_cast<const sockaddr_in&>(b).sin_addr.s_addr;
}

}  // namespace

uint64_t Server::sweep_period_us() const {
  // A few looks per the shortest deadline (the stall that frees a slot
  // included): a connection is closed at most a quarter late.
  const Node::Options& opt = node_.options();
  uint64_t shortest_us = kStalledUs;
  for (uint32_t t : {opt.hello_timeout_ms, opt.idle_timeout_ms}) {
    if (t != 0) shortest_us = std::min<uint64_t>(shortest_us, uint64_t(t) * 1000);
  }
  return std::max<uint64_t>(shortest_us / 4, 10'000);
}

void Server::check_progress(Client& c, uint64_t now) {
  if (c.state == State::Free) return;
  // What the peer has not acknowledged yet is still in our socket: bytes
  // handed to it minus those are what the peer has taken. The kernel's send
  // buffer grows to megabytes on a fast link, so a peer that stops reading a
  // 10 Hz stream would take minutes to make our own writes fail; its
  // acknowledgements stop at once, when its receive buffer is full.
  int in_socket = 0;
  if (ioctl(c.fd, SIOCOUTQ, &in_socket) != 0) in_socket = 0;
  const uint64_t taken = c.written - uint64_t(std::max(in_socket, 0));
  const bool waiting = in_socket > 0 || c.writing;
  if (!waiting) {
    c.stalled_us = 0;
  } else if (taken != c.taken || c.stalled_us == 0) {
    c.stalled_us = now;  // took something (or just fell behind): counts from now
  }
  c.taken = taken;
}

uint32_t Server::slot_for(const sockaddr_storage& peer) {
  const uint16_t per_address = node_.options().max_clients_per_address;
  uint32_t free_slot = UINT32_MAX, from_address = 0;
  for (uint32_t i = 0; i < clients_.size(); ++i) {
    if (clients_[i].state == State::Free) {
      if (free_slot == UINT32_MAX) free_slot = i;
    } else {
      from_address += same_host(clients_[i].peer, peer);
    }
  }
  const bool address_full = per_address != 0 && from_address >= per_address;
  if (free_slot != UINT32_MAX && !address_full) return free_slot;
  // Full: a connection being closed gives up its slot, else the oldest that
  // has not said anything, else the one whose peer has taken nothing of what
  // waits for it for longest (one of this address when that is what is
  // full). A client that spoke and reads its data, or has none to read, is
  // never displaced.
  const uint64_t now = node_.loop().now_us();
  enum Rank { Closing, Silent, Stalled, Kept };
  auto rank_of = [now](const Client& c) {
    if (c.state == State::Draining) return Closing;
    if (c.heard_us == 0) return Silent;
    if (c.stalled_us != 0 && now - c.stalled_us >= kStalledUs) return Stalled;
    return Kept;
  };
  uint32_t victim = UINT32_MAX;
  Rank victim_rank = Kept;
  uint64_t victim_since = 0;
  for (uint32_t i = 0; i < clients_.size(); ++i) {
    Client& c = clients_[i];
    if (c.state == State::Free || (address_full && !same_host(c.peer, peer))) continue;
    check_progress(c, now);
    const Rank rank = rank_of(c);
    // Within a rank, the one waiting longest: since it connected, or since
    // its peer last took bytes.
    const uint64_t since = rank == Stalled ? c.stalled_us : c.connected_us;
    if (rank < victim_rank || (rank == victim_rank && rank != Kept && since < victim_since)) {
      victim = i;
      victim_rank = rank;
      victim_since = since;
    }
  }
  if (victim_rank == Kept) return UINT32_MAX;
  if (victim_rank != Closing) {
    // Straight to the socket, best effort: a stalled reader's is full, and
    // the slot is needed now, not after a linger.
    send_error_now(
        clients_[victim].fd, wire::ErrorCode::Timeout,
        victim_rank == Silent
            ? "closed for a new client: this connection had sent nothing"
            : "closed for a new client: this connection had read nothing it was sent for a second");
  }
  log_info("client %u closed to make room for a new connection", victim);
  close_client(victim);
  return victim;
}

void Server::sweep() {
  const Node::Options& opt = node_.options();
  const uint64_t now = node_.loop().now_us();
  for (uint32_t i = 0; i < clients_.size(); ++i) {
    Client& c = clients_[i];
    if (c.state != State::Open) continue;
    check_progress(c, now);
    char text[80];
    if (c.heard_us == 0 && opt.hello_timeout_ms != 0 &&
        now - c.connected_us > uint64_t(opt.hello_timeout_ms) * 1000) {
      snprintf(text, sizeof text, "no Hello (no valid frame) within %u ms of connecting",
               opt.hello_timeout_ms);
    } else if (c.heard_us != 0 && c.opened.empty() && opt.idle_timeout_ms != 0 &&
               now - c.heard_us > uint64_t(opt.idle_timeout_ms) * 1000) {
      snprintf(text, sizeof text, "silent for %u ms with no device open", opt.idle_timeout_ms);
    } else if (c.stalled_us != 0 && opt.idle_timeout_ms != 0 &&
               now - c.stalled_us > uint64_t(opt.idle_timeout_ms) * 1000) {
      snprintf(text, sizeof text, "not reading: the connection took no data for %u ms", opt.idle_timeout_ms);
    } else {
      continue;
    }
    log_info("client %u: %s; closing", i, text);
    close_with_error(i, wire::ErrorCode::Timeout, text);
  }
}

}  // namespace troupe
