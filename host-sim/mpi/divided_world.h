// A world divided between MPI processes (ranks): each steps the robots
// whose centre lies in its region (Tiles), with ghost copies of the robots
// near it, and hands robots over as they cross into another region.
//
// Every rank loads the whole world file, so a robot's make-up never
// travels: only what changes as it runs (World::save_robot). Each robot is
// computed exactly as one process would compute it, from the same values,
// so a run's trajectory log is the same bytes at any number of ranks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host-sim/mpi/comm.h"
#include "host-sim/mpi/tiles.h"
#include "host-sim/sim/division.h"

namespace troupe::sim::mpi {

class DividedWorld final : public Division {
 public:
  struct Options {
    /// Steps between redrawing the regions around where the robots are
    /// (so each rank keeps about as many); 0: never.
    uint64_t rebalance_every = 100;
    /// Regions of about equal measured step time (each process's work
    /// since the last redraw, spread over its robots); false: of about as
    /// many robots.
    bool balance_time = false;
    /// The leader holds the whole static map (it serves it to the viewer
    /// or draws it in a snapshot); false: only its region's part, as the
    /// other processes do.
    bool leader_holds_map = true;
  };
  /// Balanced by time, the first redraw comes this soon (steps) when
  /// rebalance_every is longer: the first step times measured fix the
  /// start's cut, drawn by robot count, before most of a short run has
  /// passed.
  static constexpr uint64_t kFirstRedraw = 10;

  DividedWorld(Comm& comm, Options options);

  bool start(World& world, std::string& error) override;
  Order sync(World& world, Order order) override;
  bool pending() const override { return !journal_.empty(); }
  void proposed(World& world) override;
  void moved(World& world) override;
  void after_step(World& world) override;
  void ghosts(World& world) override { proposed(world); }
  void restart(World& world) override;
  void mirror(World& world) override;
  bool gather_poses(const World& world, std::vector<Pose>& poses) override;
  bool first() const override { return comm_.rank() == 0; }
  bool any(bool mine) override { return comm_.any(mine); }
  std::string report(const World& world) override;

  /// The regions as they stand.
  const Tiles& tiles() const { return tiles_; }
  /// The robots this rank steps, ascending.
  const std::vector<RobotId>& owned() const { return owned_; }
  /// How far beyond its region a rank sees other robots, m
  /// (World::interaction_reach).
  double halo() const { return halo_; }

 private:
  /// Every robot's owner from the tiles; robots that change owner move.
  void migrate(World& world);
  /// This process's work so far: CPU time outside MPI calls, s.
  double work_s() const;
  /// New tiles from every rank's robots (and their costs), then migrate().
  void rebalance(World& world);
  /// Ranks hold the static map around their region only (but a leader
  /// that serves or draws the whole map); rebuilt when a new region needs
  /// more than the part held.
  void fit_map(World& world);
  /// The ghosts of the last exchange back to absent.
  void forget_ghosts(World& world);
  /// Robot `id`'s record: its number, its state's length, its state.
  static void put_state(const World& world, RobotId id, Bytes& out);
  /// Restores every record in `from` (sent by `rank`), appending the
  /// robots to `taken` when given. A record that does not fit ends the run.
  void take_states(World& world, const Bytes& from, int rank, std::vector<RobotId>* taken);

  Comm& comm_;
  Options options_;
  Tiles tiles_;
  double halo_ = 0;
  std::vector<RobotId> owned_;
  // The leader's world's inputs since the last sync().
  std::vector<std::byte> journal_;
  std::vector<RobotId> ghosts_;
  // The robots sent to each rank as ghosts by proposed(), whose final
  // poses moved() sends the same way.
  std::vector<std::vector<RobotId>> sent_;
  // The part of the map this rank holds (world frame, m); empty: all.
  Vec2 held_lo_{0, 0}, held_hi_{-1, -1};
  uint64_t steps_ = 0;
  uint64_t migrations_ = 0;  // robots this rank handed over
  uint64_t rebalances_ = 0;
  uint64_t map_builds_ = 0;
  // This process's own work (CPU time outside MPI) at the last redraw, s.
  double redrawn_work_s_ = 0;
  double started_s_ = 0;         // wall clock when start() ended (the world loaded), s
  uint64_t started_cpu_ns_ = 0;  // this process's CPU time then, ns
  // Comm's counters then: the report counts the run, not the start.
  uint64_t started_bytes_ = 0, started_messages_ = 0;
  double started_comm_s_ = 0, started_wait_s_ = 0, started_mpi_cpu_s_ = 0;
};

}  // namespace troupe::sim::mpi
