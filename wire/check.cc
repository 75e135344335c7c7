#include "wire/check.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>

namespace troupe::wire {
namespace {

using I = Interface;
using K = Kind;

template <typename E>
constexpr uint8_t sub(E e) {
  return uint8_t(e);
}

// Indexed by nothing: a linear search over a few dozen rows is cheaper, in
// code and time, than any map on a small board.
constexpr BodyRule kRules[] = {
    {I::Position2d, K::Command, sub(Position2dCmdSub::Vel), Body::Position2dVel, true},
    {I::Position2d, K::Command, sub(Position2dCmdSub::Goto), Body::Position2dGoto, true},
    {I::Position2d, K::Request, sub(Position2dReqSub::Geometry), Body::NONE, false},
    {I::Position2d, K::Request, sub(Position2dReqSub::MotorPower), Body::Switch, true},
    {I::Position2d, K::Request, sub(Position2dReqSub::SetOdometry), Body::Position2dSetOdom, true},
    {I::Position2d, K::Request, sub(Position2dReqSub::ResetOdometry), Body::NONE, false},
    {I::Ranger, K::Request, sub(RangerReqSub::Geometry), Body::NONE, false},
    {I::Ranger, K::Request, sub(RangerReqSub::GetConfig), Body::NONE, false},
    {I::Ranger, K::Request, sub(RangerReqSub::SetConfig), Body::RangerConfig, true},
    {I::Ranger, K::Request, sub(RangerReqSub::Power), Body::Switch, true},
    {I::Bumper, K::Request, sub(BumperReqSub::Geometry), Body::NONE, false},
    {I::Fiducial, K::Request, sub(FiducialReqSub::Geometry), Body::NONE, false},
    {I::Actuator, K::Command, sub(ActuatorCmdSub::Action), Body::ActuatorCommand, true},
    {I::Localize, K::Request, sub(LocalizeReqSub::SetPose), Body::LocalizeSetPose, true},
    {I::Localize, K::Request, sub(LocalizeReqSub::Global), Body::NONE, false},
    {I::Map, K::Request, sub(MapReqSub::Info), Body::NONE, false},
    {I::Map, K::Request, sub(MapReqSub::Tile), Body::MapTileRequest, true},
    {I::Simulation, K::Request, sub(SimulationReqSub::Pause), Body::NONE, false},
    {I::Simulation, K::Request, sub(SimulationReqSub::Resume), Body::NONE, false},
    {I::Simulation, K::Request, sub(SimulationReqSub::Step), Body::SimStep, false},
    {I::Simulation, K::Request, sub(SimulationReqSub::SetSpeed), Body::SimSpeed, true},
    {I::Simulation, K::Request, sub(SimulationReqSub::GetPose), Body::SimModel, true},
    {I::Simulation, K::Request, sub(SimulationReqSub::SetPose), Body::SimPose, true},
    {I::Simulation, K::Request, sub(SimulationReqSub::Reset), Body::NONE, false},
    {I::Simulation, K::Request, sub(SimulationReqSub::GetClock), Body::NONE, false},
    {I::Simulation, K::Request, sub(SimulationReqSub::StartPlayer), Body::SimPlayer, true},
    {I::Simulation, K::Request, sub(SimulationReqSub::StopPlayer), Body::SimModel, true},
    {I::Simulation, K::Request, sub(SimulationReqSub::GetGame), Body::NONE, false},
    {I::Simulation, K::Request, sub(SimulationReqSub::Models), Body::NONE, false},
    {I::Opaque, K::Command, sub(OpaqueSub::Bytes), Body::OpaqueBytes, false},
    {I::Opaque, K::Request, sub(OpaqueSub::Bytes), Body::OpaqueBytes, false},
    {I::Camera, K::Request, sub(CameraReqSub::Geometry), Body::NONE, false},
    {I::Camera, K::Request, sub(CameraReqSub::GetConfig), Body::NONE, false},
    {I::Camera, K::Request, sub(CameraReqSub::SetConfig), Body::CameraConfig, true},
};

struct Range {
  float lo, hi;
  const char* unit;
};
constexpr Range kCoordinate{-kMaxCoordinate, kMaxCoordinate, "m"};
constexpr Range kAngle{-kMaxAngle, kMaxAngle, "rad"};
constexpr Range kVelocity{-kMaxSpeed, kMaxSpeed, "m/s"};
constexpr Range kTurnRate{-kMaxTurnRate, kMaxTurnRate, "rad/s"};
constexpr Range kSpeedLimit{0, kMaxSpeed, "m/s"};
constexpr Range kTurnLimit{0, kMaxTurnRate, "rad/s"};
constexpr Range kVariance{0, kMaxVariance, ""};
constexpr Range kCovariance{-kMaxVariance, kMaxVariance, ""};
constexpr Range kScanAngle{-kMaxScanAngle, kMaxScanAngle, "rad"};
constexpr Range kResolution{0, kMaxScanAngle, "rad"};
constexpr Range kRange{0, kMaxCoordinate, "m"};
constexpr Range kFrequency{0, kMaxFrequency, "Hz"};

// Fills the refusal; every check below returns through it.
class Check {
 public:
  explicit Check(Refusal& r) : r_(r) {}

  bool fail(ErrorCode code, const char* parent, const char* member, const char* format, ...)
      __attribute__((format(printf, 5, 6))) {
    r_.code = code;
    snprintf(r_.field, sizeof r_.field, "%s%s%s", parent, *member ? "." : "", member);
    va_list args;
    va_start(args, format);
    vsnprintf(r_.text, sizeof r_.text, format, args);
    va_end(args);
    return false;
  }

  bool present(const void* p, const char* parent, const char* member = "") {
    return p != nullptr || fail(ErrorCode::BadBody, parent, member, "%s%s%s is missing", parent,
                                *member ? "." : "", member);
  }

  bool number(float v, const Range& r, const char* parent, const char* member = "") {
    if (std::isfinite(v) && v >= r.lo && v <= r.hi) return true;
    return fail(ErrorCode::BadValue, parent, member, "%s%s%s is %g: it must be finite, from %g to %g%s%s", parent,
                *member ? "." : "", member, double(v), double(r.lo), double(r.hi), *r.unit ? " " : "", r.unit);
  }

  bool count(uint64_t v, uint64_t lo, uint64_t hi, const char* field) {
    if (v >= lo && v <= hi) return true;
    return fail(ErrorCode::BadValue, field, "", "%s is %llu: it must be from %llu to %llu", field,
                static_cast<unsigned long long>(v), static_cast<unsigned long long>(lo),
                static_cast<unsigned long long>(hi));
  }

  bool name(const flatbuffers::String* s, const char* field) {
    if (!present(s, field)) return false;
    return s->size() > 0 || fail(ErrorCode::BadValue, field, "", "%s is empty", field);
  }

  // A pose or velocity: x and y in `xy`, a in `a`. Absent is fine unless
  // `required`.
  bool pose(const Pose2d* p, bool required, const Range& xy, const Range& a, const char* field) {
    if (p == nullptr) return !required || present(p, field);
    return number(p->x(), xy, field, "x") && number(p->y(), xy, field, "y") && number(p->a(), a, field, "a");
  }

  bool ordered(float lo, float hi, const char* lo_name, const char* hi_name) {
    return lo <= hi || fail(ErrorCode::BadValue, hi_name, "", "%s (%g) is below %s (%g)", hi_name, double(hi),
                            lo_name, double(lo));
  }

 private:
  Refusal& r_;
};

bool check_ranger_config(Check& c, const RangerConfig& b) {
  return c.number(b.min_angle(), kScanAngle, "min_angle") && c.number(b.max_angle(), kScanAngle, "max_angle") &&
         c.ordered(b.min_angle(), b.max_angle(), "min_angle", "max_angle") &&
         c.number(b.angular_res(), kResolution, "angular_res") && c.number(b.min_range(), kRange, "min_range") &&
         c.number(b.max_range(), kRange, "max_range") &&
         c.ordered(b.min_range(), b.max_range(), "min_range", "max_range") &&
         c.number(b.range_res(), kRange, "range_res") && c.number(b.frequency(), kFrequency, "frequency");
}

bool check_covariance(Check& c, const Cov2d* v) {
  return v == nullptr ||
         (c.number(v->xx(), kVariance, "cov", "xx") && c.number(v->xy(), kCovariance, "cov", "xy") &&
          c.number(v->xa(), kCovariance, "cov", "xa") && c.number(v->yy(), kVariance, "cov", "yy") &&
          c.number(v->ya(), kCovariance, "cov", "ya") && c.number(v->aa(), kVariance, "cov", "aa"));
}

bool check_actuator(Check& c, const ActuatorCommand& b) {
  if (!c.count(uint64_t(b.action()), 0, uint64_t(ActuatorAction::MAX), "action")) return false;
  return b.action() == ActuatorAction::Kick ? c.number(b.value(), kSpeedLimit, "value")
                                            : c.number(b.value(), kCoordinate, "value");
}

// The values of a body a client may send. Bodies only nodes send (data,
// replies) have no rules here: a node refuses them from clients anyway.
bool check_body(Check& c, Body type, const void* body) {
  switch (type) {
    case Body::Hello: {
      uint32_t max_frame = static_cast<const Hello*>(body)->max_frame_bytes();
      return max_frame == 0 || c.count(max_frame, kMinFrameBytes, UINT32_MAX, "max_frame_bytes");
    }
    case Body::Open: {
      auto* b = static_cast<const Open*>(body);
      return c.count(uint64_t(b->access()), uint64_t(Access::Read), uint64_t(Access::All), "access") &&
             c.count(uint64_t(b->delivery()), 0, uint64_t(Delivery::MAX), "delivery") &&
             c.count(uint64_t(b->compression()), 0, uint64_t(ImageCompression::MAX), "compression");
    }
    case Body::Position2dVel:
      return c.pose(static_cast<const Position2dVel*>(body)->vel(), true, kVelocity, kTurnRate, "vel");
    case Body::Position2dGoto: {
      auto* b = static_cast<const Position2dGoto*>(body);
      return c.pose(b->pose(), true, kCoordinate, kAngle, "pose") &&
             c.pose(b->max_vel(), false, kSpeedLimit, kTurnLimit, "max_vel");
    }
    case Body::Position2dSetOdom:
      return c.pose(static_cast<const Position2dSetOdom*>(body)->pose(), true, kCoordinate, kAngle, "pose");
    case Body::RangerConfig: return check_ranger_config(c, *static_cast<const RangerConfig*>(body));
    case Body::ActuatorCommand: return check_actuator(c, *static_cast<const ActuatorCommand*>(body));
    case Body::LocalizeSetPose: {
      auto* b = static_cast<const LocalizeSetPose*>(body);
      return c.pose(b->mean(), true, kCoordinate, kAngle, "mean") && check_covariance(c, b->cov());
    }
    case Body::MapTileRequest: {
      auto* b = static_cast<const MapTileRequest*>(body);
      return c.count(b->width(), 1, kMaxTileCells, "width") && c.count(b->height(), 1, kMaxTileCells, "height") &&
             c.count(uint64_t(b->width()) * b->height(), 1, kMaxTileCells, "width*height");
    }
    case Body::CameraConfig: {
      auto* b = static_cast<const CameraConfig*>(body);
      return c.count(b->width(), 0, kMaxImageSide, "width") && c.count(b->height(), 0, kMaxImageSide, "height") &&
             c.number(b->rate(), Range{0, kMaxImageRate, "Hz"}, "rate") &&
             c.count(uint64_t(b->format()), 0, uint64_t(PixelFormat::MAX), "format");
    }
    case Body::SimStep: return c.count(static_cast<const SimStep*>(body)->steps(), 1, kMaxSteps, "steps");
    case Body::SimSpeed:
      return c.number(static_cast<const SimSpeed*>(body)->speed(), Range{0, kMaxSimSpeed, "x real time"}, "speed");
    case Body::SimModel: return c.name(static_cast<const SimModel*>(body)->name(), "name");
    case Body::SimPose: {
      auto* b = static_cast<const SimPose*>(body);
      return c.name(b->name(), "name") && c.pose(b->pose(), true, kCoordinate, kAngle, "pose") &&
             c.pose(b->velocity(), false, kVelocity, kTurnRate, "velocity");
    }
    case Body::SimPlayer: {
      auto* b = static_cast<const SimPlayer*>(body);
      return c.name(b->robot(), "robot") && c.name(b->plugin(), "plugin");
    }
    default: return true;
  }
}

const BodyRule* find_rule(uint16_t iface, Kind kind, uint8_t subtype) {
  for (const BodyRule& r : kRules) {
    if (uint16_t(r.iface) == iface && r.kind == kind && r.subtype == subtype) return &r;
  }
  return nullptr;
}

}  // namespace

std::span<const BodyRule> body_rules() { return kRules; }

bool check_message(const Message& msg, Refusal& why) {
  Check c(why);
  const Header& h = *msg.header();
  const Body type = msg.body_type();
  const char* type_name = EnumNameBody(type);
  if (type != Body::NONE && msg.body() == nullptr) {
    return c.fail(ErrorCode::BadBody, "body", "", "the body type is %s, but the body is missing", type_name);
  }
  const Kind kind = h.kind();
  if ((kind == Kind::Hello || kind == Kind::TimeSync) && type == Body::NONE) {
    return c.fail(ErrorCode::BadBody, "body", "", "a %s message needs its body", EnumNameKind(kind));
  }
  if (kind == Kind::Command || kind == Kind::Request) {
    const uint16_t iface = h.addr().iface();
    const BodyRule* rule = find_rule(iface, kind, h.subtype());
    const char* iface_name = interface_name(iface).data();  // the names are literals
    if (rule == nullptr && kind == Kind::Command) {
      return c.fail(ErrorCode::Unsupported, "", "", "%s has no command of subtype %u", iface_name,
                    unsigned(h.subtype()));
    }
    // A request subtype the schemas do not define is the driver's to answer
    // (its default: Nack Unsupported); its body, if any, is checked below.
    if (rule != nullptr && type != rule->body && !(type == Body::NONE && !rule->required)) {
      return c.fail(ErrorCode::BadBody, "body", "", "%s %s subtype %u takes %s, not %s", iface_name,
                    EnumNameKind(kind), unsigned(h.subtype()),
                    rule->body == Body::NONE ? "no body" : EnumNameBody(rule->body), type_name);
    }
  }
  return type == Body::NONE || check_body(c, type, msg.body());
}

}  // namespace troupe::wire
