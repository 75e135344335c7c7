// The loader's insides, shared by loader.cc (world, statics, geometry) and
// load_robot.cc (robots and their sensors). Private to host-sim/sim.
#pragma once

#include <memory>
#include <string>

#include "host-sim/sim/desc.h"
#include "host-sim/sim/loader.h"
#include "host-sim/sim/reader.h"
#include "host-sim/world/worldfile.h"

namespace troupe::sim {

enum class ModelKind {
  Model,
  Position,
  Ranger,
  Laser,
  Sensor,
  Blobfinder,
  Fiducial,
  Bumper,
  Camera,
  Gripper,
  Kicker,
  Ball,
  Block,
  Window,
  NotSimulated,
  Unknown,
};

/// The type table: world-file keyword -> what it loads as.
ModelKind model_kind(const std::string& type);

/// What every model has, read once.
struct ModelCommon {
  std::string name;
  Pose pose;    // relative to the parent (world for top-level models)
  Pose origin;  // body offset from pose
  Vec2 size{0.1, 0.1};
  Appearance look;
};

class Loader {
 public:
  Loader(const world::WorldFile& file, world::Diagnostics& diags, ModelHandoff* handoff = nullptr)
      : file_(file), read_(diags), handoff_(handoff) {}
  bool run(WorldDesc& out);
  /// load_robot_sensors().
  bool robot_sensors(const world::Entity& model, RobotDesc& out);
  /// load_ball(): a ball's keys.
  bool ball_keys(const world::Entity& e, BallDesc& b);

 private:
  world::Diagnostics& diags() { return read_.diags(); }

  // loader.cc
  void world_properties(const world::Entity& w, WorldDesc& out);
  void window(const world::Entity& e, WindowDesc& out);
  ModelCommon common(const world::Entity& e, ModelKind kind);
  /// The model's blocks (or its default box), scaled to its size and
  /// offset by its origin: polygons in the model's frame.
  Polygons body(const world::Entity& e, const ModelCommon& c, bool default_block);
  std::shared_ptr<BitmapDesc> bitmap(const world::Entity& e);
  void static_model(const world::Entity& e, const Pose& parent, WorldDesc& out);
  /// A top-level model with `gripper_return 1`: a movable object.
  void puck(const world::Entity& e, WorldDesc& out);
  void check_grid_size(const world::Entity& w, const WorldDesc& out);
  /// A top-level `ball`: a puck with a round rigid body (rigid worlds).
  void ball(const world::Entity& e, WorldDesc& out);

  // load_robot.cc
  void robot(const world::Entity& e, WorldDesc& out);
  void robot_part(const world::Entity& e, const Pose& parent, RobotDesc& r);
  void ranger(const world::Entity& e, const ModelCommon& c, const Pose& at, ModelKind kind, RobotDesc& r);
  TransducerDesc transducer(const world::Entity& e, const Pose& ranger_at);
  void blobfinder(const world::Entity& e, const Pose& at, RobotDesc& r);
  void fiducial(const world::Entity& e, const ModelCommon& c, const Pose& at, RobotDesc& r);
  void bumper(const world::Entity& e, const Pose& at, RobotDesc& r);
  void camera(const world::Entity& e, const ModelCommon& c, const Pose& at, RobotDesc& r);
  void gripper(const world::Entity& e, const ModelCommon& c, const Pose& at, RobotDesc& r);
  void kicker(const world::Entity& e, const ModelCommon& c, const Pose& at, RobotDesc& r);
  /// False after an error at `e`: `what` needs physics "rigid".
  bool needs_rigid(const world::Entity& e, const char* what);
  /// A camera's `mirror` keys; false after reporting a bad one.
  bool omni_mirror(const world::Entity& e, CameraDesc& d);
  void power(const world::Entity& e, RobotDesc& r);

  const world::WorldFile& file_;
  Reader read_;
  // Robots (not pucks) in the description so far: an unnamed robot is
  // named r<this>. Counted as they come, since counting them again for
  // each robot took most of a 100,000-robot world's load.
  size_t robots_ = 0;
  // The last robot's rangers, for the next robot of the same make-up to
  // share (a world of one robot type holds one list).
  SharedList<RangerDesc> last_rangers_;
  ModelHandoff* handoff_;
  int pucks_ = 0;                         // unnamed pucks so far, for their default names
  int balls_ = 0;                         // unnamed balls so far, likewise
  Physics physics_ = Physics::Kinematic;  // the world's, read before its models
};

}  // namespace troupe::sim
