#include "tests/runtime/value_probe.h"

#include <gtest/gtest.h>

#include <cstring>

#include "flatbuffers/reflection.h"

extern const unsigned char troupe_message_bfbs[];

namespace troupe::testing {
namespace {

const reflection::Schema& schema() { return *reflection::GetSchema(troupe_message_bfbs); }

bool is_unsigned(reflection::BaseType t) {
  return t == reflection::UByte || t == reflection::UShort || t == reflection::UInt || t == reflection::ULong;
}

size_t scalar_bytes(reflection::BaseType t) {
  switch (t) {
    case reflection::UByte: return 1;
    case reflection::UShort: return 2;
    case reflection::ULong: return 8;
    default: return 4;
  }
}

}  // namespace

std::vector<ValueSite> value_sites(std::span<const uint8_t> frame) {
  std::vector<ValueSite> sites;
  const wire::Message* msg = wire::verify_frame(frame, wire::Limits{});
  if (msg == nullptr || msg->body() == nullptr) return sites;
  std::string name = std::string("troupe.wire.") + wire::EnumNameBody(msg->body_type());
  const reflection::Object* object = schema().objects()->LookupByKey(name.c_str());
  EXPECT_NE(object, nullptr) << name;
  if (object == nullptr) return sites;
  auto* table = reinterpret_cast<const flatbuffers::Table*>(msg->body());
  for (const reflection::Field* f : *object->fields()) {
    const reflection::BaseType t = f->type()->base_type();
    const bool number = t == reflection::Float || is_unsigned(t);
    const reflection::Object* inner =
        t == reflection::Obj ? schema().objects()->Get(uint32_t(f->type()->index())) : nullptr;
    if (!number && !(inner && inner->is_struct())) continue;  // strings, vectors, bools: no range
    const uint8_t* at = table->GetAddressOf(f->offset());
    EXPECT_NE(at, nullptr) << name << "." << f->name()->str() << " is not set in the sample";
    if (at == nullptr) continue;
    const size_t base = size_t(at - frame.data());
    if (number) {
      ValueSite s{f->name()->str(), base, ValueSite::Type::Float, scalar_bytes(t)};
      if (t != reflection::Float) s.type = f->type()->index() >= 0 ? ValueSite::Type::Enum : ValueSite::Type::Unsigned;
      sites.push_back(s);
      continue;
    }
    for (const reflection::Field* m : *inner->fields()) {
      if (m->type()->base_type() != reflection::Float) continue;
      sites.push_back({f->name()->str() + "." + m->name()->str(), base + m->offset(), ValueSite::Type::Float, 4});
    }
  }
  return sites;
}

std::vector<uint8_t> with_float(std::span<const uint8_t> frame, const ValueSite& site, float value) {
  std::vector<uint8_t> out(frame.begin(), frame.end());
  std::memcpy(out.data() + site.offset, &value, sizeof value);  // little-endian host, as the wire
  return out;
}

std::vector<uint8_t> with_unsigned(std::span<const uint8_t> frame, const ValueSite& site, uint64_t value) {
  std::vector<uint8_t> out(frame.begin(), frame.end());
  std::memcpy(out.data() + site.offset, &value, site.bytes);
  return out;
}

Answer exchange(RawConnection& raw, std::span<const uint8_t> frame, uint32_t seq) {
  Answer a;
  std::vector<uint8_t> copy(frame.begin(), frame.end());
  const wire::Message* m = wire::trusted_message(copy);
  const wire::Kind kind = m->header()->kind();
  // seq sits after the address (6 bytes), kind and subtype in the header.
  std::memcpy(const_cast<uint8_t*>(reinterpret_cast<const uint8_t*>(m->header())) + 8, &seq, 4);
  if (!raw.send_bytes(copy)) return a;
  const uint32_t barrier = seq ^ 0x80000000u;
  if (kind == wire::Kind::Command && !raw.send_bytes(empty_frame({}, wire::Kind::DeviceList, 0, barrier))) return a;
  for (;;) {
    auto f = raw.read_frame(5000);
    if (f.empty()) return a;
    const wire::Message* r = wire::verify_frame(f, wire::Limits{});
    if (r == nullptr) return a;
    const wire::Header& h = *r->header();
    if (h.kind() == wire::Kind::DeviceList && h.seq() == barrier) {
      a.ok = true;
      return a;
    }
    if (h.seq() != seq || h.kind() == wire::Kind::Data) continue;
    a.replied = true;
    a.kind = h.kind();
    a.seq = h.seq();
    if (const wire::Error* e = r->body_as_Error()) {
      a.code = e->code();
      a.text = e->text() ? e->text()->str() : "";
    }
    if (kind != wire::Kind::Command || h.kind() == wire::Kind::Error) {
      a.ok = h.kind() != wire::Kind::Error;
      return a;
    }
  }
}

}  // namespace troupe::testing
