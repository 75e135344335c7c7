#include "host-sim/mpi/divided_world.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "host-sim/sim/bytes.h"
#include "host-sim/sim/profile.h"
#include "host-sim/sim/static_map.h"

namespace troupe::sim::mpi {
namespace {

using bytes::get;
using bytes::put;

double wall_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

Vec2 centre(const World& world, RobotId id) {
  const Pose& p = world.ghost_motion(id).pose;
  return {p.x, p.y};
}

// A ghost record: its robot, then its motion field by field (no padding
// travels).
void put_motion(Bytes& out, RobotId id, const World::GhostMotion& m) {
  put(out, id);
  put(out, m.pose);
  put(out, m.proposed);
  put(out, uint8_t(m.moved));
}

}  // namespace

DividedWorld::DividedWorld(Comm& comm, Options options) : comm_(comm), options_(options) {}

bool DividedWorld::start(World& world, std::string& error) {
  if (!world.divisible(error)) {
    error = "this world cannot be divided between processes: " + error;
    return false;
  }
  halo_ = world.interaction_reach();
  sent_.assign(size_t(comm_.size()), {});
  // Clients reach the leader; the robots' owners take their inputs.
  if (first()) world.set_journal(&journal_);
  restart(world);
  // The report's times count from here: loading the world is not stepping it.
  started_s_ = wall_s();
  started_cpu_ns_ = process_cpu_ns();
  started_bytes_ = comm_.bytes_sent();
  started_messages_ = comm_.messages_sent();
  started_comm_s_ = comm_.seconds();
  started_wait_s_ = comm_.wait_seconds();
  started_mpi_cpu_s_ = comm_.cpu_seconds();
  redrawn_work_s_ = work_s();
  return true;
}

void DividedWorld::restart(World& world) {
  // Every rank holds the same poses (a loaded or reset world): the same
  // tiles everywhere, with no message.
  std::vector<Vec2> starts(world.robot_count());
  for (RobotId i = 0; i < world.robot_count(); ++i) starts[i] = centre(world, i);
  tiles_ = Tiles::balanced(comm_.size(), starts);
  owned_.clear();
  for (RobotId i = 0; i < world.robot_count(); ++i) {
    const bool mine = tiles_.owner(starts[i]) == comm_.rank();
    world.set_residence(i, mine ? World::Residence::Owned : World::Residence::Absent);
    if (mine) owned_.push_back(i);
  }
  ghosts_.clear();
  fit_map(world);
  // The ghosts the first sensors see (nobody has moved yet).
  proposed(world);
}

void DividedWorld::fit_map(World& world) {
  if ((first() && options_.leader_holds_map) || comm_.size() == 1) return;
  Vec2 lo, hi;
  tiles_.region(comm_.rank(), lo, hi);
  // What this rank's robots can reach: its region and the halo.
  const StaticMap& map = world.map();
  const Vec2 grid_lo = map.origin(),
             grid_hi = grid_lo + Vec2{map.width() * map.resolution(), map.height() * map.resolution()};
  auto clip = [&](Vec2 p) {
    return Vec2{std::clamp(p.x, grid_lo.x, grid_hi.x), std::clamp(p.y, grid_lo.y, grid_hi.y)};
  };
  const Vec2 need_lo = clip(lo - Vec2{halo_, halo_}), need_hi = clip(hi + Vec2{halo_, halo_});
  if (held_lo_.x <= need_lo.x && held_lo_.y <= need_lo.y && held_hi_.x >= need_hi.x &&
      held_hi_.y >= need_hi.y)
    return;
  // A halo more each way, so regions redrawn a little need no new map.
  held_lo_ = clip(need_lo - Vec2{halo_, halo_});
  held_hi_ = clip(need_hi + Vec2{halo_, halo_});
  if (!world.keep_map_within(held_lo_, held_hi_)) {
    held_lo_ = grid_lo;  // held whole: never rebuilt
    held_hi_ = grid_hi;
  }
  ++map_builds_;
}

DividedWorld::Order DividedWorld::sync(World& world, Order order) {
  Bytes message;
  if (first()) {
    // Sized first, then filled: GCC 12 warns falsely (-Warray-bounds) on
    // an insert after a push_back.
    message.resize(1 + journal_.size());
    message[0] = std::byte(order);
    if (!journal_.empty()) std::memcpy(message.data() + 1, journal_.data(), journal_.size());
    journal_.clear();
  }
  comm_.broadcast(message);
  if (message.empty()) comm_.abort(1);  // cannot be: the leader always sends its order
  const Order received = Order(message[0]);
  if (!first() && !world.replay(std::span<const std::byte>(message).subspan(1))) {
    std::fprintf(stderr, "troupe-sim: rank %d: the leader's inputs do not fit this world; stopping\n",
                 comm_.rank());
    comm_.abort(1);
  }
  // A teleported robot is stepped by its new region's process.
  if (received == Order::Step || received == Order::Refresh) migrate(world);
  return received;
}

void DividedWorld::mirror(World& world) {
  Bytes mine;
  for (RobotId id : owned_) put_state(world, id, mine);
  std::vector<Bytes> all;
  comm_.gather(mine, all);
  for (size_t r = 1; r < all.size(); ++r) take_states(world, all[r], int(r), nullptr);
}

void DividedWorld::put_state(const World& world, RobotId id, Bytes& out) {
  put(out, id);
  const size_t at = out.size();
  put(out, uint64_t(0));  // its length, once known
  world.save_robot(id, out);
  const uint64_t size = out.size() - at - sizeof(uint64_t);
  std::memcpy(out.data() + at, &size, sizeof size);
}

void DividedWorld::take_states(World& world, const Bytes& from, int rank, std::vector<RobotId>* taken) {
  std::span<const std::byte> in(from);
  RobotId id = 0;
  uint64_t size = 0;
  while (get(in, id) && get(in, size)) {
    std::span<const std::byte> record = in.subspan(0, std::min<size_t>(size, in.size()));
    in = in.subspan(record.size());
    // Both ranks run the same build on the same world: a record that does
    // not fit is a bug, and a robot lost would silently change the run,
    // so the run ends.
    if (size > record.size() || !world.restore_robot(id, record) || !record.empty()) {
      std::fprintf(stderr, "troupe-sim: rank %d: robot %u's state from rank %d does not fit; stopping\n",
                   comm_.rank(), id, rank);
      comm_.abort(1);
    }
    if (taken) taken->push_back(id);
  }
}

void DividedWorld::forget_ghosts(World& world) {
  for (RobotId id : ghosts_) {
    if (world.residence(id) == World::Residence::Ghost) world.set_residence(id, World::Residence::Absent);
  }
  ghosts_.clear();
}

void DividedWorld::proposed(World& world) {
  std::vector<Bytes> send(size_t(comm_.size())), recv;
  std::vector<int> ranks;
  for (auto& s : sent_) s.clear();
  for (RobotId id : owned_) {
    const World::GhostMotion m = world.ghost_motion(id);
    tiles_.near({m.pose.x, m.pose.y}, halo_, ranks);
    for (int r : ranks) {
      if (r == comm_.rank()) continue;
      put_motion(send[size_t(r)], id, m);
      sent_[size_t(r)].push_back(id);
    }
  }
  comm_.exchange(send, recv);
  forget_ghosts(world);
  for (const Bytes& from : recv) {
    std::span<const std::byte> in(from);
    RobotId id = 0;
    World::GhostMotion m;
    uint8_t moved = 0;
    while (get(in, id) && get(in, m.pose) && get(in, m.proposed) && get(in, moved)) {
      m.moved = moved != 0;
      world.set_ghost_motion(id, m);
      world.set_residence(id, World::Residence::Ghost);
      ghosts_.push_back(id);
    }
  }
}

void DividedWorld::moved(World& world) {
  std::vector<Bytes> send(size_t(comm_.size())), recv;
  for (size_t r = 0; r < sent_.size(); ++r) {
    for (RobotId id : sent_[r]) {
      put(send[r], id);
      put(send[r], world.ghost_motion(id).pose);
    }
  }
  comm_.exchange(send, recv);
  for (const Bytes& from : recv) {
    std::span<const std::byte> in(from);
    RobotId id = 0;
    Pose pose;
    while (get(in, id) && get(in, pose)) world.set_ghost_motion(id, {pose, pose, false});
  }
}

void DividedWorld::migrate(World& world) {
  std::vector<Bytes> send(size_t(comm_.size())), recv;
  std::vector<RobotId> kept;
  kept.reserve(owned_.size());
  for (RobotId id : owned_) {
    const int to = tiles_.owner(centre(world, id));
    if (to == comm_.rank()) {
      kept.push_back(id);
      continue;
    }
    put_state(world, id, send[size_t(to)]);
    world.set_residence(id, World::Residence::Absent);
    ++migrations_;
  }
  comm_.exchange(send, recv);
  owned_ = std::move(kept);
  for (size_t r = 0; r < recv.size(); ++r) {
    const size_t before = owned_.size();
    take_states(world, recv[r], int(r), &owned_);
    for (size_t k = before; k < owned_.size(); ++k) world.set_residence(owned_[k], World::Residence::Owned);
  }
  std::sort(owned_.begin(), owned_.end());
}

double DividedWorld::work_s() const {
  return double(process_cpu_ns()) * 1e-9 - comm_.cpu_seconds();
}

void DividedWorld::rebalance(World& world) {
  // What a robot of this process has cost since the last redraw, s: the
  // process's work shared out evenly (its region's robots are alike
  // enough; the next redraw corrects what they are not).
  const double work = work_s();
  const double each = (work - redrawn_work_s_) / double(std::max<size_t>(owned_.size(), 1));
  redrawn_work_s_ = work;
  Bytes mine;
  put(mine, each);
  for (RobotId id : owned_) put(mine, centre(world, id));
  std::vector<Bytes> all;
  comm_.all_gather(mine, all);
  // Every rank orders the same centres the same way (Tiles sorts them),
  // so all draw the same tiles.
  std::vector<Vec2> centres;
  std::vector<double> costs;
  for (const Bytes& b : all) {
    std::span<const std::byte> in(b);
    double cost = 0;
    if (!get(in, cost)) continue;
    Vec2 c;
    while (get(in, c)) {
      centres.push_back(c);
      costs.push_back(cost);
    }
  }
  tiles_ = options_.balance_time ? Tiles::balanced(comm_.size(), centres, costs)
                                 : Tiles::balanced(comm_.size(), centres);
  ++rebalances_;
  fit_map(world);
}

void DividedWorld::after_step(World& world) {
  ++steps_;
  const uint64_t every = options_.rebalance_every;
  const bool first_look = options_.balance_time && steps_ == std::min(every, kFirstRedraw);
  if (every > 0 && (steps_ % every == 0 || first_look)) rebalance(world);
  migrate(world);
}

bool DividedWorld::gather_poses(const World& world, std::vector<Pose>& poses) {
  Bytes mine;
  for (RobotId id : owned_) {
    put(mine, id);
    put(mine, world.state(id).pose);
  }
  std::vector<Bytes> all;
  comm_.gather(mine, all);
  if (!first()) return false;
  poses.assign(world.robot_count(), Pose{});
  for (const Bytes& b : all) {
    std::span<const std::byte> in(b);
    RobotId id = 0;
    Pose p;
    while (get(in, id) && get(in, p)) {
      if (id < poses.size()) poses[id] = p;
    }
  }
  return true;
}

std::string DividedWorld::report(const World& world) {
  struct Row {
    uint64_t robots, bytes, messages, migrations, world_bytes, map_builds;
    double comm_s, wait_s, wall_s, cpu_s, mpi_cpu_s;
  };
  const Row mine{owned_.size(),
                 comm_.bytes_sent() - started_bytes_,
                 comm_.messages_sent() - started_messages_,
                 migrations_,
                 world.memory_bytes(),
                 map_builds_,
                 comm_.seconds() - started_comm_s_,
                 comm_.wait_seconds() - started_wait_s_,
                 wall_s() - started_s_,
                 double(process_cpu_ns() - started_cpu_ns_) * 1e-9,
                 comm_.cpu_seconds() - started_mpi_cpu_s_};
  Bytes b;
  put(b, mine);
  std::vector<Bytes> all;
  comm_.gather(b, all);
  if (!first()) return "";
  const double steps = double(std::max<uint64_t>(steps_, 1));
  // Waiting s (part of exchanging s), CPU s and the part of it in MPI
  // come last, so readers of the older columns read them where they were.
  // CPU s less MPI CPU s is the rank's own work, whatever the machine's
  // load.
  std::string out;
  char line[320];
  std::snprintf(
      line, sizeof line,
      "%d ranks (%d x %d tiles), halo %.2f m, %llu steps, regions redrawn %llu times\n"
      "rank  robots  bytes/step  messages/step  migrated  exchanging s  other s  world MB  map builds  "
      "waiting s  CPU s  MPI CPU s\n",
      tiles_.ranks(), tiles_.cols(), tiles_.rows(), halo_, static_cast<unsigned long long>(steps_),
      static_cast<unsigned long long>(rebalances_));
  out += line;
  for (size_t r = 0; r < all.size(); ++r) {
    Row row{};
    std::span<const std::byte> in(all[r]);
    if (!get(in, row)) continue;
    std::snprintf(line, sizeof line,
                  "%4zu  %6llu  %10.0f  %13.1f  %8llu  %12.3f  %7.3f  %8.1f  %10llu  %9.3f  %5.2f  %9.2f\n",
                  r, static_cast<unsigned long long>(row.robots), double(row.bytes) / steps,
                  double(row.messages) / steps, static_cast<unsigned long long>(row.migrations), row.comm_s,
                  row.wall_s - row.comm_s, double(row.world_bytes) / 1e6,
                  static_cast<unsigned long long>(row.map_builds), row.wait_s, row.cpu_s, row.mpi_cpu_s);
    out += line;
  }
  return out;
}

}  // namespace troupe::sim::mpi
