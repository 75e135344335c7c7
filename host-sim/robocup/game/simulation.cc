#include "host-sim/robocup/game/simulation.h"

#include "host-sim/robocup/game/world_desc.h"
#include "runtime/log.h"

namespace troupe::robocup {
namespace {

uint64_t fnv1a(std::string_view s) {
  uint64_t h = 1469598103934665603ull;
  for (char c : s) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

// SplitMix64: spreads nearby seeds over the whole state space.
uint64_t mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace

Simulation::Simulation(WorldSpec spec, PluginLoader loader, std::unique_ptr<sim::World> engine)
    : spec_(std::move(spec)),
      loader_(std::move(loader)),
      engine_(std::move(engine)),
      world_(*engine_->rigid()),
      geometry_(field_geometry(spec_.field)),
      referee_(spec_.field, spec_.referee) {}

Simulation::~Simulation() {
  // Plugin instances go before the loader's libraries (members die in
  // reverse order, but be explicit: instances hold their libraries).
  robots_.clear();
}

std::unique_ptr<Simulation> Simulation::create(WorldSpec spec, PluginLoader loader, std::string& error) {
  loader.prepend_path(spec.plugin_path);
  auto engine = std::make_unique<sim::World>(world_desc(spec), sim::Random(spec.seed));
  std::unique_ptr<Simulation> sim(new Simulation(std::move(spec), std::move(loader), std::move(engine)));
  if (!sim->build(error)) return nullptr;
  return sim;
}

void Simulation::problem(std::string text) {
  log_error("%s", text.c_str());
  problems_.push_back(std::move(text));
}

Rng Simulation::rng_for(std::string_view robot, std::string_view instance) const {
  return Rng(mix(spec_.seed ^ mix(fnv1a(robot) ^ mix(fnv1a(instance)))));
}

bool Simulation::build(std::string& error) {
  // world_desc() made the field's statics, the ball (robot 0) and the
  // robots, in that order: the engine made their rigid bodies.
  for (size_t k = 0; k < engine_->desc().statics.size(); ++k)
    field_bodies_.push_back(engine_->rigid_static_body(k));
  ball_ = engine_->rigid_body(0);
  if (!world_.valid(ball_)) {
    error = spec_.file + ": ball: its rigid body cannot be made (radius, mass)";
    return false;
  }
  for (size_t k = 0; k < spec_.robots.size(); ++k) {
    const RobotEntry& e = spec_.robots[k];
    Robot r;
    r.name = e.name;
    r.team = e.team;
    r.start = e.start;
    r.spec = e.spec;
    r.body = engine_->rigid_body(sim::RobotId(k + 1));
    if (!world_.valid(r.body)) {
      error = e.where + ": robot " + e.name + ": its rigid body cannot be made (shapes, mass, inertia)";
      return false;
    }
    for (const Shape& s : world_.shapes(r.body)) r.radius = std::max(r.radius, reach_from(s, {0, 0}));
    robots_.push_back(std::move(r));
  }
  for (size_t i = 0; i < robots_.size(); ++i) add_robot(spec_.robots[i]);
  return true;
}

// Plugins of one robot. A plugin that fails is left out and reported.
void Simulation::add_robot(const RobotEntry& e) {
  Robot& r = robots_[size_t(find_robot(e.name))];
  std::string error;
  if (e.spec.has_motion) {
    const PluginSpec& m = e.spec.motion;
    r.motion = loader_.motion(m.plugin, error);
    Options options = m.options;
    if (!r.motion) {
      problem(m.where + ": robot " + e.name + ": " + error);
    } else if (!r.motion->configure(options, error)) {
      problem(m.where + ": robot " + e.name + ": motion plugin '" + m.plugin + "': " + error);
      r.motion.reset();
    }
  }
  for (const PluginSpec& s : e.spec.sensors) {
    Sensor sensor;
    sensor.spec = s;
    sensor.plugin = loader_.sensor(s.plugin, error);
    Options options = s.options;
    if (!sensor.plugin) {
      problem(s.where + ": robot " + e.name + ": " + error);
      continue;
    }
    if (!sensor.plugin->configure(options, error)) {
      problem(s.where + ": robot " + e.name + ": sensor plugin '" + s.plugin + "': " + error);
      continue;
    }
    sensor.rng = rng_for(e.name, "sensor/" + s.name);
    SensorReading reading;
    reading.name = s.name;
    reading.model = s.plugin;
    r.sensors.push_back(std::move(sensor));
    r.readings.push_back(std::move(reading));
  }
  if (e.has_player && !start_player(e.name, e.player, error)) problem(error);
}

bool Simulation::start_player(std::string_view name, const PluginSpec& p, std::string& error) {
  const int index = find_robot(name);
  if (index < 0) {
    error = p.where + ": no robot named '" + std::string(name) + "'";
    return false;
  }
  Robot& r = robots_[size_t(index)];
  const std::string where = (p.where.empty() ? "" : p.where + ": ") + "robot " + r.name + ": ";
  PluginInstance<PlayerPlugin> player = loader_.player(p.plugin, error);
  if (!player) {
    error = where + error;
    return false;
  }
  Options options = p.options;
  if (!player->configure(options, error)) {
    error = where + "player plugin '" + p.plugin + "': " + error;
    return false;
  }
  // Only a player that configured replaces the one running.
  stop_player(name);
  r.player = std::move(player);
  r.player_name = p.plugin;
  r.player_rng = rng_for(r.name, "player/" + p.plugin + "/" + std::to_string(r.player_starts++));
  r.command = {};
  r.player->start(*this, {r.name, index, r.team, &r.player_rng});
  return true;
}

bool Simulation::start_player(std::string_view robot, std::string_view plugin, const Options& options,
                              std::string& error) {
  PluginSpec p;
  p.plugin = std::string(plugin);
  p.name = p.plugin;
  p.options = options;
  p.where = options.where();
  return start_player(robot, p, error);
}

void Simulation::stop_player(std::string_view name) {
  const int index = find_robot(name);
  if (index < 0) return;
  Robot& r = robots_[size_t(index)];
  r.player.reset();
  r.player_name.clear();
  r.command = {};
}

std::string Simulation::player_of(int robot) const {
  return robot >= 0 && robot < robot_count() ? robots_[size_t(robot)].player_name : "";
}

void Simulation::command(int robot, const MotionCommand& c) {
  if (robot >= 0 && robot < robot_count() && !robots_[size_t(robot)].player)
    robots_[size_t(robot)].command = c;
}

void Simulation::kick(int robot) {
  if (robot >= 0 && robot < robot_count()) robots_[size_t(robot)].kick_requested = true;
}

std::span<const SensorReading> Simulation::readings(int robot) const {
  if (robot < 0 || robot >= robot_count()) return {};
  return robots_[size_t(robot)].readings;
}

std::string Simulation::kicker_state(int robot) const {
  if (robot < 0 || robot >= robot_count()) return "";
  const Robot& r = robots_[size_t(robot)];
  return r.spec.has_kicker ? r.spec.kicker.states[size_t(r.kicker_state)].name : "";
}

BodyId Simulation::robot_body(int robot) const {
  return robot >= 0 && robot < robot_count() ? robots_[size_t(robot)].body : kNoBody;
}

void Simulation::set_kicker_state(Robot& r, int state) {
  r.kicker_state = state;
  r.kicker_since_s = time_s();
  std::string error;
  world_.set_shapes(r.body, robot_shapes(r.spec, state), error);  // validated when the robot file was read
}

void Simulation::step() {
  // Each phase's time ends where the next one starts.
  sim::PhaseLaps laps(profile_);
  run_players();
  laps.lap(ph_players_);
  run_motion();
  laps.lap(ph_motion_);
  run_kickers();
  laps.lap(ph_kickers_);
  engine_->step();
  laps.lap(ph_physics_);
  run_referee();
  laps.lap(ph_referee_);
  run_sensors();
  laps.lap(ph_sensors_);
  inbox_.swap(outbox_);
  outbox_.clear();
  profile_.count_step();
}

std::string Simulation::profile_table() const {
  // The physics phase is the engine's step; its integrate phase holds the
  // rigid-body step.
  return profile_.table() + "physics, by phase:\n" + engine_->profile().table() +
         "rigid bodies (in integrate), by phase:\n" + world_.profile().table();
}

void Simulation::run_for(double seconds) {
  const long n = std::lround(seconds / cycle_s());
  for (long i = 0; i < n; ++i) step();
}

void Simulation::reset() {
  for (Robot& r : robots_) {
    world_.set_pose(r.body, r.start);
    world_.set_velocity(r.body, {});
    r.command = {};
    r.kick_requested = false;
    if (r.spec.has_kicker && r.kicker_state != 0) set_kicker_state(r, 0);
  }
  world_.set_pose(ball_, {spec_.ball.start.x, spec_.ball.start.y, 0});
  world_.set_velocity(ball_, {});
  engine_->rigid_moved();
}

}  // namespace troupe::robocup
