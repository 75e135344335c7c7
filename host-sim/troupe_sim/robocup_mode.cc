#include "host-sim/troupe_sim/robocup_mode.h"

#include <cstdio>
#include <filesystem>

#include "host-sim/robocup/game/world_spec.h"
#include "runtime/log.h"

namespace troupe::sim {

bool is_robocup_world(const std::string& path) {
  world::WorldFile file;
  world::Diagnostics diags;
  if (!file.load(path, diags)) return false;
  for (const world::Entity& e : file.root().children) {
    if (e.type == "robocup_field" || e.type == "robocup_robot") return true;
  }
  return false;
}

bool RobocupMode::init(const SimOptions& options, std::string& error) {
  // What belongs to the Stage engine alone.
  const char* refused = !options.emulate.empty()      ? "--emulate"
                        : options.port_per_robot      ? "--port-per-robot"
                        : !options.snapshot.empty()   ? "--snapshot"
                        : !options.log.empty()        ? "--log"
                        : options.ignore_missing_ctrl ? "--ignore-missing-ctrl"
                        : options.no_ctrl             ? "--no-ctrl"
                                                      : nullptr;
  if (refused) {
    error = std::string(refused) + " is for Stage worlds; " + options.world + " is a RoboCup world";
    return false;
  }
  profile_ = options.profile;
  robocup::WorldSpec spec;
  if (!robocup::load_world_file(options.world, spec, error)) return false;
  if (options.seed != 0) spec.seed = options.seed;
  const std::string folder = std::filesystem::path(options.world).parent_path().string();
  robocup::PluginLoader loader(plugin::search_path(options.plugin_path, folder));
  sim_ = robocup::Simulation::create(std::move(spec), std::move(loader), error);
  if (!sim_) return false;
  // A plugin that is missing or refuses its options was reported with its
  // file and line; the match goes on without it.
  robocup::ServeOptions so;
  so.listen = options.listen;
  so.port = options.port;
  so.speed = options.fast ? 0 : options.speed >= 0 ? options.speed : 1;
  so.paused = options.paused;
  so.seconds = options.quit_time > 0 ? options.quit_time : 0;
  so.serve = options.serve;
  so.secure = options.secure;
  loop_ = std::make_unique<robocup::ServeLoop>(*sim_);
  return loop_->start(so, error);
}

int RobocupMode::run() {
  loop_->run();
  const robocup::Score s = sim_->score();
  log_info("%.2f s simulated; score blue %d : %d yellow", sim_->time_s(), s.blue, s.yellow);
  // Where a Stage world prints its step's table (runner.cc), in its format.
  if (profile_) std::fprintf(stderr, "%s", sim_->profile_table().c_str());
  return 0;
}

}  // namespace troupe::sim
