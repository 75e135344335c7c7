// The one handler of simulation:0's requests, for every simulator: the
// clock (sim_control.h), ground-truth poses, reset, the model list for
// viewers, and, where the simulator has them, player plugins and a game.
// A simulator describes what it can do by implementing SimulationModels;
// the handler checks every request (names, finite numbers, options) before
// it calls in, and answers with an Ack or a Nack saying why.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "host-sim/sim_control/sim_control.h"
#include "wire/geometry.h"

namespace troupe::sim {

class SimulationModels {
 public:
  virtual ~SimulationModels() = default;

  /// The simulation's clock.
  virtual SimTime now() const = 0;
  /// The world pose of model `name` (m, m, rad) and its velocity (m/s,
  /// m/s, rad/s; world frame) where known. False with `error` for a name
  /// the simulator does not know.
  virtual bool get_pose(const std::string& name, geometry::Pose2& pose, bool& has_velocity,
                        geometry::Pose2& velocity, std::string& error) = 0;
  /// Teleports model `name` (finite numbers, checked); `velocity` (null:
  /// none given) is for models that keep one (a ball). False with `error`.
  virtual bool set_pose(const std::string& name, const geometry::Pose2& pose, const geometry::Pose2* velocity,
                        std::string& error) = 0;
  /// The Models answer: every model a viewer draws, in the order of Poses.
  virtual flatbuffers::Offset<wire::SimModelList> models(flatbuffers::FlatBufferBuilder& b) = 0;

  /// Player plugins and a game (RoboCup worlds); the defaults say there are none.
  virtual bool start_player(const std::string& robot, const std::string& plugin,
                            const std::vector<std::pair<std::string, std::string>>& options, std::string& error);
  virtual bool stop_player(const std::string& robot, std::string& error);
  /// False: no game here.
  virtual bool game(flatbuffers::FlatBufferBuilder& b, flatbuffers::Offset<wire::SimGame>& out);
};

/// Answers any simulation request `req` (Reset runs control.reset, then
/// acks the clock).
void answer_simulation_request(Node& node, SimControl& control, const wire::Message& req, RequestToken token,
                               SimulationModels& models);

}  // namespace troupe::sim
