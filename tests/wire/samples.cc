#include "tests/wire/samples.h"

#include "wire/writer.h"

namespace troupe::testing {

using wire::Body;

flatbuffers::Offset<void> sample_body(flatbuffers::FlatBufferBuilder& b, Body type) {
  switch (type) {
    case Body::Position2dVel: {
      wire::Pose2d vel(0.3f, 0.1f, 0.2f);
      return wire::CreatePosition2dVel(b, &vel).Union();
    }
    case Body::Position2dGoto: {
      wire::Pose2d pose(1.5f, -0.5f, 0.7f), max_vel(0.4f, 0.1f, 0.5f);
      return wire::CreatePosition2dGoto(b, &pose, &max_vel).Union();
    }
    case Body::Position2dSetOdom: {
      wire::Pose2d pose(0.25f, 0.5f, 0.1f);
      return wire::CreatePosition2dSetOdom(b, &pose).Union();
    }
    case Body::Switch: return wire::CreateSwitch(b, true).Union();
    case Body::RangerConfig:
      return wire::CreateRangerConfig(b, -1.5f, 1.5f, 0.01f, 0.1f, 5.0f, 0.01f, 10.0f).Union();
    case Body::ActuatorCommand: return wire::CreateActuatorCommand(b, wire::ActuatorAction::Goto, 0.05f).Union();
    case Body::LocalizeSetPose: {
      wire::Pose2d mean(1.0f, 2.0f, 0.3f);
      wire::Cov2d cov(0.25f, 0.01f, 0.02f, 0.25f, 0.03f, 0.1f);
      return wire::CreateLocalizeSetPose(b, &mean, &cov).Union();
    }
    case Body::MapTileRequest: return wire::CreateMapTileRequest(b, 1, 2, 8, 8).Union();
    case Body::SimStep: return wire::CreateSimStep(b, 2).Union();
    case Body::SimSpeed: return wire::CreateSimSpeed(b, 2.0f).Union();
    case Body::SimModel: return wire::CreateSimModel(b, b.CreateString("r0")).Union();
    case Body::SimPose: {
      wire::Pose2d pose(0.5f, 0.5f, 0.2f), velocity(0.1f, 0.1f, 0.1f);
      auto name = b.CreateString("r0");
      return wire::CreateSimPose(b, name, &pose, &velocity).Union();
    }
    case Body::SimPlayer: {
      std::vector<flatbuffers::Offset<flatbuffers::String>> options = {b.CreateString("policy=block")};
      auto robot = b.CreateString("r0");
      auto plugin = b.CreateString("goalkeeper");
      return wire::CreateSimPlayer(b, robot, plugin, b.CreateVector(options)).Union();
    }
    case Body::CameraConfig: return wire::CreateCameraConfig(b, 64, 48, 10.0f, wire::PixelFormat::DepthU16).Union();
    case Body::OpaqueBytes: return wire::CreateOpaqueBytes(b, b.CreateVector(std::vector<uint8_t>{1, 2, 3})).Union();
    default: return 0;
  }
}

std::vector<WireSample> wire_samples() {
  std::vector<WireSample> out;
  wire::MessageWriter w;
  auto save = [&](std::string name, std::span<const uint8_t> frame) {
    out.push_back({std::move(name), {frame.begin(), frame.end()}});
  };
  auto seq = [&] { return uint32_t(1000 + out.size()); };
  const wire::Address pos(0, uint16_t(wire::Interface::Position2d), 0);
  {
    auto& b = w.start();
    auto body = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("samples"), 1u << 20, 0, 99);
    save("hello", w.finish(wire::make_header({}, wire::Kind::Hello, 0, 0, 5), Body::Hello, body.Union()));
  }
  save("devicelist", w.empty(wire::make_header({}, wire::Kind::DeviceList, 0, seq(), 5)));
  {
    auto& b = w.start();
    auto body = wire::CreateTimeSync(b, 12345);
    save("timesync", w.finish(wire::make_header({}, wire::Kind::TimeSync, 0, seq(), 5), Body::TimeSync, body.Union()));
  }
  {
    auto& b = w.start();
    auto body = wire::CreateOpen(b, wire::Access::Read, wire::Delivery::Pull, wire::ImageCompression::Png);
    save("open", w.finish(wire::make_header(pos, wire::Kind::Open, 0, seq(), 5), Body::Open, body.Union()));
  }
  save("pull", w.empty(wire::make_header(pos, wire::Kind::Pull, 0, seq(), 5)));
  save("close", w.empty(wire::make_header(pos, wire::Kind::Close, 0, seq(), 5)));
  for (const wire::BodyRule& r : wire::body_rules()) {
    const wire::Address a(0, uint16_t(r.iface), 0);
    auto& b = w.start();
    auto body = sample_body(b, r.body);
    std::string name = std::string(wire::interface_name(uint16_t(r.iface))) + "-" +
                       std::string(wire::kind_name(r.kind)) + "-" + std::to_string(r.subtype);
    save(name, w.finish(wire::make_header(a, r.kind, r.subtype, seq(), 5), r.body, body));
  }
  return out;
}

}  // namespace troupe::testing
