#include "examples/robocup/sensor_container.h"

#include <array>
#include <cmath>


namespace troupe::examples {

using client::ActuatorProxy;
using client::BumperProxy;
using client::DeviceEntry;
using client::FiducialProxy;
using client::Position2dProxy;
using client::PowerProxy;
using client::RangerProxy;
using client::Reply;
namespace {

constexpr std::array<std::string_view, 11> kFeatureNames = {
    "ballDistance",     "ballBearing",     "goalDistance", "goalBearing", "ownGoalDistance", "ownGoalBearing",
    "obstacleDistance", "obstacleBearing", "odometryX",    "odometryY",   "odometryHeading"};

}  // namespace

SensorContainer::SensorContainer(Client& client) : client_(client) {}
SensorContainer::~SensorContainer() = default;

std::span<const std::string_view> SensorContainer::feature_names() {
  return kFeatureNames;
}

void SensorContainer::add(std::string model, Proxy& proxy) {
  Entry e;
  e.model = std::move(model);
  e.proxy = &proxy;
  const uint16_t iface = proxy.address().iface();
  Reply r;
  if (iface == uint16_t(wire::Interface::Fiducial)) {
    r = client_.request(proxy.address(), uint8_t(wire::FiducialReqSub::Geometry));
    if (const wire::FiducialGeometry* g = r.ok() ? r.message()->body_as_FiducialGeometry() : nullptr;
        g && g->pose())
      e.x = g->pose()->x(), e.y = g->pose()->y(), e.a = g->pose()->yaw();
  } else if (iface == uint16_t(wire::Interface::Ranger)) {
    r = client_.request(proxy.address(), uint8_t(wire::RangerReqSub::Geometry));
    if (const wire::RangerGeometry* g = r.ok() ? r.message()->body_as_RangerGeometry() : nullptr;
        g && g->pose())
      e.x = g->pose()->x(), e.y = g->pose()->y(), e.a = g->pose()->yaw();
  }
  entries_.push_back(std::move(e));
}

bool SensorContainer::add_robot(std::string_view robot, std::string& error, wire::Delivery delivery) {
  std::vector<DeviceEntry> devices;
  if (!client_.device_list(devices)) {
    error = "cannot list the devices: " + client_.error();
    return false;
  }
  size_t found = 0;
  for (const DeviceEntry& d : devices) {
    if (d.robot_name != robot) continue;
    const uint16_t index = d.addr.index(), number = d.addr.robot();
    std::unique_ptr<Proxy> p;
    switch (wire::Interface(d.addr.iface())) {
      case wire::Interface::Position2d:
        p = std::make_unique<Position2dProxy>(client_, d.addr);
        break;
      case wire::Interface::Ranger:
        p = std::make_unique<RangerProxy>(client_, d.addr);
        break;
      case wire::Interface::Fiducial:
        p = std::make_unique<FiducialProxy>(client_, index, number);
        break;
      case wire::Interface::Actuator:
        p = std::make_unique<ActuatorProxy>(client_, index, number);
        break;
      case wire::Interface::Bumper:
        p = std::make_unique<BumperProxy>(client_, index, number);
        break;
      case wire::Interface::Power:
        p = std::make_unique<PowerProxy>(client_, index, number);
        break;
      default:
        continue;  // interfaces without features are left to the caller
    }
    if (delivery == wire::Delivery::Pull && !client_.open(d.addr, wire::Access::All, wire::Delivery::Pull)) {
      error = "cannot open " + d.text() + " in pull mode: " + client_.error();
      return false;
    }
    const size_t slash = d.driver.rfind('/');
    std::string model = slash == std::string::npos ? d.driver : d.driver.substr(slash + 1);
    // Two devices of one driver name keep apart by their address.
    if (model.empty() || this->model(model) != nullptr) model = d.text();
    add(std::move(model), *p);
    owned_.push_back(std::move(p));
    ++found;
  }
  if (found == 0) {
    error = "no devices of a robot named '" + std::string(robot) + "'";
    return false;
  }
  return true;
}

bool SensorContainer::update(int timeout_ms) {
  bool ok = true;
  for (const Entry& e : entries_) ok = client_.pull(e.proxy->address(), timeout_ms) && ok;
  return ok;
}

Proxy* SensorContainer::model(std::string_view model) const {
  for (const Entry& e : entries_) {
    if (e.model == model) return e.proxy;
  }
  return nullptr;
}

std::vector<Proxy*> SensorContainer::of_type(wire::Interface iface) const {
  std::vector<Proxy*> out;
  for (const Entry& e : entries_) {
    if (e.proxy->address().iface() == uint16_t(iface)) out.push_back(e.proxy);
  }
  return out;
}

std::vector<std::string> SensorContainer::models() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_) out.push_back(e.model);
  return out;
}

std::optional<Feature> SensorContainer::feature(std::string_view name) const {
  using wire::FiducialKind;
  const int attack = team_ == Team::Blue ? 1 : 0;  // goal ids: 0 blue (-x), 1 yellow (+x)
  const Landmark ball{FiducialKind::Ball, 0};
  const Landmark goal{FiducialKind::Goal, attack};
  const Landmark own{FiducialKind::Goal, 1 - attack};
  if (name == "ballDistance") return landmark(ball, false);
  if (name == "ballBearing") return landmark(ball, true);
  if (name == "goalDistance") return landmark(goal, false);
  if (name == "goalBearing") return landmark(goal, true);
  if (name == "ownGoalDistance") return landmark(own, false);
  if (name == "ownGoalBearing") return landmark(own, true);
  if (name == "obstacleDistance") return obstacle(false);
  if (name == "obstacleBearing") return obstacle(true);
  if (name == "odometryX") return odometry(0);
  if (name == "odometryY") return odometry(1);
  if (name == "odometryHeading") return odometry(2);
  return std::nullopt;
}

std::optional<Feature> SensorContainer::landmark(Landmark which, bool bearing) const {
  std::optional<Feature> best;
  for (const Entry& e : entries_) {
    if (e.proxy->address().iface() != uint16_t(wire::Interface::Fiducial) || e.proxy->samples() == 0)
      continue;
    if (best && e.proxy->time_us() <= best->time_us) continue;
    const auto* proxy = static_cast<const FiducialProxy*>(e.proxy);
    for (size_t i = 0; i < proxy->fiducials().size(); ++i) {
      const wire::Fiducial& f = proxy->fiducials()[i];
      if (proxy->kind(i) != which.kind || f.id() != which.id) continue;
      // Sensor frame to robot frame through the mount.
      const double c = std::cos(e.a), s = std::sin(e.a);
      const double x = e.x + c * f.x() - s * f.y(), y = e.y + s * f.x() + c * f.y();
      best = Feature{bearing ? std::atan2(y, x) : std::hypot(x, y), e.model, e.proxy->time_us()};
      break;
    }
  }
  return best;
}

std::optional<Feature> SensorContainer::obstacle(bool bearing) const {
  // The nearest return among each ranger's newest scan (newest sensors
  // first would hide a near return seen by a slower sensor: take them all).
  std::optional<Feature> best;
  double best_range = INFINITY;
  for (const Entry& e : entries_) {
    if (e.proxy->address().iface() != uint16_t(wire::Interface::Ranger) || e.proxy->samples() == 0) continue;
    const auto* r = static_cast<const RangerProxy*>(e.proxy);
    for (size_t i = 0; i < r->count(); ++i) {
      if (r->range(i) >= r->max_range() || r->range(i) <= 0) continue;
      const double c = std::cos(e.a), s = std::sin(e.a), b = r->bearing(i);
      const double sx = r->range(i) * std::cos(b), sy = r->range(i) * std::sin(b);
      const double x = e.x + c * sx - s * sy, y = e.y + s * sx + c * sy;
      const double d = std::hypot(x, y);
      if (d >= best_range) continue;
      best_range = d;
      best = Feature{bearing ? std::atan2(y, x) : d, e.model, r->time_us()};
    }
  }
  return best;
}

std::optional<Feature> SensorContainer::odometry(int axis) const {
  for (const Entry& e : entries_) {
    if (e.proxy->address().iface() != uint16_t(wire::Interface::Position2d) || e.proxy->samples() == 0)
      continue;
    const auto* p = static_cast<const Position2dProxy*>(e.proxy);
    const double v = axis == 0 ? p->x() : axis == 1 ? p->y() : p->a();
    return Feature{v, e.model, p->time_us()};
  }
  return std::nullopt;
}

}  // namespace troupe::examples
