// CAN frames on a descriptor. The driver and the emulator read and write
// `struct can_frame` bytes, one frame per read or write, and never care what
// carries them: a PF_CAN raw socket on a kernel bus (can0, vcan0) or, in
// tests and in the simulator, one end of a socketpair(AF_UNIX,
// SOCK_SEQPACKET). Every call is non-blocking.
#pragma once

#include <linux/can.h>

#include <cstdint>
#include <span>
#include <string>

namespace troupe::cansimple {

/// Opens a non-blocking PF_CAN raw socket bound to interface `ifname`
/// ("can0"). With `node_ids` non-empty, kernel filters let through only
/// standard data frames from those nodes (any command); remote frames and
/// other nodes' traffic never reach the process. Returns the descriptor, or
/// -1 with `error` saying which step failed and why, and errno
/// EAFNOSUPPORT (no CAN in this kernel) or ENODEV (no such interface) when
/// the bus is not there.
int open_can_socket(const std::string& ifname, std::span<const uint8_t> node_ids, std::string& error);

/// Sets O_NONBLOCK on a descriptor handed over by someone else.
bool make_nonblocking(int fd, std::string& error);

enum class IoResult : uint8_t {
  Frame,       // one frame transferred
  WouldBlock,  // nothing to read now / the queue is full (the frame is dropped)
  Short,       // a read returned a datagram that is not one can_frame (ignored)
  Rejected,    // the kernel refused to send this frame (EINVAL: e.g. DLC > 8)
  Down,        // the interface is down (ENETDOWN): nothing moves until it is up again,
               // and the socket stays usable
  Closed,      // the other end is gone (EOF, ENODEV, EBADF...): stop using it
};

/// Reads one frame. `errno_out` holds errno for Closed, or the byte count
/// for Short.
IoResult read_frame(int fd, can_frame& frame, int& errno_out);
/// Writes one frame. A full queue (EAGAIN, ENOBUFS on CAN) is WouldBlock: CAN
/// traffic is periodic, the next period sends the newest value anyway.
IoResult write_frame(int fd, const can_frame& frame, int& errno_out);

}  // namespace troupe::cansimple
