#include "drivers/passthrough/body_copy.h"

#include <flatbuffers/reflection.h>

#include <array>
#include <vector>

extern const unsigned char troupe_passthrough_message_bfbs[];
extern const unsigned troupe_passthrough_message_bfbs_size;

namespace troupe::drivers::passthrough {
namespace {

// The schema's table for each Body type, found once.
class BodyTypes {
 public:
  BodyTypes() {
    // Copied out of the embedded array, which has no alignment guarantee:
    // FlatBuffers reads scalars in place.
    bytes_.assign(troupe_passthrough_message_bfbs,
                  troupe_passthrough_message_bfbs + troupe_passthrough_message_bfbs_size);
    schema_ = reflection::GetSchema(bytes_.data());
    const reflection::Object* message = schema_->root_table();
    const reflection::Field* body = message ? message->fields()->LookupByKey("body") : nullptr;
    if (body == nullptr) return;  // caught by the passthrough test: every copy would fail
    const reflection::Enum* body_enum = schema_->enums()->Get(body->type()->index());
    for (const reflection::EnumVal* v : *body_enum->values()) {
      int64_t value = v->value();
      if (value <= 0 || value >= int64_t(objects_.size()) || v->union_type() == nullptr) continue;
      objects_[size_t(value)] = schema_->objects()->Get(uint32_t(v->union_type()->index()));
    }
  }
  const reflection::Schema& schema() const { return *schema_; }
  const reflection::Object* object(wire::Body type) const { return objects_[size_t(type)]; }

 private:
  std::vector<uint8_t> bytes_;
  const reflection::Schema* schema_ = nullptr;
  std::array<const reflection::Object*, 256> objects_{};
};

const BodyTypes& body_types() {
  static const BodyTypes types;
  return types;
}

}  // namespace

flatbuffers::Offset<void> copy_body(flatbuffers::FlatBufferBuilder& fbb, const wire::Message& msg) {
  if (msg.body() == nullptr) return 0;
  const BodyTypes& types = body_types();
  const reflection::Object* object = types.object(msg.body_type());
  if (object == nullptr) return 0;
  auto copied = flatbuffers::CopyTable(fbb, types.schema(), *object,
                                       *static_cast<const flatbuffers::Table*>(msg.body()));
  return flatbuffers::Offset<void>(copied.o);
}

}  // namespace troupe::drivers::passthrough
