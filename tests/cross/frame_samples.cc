#include "tests/cross/frame_samples.h"

#include <cstdio>
#include <type_traits>

#include "wire/frame.h"
#include "wire/writer.h"

namespace troupe::cross {
namespace {

using wire::Body;
using wire::Kind;

// Values chosen so that every byte of a field differs from its neighbours:
// a swapped or shifted byte cannot go unnoticed.
const wire::Address kPositionAddr(0x1234, uint16_t(wire::Interface::Position2d), 0x0102);
const wire::Address kRangerAddr(0x0003, uint16_t(wire::Interface::Ranger), 0x0001);
constexpr uint64_t kTimeUs = 0x0123456789ABCDEFull;
constexpr uint32_t kSeq = 0xDEADBEEFu;
constexpr uint16_t kRanges[] = {0x0102, 0x0304, 0xFFFE, 0x0000, 0x8001, 0x7FFF};
constexpr uint8_t kIntensities[] = {1, 2, 254, 255};
constexpr uint64_t kClientSendUs = 0x1122334455667788ull;
constexpr uint64_t kNodeRecvUs = 0x99AABBCCDDEEFF00ull;
constexpr uint64_t kNodeSendUs = 0x0F1E2D3C4B5A6978ull;
constexpr int kSamples = 6;

void add_frame(wire::MessageWriter& w, std::vector<uint8_t>& out) {
  std::span<const uint8_t> f = w.frame();
  out.insert(out.end(), f.begin(), f.end());
}

// Collects the first difference; later checks are skipped once one failed.
class Checker {
 public:
  Checker(int frame, size_t offset) : frame_(frame), offset_(offset) {}
  template <typename T>
  void equal(const std::string& field, T got, T want) {
    if (!error_.empty() || got == want) return;
    char text[200];
    if constexpr (std::is_floating_point_v<T>) {
      snprintf(text, sizeof text, "frame %d (byte %zu): %s is %.9g, expected %.9g", frame_, offset_,
               field.c_str(), double(got), double(want));
    } else {
      snprintf(text, sizeof text, "frame %d (byte %zu): %s is 0x%llx, expected 0x%llx", frame_, offset_,
               field.c_str(), static_cast<unsigned long long>(got), static_cast<unsigned long long>(want));
    }
    error_ = text;
  }
  void require(const char* what, bool ok) {
    if (!error_.empty() || ok) return;
    error_ = "frame " + std::to_string(frame_) + " (byte " + std::to_string(offset_) + "): " + what;
  }
  void header(const wire::Message& m, const wire::Address& addr, Kind kind, uint8_t subtype, uint32_t seq,
              uint64_t time) {
    const wire::Header& h = *m.header();
    equal("header.robot", h.addr().robot(), addr.robot());
    equal("header.iface", h.addr().iface(), addr.iface());
    equal("header.index", h.addr().index(), addr.index());
    equal("header.kind", unsigned(h.kind()), unsigned(kind));
    equal("header.subtype", unsigned(h.subtype()), unsigned(subtype));
    equal("header.seq", h.seq(), seq);
    equal("header.time_us", wire::time_us(h), time);
  }
  const std::string& error() const { return error_; }

 private:
  int frame_;
  size_t offset_;
  std::string error_;
};

void check_position(Checker& c, const wire::Message& m) {
  c.header(m, kPositionAddr, Kind::Data, uint8_t(wire::Position2dDataSub::State), kSeq, kTimeUs);
  const wire::Position2dState* s = m.body_as_Position2dState();
  c.require("body is not Position2dState", s && s->pose() && s->vel() && s->covariance());
  if (!c.error().empty()) return;
  c.equal("pose.x", s->pose()->x(), 1.5f);
  c.equal("pose.y", s->pose()->y(), -2.25f);
  c.equal("pose.a", s->pose()->a(), 3.14159274f);
  c.equal("vel.x", s->vel()->x(), 0.5f);
  c.equal("vel.a", s->vel()->a(), -0.75f);
  c.equal("stall", s->stall(), true);
  c.equal("covariance.xx", s->covariance()->xx(), 1e-3f);
  c.equal("covariance.aa", s->covariance()->aa(), 1e-30f);
}

void check_ranger(Checker& c, const wire::Message& m) {
  c.header(m, kRangerAddr, Kind::Data, uint8_t(wire::RangerDataSub::Scan), 7, 1);
  const wire::RangerScan* s = m.body_as_RangerScan();
  c.require("body is not RangerScan", s && s->ranges() && s->intensities());
  if (!c.error().empty()) return;
  c.equal("ranges.size", size_t(s->ranges()->size()), std::size(kRanges));
  c.equal("intensities.size", size_t(s->intensities()->size()), std::size(kIntensities));
  if (!c.error().empty()) return;
  for (size_t i = 0; i < std::size(kRanges); ++i) {
    c.equal("ranges[" + std::to_string(i) + "]", s->ranges()->Get(uint32_t(i)), kRanges[i]);
  }
  for (size_t i = 0; i < std::size(kIntensities); ++i) {
    c.equal("intensities[" + std::to_string(i) + "]", s->intensities()->Get(uint32_t(i)), kIntensities[i]);
  }
  c.equal("scale", s->scale(), 0.002f);
  c.equal("min_angle", s->min_angle(), -1.57079637f);
  c.equal("angular_res", s->angular_res(), 0.00872664619f);
  c.equal("max_range", s->max_range(), 81.92f);
}

void check_device_list(Checker& c, const wire::Message& m) {
  c.header(m, {}, Kind::DeviceList, 0, 42, kTimeUs);
  const wire::DeviceList* l = m.body_as_DeviceList();
  c.require("body is not DeviceList", l && l->devices() && l->devices()->size() == 2);
  if (!c.error().empty()) return;
  const wire::DeviceInfo* d = l->devices()->Get(1);
  c.require("devices[1] lacks fields", d->addr() && d->robot_name() && d->driver());
  if (!c.error().empty()) return;
  c.equal("devices[1].iface", d->addr()->iface(), kRangerAddr.iface());
  c.require("devices[1].robot_name is not \"r3\"", d->robot_name()->str() == "r3");
  c.require("devices[1].driver is not \"sicklms200\"", d->driver()->str() == "sicklms200");
}

void check_command(Checker& c, const wire::Message& m) {
  c.header(m, kPositionAddr, Kind::Command, uint8_t(wire::Position2dCmdSub::Vel), 9, 0);
  const wire::Position2dVel* v = m.body_as_Position2dVel();
  c.require("body is not Position2dVel", v && v->vel());
  if (!c.error().empty()) return;
  c.equal("vel.x", v->vel()->x(), -0.125f);
  c.equal("vel.a", v->vel()->a(), 1.0e6f);
}

void check_time_sync(Checker& c, const wire::Message& m) {
  c.header(m, {}, Kind::TimeSync, 0, 0xFFFFFFFFu, ~uint64_t{0});
  const wire::TimeSync* t = m.body_as_TimeSync();
  c.require("body is not TimeSync", t != nullptr);
  if (!c.error().empty()) return;
  c.equal("client_send_us", t->client_send_us(), kClientSendUs);
  c.equal("node_recv_us", t->node_recv_us(), kNodeRecvUs);
  c.equal("node_send_us", t->node_send_us(), kNodeSendUs);
}

void check_error(Checker& c, const wire::Message& m) {
  c.header(m, {}, Kind::Error, 0, 0, 0);
  const wire::Error* e = m.body_as_Error();
  c.require("body is not Error", e && e->text());
  if (!c.error().empty()) return;
  c.equal("code", unsigned(e->code()), unsigned(wire::ErrorCode::VersionMismatch));
  c.require("text differs", e->text()->str() == "big-endian \xce\xbc");
}

}  // namespace

int sample_count() {
  return kSamples;
}

void write_samples(std::vector<uint8_t>& out) {
  wire::MessageWriter w;
  {
    auto& b = w.start();
    wire::Pose2d pose(1.5f, -2.25f, 3.14159274f), vel(0.5f, 0, -0.75f);
    wire::Cov2d cov(1e-3f, 0, 0, 1e-3f, 0, 1e-30f);
    auto body = wire::CreatePosition2dState(b, &pose, &vel, true, &cov);
    w.finish(
        wire::make_header(kPositionAddr, Kind::Data, uint8_t(wire::Position2dDataSub::State), kSeq, kTimeUs),
        Body::Position2dState, body.Union());
    add_frame(w, out);
  }
  {
    auto& b = w.start();
    auto ranges = b.CreateVector(kRanges, std::size(kRanges));
    auto intensities = b.CreateVector(kIntensities, std::size(kIntensities));
    auto body = wire::CreateRangerScan(b, ranges, 0.002f, -1.57079637f, 0.00872664619f, 81.92f, intensities);
    w.finish(wire::make_header(kRangerAddr, Kind::Data, uint8_t(wire::RangerDataSub::Scan), 7, 1),
             Body::RangerScan, body.Union());
    add_frame(w, out);
  }
  {
    auto& b = w.start();
    // One string per statement: the order of a call's arguments is
    // unspecified, and compilers for different targets pick different ones
    // (the bytes would differ, not the decoded values).
    auto robot0 = b.CreateString("");
    auto driver0 = b.CreateString("p2os");
    auto first = wire::CreateDeviceInfo(b, &kPositionAddr, robot0, driver0);
    auto robot1 = b.CreateString("r3");
    auto driver1 = b.CreateString("sicklms200");
    auto second = wire::CreateDeviceInfo(b, &kRangerAddr, robot1, driver1);
    flatbuffers::Offset<wire::DeviceInfo> infos[] = {first, second};
    auto body = wire::CreateDeviceList(b, b.CreateVector(infos, 2));
    w.finish(wire::make_header({}, Kind::DeviceList, 0, 42, kTimeUs), Body::DeviceList, body.Union());
    add_frame(w, out);
  }
  {
    auto& b = w.start();
    wire::Pose2d vel(-0.125f, 0, 1.0e6f);
    auto body = wire::CreatePosition2dVel(b, &vel);
    w.finish(wire::make_header(kPositionAddr, Kind::Command, uint8_t(wire::Position2dCmdSub::Vel), 9, 0),
             Body::Position2dVel, body.Union());
    add_frame(w, out);
  }
  {
    auto& b = w.start();
    auto body = wire::CreateTimeSync(b, kClientSendUs, kNodeRecvUs, kNodeSendUs);
    w.finish(wire::make_header({}, Kind::TimeSync, 0, 0xFFFFFFFFu, ~uint64_t{0}), Body::TimeSync,
             body.Union());
    add_frame(w, out);
  }
  {
    auto& b = w.start();
    auto body = wire::CreateError(b, wire::ErrorCode::VersionMismatch, b.CreateString("big-endian \xce\xbc"));
    w.finish(wire::make_header({}, Kind::Error, 0, 0, 0), Body::Error, body.Union());
    add_frame(w, out);
  }
}

std::string check_samples(std::span<const uint8_t> bytes) {
  using Check = void (*)(Checker&, const wire::Message&);
  const Check checks[kSamples] = {check_position, check_ranger,    check_device_list,
                                  check_command,  check_time_sync, check_error};
  size_t offset = 0;
  for (int i = 0; i < kSamples; ++i) {
    if (bytes.size() - offset < wire::kPrefixBytes) {
      return "frame " + std::to_string(i) + " (byte " + std::to_string(offset) + "): missing; the data ends";
    }
    uint64_t size = uint64_t{wire::read_prefix(bytes.data() + offset)} + wire::kPrefixBytes;
    if (size > bytes.size() - offset) {
      return "frame " + std::to_string(i) + " (byte " + std::to_string(offset) + "): the prefix announces " +
             std::to_string(size) + " bytes, " + std::to_string(bytes.size() - offset) + " remain";
    }
    wire::VerifyError why{};
    const wire::Message* m = wire::verify_frame(bytes.subspan(offset, size_t(size)), wire::Limits{}, &why);
    if (m == nullptr) {
      return "frame " + std::to_string(i) + " (byte " + std::to_string(offset) +
             "): refused: " + std::string(wire::verify_error_text(why));
    }
    Checker c(i, offset);
    checks[i](c, *m);
    if (!c.error().empty()) return c.error();
    offset += size_t(size);
  }
  if (offset != bytes.size()) {
    return std::to_string(bytes.size() - offset) + " bytes after the last frame (byte " +
           std::to_string(offset) + ")";
  }
  return "";
}

}  // namespace troupe::cross
