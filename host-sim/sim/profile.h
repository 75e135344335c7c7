// Time spent in each named phase of the step, accumulated over steps, so a
// run can print where its time went.
// The one profiler of the simulator: the Stage engine's step and RoboCup
// mode's cycle and physics step all time into it, and `--profile` prints
// its table() whatever the world. Its own library (troupe_sim_profile),
// depending on nothing, so either side can use it.
#pragma once

#include <cstdint>
#include <ctime>
#include <string>
#include <vector>

namespace troupe::sim {

/// Monotonic nanoseconds.
inline uint64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return uint64_t(ts.tv_sec) * 1000000000u + uint64_t(ts.tv_nsec);
}

/// CPU nanoseconds of this process, every thread (MPI's own included): on
/// a shared machine, the work done, whatever the waiting for a core.
inline uint64_t process_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return uint64_t(ts.tv_sec) * 1000000000u + uint64_t(ts.tv_nsec);
}

class Profile {
 public:
  struct Phase {
    std::string name;
    uint64_t total_ns = 0;  // over every step since reset
    uint64_t last_ns = 0;   // the latest step
  };

  /// Adds a phase; returns its index for add().
  size_t define(std::string name);
  void add(size_t phase, uint64_t ns) {
    phases_[phase].total_ns += ns;
    phases_[phase].last_ns = ns;
  }
  void count_step() { ++steps_; }
  void reset();

  const std::vector<Phase>& phases() const { return phases_; }
  uint64_t steps() const { return steps_; }
  uint64_t total_ns() const;
  /// A table: phase, total ms, us per step, share of the total.
  std::string table() const;

 private:
  std::vector<Phase> phases_;
  uint64_t steps_ = 0;
};

/// Times one phase from construction to destruction.
class PhaseTimer {
 public:
  PhaseTimer(Profile& profile, size_t phase) : profile_(profile), phase_(phase), start_(now_ns()) {}
  ~PhaseTimer() { profile_.add(phase_, now_ns() - start_); }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  Profile& profile_;
  size_t phase_;
  uint64_t start_;
};

/// Times consecutive phases with one clock reading per boundary (half of
/// what a PhaseTimer per phase costs, which shows in a step of cheap
/// phases): each lap() charges the time since the previous lap, or since
/// construction, to `phase`.
class PhaseLaps {
 public:
  explicit PhaseLaps(Profile& profile) : profile_(profile), last_(now_ns()) {}
  void lap(size_t phase) {
    const uint64_t t = now_ns();
    profile_.add(phase, t - last_);
    last_ = t;
  }

 private:
  Profile& profile_;
  uint64_t last_;
};

}  // namespace troupe::sim
