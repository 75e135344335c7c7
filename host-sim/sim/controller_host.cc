#include "host-sim/sim/controller_host.h"

#include <cstdio>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace troupe::sim {
namespace {

class WorldRobot final : public RobotHandle {
 public:
  WorldRobot(World& world, RobotId id) : w_(world), id_(id) {}

  RobotId id() const override { return id_; }
  const std::string& name() const override { return w_.robot(id_).name; }
  const RobotState& state() const override { return w_.state(id_); }
  double time() const override { return w_.time(); }
  double interval() const override { return w_.interval(); }
  uint32_t count(SensorKind kind) const override { return range(kind).count; }
  const RangerDesc& ranger_desc(uint32_t k) const override {
    return w_.ranger_desc(index(SensorKind::Ranger, k));
  }
  RangerView ranger(uint32_t k) const override { return w_.ranger(index(SensorKind::Ranger, k)); }
  FiducialView fiducial(uint32_t k) const override { return w_.fiducial(index(SensorKind::Fiducial, k)); }
  BlobView blobfinder(uint32_t k) const override { return w_.blobfinder(index(SensorKind::Blobfinder, k)); }
  BumperView bumper(uint32_t k) const override { return w_.bumper(index(SensorKind::Bumper, k)); }
  void want(SensorKind kind, uint32_t k, bool wanted) override {
    w_.set_wanted({kind, index(kind, k)}, wanted);
  }
  // A controller computing NaN or infinity is broken: it is stopped as one
  // that throws is (update() catches this), and its robot stops.
  void command(const Command& cmd) override {
    if (w_.command(id_, cmd)) return;
    char what[128];
    std::snprintf(what, sizeof what, "non-finite command (%g, %g, %g) refused", cmd.value.x, cmd.value.y,
                  cmd.value.a);
    throw std::invalid_argument(what);
  }
  double uniform(uint64_t k) const override {
    return w_.random().uniform(Random::stream(uint64_t(RandomKind::Controller), id_, w_.steps()), k);
  }
  uint32_t gripper_count() const override { return w_.robot(id_).grippers.count; }
  GripperView gripper(uint32_t k) const override { return w_.gripper(gripper_index(k)); }
  void set_gripper(uint32_t k, bool closed) override { w_.set_gripper(gripper_index(k), closed); }
  std::span<std::byte> memory() override { return w_.controller_memory(id_); }

 private:
  IndexRange range(SensorKind kind) const {
    const RobotInfo& r = w_.robot(id_);
    switch (kind) {
      case SensorKind::Ranger:
        return r.rangers;
      case SensorKind::Fiducial:
        return r.fiducials;
      case SensorKind::Blobfinder:
        return r.blobfinders;
      case SensorKind::Bumper:
        return r.bumpers;
      case SensorKind::Camera:
        return r.cameras;
    }
    return {};
  }
  // Out-of-range k is the controller's bug: World's accessors throw on it.
  uint32_t index(SensorKind kind, uint32_t k) const {
    const IndexRange r = range(kind);
    return k < r.count ? r.first + k : UINT32_MAX;
  }

  uint32_t gripper_index(uint32_t k) const {
    const IndexRange r = w_.robot(id_).grippers;
    return k < r.count ? r.first + k : UINT32_MAX;
  }

  World& w_;
  RobotId id_;
};

}  // namespace

bool ControllerHost::load(World& world, const Options& options, world::Diagnostics& diags) {
  const size_t errors = diags.error_count();
  plugin::Loader loader(options.search_path);
  std::set<std::string> missing;
  for (RobotId id = 0; id < world.robot_count(); ++id) {
    const RobotDesc& desc = world.desc().robots[id];
    if (desc.ctrl.empty()) continue;
    std::istringstream words(desc.ctrl);
    std::string name;
    words >> name;
    std::string args;
    std::getline(words, args);
    args.erase(0, args.find_first_not_of(' '));
    if (!loader.has(name)) {
      if (!missing.insert(name).second) continue;  // said once per name
      std::string error;
      loader.make<Controller>(name, TROUPE_PLUGIN_CONTROLLER, kControllerInterfaceVersion, nullptr, error);
      const std::string msg = error + ", for robot '" + desc.name + "'";
      if (options.ignore_missing) {
        diags.warn(desc.ctrl_loc, msg + "; the robot stays idle");
      } else {
        diags.error(desc.ctrl_loc, msg + "; --ignore-missing-ctrl loads the world with such robots idle");
      }
      continue;
    }
    std::string error;
    auto c = loader.make<Controller>(name, TROUPE_PLUGIN_CONTROLLER, kControllerInterfaceVersion,
                                     args.c_str(), error);
    if (!c) {
      diags.error(desc.ctrl_loc, error);
      continue;
    }
    if (!attach(world, id, std::move(c), error)) {
      diags.error(desc.ctrl_loc, "controller '" + name + "' cannot run robot '" + desc.name + "': " + error);
    }
  }
  return diags.error_count() == errors;
}

bool ControllerHost::attach(World& world, RobotId robot, std::unique_ptr<Controller> controller,
                            std::string& error) {
  Controller* raw = controller.release();
  return attach(
      world, robot,
      plugin::Instance<Controller>(nullptr, raw, [](void* p) { delete static_cast<Controller*>(p); }), error);
}

bool ControllerHost::attach(World& world, RobotId robot, plugin::Instance<Controller> controller,
                            std::string& error) {
  // A robot that already has memory of this size keeps it: a fresh
  // instance takes over where the last one left off.
  const size_t bytes = controller->memory_size();
  if (world.controller_memory(robot).size() != bytes) world.set_controller_memory_size(robot, bytes);
  WorldRobot handle(world, robot);
  if (!controller->init(handle, error)) return false;
  entries_.push_back({robot, std::move(controller)});
  return true;
}
void ControllerHost::update(World& world) {
  if (phase_ == SIZE_MAX) {
    for (size_t i = 0; i < world.profile().phases().size(); ++i) {
      if (world.profile().phases()[i].name == "controllers") phase_ = i;
    }
    if (phase_ == SIZE_MAX) phase_ = world.profile().define("controllers");
  }
  PhaseTimer timer(world.profile(), phase_);
  // A divided world's leader journals its inputs for the other processes
  // (host-sim/mpi); a controller's are not among them: it runs where its
  // robot is owned, and its robot's command and sensors travel with the
  // robot when it migrates. Journaled, they went to every process each step
  // (150 KB a step from a leader of 5,000 wandering robots).
  struct Unjournaled {
    World& w;
    std::vector<std::byte>* saved;
    explicit Unjournaled(World& on) : w(on), saved(on.journal()) { w.set_journal(nullptr); }
    ~Unjournaled() { w.set_journal(saved); }
  } unjournaled(world);
  for (Entry& e : entries_) {
    // Another process steps a robot this one does not own (host-sim/mpi).
    if (!e.controller || world.residence(e.robot) != World::Residence::Owned) continue;
    WorldRobot handle(world, e.robot);
    try {
      e.controller->update(handle);
    } catch (const std::exception& ex) {
      // A broken controller stops its own robot, nothing else.
      errors_.push_back("controller of robot '" + world.robot(e.robot).name +
                        "' failed and was stopped: " + ex.what());
      e.controller.reset();
      world.command(e.robot, Command::velocity(0, 0, 0));
    }
  }
}

std::vector<std::string> ControllerHost::take_errors() {
  return std::exchange(errors_, {});
}

}  // namespace troupe::sim
