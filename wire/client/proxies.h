// One proxy per interface. Each holds the latest data of its device in SI
// units and turns commands and requests into method calls. Construct one
// per device; it opens the device at once (Player's habit).
//
//   troupe::client::Client client("localhost");
//   client.connect();
//   troupe::client::Position2dProxy base(client);       // position2d:0
//   base.set_velocity(0.3, 0, 0.2);                     // m/s, m/s, rad/s
//   while (client.spin_once(100)) printf("x=%.2f\n", base.x());
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "wire/client/proxy.h"
#include "wire/geometry.h"

namespace troupe::client {

/// A pose or velocity in the plane: m, m, rad (or per second).
using Pose2 = geometry::Pose2;

class Position2dProxy final : public Proxy {
 public:
  explicit Position2dProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  Position2dProxy(Client& client, const wire::Address& addr);

  /// Odometric pose (or map pose for a localizer): m, m, rad.
  const Pose2& pose() const { return pose_; }
  float x() const { return pose_.x; }
  float y() const { return pose_.y; }
  float a() const { return pose_.a; }
  /// Velocity in the robot frame: m/s, m/s, rad/s.
  const Pose2& velocity() const { return vel_; }
  bool stall() const { return stall_; }
  /// Pose covariance (xx, xy, xa, yy, ya, aa: m^2, m*rad, rad^2) when sent.
  const std::optional<std::array<float, 6>>& covariance() const { return cov_; }

  /// Commands the velocity: m/s forward, m/s left, rad/s.
  bool set_velocity(float vx, float vy, float va);
  /// Commands driving to a pose in the odometry frame: m, m, rad.
  bool go_to(float x, float y, float a);
  bool set_motor_power(bool on);
  bool set_odometry(float x, float y, float a);
  bool reset_odometry();
  /// The base's size (m) and body offset (m, rad) from the geometry request.
  bool geometry(wire::Vec3& size, wire::Pose3d& offset);

 private:
  void update(const wire::Message& msg) override;
  Pose2 pose_, vel_;
  bool stall_ = false;
  std::optional<std::array<float, 6>> cov_;
};

class RangerProxy final : public Proxy {
 public:
  explicit RangerProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  RangerProxy(Client& client, const wire::Address& addr);

  /// Ranges of the latest scan, m. A value >= max_range() means no return.
  const std::vector<float>& ranges() const { return ranges_; }
  size_t count() const { return ranges_.size(); }
  float range(size_t i) const { return ranges_.at(i); }
  /// Scanning sensors: bearing of beam i in the sensor frame, rad.
  float bearing(size_t i) const { return min_angle_ + float(i) * angular_res_; }
  float min_angle() const { return min_angle_; }      // rad
  float angular_res() const { return angular_res_; }  // rad
  float max_range() const { return max_range_; }      // m
  const std::vector<uint8_t>& intensities() const { return intensities_; }

  /// Sensor pose on the robot and each transducer's pose (m, rad).
  bool geometry(wire::Pose3d& pose, std::vector<wire::Pose3d>& elements);
  bool set_power(bool on);

 private:
  void update(const wire::Message& msg) override;
  std::vector<float> ranges_;
  std::vector<uint8_t> intensities_;
  float min_angle_ = 0, angular_res_ = 0, max_range_ = 0;
};

class PowerProxy final : public Proxy {
 public:
  explicit PowerProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  /// Each is empty when the device does not measure it.
  std::optional<float> volts() const { return volts_; }      // V
  std::optional<float> percent() const { return percent_; }  // %
  std::optional<float> watts() const { return watts_; }      // W
  std::optional<bool> charging() const { return charging_; }

 private:
  void update(const wire::Message& msg) override;
  std::optional<float> volts_, percent_, watts_;
  std::optional<bool> charging_;
};

class BumperProxy final : public Proxy {
 public:
  explicit BumperProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  unsigned count() const { return count_; }
  bool pressed(unsigned i) const { return i < 32 && (bits_ >> i) & 1u; }
  bool any() const { return bits_ != 0; }

 private:
  void update(const wire::Message& msg) override;
  uint32_t bits_ = 0;
  unsigned count_ = 0;
};

class BlobfinderProxy final : public Proxy {
 public:
  explicit BlobfinderProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  /// Blobs of the latest image, in image pixels (see wire/schemas/blobfinder.fbs).
  const std::vector<wire::Blob>& blobs() const { return blobs_; }
  unsigned width() const { return width_; }    // px
  unsigned height() const { return height_; }  // px

 private:
  void update(const wire::Message& msg) override;
  std::vector<wire::Blob> blobs_;
  unsigned width_ = 0, height_ = 0;
};

/// The latest image of a camera device, as it came: pixels row by row
/// (see wire/schemas/camera.fbs for the formats).
struct Image {
  unsigned width = 0, height = 0;  // px
  wire::PixelFormat format = wire::PixelFormat::Rgb8;
  unsigned stride = 0;  // bytes from one row to the next
  wire::ImageCompression compression = wire::ImageCompression::None;
  std::vector<uint8_t> data;
  uint64_t stamp_us = 0;  // when it was taken, sender's clock, us
};

/// What a camera's geometry request tells: pose on the robot (m, rad),
/// fields of view (rad), intrinsics (px) and range (m).
struct CameraModel {
  wire::Pose3d pose;
  float hfov = 0, vfov = 0;
  float fx = 0, fy = 0, cx = 0, cy = 0;
  float near = 0, far = 0;
  /// How pixels map to rays; OmniIsometric fills the four below (px, px, m,
  /// rad: schemas/camera.fbs says what they mean).
  wire::CameraProjection projection = wire::CameraProjection::Pinhole;
  float ground_radius = 0, rim_radius = 0, mirror_range = 0, rim_elevation = 0;
};

/// A camera's configuration: image size (px), images per second (Hz),
/// pixel format.
struct CameraSettings {
  unsigned width = 0, height = 0;
  float rate = 0;
  wire::PixelFormat format = wire::PixelFormat::Rgb8;
};

class CameraProxy final : public Proxy {
 public:
  /// `compression`: how the camera should pack images (Png: PNG files, as
  /// image().compression then says; a camera that cannot sends raw rows).
  explicit CameraProxy(Client& client, uint16_t index = 0, uint16_t robot = 0,
                       wire::ImageCompression compression = wire::ImageCompression::None);
  const Image& image() const { return image_; }
  /// Depth images: the distance at pixel (u, v) along its ray, m; infinity
  /// where nothing is in range. NaN when the image is not a depth image or
  /// (u, v) is outside it.
  float depth(unsigned u, unsigned v) const;
  bool geometry(CameraModel& out);
  /// Asks for `want` (0 keeps a width, height or rate); `want` becomes
  /// what the device took.
  bool configure(CameraSettings& want);

 private:
  void update(const wire::Message& msg) override;
  Image image_;
};

class FiducialProxy final : public Proxy {
 public:
  explicit FiducialProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  /// Detections in the sensor frame: id, x (m), y (m), yaw (rad).
  const std::vector<wire::Fiducial>& fiducials() const { return fiducials_; }
  /// What detection i is (ball, goal, ...; Generic when the sender did not say).
  wire::FiducialKind kind(size_t i) const { return i < kinds_.size() ? kinds_[i] : wire::FiducialKind::Generic; }

 private:
  void update(const wire::Message& msg) override;
  std::vector<wire::Fiducial> fiducials_;
  std::vector<wire::FiducialKind> kinds_;
};

class ActuatorProxy final : public Proxy {
 public:
  explicit ActuatorProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  wire::ActuatorMode mode() const { return mode_; }
  float position() const { return position_; }  // m or rad
  uint32_t beams() const { return beams_; }
  unsigned stored() const { return stored_; }
  bool open();
  bool close();
  bool stop();
  /// Kicks with the given ball speed, m/s (0: the device's default).
  bool kick(float speed = 0);
  /// Moves to a position, m or rad.
  bool go_to(float position);

 private:
  void update(const wire::Message& msg) override;
  bool act(wire::ActuatorAction action, float value);
  wire::ActuatorMode mode_ = wire::ActuatorMode::Idle;
  float position_ = 0;
  uint32_t beams_ = 0;
  unsigned stored_ = 0;
};

class ImuProxy final : public Proxy {
 public:
  explicit ImuProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  const std::optional<wire::Vec3>& gyro() const { return gyro_; }                // rad/s
  const std::optional<wire::Vec3>& accel() const { return accel_; }              // m/s^2
  const std::optional<wire::Vec3>& orientation() const { return orientation_; }  // roll, pitch, yaw: rad

 private:
  void update(const wire::Message& msg) override;
  std::optional<wire::Vec3> gyro_, accel_, orientation_;
};

class LocalizeProxy final : public Proxy {
 public:
  explicit LocalizeProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  /// Pose hypotheses, best first (map frame; m, rad).
  const std::vector<wire::Hypothesis>& hypotheses() const { return hypotheses_; }
  /// The localizer says it is lost: the hypotheses are not to be trusted.
  bool lost() const { return lost_; }
  /// Starts pose tracking from a pose (m, m, rad) with a diagonal
  /// covariance: standard deviations in m, m, rad.
  bool set_pose(float x, float y, float a, float sx, float sy, float sa);
  /// Restarts global localization.
  bool global();

 private:
  void update(const wire::Message& msg) override;
  std::vector<wire::Hypothesis> hypotheses_;
  bool lost_ = false;
};

/// An occupancy grid fetched whole from a map device.
struct GridMap {
  uint32_t width = 0, height = 0;  // cells
  float resolution = 0;            // m per cell
  Pose2 origin;                    // pose of cell (0,0)'s corner: m, m, rad
  std::vector<uint8_t> cells;      // wire::Cell values, row-major from (0,0)
};

class MapProxy final : public Proxy {
 public:
  explicit MapProxy(Client& client, uint16_t index = 0, uint16_t robot = 0);
  /// Fetches the whole map in tiles of at most `tile` x `tile` cells.
  bool fetch(GridMap& out, uint32_t tile = 256);

 private:
  void update(const wire::Message&) override {}
};

/// A game's score and state (simulators with a referee: RoboCup mode).
struct GameState {
  unsigned score_blue = 0, score_yellow = 0;
  wire::GamePhase phase = wire::GamePhase::Play;
  /// Referee events since the start, and the latest ("goal yellow").
  uint32_t events = 0;
  std::string last_event;
  /// Simulated time of the latest event, us.
  uint64_t last_event_time_us = 0;
};

class SimulationProxy final : public Proxy {
 public:
  explicit SimulationProxy(Client& client, uint16_t index = 0);
  /// Latest clock data: simulated time (us), paused, real-time factor.
  uint64_t sim_time_us() const { return sim_time_us_; }
  /// Steps run since the start.
  uint64_t steps() const { return steps_; }
  bool paused() const { return paused_; }
  float real_time_factor() const { return rtf_; }
  /// The latest game data (all zero from simulators without a game).
  const GameState& game() const { return game_; }
  /// Asks for the game state now (also updates game()).
  bool get_game(GameState& out);

  bool pause();
  bool resume();
  /// Runs `steps` steps (while paused) and returns after they ran.
  bool step(uint32_t steps = 1);
  /// Multiple of real time; 0: as fast as possible.
  bool set_speed(float speed);
  /// Ground-truth pose of a model (world frame: m, m, rad).
  bool get_pose(const std::string& model, Pose2& pose);
  bool set_pose(const std::string& model, const Pose2& pose);
  /// Ground truth with the world-frame velocity (m/s, m/s, rad/s), where
  /// the simulator knows it.
  bool get_pose(const std::string& model, Pose2& pose, Pose2& velocity);
  /// Teleports a model and gives it a world-frame velocity (a ball: m/s;
  /// robots stop).
  bool set_pose(const std::string& model, const Pose2& pose, const Pose2& velocity);
  bool reset();
  /// Starts a player plugin on a robot with "key=value" options; the
  /// robot's previous player stops. False with client().error() naming the
  /// problem (missing plugin, bad option); the running player goes on.
  bool start_player(const std::string& robot, const std::string& plugin,
                    const std::vector<std::string>& options = {});
  /// Stops the robot's player: it then obeys its position2d commands.
  bool stop_player(const std::string& robot);

 private:
  void update(const wire::Message& msg) override;
  bool clock_request(wire::SimulationReqSub sub);
  void read_game(const wire::SimGame& g);
  uint64_t sim_time_us_ = 0;
  uint64_t steps_ = 0;
  bool paused_ = false;
  float rtf_ = 0;
  GameState game_;
};

}  // namespace troupe::client
