#include "wire/body_copy.h"

extern const unsigned char troupe_message_bfbs[];
extern const unsigned troupe_message_bfbs_size;

namespace troupe::wire {

std::span<const uint8_t> message_schema() {
  return {troupe_message_bfbs, troupe_message_bfbs_size};
}

BodyCopier::BodyCopier() : bfbs_(message_schema().begin(), message_schema().end()) {
  // The embedded array is only byte-aligned; the copy is aligned for the verifier.
  flatbuffers::Verifier verifier(bfbs_.data(), bfbs_.size());
  if (!reflection::VerifySchemaBuffer(verifier)) return;
  const reflection::Schema* schema = reflection::GetSchema(bfbs_.data());
  const reflection::Field* body = schema->root_table()->fields()->LookupByKey("body");
  if (body == nullptr || body->type()->base_type() != reflection::Union) return;
  for (const reflection::EnumVal* v : *schema->enums()->Get(uint32_t(body->type()->index()))->values()) {
    if (v->union_type() == nullptr || v->union_type()->base_type() != reflection::Obj) continue;
    size_t type = size_t(v->value());
    if (by_type_.size() <= type) by_type_.resize(type + 1, nullptr);
    by_type_[type] = schema->objects()->Get(uint32_t(v->union_type()->index()));
  }
  schema_ = schema;
}

bool BodyCopier::can_copy(Body type) const {
  size_t t = size_t(type);
  return t < by_type_.size() && by_type_[t] != nullptr;
}

flatbuffers::Offset<void> BodyCopier::copy(flatbuffers::FlatBufferBuilder& fbb, const Message& msg) const {
  const auto* body = static_cast<const flatbuffers::Table*>(msg.body());
  if (schema_ == nullptr || body == nullptr || !can_copy(msg.body_type())) return 0;
  return flatbuffers::Offset<void>(
      flatbuffers::CopyTable(fbb, *schema_, *by_type_[size_t(msg.body_type())], *body).o);
}

const BodyCopier& body_copier() {
  static const BodyCopier copier;
  return copier;
}

}  // namespace troupe::wire
