#include "host-sim/sim/profile.h"

#include <cstdio>

namespace troupe::sim {

size_t Profile::define(std::string name) {
  phases_.push_back({std::move(name), 0, 0});
  return phases_.size() - 1;
}

void Profile::reset() {
  for (Phase& p : phases_) p.total_ns = p.last_ns = 0;
  steps_ = 0;
}

uint64_t Profile::total_ns() const {
  uint64_t t = 0;
  for (const Phase& p : phases_) t += p.total_ns;
  return t;
}

std::string Profile::table() const {
  std::string out;
  char line[160];
  std::snprintf(line, sizeof line, "%-14s %12s %12s %7s\n", "phase", "total ms", "us/step", "share");
  out += line;
  const double total = double(total_ns());
  const double steps = steps_ > 0 ? double(steps_) : 1.0;
  for (const Phase& p : phases_) {
    std::snprintf(line, sizeof line, "%-14s %12.2f %12.2f %6.1f%%\n", p.name.c_str(), p.total_ns * 1e-6,
                  p.total_ns * 1e-3 / steps, total > 0 ? 100.0 * p.total_ns / total : 0.0);
    out += line;
  }
  std::snprintf(line, sizeof line, "%-14s %12.2f %12.2f %6.1f%%  (%llu steps)\n", "all", total * 1e-6,
                total * 1e-3 / steps, 100.0, static_cast<unsigned long long>(steps_));
  out += line;
  return out;
}

}  // namespace troupe::sim
