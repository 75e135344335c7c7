// The bridge's life: options and devices at setup, the DDS readers' wake-ups,
// the once-a-second tick (requests, health, diagnostics), replies. What each
// device's data becomes is in publish.cc.
#include "drivers/ros2/ros2.h"

#include <sys/epoll.h>

#include <algorithm>
#include <cstdlib>

#include "runtime/log.h"
#include "runtime/node.h"
#include "wire/address.h"

namespace troupe::drivers::ros2 {

namespace {

constexpr uint64_t kTickUs = 1'000'000;   // health, diagnostics, retries
constexpr uint64_t kRetryUs = 1'000'000;  // a refused geometry, config or map request
constexpr int kMaxInFlight = 32;          // requests to devices at once
constexpr int kMaxDomain = 232;           // DDS's port mapping ends there
constexpr int kMaxTake = 16;              // samples taken from a reader at once

using StringList = flatbuffers::Vector<flatbuffers::Offset<flatbuffers::String>>;

std::string option(const flatbuffers::String* s, const char* fallback) {
  return s != nullptr && s->size() != 0 ? s->str() : std::string(fallback);
}

// Entry i of a list parallel to `uses`, "" when absent.
std::string entry(const StringList* list, size_t i) {
  return list != nullptr && i < list->size() ? list->Get(flatbuffers::uoffset_t(i))->str() : std::string();
}

}  // namespace

bool Ros2Bridge::setup(Node& node, const DriverSetup& setup, std::string& error) {
  name_ = setup.name;
  OptionsView<Options> view(setup);
  const Options& opt = *view.operator->();
  for (DeviceId id : setup.provides) {
    if (node.address(id).iface() != uint16_t(wire::Interface::Opaque) || status_ != kNoDevice) {
      error = "ros2 provides one opaque device (its status), not " + wire::format_address(node.address(id));
      return false;
    }
    status_ = id;
  }
  if (setup.required.empty()) {
    error = "ros2 uses no device: list the devices to bridge in \"uses\"";
    return false;
  }

  int domain = opt.domain_id();
  if (domain < 0) {
    domain = 0;
    if (const char* env = std::getenv("ROS_DOMAIN_ID"); env != nullptr && *env != '\0') {
      char* end = nullptr;
      domain = int(std::strtol(env, &end, 10));
      if (*end != '\0') {
        error = std::string("ROS_DOMAIN_ID '") + env + "' is not a number";
        return false;
      }
    }
  }
  if (domain < 0 || domain > kMaxDomain) {
    error = "DDS domain " + std::to_string(domain) + " is outside 0.." + std::to_string(kMaxDomain);
    return false;
  }
  domain_ = uint32_t(domain);
  base_frame_ = option(opt.base_frame(), "base_link");
  odom_frame_ = option(opt.odom_frame(), "odom");
  map_frame_ = option(opt.map_frame(), "map");
  publish_tf_ = opt.publish_tf();
  const std::string node_name = option(opt.node_name(), "troupe_bridge");
  const std::string node_ns = option(opt.node_namespace(), "/");
  if (!valid_ros_token(node_name) || node_ns[0] != '/' ||
      (node_ns != "/" && !valid_ros_path(node_ns.substr(1)))) {
    error = "node_name '" + node_name + "' or node_namespace '" + node_ns + "' is not a valid ROS name";
    return false;
  }
  for (const std::string* f : {&base_frame_, &odom_frame_, &map_frame_}) {
    if (!valid_ros_path(*f)) {
      error = "frame '" + *f + "' is not a valid ROS name";
      return false;
    }
  }
  limits_.linear = opt.max_linear();
  limits_.angular = opt.max_angular();
  if (!(limits_.linear >= 0) || !(limits_.angular >= 0)) {
    error = "max_linear and max_angular must be numbers >= 0";
    return false;
  }
  stale_after_us_ = uint64_t(std::max(0.1f, opt.stale_after()) * 1e6f);

  bool has_sim = false;
  for (DeviceId id : setup.required)
    has_sim |= node.address(id).iface() == uint16_t(wire::Interface::Simulation);
  const TimeSource ts = opt.time();
  stamps_ = std::make_unique<StampMap>(ts == TimeSource::Sim || (ts == TimeSource::Auto && has_sim));

  // Every name checked before the network is touched.
  for (size_t i = 0; i < setup.required.size(); ++i) {
    if (!add_device(setup.required[i], i, opt, error)) return false;
  }
  if (!dds_.open(domain_, error) || !graph_.open(dds_, node_name, node_ns, error)) return false;
  tf_ = writer("/tf", tf2_msgs_msg_dds__TFMessage__desc, kTfQos, error);
  tf_static_ = writer("/tf_static", tf2_msgs_msg_dds__TFMessage__desc, kLatchedQos, error);
  diagnostics_ = writer("/diagnostics", diagnostic_msgs_msg_dds__DiagnosticArray__desc, kDefaultQos, error);
  if (tf_ == 0 || tf_static_ == 0 || diagnostics_ == 0) return false;
  for (Bridged& b : devices_) {
    if (!open_endpoints(b, error)) return false;
    node.subscribe(b.id, this);
  }
  graph_.publish();

  if (!node.loop().watch(dds_.wake_fd(), EPOLLIN, this)) {
    error = "cannot watch the DDS wake-up descriptor";
    return false;
  }
  start_us_ = node.loop().now_us();
  tick_ = node.loop().start_timer(0, kTickUs, this);
  if (tick_ == 0) {
    error = "no timer left for the bridge";
    return false;
  }
  log_info("%s: %zu devices on DDS domain %u as ROS 2 node %s%s%s (%s time)", name_.c_str(), devices_.size(),
           domain_, node_ns.c_str(), node_ns == "/" ? "" : "/", node_name.c_str(),
           stamps_->sim() ? "simulated" : "wall");
  return true;
}

bool Ros2Bridge::add_device(DeviceId id, size_t use_index, const Options& opt, std::string& error) {
  Bridged b;
  b.id = id;
  b.addr = node_->address(id);
  const uint16_t index = b.addr.index();
  switch (wire::Interface(b.addr.iface())) {
    case wire::Interface::Position2d:
      b.kind = Kind::Position;
      break;
    case wire::Interface::Ranger:
      b.kind = Kind::Ranger;
      break;
    case wire::Interface::Power:
      b.kind = Kind::Power;
      break;
    case wire::Interface::Imu:
      b.kind = Kind::Inertial;
      break;
    case wire::Interface::Bumper:
      b.kind = Kind::Bumper;
      break;
    case wire::Interface::Localize:
      b.kind = Kind::Localize;
      break;
    case wire::Interface::Map:
      b.kind = Kind::Map;
      break;
    case wire::Interface::Simulation:
      b.kind = Kind::Simulation;
      break;
    default:
      error = "ros2 has no ROS 2 message for " + std::string(wire::interface_name(b.addr.iface())) +
              " devices (uses[" + std::to_string(use_index) + "])";
      return false;
  }
  std::string ns = entry(opt.namespaces(), use_index);
  if (ns.empty() && b.addr.robot() != 0) ns = "robot" + std::to_string(b.addr.robot());
  if (!ns.empty() && ns.front() == '/') ns.erase(0, 1);
  if (!ns.empty() && !valid_ros_path(ns)) {
    error = "namespaces[" + std::to_string(use_index) + "] '" + ns + "' is not a valid ROS name";
    return false;
  }
  b.ns = ns;
  b.label = wire::format_address(b.addr, ns);
  const std::string topic = entry(opt.topics(), use_index);
  const std::string frame = entry(opt.frames(), use_index);
  auto data_topic = [&](const char* name) {
    b.topic = topic_in_ns(ns, topic.empty() ? suffixed(name, index) : topic);
  };
  auto sensor_frame = [&](const std::string& name) { b.frame = in_ns(ns, frame.empty() ? name : frame); };
  switch (b.kind) {
    case Kind::Position: {
      data_topic("odom");
      b.command_topic = topic_in_ns(ns, suffixed("cmd_vel", index));
      sensor_frame(base_frame_);
      b.odom_frame = in_ns(ns, odom_frame_);
      bool first = true;
      for (const Bridged& o : devices_) first &= !(o.kind == Kind::Position && o.ns == ns);
      b.tf = first && publish_tf_;
      break;
    }
    case Kind::Ranger:
      // Whether it is a scan (topic scan) or a ring (sonar) shows in its
      // first sample: the topic is named then.
      b.frame_given = frame;
      if (!topic.empty()) b.topic = topic_in_ns(ns, topic);
      b.geometry.wanted = b.config.wanted = true;
      break;
    case Kind::Power:
      data_topic("battery");
      sensor_frame(base_frame_);
      break;
    case Kind::Inertial:
      data_topic("imu");
      sensor_frame(base_frame_);
      break;
    case Kind::Bumper:
      data_topic("bumper");
      sensor_frame(suffixed("bumper", index));
      b.geometry.wanted = true;
      break;
    case Kind::Localize:
      data_topic("amcl_pose");
      b.command_topic = topic_in_ns(ns, suffixed("initialpose", index));
      b.frame = map_frame_;
      break;
    case Kind::Map:
      data_topic("map");
      b.frame = map_frame_;
      break;
    case Kind::Simulation:
      b.topic = "/clock";
      break;
  }
  if (!b.topic.empty() && !valid_ros_path(b.topic.substr(1))) {
    error = "topic '" + b.topic + "' of " + b.label + " is not a valid ROS name";
    return false;
  }
  if (!b.frame.empty() && !valid_ros_path(b.frame)) {
    error = "frame '" + b.frame + "' of " + b.label + " is not a valid ROS name";
    return false;
  }
  for (const Bridged& o : devices_) {
    if (!b.topic.empty() && o.topic == b.topic) {
      error = b.label + " and " + o.label + " would both publish " + b.topic + " (give one of them a topic)";
      return false;
    }
  }
  index_[id] = devices_.size();
  devices_.push_back(std::move(b));
  return true;
}

bool Ros2Bridge::open_endpoints(Bridged& b, std::string& error) {
  const std::string& t = b.topic;
  switch (b.kind) {
    case Kind::Position:
      b.writer = writer(t, nav_msgs_msg_dds__Odometry__desc, kDefaultQos, error);
      b.reader = dds_.create_reader(dds_topic_name(b.command_topic), geometry_msgs_msg_dds__Twist__desc,
                                    kDefaultQos, error);
      break;
    case Kind::Ranger:
      return true;  // at the first sample
    case Kind::Power:
      b.writer = writer(t, sensor_msgs_msg_dds__BatteryState__desc, kDefaultQos, error);
      break;
    case Kind::Inertial:
      b.writer = writer(t, sensor_msgs_msg_dds__Imu__desc, kSensorDataQos, error);
      break;
    case Kind::Bumper:
      b.writer = writer(t, sensor_msgs_msg_dds__Range__desc, kSensorDataQos, error);
      break;
    case Kind::Localize:
      // As amcl publishes amcl_pose and takes initialpose.
      b.writer = writer(t, geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc, kLatchedQos, error);
      b.reader =
          dds_.create_reader(dds_topic_name(b.command_topic),
                             geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc, kDefaultQos, error);
      break;
    case Kind::Map:
      b.writer = writer(t, nav_msgs_msg_dds__OccupancyGrid__desc, kLatchedQos, error);
      break;
    case Kind::Simulation:
      if (stamps_->sim() && clock_ == 0)
        clock_ = writer("/clock", rosgraph_msgs_msg_dds__Clock__desc, kClockQos, error);
      return clock_ != 0 || !stamps_->sim();
  }
  if (b.writer == 0) return false;
  if (!b.command_topic.empty()) {
    if (b.reader == 0) return false;
    graph_.add_reader(b.reader);
  }
  return true;
}

dds_entity_t Ros2Bridge::writer(const std::string& ros_topic, const dds_topic_descriptor_t& desc,
                                const QosProfile& qos, std::string& error) {
  dds_entity_t w = dds_.create_writer(dds_topic_name(ros_topic), desc, qos, error);
  if (w != 0) graph_.add_writer(w);
  return w;
}

Ros2Bridge::Bridged* Ros2Bridge::by_id(DeviceId id) {
  auto it = index_.find(id);
  return it == index_.end() ? nullptr : &devices_[it->second];
}

// ---- Data in -------------------------------------------------------------------

void Ros2Bridge::on_data(DeviceId source, const wire::Message& msg) {
  Bridged* b = by_id(source);
  if (b == nullptr) return;
  b->samples++;
  b->last_data_us = node_->loop().now_us();
  if (b->stale) {
    b->stale = false;
    log_info("%s: %s sends data again", name_.c_str(), b->label.c_str());
  }
  switch (b->kind) {
    case Kind::Position:
      return publish_position(*b, msg);
    case Kind::Ranger:
      return publish_ranger(*b, msg);
    case Kind::Bumper:
      return publish_bumper(*b, msg);
    case Kind::Power:
      return publish_sensor<BatteryState>(*b, msg, msg.body_as_PowerState(), fill_battery);
    case Kind::Inertial:
      return publish_sensor<Imu>(*b, msg, msg.body_as_ImuState(), fill_imu);
    case Kind::Localize:
      if (const wire::LocalizeState* s = msg.body_as_LocalizeState()) {
        PoseWithCovarianceStamped out;
        // The estimate refers to the odometry reading it names, when it names one.
        const Time stamp = s->pending_time_us() != 0 ? stamp_at(*b, s->pending_time_us()) : stamp_of(*b, msg);
        if (fill_amcl_pose(*s, stamp, b->frame, out)) write(*b, b->writer, &out);
      }
      return;
    case Kind::Simulation:
      if (const wire::SimClock* c = msg.body_as_SimClock()) {
        latest_sim_us_ = std::max(latest_sim_us_, c->sim_time_us());
        if (clock_ != 0) {
          Clock out;
          out.clock = ros_time(c->sim_time_us());
          write(*b, clock_, &out);
        }
      }
      return;
    case Kind::Map:
      return;  // maps answer requests; they publish no data
  }
}

Time Ros2Bridge::stamp_of(const Bridged& b, const wire::Message& msg) {
  return stamp_at(b, wire::time_us(*msg.header()));
}

Time Ros2Bridge::stamp_at(const Bridged& b, uint64_t device_us) {
  if (stamps_->sim()) latest_sim_us_ = std::max(latest_sim_us_, device_us);
  return ros_time(stamps_->to_ros_us(device_us, b.addr.robot(), wall_clock_us()));
}

Time Ros2Bridge::ros_now() const {
  return ros_time(stamps_->sim() ? latest_sim_us_ : wall_clock_us());
}

void Ros2Bridge::write(Bridged& b, dds_entity_t w, const void* sample) {
  const dds_return_t rc = dds_write(w, sample);
  if (rc != DDS_RETCODE_OK) {
    const std::string why = std::string("DDS write failed: ") + dds_strretcode(rc);
    if (why != b.problem) log_warn("%s: %s: %s", name_.c_str(), b.label.c_str(), why.c_str());
    b.problem = why;
  }
}

// ---- Commands from ROS -----------------------------------------------------------

void Ros2Bridge::on_fd(int /*fd*/, uint32_t /*events*/) {
  dds_.drain_wake();
  for (Bridged& b : devices_) {
    if (b.reader == 0) continue;
    if (b.kind == Kind::Position) {
      take_commands(b);
    } else {
      take_initial_poses(b);
    }
  }
}

void Ros2Bridge::take_commands(Bridged& b) {
  void* samples[kMaxTake] = {};
  dds_sample_info_t infos[kMaxTake];
  int n;
  // Loaned samples: no copy, no allocation; every one handed back below.
  while ((n = dds_take(b.reader, samples, infos, kMaxTake, kMaxTake)) > 0) {
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      wire::Pose2d vel;
      std::string why;
      const Verdict v = vel_from_twist(*static_cast<const Twist*>(samples[i]), limits_, vel, why);
      if (v == Verdict::Refused) {
        // A controller sending NaN is broken: the base stops rather than
        // keep the last speed it was given.
        vel = wire::Pose2d(0, 0, 0);
        b.refused++;
        if (why != b.problem) {
          log_warn("%s: %s: %s; refused, the base is told to stop", name_.c_str(), b.label.c_str(),
                   why.c_str());
        }
      } else if (v == Verdict::Clamped) {
        b.clamped++;
        if (why != b.problem) log_warn("%s: %s: %s", name_.c_str(), b.label.c_str(), why.c_str());
      }
      if (v != Verdict::Ok) b.problem = why;
      auto& fb = node_->begin();
      auto body = wire::CreatePosition2dVel(fb, &vel);
      node_->command(b.id, uint8_t(wire::Position2dCmdSub::Vel), wire::Body::Position2dVel, body.Union());
    }
    dds_return_loan(b.reader, samples, n);
  }
}

void Ros2Bridge::take_initial_poses(Bridged& b) {
  void* samples[kMaxTake] = {};
  dds_sample_info_t infos[kMaxTake];
  int n;
  while ((n = dds_take(b.reader, samples, infos, kMaxTake, kMaxTake)) > 0) {
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto& msg = *static_cast<const PoseWithCovarianceStamped*>(samples[i]);
      wire::Pose2d mean;
      wire::Cov2d cov;
      std::string why;
      std::string frame = msg.header.frame_id != nullptr ? msg.header.frame_id : "";
      if (!frame.empty() && frame.front() == '/') frame.erase(0, 1);
      if (frame != map_frame_) {
        why = "initialpose in frame '" + frame + "', not the map frame '" + map_frame_ + "'";
      } else {
        pose_from_initialpose(msg, mean, cov, why);
      }
      if (!why.empty()) {
        b.refused++;
        b.problem = why;
        log_warn("%s: %s: %s; refused", name_.c_str(), b.label.c_str(), why.c_str());
        continue;
      }
      auto& fb = node_->begin();
      auto body = wire::CreateLocalizeSetPose(fb, &mean, &cov);
      if (!node_->request(b.id, uint8_t(wire::LocalizeReqSub::SetPose), ++seq_, wire::Body::LocalizeSetPose,
                          body.Union(), this)) {
        b.problem = "no request slot for initialpose";
        log_warn("%s: %s: %s", name_.c_str(), b.label.c_str(), b.problem.c_str());
      }
    }
    dds_return_loan(b.reader, samples, n);
  }
}

// ---- Requests to devices ---------------------------------------------------------

void Ros2Bridge::send_fetch(Bridged& b, Fetch& f, uint8_t subtype) {
  if (!f.wanted || f.done || f.seq != 0 || node_->loop().now_us() < f.retry_at ||
      in_flight_ >= kMaxInFlight) {
    return;
  }
  f.seq = ++seq_;
  in_flight_++;
  node_->begin();
  if (!node_->request(b.id, subtype, f.seq, wire::Body::NONE, 0, this)) {
    f.seq = 0;
    in_flight_--;
    f.retry_at = node_->loop().now_us() + kRetryUs;
  }
}

void Ros2Bridge::send_requests() {
  // Replies may come before request() returns, and a reply sends the next
  // request: one pass at a time.
  sending_ = true;
  const uint64_t now = node_->loop().now_us();
  for (Bridged& b : devices_) {
    if (b.kind == Kind::Ranger) {
      send_fetch(b, b.geometry, uint8_t(wire::RangerReqSub::Geometry));
      send_fetch(b, b.config, uint8_t(wire::RangerReqSub::GetConfig));
    } else if (b.kind == Kind::Bumper) {
      send_fetch(b, b.geometry, uint8_t(wire::BumperReqSub::Geometry));
    } else if (b.kind == Kind::Map && !b.map_published && !b.map.busy() && now >= b.map_retry_at) {
      if (!b.map.start(*node_, *this, b.id)) b.map_retry_at = now + kRetryUs;
    }
  }
  sending_ = false;
}

void Ros2Bridge::on_reply(DeviceId device, const wire::Message& reply) {
  Bridged* b = by_id(device);
  if (b == nullptr) return;
  const uint32_t seq = reply.header()->seq();
  const bool ack = reply.header()->kind() == wire::Kind::Ack;
  std::string why;
  // Only a device that is away or late is asked again.
  bool transient = true;
  if (!ack) {
    const wire::Error* e = reply.body_as_Error();
    why = e != nullptr && e->text() != nullptr ? e->text()->str() : "refused";
    transient =
        e == nullptr || e->code() == wire::ErrorCode::DeviceFailed || e->code() == wire::ErrorCode::Timeout;
  }
  if (b->kind == Kind::Map) {
    if (b->map.on_reply(reply, why)) {
      publish_map(*b);
    } else if (!b->map.busy() && !b->map_published) {
      b->problem = why;
      b->map_retry_at = node_->loop().now_us() + kRetryUs;
    }
    return;
  }
  for (Fetch* f : {&b->geometry, &b->config}) {
    if (f->seq != seq || seq == 0) continue;
    f->seq = 0;
    in_flight_--;
    if (!ack && transient) {
      // Typically a passthrough whose remote is away: ask again later.
      f->retry_at = node_->loop().now_us() + kRetryUs;
      log_debug("%s: %s: %s", name_.c_str(), b->label.c_str(), why.c_str());
      return;
    }
    f->done = true;
    if (!ack) {
      // The sensor stays at the robot's origin on /tf_static, its range
      // limits unknown (0).
      log_info("%s: %s answers no %s: %s", name_.c_str(), b->label.c_str(),
               f == &b->geometry ? "geometry" : "config", why.c_str());
      return;
    }
    if (f == &b->geometry) {
      on_geometry(*b, reply);
    } else if (const wire::RangerConfig* c = reply.body_as_RangerConfig()) {
      b->min_range = c->min_range();
      b->field_of_view = std::max(0.0f, c->max_angle() - c->min_angle());
      b->scan_time = c->frequency() > 0 ? 1.0f / c->frequency() : 0.0f;
    }
    // A slot is free: the next request goes now rather than at the next tick.
    if (!sending_) send_requests();
    return;
  }
  // A SetPose from initialpose.
  if (!ack) {
    b->problem = "initialpose refused by the localizer: " + why;
    log_warn("%s: %s: %s", name_.c_str(), b->label.c_str(), b->problem.c_str());
  }
}

void Ros2Bridge::on_request(DeviceId device, const wire::Message& request, RequestToken token) {
  if (device != status_) return Driver::on_request(device, request, token);
  const std::string text = status_text();
  auto& fb = node_->begin();
  auto body = wire::CreateOpaqueBytes(
      fb, fb.CreateVector(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
  node_->ack(token, wire::Body::OpaqueBytes, body.Union());
}

// ---- The tick --------------------------------------------------------------------

void Ros2Bridge::on_timer(TimerId /*id*/) {
  send_requests();
  check_health();
  publish_static_tf();
  publish_diagnostics();
  publish_status();
}

void Ros2Bridge::check_health() {
  const uint64_t now = node_->loop().now_us();
  for (Bridged& b : devices_) {
    if (b.kind == Kind::Map || b.stale || b.last_data_us == 0) continue;
    if (now - b.last_data_us >= stale_after_us_) {
      // The topics stay: subscribers keep their matches and see data again
      // when the device is back. /diagnostics says STALE meanwhile.
      b.stale = true;
      log_warn("%s: %s sent nothing for %.1f s: stale", name_.c_str(), b.label.c_str(),
               double(now - b.last_data_us) / 1e6);
    }
  }
}

void Ros2Bridge::shutdown() {
  if (dds_.wake_fd() >= 0) node_->loop().unwatch(dds_.wake_fd());
  if (tick_ != 0) node_->loop().cancel_timer(tick_);
  tick_ = 0;
  // Remote subscribers see every writer disposed at once.
  dds_.close();
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"ros2", []() -> Driver* { return new Ros2Bridge; }};

}  // namespace troupe::drivers::ros2
