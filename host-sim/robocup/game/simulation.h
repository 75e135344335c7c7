// The RoboCup simulation: the game layer (players, motion plugins, kickers,
// referee, sensor plugins) over the one engine's world (sim::World in rigid
// mode, built by world_desc()), which owns the field, the ball and the
// robots as rigid bodies, run in fixed cycles. This is the
// integration point for troupe-sim: one Simulation per RoboCup world, its
// robots' readings and commands mapped onto devices, its score and game
// state onto the simulation interface (README.md, "Serving it").
//
// A cycle is a fixed pipeline of named phases, each timed into profile()
// (the simulator's one Profile, as the Stage engine's step is):
//   players  each running player senses (last readings, broadcast inbox)
//            and acts (command, kick, messages)
//   motion   each robot's motion plugin turns its command into velocity
//   kickers  kicker states advance; a kick pushes a touching ball
//   physics  the engine's step: the rigid-body step (impacts, restitution,
//            friction), then the engine's own wanted sensors
//   referee  goals, ball out, resets
//   sensors  each sensor plugin measures the new state
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "host-sim/robocup/api/plugin.h"
#include "host-sim/robocup/game/plugin_loader.h"
#include "host-sim/robocup/game/world_spec.h"
#include "host-sim/sim/profile.h"
#include "host-sim/sim/world.h"

namespace troupe::robocup {

class Simulation final : public WorldControl {
 public:
  /// Builds the world. Plugin problems (missing, bad symbol, bad option)
  /// do not fail it: each goes to problems() and the log, and the robot
  /// runs without that plugin. Returns null with `error` only when the
  /// world itself cannot be built.
  static std::unique_ptr<Simulation> create(WorldSpec spec, PluginLoader loader, std::string& error);
  ~Simulation() override;

  // ---- Running ---------------------------------------------------------------

  /// Runs one cycle.
  void step();
  /// Runs whole cycles for `seconds` of simulated time.
  void run_for(double seconds);
  /// Robots and ball back to their kick-off places, stopped; the score stays.
  void reset();

  // ---- The game --------------------------------------------------------------

  const Score& score() const { return referee_.score(); }
  GamePhase phase() const { return referee_.phase(); }
  /// Referee events of the last cycle, and of the whole run.
  const std::vector<RefereeEvent>& events() const { return referee_.last_events(); }
  const std::vector<RefereeEvent>& history() const { return referee_.history(); }
  Referee& referee() { return referee_; }

  // ---- Robots and their plugins ----------------------------------------------

  /// Starts `player` on `robot`, replacing the one running there. False
  /// with an error naming the plugin; the running player then goes on.
  bool start_player(std::string_view robot, const PluginSpec& player, std::string& error);
  /// The same from a plugin name and "key=value" options.
  bool start_player(std::string_view robot, std::string_view plugin, const Options& options,
                    std::string& error);
  void stop_player(std::string_view robot);
  /// The running player's plugin name, or "" when none runs.
  std::string player_of(int robot) const;
  /// A command from outside (a client): used while no player runs.
  void command(int robot, const MotionCommand& command);
  /// Fires the robot's kicker from outside.
  void kick(int robot);
  /// The robot's sensor readings of the last cycle.
  std::span<const SensorReading> readings(int robot) const;
  /// The kicker's current state name ("" without a kicker).
  std::string kicker_state(int robot) const;
  /// Plugin problems so far, each "file:line: robot NAME: ...".
  const std::vector<std::string>& problems() const { return problems_; }
  /// Messages on the broadcast channel in the last cycle.
  const std::vector<Message>& broadcasts() const { return inbox_; }

  // ---- Under the hood --------------------------------------------------------

  /// The engine's rigid-body world (sim::World::rigid()).
  World& physics() { return world_; }
  /// The engine's world: robot 0 is the ball, robot i + 1 is robot i.
  sim::World& engine() { return *engine_; }
  BodyId ball_body() const { return ball_; }
  BodyId robot_body(int robot) const;
  const WorldSpec& spec() const { return spec_; }
  /// Wall-clock time of each phase of the cycle, over every cycle so far
  /// and the latest one; engine().profile() splits the physics phase.
  const sim::Profile& profile() const { return profile_; }
  sim::Profile& profile() { return profile_; }
  /// What `--profile` prints: the cycle's table, then the engine's step's
  /// (the physics phase), then the rigid-body step's (inside the engine's
  /// integrate phase), each in Profile::table() format.
  std::string profile_table() const;

  // ---- WorldView / WorldControl ----------------------------------------------

  double time_s() const override { return world_.time_s(); }
  double cycle_s() const override { return world_.settings().cycle_s; }
  const FieldGeometry& field() const override { return geometry_; }
  BallInfo ball() const override;
  int robot_count() const override { return int(robots_.size()); }
  RobotInfo robot(int index) const override;
  int find_robot(std::string_view name) const override;
  GameInfo game() const override { return {referee_.score(), referee_.phase(), time_s()}; }
  bool raycast(Vec2 origin, double angle_rad, double max_range, double z, int ignore_robot,
               RayResult& out) const override;
  bool line_of_sight(Vec2 from, Vec2 to, double z, int ignore_robot, int target_robot,
                     double clearance) const override;
  void place_ball(Vec2 position, Vec2 velocity) override;
  void place_robot(int index, Pose2 pose) override;

 private:
  struct Sensor {
    PluginSpec spec;
    PluginInstance<SensorPlugin> plugin;
    Rng rng;
  };
  struct Robot {
    std::string name;
    Team team = Team::Blue;
    Pose2 start;
    RobotSpec spec;
    BodyId body;
    double radius = 0;
    PluginInstance<MotionPlugin> motion;
    std::vector<Sensor> sensors;
    std::vector<SensorReading> readings;  // one per sensor, same order
    PluginInstance<PlayerPlugin> player;
    std::string player_name;
    Rng player_rng;
    /// Players started on this robot so far: each start draws its own
    /// random numbers (a restarted random keeper does not repeat itself).
    int player_starts = 0;
    MotionCommand command;
    bool kick_requested = false;
    int kicker_state = 0;
    double kicker_since_s = 0;
  };

  Simulation(WorldSpec spec, PluginLoader loader, std::unique_ptr<sim::World> engine);
  bool build(std::string& error);
  void add_robot(const RobotEntry& entry);
  void problem(std::string text);
  Rng rng_for(std::string_view robot, std::string_view instance) const;
  void set_kicker_state(Robot& r, int state);

  // simulation_phases.cc
  void run_players();
  void run_motion();
  void run_kickers();
  void run_referee();
  void run_sensors();
  Vec2 free_spot(Vec2 wanted);

  WorldSpec spec_;
  PluginLoader loader_;
  std::unique_ptr<sim::World> engine_;
  World& world_;  // *engine_->rigid()
  FieldGeometry geometry_;
  Referee referee_;
  std::vector<BodyId> field_bodies_;
  BodyId ball_;
  std::vector<Robot> robots_;
  std::vector<Message> inbox_, outbox_;
  std::vector<std::string> problems_;
  // The phases, in pipeline order; defined here, after profile_, so that
  // every constructor gets them.
  sim::Profile profile_;
  size_t ph_players_ = profile_.define("players");
  size_t ph_motion_ = profile_.define("motion");
  size_t ph_kickers_ = profile_.define("kickers");
  size_t ph_physics_ = profile_.define("physics");
  size_t ph_referee_ = profile_.define("referee");
  size_t ph_sensors_ = profile_.define("sensors");
};

}  // namespace troupe::robocup
