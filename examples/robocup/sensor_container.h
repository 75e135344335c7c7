// A robot's sensors in one place, so an algorithm asks for what it needs
// (the ball's distance) rather than for a particular device: proxies are
// looked up by model name ("omni", "laser"), by interface, or through named
// features computed from whichever sensor currently provides them.
//
//   SensorContainer robot(client);
//   robot.add_robot("yellow3");                    // every device of the robot
//   robot.set_team(Team::Yellow);                  // which goal is "goal"
//   if (auto d = robot.feature("ballDistance")) printf("%.2f m (%s)\n", d->value, d->model.c_str());
//
// Features (robot frame: x forward, y left; m and rad counter-clockwise):
//   ballDistance, ballBearing        the ball, from any fiducial sensor
//   goalDistance, goalBearing        the centre of the goal to attack
//   ownGoalDistance, ownGoalBearing  the centre of the goal to defend
//   obstacleDistance, obstacleBearing  the nearest return of any ranger
//   odometryX, odometryY, odometryHeading  the base's odometry (m, m, rad)
// Fiducials are told apart by their kind (ball, goal) and id, as a RoboCup
// world serves them (host-sim/robocup/api/fiducial_key.h).
// When several sensors provide a feature, the newest sample wins.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "wire/client/proxies.h"

namespace troupe::examples {

using client::Client;
using client::Proxy;

enum class Team : uint8_t { Blue = 0, Yellow = 1 };

/// One feature's value and where it came from.
struct Feature {
  /// m or rad (see the feature list above).
  double value = 0;
  /// The model name of the sensor that produced it.
  std::string model;
  /// When that sensor measured, us of the node's clock (simulated time
  /// from a simulator).
  uint64_t time_us = 0;
};

class SensorContainer {
 public:
  explicit SensorContainer(Client& client);
  ~SensorContainer();
  SensorContainer(const SensorContainer&) = delete;
  SensorContainer& operator=(const SensorContainer&) = delete;

  /// Registers a proxy the caller owns under a model name. For fiducial and
  /// ranger proxies it asks the device for its mount on the robot, so
  /// features come out in the robot frame (a device without geometry is
  /// taken as mounted at the robot's origin).
  void add(std::string model, Proxy& proxy);
  /// Builds (and owns) proxies for every device of the robot named `robot`
  /// in the node's device list; each sensor's model name is the last part
  /// of its driver column ("robocup/omni": "omni"). `delivery` Pull opens
  /// them in pull mode: data then comes only through update(). False with
  /// `error` when the list cannot be read or the robot has no devices.
  bool add_robot(std::string_view robot, std::string& error, wire::Delivery delivery = wire::Delivery::Push);

  /// Pull mode: asks every device for its latest data (they reach the
  /// proxies before it returns). Push mode: nothing to do. False when a
  /// pull failed (see client().error()).
  bool update(int timeout_ms = 2000);

  /// The proxy registered under `model`, or null.
  Proxy* model(std::string_view model) const;
  /// The same, typed: null when the model is another interface.
  template <typename P>
  P* get(std::string_view name) const {
    return dynamic_cast<P*>(model(name));
  }
  /// Every proxy of an interface, in the order they were added.
  std::vector<Proxy*> of_type(wire::Interface iface) const;
  /// Model names in the order they were added.
  std::vector<std::string> models() const;

  /// Which goal the robot attacks: Blue attacks the yellow goal (+x).
  void set_team(Team team) { team_ = team; }
  /// The named feature, or nothing when no sensor provides it now (the
  /// ball out of sight) or the name is unknown.
  std::optional<Feature> feature(std::string_view name) const;
  /// The names feature() knows.
  static std::span<const std::string_view> feature_names();

  Client& client() { return client_; }

 private:
  struct Entry {
    std::string model;
    Proxy* proxy = nullptr;
    /// Mount on the robot: m, m, rad.
    double x = 0, y = 0, a = 0;
  };
  /// Landmark `code`'s distance (m) or bearing (rad) in the robot frame,
  /// from the newest sensor whose latest sample holds it.
  struct Landmark {
    wire::FiducialKind kind;
    int32_t id;
  };
  std::optional<Feature> landmark(Landmark which, bool bearing) const;
  std::optional<Feature> obstacle(bool bearing) const;
  std::optional<Feature> odometry(int axis) const;

  Client& client_;
  std::vector<Entry> entries_;
  std::vector<std::unique_ptr<Proxy>> owned_;
  Team team_ = Team::Blue;
};

}  // namespace troupe::examples
