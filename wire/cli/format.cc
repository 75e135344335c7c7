// How messages look on a terminal: one line of text per message, or JSON
// generated from the embedded schema (so every body prints, even ones this
// file has no special case for).
#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <memory>

#include "flatbuffers/idl.h"
#include "wire/address.h"
#include "wire/body_copy.h"
#include "wire/cli/cli.h"

namespace troupe::cli {
namespace {

void append(std::string& out, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
void append(std::string& out, const char* fmt, ...) {
  char buf[256];
  va_list args;
  va_start(args, fmt);
  int n = vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  if (n > 0) out.append(buf, size_t(n) < sizeof buf ? size_t(n) : sizeof buf - 1);
}

void pose(std::string& out, const char* name, const wire::Pose2d* p) {
  if (p) append(out, " %s=%.3f,%.3f,%.3f", name, double(p->x()), double(p->y()), double(p->a()));
}

void vec(std::string& out, const char* name, const wire::Vec3* v) {
  if (v) append(out, " %s=%.3f,%.3f,%.3f", name, double(v->x()), double(v->y()), double(v->z()));
}

flatbuffers::Parser& schema() {
  static std::unique_ptr<flatbuffers::Parser> parser = [] {
    flatbuffers::IDLOptions opts;
    opts.strict_json = true;
    opts.indent_step = -1;  // one line
    auto p = std::make_unique<flatbuffers::Parser>(opts);
    std::span<const uint8_t> bfbs = wire::message_schema();
    p->Deserialize(bfbs.data(), bfbs.size());
    return p;
  }();
  return *parser;
}

}  // namespace

// The header is printed here and only the body table goes to the FlatBuffers
// printer: given a whole Message whose union type is absent but whose body
// offset is not, libflatbuffers 2.0.8's printer reads garbage (our fuzzer
// found it). The verifier rightly ignores such a body, and so does this.
std::string to_json(const wire::Message& msg) {
  const wire::Header& h = *msg.header();
  std::string out;
  append(out, "{\"addr\": {\"robot\": %u, \"iface\": \"%s\", \"index\": %u}, ", unsigned(h.addr().robot()),
         std::string(wire::interface_name(h.addr().iface())).c_str(), unsigned(h.addr().index()));
  append(out, "\"kind\": \"%s\", \"subtype\": %u, \"seq\": %u, \"time_us\": %" PRIu64 ", ",
         std::string(wire::kind_name(h.kind())).c_str(), unsigned(h.subtype()), unsigned(h.seq()),
         wire::time_us(h));
  const char* type = wire::is_known_body(msg.body_type()) ? wire::EnumNameBody(msg.body_type()) : "unknown";
  append(out, "\"body_type\": \"%s\", \"body\": ", type);
  return out + body_json(msg) + "}";
}

std::string body_json(const wire::Message& msg) {
  if (msg.body_type() == wire::Body::NONE || !wire::is_known_body(msg.body_type()) || msg.body() == nullptr) {
    return "{}";
  }
  std::string name = std::string("troupe.wire.") + wire::EnumNameBody(msg.body_type());
  std::string json;
  if (!GenerateTextFromTable(schema(), msg.body(), name, &json)) return "{}";
  return json;
}

std::string summary(const wire::Message& msg) {
  const wire::Header& h = *msg.header();
  uint64_t t = wire::time_us(h);
  std::string out;
  append(out, "t=%" PRIu64 ".%06" PRIu64 " seq=%u", t / 1000000u, t % 1000000u, unsigned(h.seq()));
  switch (msg.body_type()) {
    case wire::Body::Position2dState: {
      auto* s = msg.body_as_Position2dState();
      pose(out, "pose", s->pose());
      pose(out, "vel", s->vel());
      append(out, " stall=%d", int(s->stall()));
      if (s->fault()) append(out, " fault=\"%s\"", s->fault()->c_str());
      if (auto* c = s->covariance()) {
        append(out, " cov=%.4g,%.4g,%.4g", double(c->xx()), double(c->yy()), double(c->aa()));
      }
      return out;
    }
    case wire::Body::RangerScan: {
      auto* s = msg.body_as_RangerScan();
      size_t n = s->ranges() ? s->ranges()->size() : 0;
      append(out, " n=%zu", n);
      if (s->angular_res() != 0) {
        append(out, " min_angle=%.4f res=%.4f", double(s->min_angle()), double(s->angular_res()));
      }
      append(out, " max_range=%.3f ranges=", double(s->max_range()));
      for (size_t i = 0; i < n; ++i) {
        append(out, i ? ",%.3f" : "%.3f", double(s->ranges()->Get(flatbuffers::uoffset_t(i)) * s->scale()));
      }
      return out;
    }
    case wire::Body::PowerState: {
      auto* s = msg.body_as_PowerState();
      if (s->volts()) append(out, " volts=%.2f", double(*s->volts()));
      if (s->percent()) append(out, " percent=%.1f", double(*s->percent()));
      if (s->watts()) append(out, " watts=%.2f", double(*s->watts()));
      if (s->charging()) append(out, " charging=%d", int(*s->charging()));
      return out;
    }
    case wire::Body::BumperState: {
      auto* s = msg.body_as_BumperState();
      append(out, " count=%u pressed=", unsigned(s->count()));
      for (unsigned i = 0; i < s->count() && i < 32; ++i) out.push_back((s->pressed() >> i) & 1u ? '1' : '0');
      return out;
    }
    case wire::Body::BlobList: {
      auto* s = msg.body_as_BlobList();
      size_t n = s->blobs() ? s->blobs()->size() : 0;
      append(out, " image=%ux%u blobs=%zu", unsigned(s->width()), unsigned(s->height()), n);
      for (size_t i = 0; i < n; ++i) {
        const wire::Blob* b = s->blobs()->Get(flatbuffers::uoffset_t(i));
        append(out, " [#%06x x=%u y=%u area=%u range=%.3f]", unsigned(b->color()), unsigned(b->x()),
               unsigned(b->y()), unsigned(b->area()), double(b->range_mm()) / 1000.0);
      }
      return out;
    }
    case wire::Body::CameraImage: {
      // The pixels are not text: their size and a checksum tell images apart.
      auto* s = msg.body_as_CameraImage();
      const size_t n = s->data() ? s->data()->size() : 0;
      uint32_t sum = 2166136261u;  // FNV-1a
      for (size_t i = 0; i < n; ++i) sum = (sum ^ s->data()->Get(flatbuffers::uoffset_t(i))) * 16777619u;
      append(out, " image=%ux%u format=%s stride=%u compression=%s bytes=%zu fnv=%08x", unsigned(s->width()),
             unsigned(s->height()), wire::EnumNamePixelFormat(s->format()), unsigned(s->stride()),
             wire::EnumNameImageCompression(s->compression()), n, unsigned(sum));
      return out;
    }
    case wire::Body::FiducialList: {
      auto* s = msg.body_as_FiducialList();
      size_t n = s->fiducials() ? s->fiducials()->size() : 0;
      append(out, " fiducials=%zu", n);
      for (size_t i = 0; i < n; ++i) {
        const wire::Fiducial* f = s->fiducials()->Get(flatbuffers::uoffset_t(i));
        const bool typed = s->kinds() && i < s->kinds()->size();
        const auto kind = typed ? wire::FiducialKind(s->kinds()->Get(flatbuffers::uoffset_t(i))) : wire::FiducialKind::Generic;
        append(out, " [%s id=%d x=%.3f y=%.3f yaw=%.3f]", wire::EnumNameFiducialKind(kind),
               int(f->id()), double(f->x()), double(f->y()), double(f->yaw()));
      }
      return out;
    }
    case wire::Body::ActuatorState: {
      auto* s = msg.body_as_ActuatorState();
      append(out, " mode=%s position=%.3f beams=0x%x stored=%u", wire::EnumNameActuatorMode(s->mode()),
             double(s->position()), unsigned(s->beams()), unsigned(s->stored()));
      return out;
    }
    case wire::Body::ImuState: {
      auto* s = msg.body_as_ImuState();
      vec(out, "gyro", s->gyro());
      vec(out, "accel", s->accel());
      vec(out, "rpy", s->orientation());
      return out;
    }
    case wire::Body::LocalizeState: {
      auto* s = msg.body_as_LocalizeState();
      size_t n = s->hypotheses() ? s->hypotheses()->size() : 0;
      append(out, " hypotheses=%zu", n);
      for (size_t i = 0; i < n; ++i) {
        const wire::Hypothesis* hyp = s->hypotheses()->Get(flatbuffers::uoffset_t(i));
        append(out, " [%.3f,%.3f,%.3f w=%.3f]", double(hyp->mean().x()), double(hyp->mean().y()),
               double(hyp->mean().a()), double(hyp->weight()));
      }
      return out;
    }
    case wire::Body::SimClock: {
      auto* s = msg.body_as_SimClock();
      append(out, " sim_time=%.3f steps=%" PRIu64 " paused=%d speed=%.2f rtf=%.2f",
             double(s->sim_time_us()) / 1e6, uint64_t(s->steps()), int(s->paused()), double(s->speed()),
             double(s->real_time_factor()));
      return out;
    }
    case wire::Body::OpaqueBytes: {
      // Text (a passthrough's status, a JSON note between clients) reads
      // better as text than as a list of numbers.
      auto* o = msg.body_as_OpaqueBytes();
      bool text = o->bytes() != nullptr && o->bytes()->size() > 0;
      for (size_t i = 0; text && i < o->bytes()->size(); ++i) {
        uint8_t c = o->bytes()->Get(flatbuffers::uoffset_t(i));
        text = c >= 0x20 && c < 0x7f;
      }
      if (!text) break;
      out += " text=";
      out.append(reinterpret_cast<const char*>(o->bytes()->data()), o->bytes()->size());
      return out;
    }
    default:
      break;
  }
  out += " ";
  out += wire::EnumNameBody(msg.body_type());
  out += " ";
  out += body_json(msg);
  return out;
}

}  // namespace troupe::cli
