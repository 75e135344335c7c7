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
  /// What the first process (the leader: it keeps the pace and serves
  /// clients) tells the others to do next.
  enum class Order : uint8_t {
    Step,     // one step of the world
    Refresh,  // sensors for the robots where they are, without a step
    Reset,    // every robot back to its start
    Stop,     // the run ends
  };

  /// Takes this process's share of the robots and brings in its ghosts,
  /// before the first sensors are computed. False with `error` when the
  /// world cannot be divided. Collective: every process calls it.
  virtual bool start(World& world, std::string& error) = 0;
  /// The leader sends `order` with the inputs its world took since the
  /// last one (commands, teleports, wanted sensors: World::set_journal);
  /// the others wait for it, take the same inputs and return it. Then a
  /// robot a teleport moved goes to its new region's process. Collective.
  virtual Order sync(World& world, Order order) = 0;
  /// True when the leader's world took inputs not yet sent.
  virtual bool pending() const = 0;
  /// After every step: robots that left this process's region go to the
  /// process whose region they entered, and now and then the regions are
  /// redrawn. Collective.
  virtual void after_step(World& world) = 0;
  /// Brings in the ghosts of robots as they stand, for sensors computed
  /// without a step (Order::Refresh). Collective.
  virtual void ghosts(World& world) = 0;
  /// After World::reset(): regions drawn again from the start poses, and
  /// the ghosts brought in. Collective.
  virtual void restart(World& world) = 0;
  /// Every robot's whole state into the leader's world, so it serves and
  /// draws the whole world. Collective.
  virtual void mirror(World& world) = 0;
  /// Every robot's pose (world frame: m, m, rad) in robot order, into
  /// `poses` on the leader (true there); false elsewhere. Collective.
  virtual bool gather_poses(const World& world, std::vector<Pose>& poses) = 0;
  /// The leader: the first process, the one that serves, writes logs and
  /// prints results.
  virtual bool first() const = 0;
  /// True on every process when `mine` is true on any: a failure one
  /// process met stops them all, not it alone. Collective.
  virtual bool any(bool mine) = 0;
  /// A table of what each process did: robots owned, bytes and messages
  /// exchanged per step, time spent exchanging against stepping, memory
  /// its world holds.
  /// Collective; the text on the leader, "" elsewhere.
  virtual std::string report(const World& world) = 0;
};

}  // namespace troupe::sim
