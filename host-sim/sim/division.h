// A world divided between processes, as troupe-sim's run loop sees it.
// host-sim/mpi implements it with MPI; troupe-sim built or started without
// MPI has none and steps the whole world itself.
#pragma once

#include <string>
#include <vector>

#include "host-sim/sim/world.h"

namespace troupe::sim {

class Division : public World::StepExchange {
 public:
  /// Takes this process's share of the robots and brings in its ghosts,
  /// before the first sensors are computed. False with `error` when the
  /// world cannot be divided. Collective: every process calls it.
  virtual bool start(World& world, std::string& error) = 0;
  /// After every step: robots that left this process's region go to the
  /// process whose region they entered, and now and then the regions are
  /// redrawn. `stop`: this process was asked to stop; the answer is true
  /// when any process was, so all stop at the same step. Collective.
  virtual bool after_step(World& world, bool stop) = 0;
  /// Every robot's pose (world frame: m, m, rad) in robot order, into
  /// `poses` on the first process (true there); false elsewhere.
  /// Collective.
  virtual bool gather_poses(const World& world, std::vector<Pose>& poses) = 0;
  /// The first process: the one that writes logs and prints results.
  virtual bool first() const = 0;
  /// True on every process when `mine` is true on any: a failure one
  /// process met stops them all, not it alone. Collective.
  virtual bool any(bool mine) = 0;
  /// A table of what each process did: robots owned, bytes and messages
  /// exchanged per step, time spent exchanging against stepping.
  /// Collective; the text on the first process, "" elsewhere.
  virtual std::string report() = 0;
};

}  // namespace troupe::sim
