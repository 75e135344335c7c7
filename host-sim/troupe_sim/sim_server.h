// Serves a simulated world over the wire: one runtime Driver that provides
// every robot's devices (robot i, named by its world-file name:
// position2d:0, ranger:k, blobfinder:k, fiducial:k, bumper:k, camera:k,
// power:0, actuator:k: its grippers, then its kickers) and
// the simulation:0 and map:0 devices (map:0: the static obstacles as an
// occupancy grid, for viewers). Commands go to the robots; after every step the
// data of each device that someone reads is published, and a sensor is
// computed only while it is read (or a controller wants it).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "host-sim/sim/kicker.h"
#include "host-sim/sim/world.h"
#include "host-sim/sim_control/sim_control.h"
#include "host-sim/sim_control/sim_requests.h"
#include "runtime/driver.h"
#include "runtime/node.h"

namespace troupe::sim {

class SimServer final : public Driver, private SimulationModels {
 public:
  /// Which of the world's robots and devices this server serves.
  struct Scope {
    /// Serve just this robot, as robot 0 (--port-per-robot); -1: all.
    int only = -1;
    /// Robots before this one are not served, and this one is robot 0 on
    /// the wire (a RoboCup world's engine holds its ball first).
    RobotId first_robot = 0;
    /// Only the robots' sensors and grippers: another driver serves their
    /// position2d, and simulation:0 (RoboCup's game layer).
    bool sensors_only = false;
    /// The first index of an interface's devices on a robot (by its number
    /// on the wire), so these follow the ones another driver serves there;
    /// empty: 0.
    std::function<uint16_t(uint16_t robot, wire::Interface iface)> first_index;
  };

  /// `only`: serve just this robot, as robot 0 (--port-per-robot); -1: all.
  SimServer(World& world, SimControl& control, int only = -1);
  SimServer(World& world, SimControl& control, Scope scope);

  bool setup(Node& node, const DriverSetup& setup, std::string& error) override;
  void on_command(DeviceId device, const wire::Message& command) override;
  void on_request(DeviceId device, const wire::Message& request, RequestToken token) override;
  void on_read_start(DeviceId device) override;
  void on_packing_start(DeviceId device, wire::ImageCompression compression) override;

  /// Sets every sensor's wanted flag: read by a client, or asked for by a
  /// controller (the flags set before the server started). True when a
  /// sensor that was not computed is now wanted.
  bool sync_wanted();
  /// Publishes the latest data of every device someone reads.
  void publish();
  /// Publishes only the sensors sync_wanted() found newly wanted, once
  /// World::refresh_new_sensors() computed them: a paused world's older
  /// readers hold their sample already and get nothing again.
  void publish_woken();

  size_t device_count() const { return devices_.size(); }

 private:
  enum class Kind : uint8_t {
    Position,
    Ranger,
    Blobfinder,
    Fiducial,
    Bumper,
    Camera,
    Power,
    Gripper,
    Kicker,
    Simulation,
    Map
  };
  struct Device {
    DeviceId id = kNoDevice;
    Kind kind;
    RobotId robot = 0;
    uint32_t index = 0;     // world-wide sensor (or gripper, or kicker) index
    bool pinned = false;    // a controller wants it whether read or not
    bool motors_on = true;  // position2d only
    // camera only: what its images carry (SetConfig chooses).
    wire::PixelFormat format = wire::PixelFormat::Rgb8;
    float rate = 0;               // images per simulated second; 0: every step
    double last_image = -1;       // simulated time of the last image sent, s
    bool refused_logged = false;  // the too-large image was logged
  };

  void add(Node& node, Kind kind, RobotId robot, uint32_t index, wire::Interface iface, uint16_t local);
  const Device* find(DeviceId id) const;
  void publish_one(const Device& d);
  /// publish_one(), or publish_camera(), when someone reads it.
  void publish_if_read(Device& d);
  void publish_position(const Device& d);
  void publish_ranger(const Device& d);
  void publish_blobs(const Device& d);
  void publish_fiducials(const Device& d);
  void publish_bumper(const Device& d);
  /// The camera's current image, to the readers that asked for `only`
  /// (whatever the rate), or to every reader, packed as each asked.
  void publish_camera(Device& d, std::optional<wire::ImageCompression> only = std::nullopt);
  void publish_power(const Device& d);
  void publish_gripper(const Device& d);
  void publish_clock(const Device& d);
  void publish_poses(const Device& d);
  // simulation:0 (sim_requests.h): robots move, static models only tell
  // where they are.
  SimTime now() const override { return {world_.time(), world_.steps()}; }
  bool get_pose(const std::string& name, Pose& pose, bool& has_velocity, Pose& velocity,
                std::string& error) override;
  bool set_pose(const std::string& name, const Pose& pose, const Pose* velocity, std::string& error) override;
  flatbuffers::Offset<wire::SimModelList> models(flatbuffers::FlatBufferBuilder& b) override;
  void position_request(Device& d, const wire::Message& request, RequestToken token);
  void ranger_request(const Device& d, const wire::Message& request, RequestToken token);
  void map_request(const Device& d, const wire::Message& request, RequestToken token);
  void camera_request(Device& d, const wire::Message& request, RequestToken token);
  /// Logs a command, teleport or odometry reset the world refused.
  void log_refused(const char* what, RobotId robot, const Pose& value);

  World& world_;
  /// The robots' kickers (a Stage robot's `kicker` model), fired by their
  /// actuator's Kick command.
  Kickers kickers_;
  SimControl& control_;
  Scope scope_;
  std::vector<Device> devices_;
  DeviceId first_ = kNoDevice;
  // Indices into devices_ of the sensors sync_wanted() found newly wanted
  // since the last publish.
  std::vector<uint32_t> woken_;
  std::vector<uint16_t> scratch_ranges_;
  std::vector<wire::Pose2d> scratch_poses_;
  std::vector<uint8_t> scratch_cells_;
  std::vector<uint8_t> scratch_pixels_;
  std::vector<uint8_t> scratch_png_;  // the step's image as PNG, shared by every reader that asked
  uint64_t refused_ = 0;              // inputs the world refused, for log_refused()
};

}  // namespace troupe::sim
