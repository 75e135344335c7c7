// What each device's data becomes on ROS 2, and the bridge's own topics:
// /tf_static from the devices' geometry, /diagnostics, the status device.
#include <algorithm>
#include <cstdio>

#include "drivers/ros2/ros2.h"
#include "runtime/log.h"
#include "runtime/node.h"

namespace troupe::drivers::ros2 {

namespace {

template <typename Seq, typename T>
Seq sequence_of(std::vector<T>& v) {
  return Seq{uint32_t(v.size()), uint32_t(v.size()), v.data(), false};
}

char* text(const std::string& s) {
  return const_cast<char*>(s.c_str());
}

// A pose in the plane as a transform in space.
Transform planar_transform(const wire::Pose2d& p) {
  return transform_of(wire::Pose3d(p.x(), p.y(), 0, 0, 0, p.a()));
}

}  // namespace

void Ros2Bridge::publish_position(Bridged& b, const wire::Message& msg) {
  const wire::Position2dState* s = msg.body_as_Position2dState();
  if (s == nullptr) return;
  Odometry odom;
  fill_odometry(*s, stamp_of(b, msg), b.odom_frame, b.frame, odom);
  write(b, b.writer, &odom);
  if (b.tf) {
    TransformStamped t;
    fill_odom_transform(odom, t);
    TFMessage tf;
    tf.transforms = {1, 1, &t, false};
    write(b, tf_, &tf);
  }
}

bool Ros2Bridge::name_ranger(Bridged& b, const wire::RangerScan& scan) {
  // A scanner, or a ring of separate transducers: one Range per transducer,
  // each in its own frame, as ROS drivers publish sonars.
  b.shape = is_scan(scan) ? RangerShape::Scan : RangerShape::Array;
  const bool ring = b.shape == RangerShape::Array;
  const uint16_t index = b.addr.index();
  if (b.topic.empty()) b.topic = topic_in_ns(b.ns, suffixed(ring ? "sonar" : "scan", index));
  b.frame =
      in_ns(b.ns, b.frame_given.empty() ? suffixed(ring ? "sonar" : "base_scan", index) : b.frame_given);
  std::string error;
  b.writer = writer(b.topic, ring ? sensor_msgs_msg_dds__Range__desc : sensor_msgs_msg_dds__LaserScan__desc,
                    kSensorDataQos, error);
  for (const Bridged& o : devices_) {
    if (&o != &b && o.topic == b.topic) error = "its topic " + b.topic + " is " + o.label + "'s already";
  }
  if (b.writer == 0 || !error.empty()) {
    b.problem = "cannot publish: " + error;
    log_error("%s: %s: %s", name_.c_str(), b.label.c_str(), b.problem.c_str());
    return false;
  }
  graph_.publish();
  ranger_static_tf(b);  // when the geometry came first
  log_info("%s: %s is a %s: %s", name_.c_str(), b.label.c_str(),
           b.shape == RangerShape::Scan ? "scanning sensor" : "transducer array", b.topic.c_str());
  return true;
}

void Ros2Bridge::publish_ranger(Bridged& b, const wire::Message& msg) {
  const wire::RangerScan* scan = msg.body_as_RangerScan();
  if (scan == nullptr || scan->ranges() == nullptr) return;
  if (b.shape == RangerShape::Unknown && !name_ranger(b, *scan)) return;
  if (b.writer == 0) return;
  const Time stamp = stamp_of(b, msg);
  if (b.shape == RangerShape::Scan) {
    LaserScan out;
    fill_laser_scan(*scan, stamp, b.frame, b.min_range, b.scan_time, ranges_, intensities_, out);
    return write(b, b.writer, &out);
  }
  const size_t n = scan->ranges()->size();
  if (b.element_frames.size() != n) {
    b.element_frames.resize(n);
    for (size_t i = 0; i < n; ++i) b.element_frames[i] = b.frame + "_" + std::to_string(i);
    ranger_static_tf(b);
  }
  for (size_t i = 0; i < n; ++i) {
    Range out;
    fill_sonar_range(*scan, i, stamp, b.element_frames[i], b.field_of_view, b.min_range, out);
    write(b, b.writer, &out);
  }
}

void Ros2Bridge::publish_bumper(Bridged& b, const wire::Message& msg) {
  const wire::BumperState* s = msg.body_as_BumperState();
  if (s == nullptr) return;
  const size_t n = std::min<size_t>(s->count(), 32);
  if (b.element_frames.size() < n) {
    for (size_t i = b.element_frames.size(); i < n; ++i)
      b.element_frames.push_back(b.frame + "_" + std::to_string(i));
  }
  const Time stamp = stamp_of(b, msg);
  for (size_t i = 0; i < n; ++i) {
    Range out;
    fill_bumper_range((s->pressed() >> i) & 1u, stamp, b.element_frames[i], out);
    write(b, b.writer, &out);
  }
}

void Ros2Bridge::publish_map(Bridged& b) {
  OccupancyGrid out;
  fill_occupancy_grid(b.map.grid(), ros_now(), b.frame, cells_, out);
  write(b, b.writer, &out);
  b.map_published = true;
  b.problem.clear();
  log_info("%s: %s published on %s (%ux%u cells of %.3f m, latched)", name_.c_str(), b.label.c_str(),
           b.topic.c_str(), b.map.grid().width(), b.map.grid().height(), b.map.grid().resolution());
}

// ---- /tf_static -------------------------------------------------------------------

void Ros2Bridge::set_static_tf(const std::string& parent, const std::string& child, const Transform& t) {
  static_tf_[child] = {parent, t};
  static_tf_dirty_ = true;
}

void Ros2Bridge::on_geometry(Bridged& b, const wire::Message& reply) {
  const std::string base = b.ns.empty() ? base_frame_ : b.ns + "/" + base_frame_;
  if (const wire::RangerGeometry* g = reply.body_as_RangerGeometry()) {
    b.has_geometry = true;
    if (g->pose() != nullptr) b.pose = *g->pose();
    b.elements.clear();
    if (g->elements() != nullptr) {
      for (const wire::Pose3d* e : *g->elements()) b.elements.push_back(*e);
    }
    ranger_static_tf(b);
  } else if (const wire::BumperGeometry* bg = reply.body_as_BumperGeometry(); bg && bg->bumpers()) {
    for (flatbuffers::uoffset_t i = 0; i < bg->bumpers()->size(); ++i) {
      set_static_tf(base, b.frame + "_" + std::to_string(i), planar_transform(bg->bumpers()->Get(i)->pose()));
    }
  }
  publish_static_tf();
}

void Ros2Bridge::ranger_static_tf(Bridged& b) {
  if (!b.has_geometry || b.shape == RangerShape::Unknown) return;
  const std::string base = b.ns.empty() ? base_frame_ : b.ns + "/" + base_frame_;
  if (b.shape == RangerShape::Scan) return set_static_tf(base, b.frame, transform_of(b.pose));
  // Each transducer where the geometry puts it; all at the sensor's pose
  // when the device gives no per-transducer poses.
  for (size_t i = 0; i < b.element_frames.size(); ++i) {
    set_static_tf(base, b.element_frames[i], transform_of(i < b.elements.size() ? b.elements[i] : b.pose));
  }
}

void Ros2Bridge::publish_static_tf() {
  if (!static_tf_dirty_) return;
  static_tf_dirty_ = false;
  // One message with every static transform: a latched topic keeps only the
  // newest, so each message must hold them all (as tf2's static broadcaster).
  std::vector<TransformStamped> all;
  all.reserve(static_tf_.size());
  const Time stamp = ros_now();
  for (const auto& [child, entry] : static_tf_) {
    TransformStamped t{};
    t.header.stamp = stamp;
    t.header.frame_id = text(entry.first);
    t.child_frame_id = text(child);
    t.transform = entry.second;
    all.push_back(t);
  }
  TFMessage msg;
  msg.transforms = sequence_of<decltype(msg.transforms)>(all);
  const dds_return_t rc = dds_write(tf_static_, &msg);
  if (rc != DDS_RETCODE_OK)
    log_warn("%s: /tf_static: DDS write failed: %s", name_.c_str(), dds_strretcode(rc));
}

// ---- /diagnostics and the status device -------------------------------------------

void Ros2Bridge::publish_diagnostics() {
  // Everything the messages point at lives in `texts` while they are written.
  struct Texts {
    std::string name, message;
    std::vector<std::string> kv;  // key, value, key, value, ...
    std::vector<KeyValue> values;
  };
  const uint64_t now = node_->loop().now_us();
  std::vector<Texts> texts(devices_.size());
  std::vector<DiagnosticStatus> status(devices_.size());
  for (size_t i = 0; i < devices_.size(); ++i) {
    const Bridged& b = devices_[i];
    Texts& t = texts[i];
    DiagnosticStatus& s = status[i];
    s = DiagnosticStatus{};
    t.name = name_ + ": " + b.label;
    const double age_s = b.last_data_us ? double(now - b.last_data_us) / 1e6 : -1;
    char line[96];
    if (b.kind == Kind::Map) {
      s.level = b.map_published ? diagnostic_msgs_msg_dds__DiagnosticStatus_Constants_OK
                                : diagnostic_msgs_msg_dds__DiagnosticStatus_Constants_WARN;
      t.message = b.map_published ? "map published" : "fetching the map";
    } else if (b.stale) {
      s.level = diagnostic_msgs_msg_dds__DiagnosticStatus_Constants_STALE;
      std::snprintf(line, sizeof line, "stale: no data for %.1f s", age_s);
      t.message = line;
    } else if (b.last_data_us == 0) {
      const bool waited = now - start_us_ >= stale_after_us_;
      s.level = waited ? diagnostic_msgs_msg_dds__DiagnosticStatus_Constants_STALE
                       : diagnostic_msgs_msg_dds__DiagnosticStatus_Constants_WARN;
      t.message = waited ? "stale: no data since the bridge started" : "waiting for the first sample";
    } else {
      s.level = diagnostic_msgs_msg_dds__DiagnosticStatus_Constants_OK;
      t.message = "ok";
    }
    std::snprintf(line, sizeof line, "%.3f", age_s);
    t.kv = {"topic",   b.topic,
            "samples", std::to_string(b.samples),
            "age_s",   line,
            "clamped", std::to_string(b.clamped),
            "refused", std::to_string(b.refused),
            "problem", b.problem};
    if (!b.command_topic.empty()) t.kv.insert(t.kv.end(), {"command_topic", b.command_topic});
    for (size_t k = 0; k + 1 < t.kv.size(); k += 2) t.values.push_back({text(t.kv[k]), text(t.kv[k + 1])});
    s.name = text(t.name);
    s.message = text(t.message);
    s.hardware_id = text(b.label);
    s.values = sequence_of<decltype(s.values)>(t.values);
  }
  DiagnosticArray msg{};
  msg.header.stamp = ros_now();
  static const std::string kNoFrame;
  msg.header.frame_id = text(kNoFrame);
  msg.status = sequence_of<decltype(msg.status)>(status);
  dds_write(diagnostics_, &msg);
}

std::string Ros2Bridge::status_text() const {
  size_t stale = 0;
  uint64_t samples = 0, clamped = 0, refused = 0;
  for (const Bridged& b : devices_) {
    stale += b.stale;
    samples += b.samples;
    clamped += b.clamped;
    refused += b.refused;
  }
  char out[256];
  std::snprintf(out, sizeof out,
                "{\"domain\":%u,\"node\":\"%s\",\"devices\":%zu,\"stale\":%zu,\"samples\":%llu,"
                "\"clamped\":%llu,\"refused\":%llu,\"time\":\"%s\"}",
                domain_, graph_.name().c_str(), devices_.size(), stale, (unsigned long long)samples,
                (unsigned long long)clamped, (unsigned long long)refused, stamps_->sim() ? "sim" : "wall");
  return out;
}

void Ros2Bridge::publish_status() {
  if (status_ == kNoDevice) return;
  const std::string text = status_text();
  auto& fb = node_->begin();
  auto body = wire::CreateOpaqueBytes(
      fb, fb.CreateVector(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
  node_->publish(status_, uint8_t(wire::OpaqueSub::Bytes), wire::Body::OpaqueBytes, body.Union());
}

}  // namespace troupe::drivers::ros2
