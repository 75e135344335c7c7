// Serves a RoboCup Simulation over the wire: one runtime Driver providing
// every robot's devices (robot number = the robot's index in the world
// file, named by its world-file name) and simulation:0.
//
//   position2d:0   the first odometry sensor's pose and velocity; velocity
//                  commands (obeyed while no player plugin runs)
//   actuator:0     the kicker: Kick commands, its state (robots with one)
//   fiducial:k     the k-th iconic sensor (camera, omnivision, laser in
//                  iconic mode): detections with their kind and id
//                  (api/fiducial_key.h)
//   ranger:k       the k-th range sensor (laser raw, ultrasonic)
//   simulation:0   clock, score and game state, pause/step/speed/reset,
//                  ground-truth poses of robots and the ball, players
//
// Each sensor's device names its instance in the device list's driver
// column ("robocup/omni"), which is how clients find sensors by model.
// Data carries the simulated time of its measurement.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host-sim/robocup/game/simulation.h"
#include "host-sim/sim_control/sim_control.h"
#include "host-sim/sim_control/sim_requests.h"
#include "runtime/driver.h"
#include "runtime/node.h"

namespace troupe::robocup {

/// What the simulation device changes in the running loop (owned by the
/// runner; the server only edits it).
class RobocupServer final : public Driver, private sim::SimulationModels {
 public:
  RobocupServer(Simulation& sim, sim::SimControl& control);

  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_command(DeviceId device, const wire::Message& command) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;

  /// Publishes what changed since the last call to the devices someone
  /// reads: a sensor's data once per measurement, the clock every call.
  void publish();

  size_t device_count() const { return devices_.size(); }
  /// How many devices of `iface` robot `robot` has here (another driver's
  /// devices of that interface on the robot come after them).
  uint16_t device_count(int robot, wire::Interface iface) const;

 private:
  enum class Kind : uint8_t { Position, Kicker, Fiducial, Ranger, Simulation };
  struct Device {
    DeviceId id = kNoDevice;
    Kind kind = Kind::Position;
    int robot = 0;
    /// Index into the robot's readings (-1: none, e.g. no odometry).
    int reading = -1;
    /// Simulated time of the last reading published, s (-1: none yet).
    double published_s = -1;
    /// Actuator: the kicker state last published (-1: none yet).
    int kicker_state = -1;
    bool motors_on = true;
  };

  void add(Node& node, Kind kind, int robot, int reading, wire::Interface iface, uint16_t index,
           const std::string& model);
  Device* find(DeviceId id);
  const PluginSpec* sensor_spec(const Device& d) const;

  // robocup_publish.cc
  void publish_position(Device& d);
  void publish_kicker(Device& d);
  void publish_fiducials(Device& d);
  void publish_ranges(Device& d);
  void publish_clock(const Device& d);
  void publish_game(const Device& d);
  void publish_poses(const Device& d);
  flatbuffers::Offset<wire::SimGame> build_game(flatbuffers::FlatBufferBuilder& b);

  // robocup_requests.cc
  void sensor_request(Device& d, const wire::Message& request, RequestToken token);

  // robocup_models.cc: simulation:0 (host-sim/sim_control/sim_requests.h).
  // Models are the robots, then the ball; Poses come in that order.
  sim::SimTime now() const override;
  bool get_pose(const std::string& name, Pose2& pose, bool& has_velocity, Pose2& velocity,
                std::string& error) override;
  bool set_pose(const std::string& name, const Pose2& pose, const Pose2* velocity, std::string& error) override;
  flatbuffers::Offset<wire::SimModelList> models(flatbuffers::FlatBufferBuilder& b) override;
  bool start_player(const std::string& robot, const std::string& plugin,
                    const std::vector<std::pair<std::string, std::string>>& options, std::string& error) override;
  bool stop_player(const std::string& robot, std::string& error) override;
  bool game(flatbuffers::FlatBufferBuilder& b, flatbuffers::Offset<wire::SimGame>& out) override;

  Simulation& sim_;
  sim::SimControl& control_;
  std::vector<Device> devices_;
  DeviceId first_ = kNoDevice;
  /// The game as last published: score, phase, event count.
  Score game_score_;
  GamePhase game_phase_ = GamePhase::Play;
  size_t game_events_ = SIZE_MAX;
  std::vector<uint16_t> scratch_ranges_;
  std::vector<wire::Fiducial> scratch_fiducials_;
  std::vector<wire::FiducialKind> scratch_kinds_;
  std::vector<wire::Pose2d> scratch_poses_;
};

/// How a sensor's readings go on the wire: odometry on position2d,
/// detections on fiducial, ranges on ranger. Decided from the plugin and
/// its options, before the sensor first measures.
ReadingKind served_kind(const PluginSpec& sensor);

}  // namespace troupe::robocup
