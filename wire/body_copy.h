// Copies a message's body into another builder without knowing its type at
// compile time, through the protocol's reflection schema (message.bfbs,
// embedded once at build time). The replay driver republishes recorded
// bodies this way, and passthrough forwards bodies it does not interpret (a
// scan, a map tile, a reply to any request): a body type added to
// wire/schemas later is copied without a change here.
#pragma once

#include <flatbuffers/reflection.h>

#include <span>
#include <vector>

#include "wire/message.h"

namespace troupe::wire {

/// The protocol's binary schema (message.bfbs), as embedded.
std::span<const uint8_t> message_schema();

class BodyCopier {
 public:
  BodyCopier();
  /// False when the embedded schema did not verify (a build problem).
  bool ok() const { return schema_ != nullptr; }
  /// True when this build knows `type` and can copy it.
  bool can_copy(Body type) const;
  /// Copies the (verified) message's body into `fbb`, which must have no
  /// table open; 0 when it has none or its type is one this build does not
  /// know (is_known_body() tells the two apart).
  flatbuffers::Offset<void> copy(flatbuffers::FlatBufferBuilder& fbb, const Message& msg) const;

 private:
  std::vector<uint8_t> bfbs_;  // an aligned copy of the embedded schema
  const reflection::Schema* schema_ = nullptr;
  std::vector<const reflection::Object*> by_type_;  // indexed by Body value
};

/// One copier for the whole process, built on first use.
const BodyCopier& body_copier();

}  // namespace troupe::wire
