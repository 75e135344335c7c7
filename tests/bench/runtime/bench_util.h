// Helpers shared by the runtime benchmarks: child processes serving on
// loopback, blocking frame I/O, statistics.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace troupe::bench {

/// Runs `serve(report_port)` in a child process; returns its pid and the TCP
/// port it reported.
pid_t spawn_server(const std::function<void(const std::function<void(uint16_t)>&)>& serve, uint16_t& port);
void stop_server(pid_t pid);
/// CPU time (user + system) a process used so far, seconds.
double cpu_seconds(pid_t pid);

/// A blocking TCP connection to 127.0.0.1:port with TCP_NODELAY.
int connect_loopback(uint16_t port);
bool write_all(int fd, std::span<const uint8_t> bytes);
bool read_exact(int fd, uint8_t* out, size_t n);
/// Reads one frame (4-byte little-endian length, then the bytes).
bool read_frame(int fd, std::vector<uint8_t>& frame);

/// Median and the p-th percentile (0..100) of `samples` (sorted in place).
double percentile(std::vector<double>& samples, double p);
double monotonic_seconds();

}  // namespace troupe::bench
