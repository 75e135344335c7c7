#include "wire/message.h"

#include <array>

namespace troupe::wire {
namespace {

// Indexed by Interface code; append in the order of the enum.
constexpr std::array<std::string_view, 14> kInterfaceNames = {
    "none",     "position2d", "ranger",   "power", "bumper",     "blobfinder", "fiducial",
    "actuator", "imu",        "localize", "map",   "simulation", "opaque",     "camera"};

constexpr std::array<std::string_view, 13> kKindNames = {
    "invalid", "data",       "command", "request", "ack",      "nack", "hello",
    "devlist", "open",       "close",   "pull",    "timesync", "error"};

}  // namespace

std::string_view interface_name(uint16_t iface) {
  return iface < kInterfaceNames.size() ? kInterfaceNames[iface] : "unknown";
}

Interface interface_from_name(std::string_view name) {
  for (size_t i = 1; i < kInterfaceNames.size(); ++i) {
    if (kInterfaceNames[i] == name) return static_cast<Interface>(i);
  }
  return Interface::None;
}

std::string_view kind_name(Kind kind) {
  auto k = static_cast<size_t>(kind);
  return k < kKindNames.size() ? kKindNames[k] : "unknown";
}

uint16_t body_interface(Body body) {
  using I = Interface;
  auto code = [](I i) { return static_cast<uint16_t>(i); };
  switch (body) {
    case Body::NONE:
    case Body::Hello:
    case Body::DeviceList:
    case Body::Open:
    case Body::TimeSync:
    case Body::Error: return code(I::None);
    case Body::Switch: return kAnyInterface;
    case Body::Position2dState:
    case Body::Position2dVel:
    case Body::Position2dGoto:
    case Body::Position2dGeometry:
    case Body::Position2dSetOdom: return code(I::Position2d);
    case Body::RangerScan:
    case Body::RangerGeometry:
    case Body::RangerConfig: return code(I::Ranger);
    case Body::PowerState: return code(I::Power);
    case Body::BumperState:
    case Body::BumperGeometry: return code(I::Bumper);
    case Body::BlobList: return code(I::Blobfinder);
    case Body::FiducialList:
    case Body::FiducialGeometry: return code(I::Fiducial);
    case Body::ActuatorState:
    case Body::ActuatorCommand: return code(I::Actuator);
    case Body::ImuState: return code(I::Imu);
    case Body::LocalizeState:
    case Body::LocalizeSetPose: return code(I::Localize);
    case Body::MapInfo:
    case Body::MapTileRequest:
    case Body::MapTile: return code(I::Map);
    case Body::SimClock:
    case Body::SimStep:
    case Body::SimSpeed:
    case Body::SimModel:
    case Body::SimPose:
    case Body::SimGame:
    case Body::SimPlayer:
    case Body::SimModelList:
    case Body::SimPoses: return code(I::Simulation);
    case Body::OpaqueBytes: return code(I::Opaque);
    case Body::CameraImage:
    case Body::CameraGeometry:
    case Body::CameraConfig: return code(I::Camera);
  }
  return code(I::None);
}

bool body_fits(Kind kind, uint16_t iface, Body body) {
  if (!is_known_body(body)) return false;
  switch (kind) {
    case Kind::Hello: return body == Body::Hello;
    case Kind::DeviceList: return body == Body::NONE || body == Body::DeviceList;
    case Kind::Open: return body == Body::NONE || body == Body::Open;
    case Kind::Close:
    case Kind::Pull: return body == Body::NONE;
    case Kind::TimeSync: return body == Body::TimeSync;
    case Kind::Error:
    case Kind::Nack: return body == Body::NONE || body == Body::Error;
    case Kind::Data:
    case Kind::Command:
    case Kind::Request:
    case Kind::Ack: {
      if (body == Body::NONE) return kind != Kind::Data;
      uint16_t owner = body_interface(body);
      return owner == kAnyInterface || owner == iface;
    }
    case Kind::Invalid: return false;
  }
  return false;
}

}  // namespace troupe::wire
