// Troupe logs for troupe play to chew on, written with the project's own
// LogWriter: a node's Hello, a DeviceList naming position2d:0, then one
// position2d Data frame per receive time given (which may jump about).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace troupe::attack {

/// Writes the log; false with `error`. `times_us`: each Data record's
/// receive time, us since the recording started.
bool write_recording(const std::string& path, const std::vector<uint64_t>& times_us, std::string& error);

/// `n` receive times `period_us` apart, starting at 0.
std::vector<uint64_t> steady_times(int n, uint64_t period_us);

}  // namespace troupe::attack
