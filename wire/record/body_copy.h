// Copies a message's body into another builder without knowing its type at
// compile time, through the reflection schema of wire/schemas (message.bfbs,
// embedded at build time). The replay driver republishes recorded bodies
// this way: Node::publish() takes a body built in the node's own builder.
#pragma once

#include <flatbuffers/reflection.h>

#include <vector>

#include "wire/message.h"

namespace troupe::record {

class BodyCopier {
 public:
  BodyCopier();
  /// False when the embedded schema did not verify (a build problem).
  bool ok() const { return schema_ != nullptr; }
  /// True when this build knows `type` and can copy it.
  bool can_copy(wire::Body type) const;
  /// Copies the (verified) message's body into `fbb`; 0 when it has none or
  /// its type is one this build does not know.
  flatbuffers::Offset<void> copy(flatbuffers::FlatBufferBuilder& fbb, const wire::Message& msg) const;

 private:
  std::vector<uint8_t> bfbs_;  // an aligned copy of the embedded schema
  const reflection::Schema* schema_ = nullptr;
  std::vector<const reflection::Object*> by_type_;  // indexed by Body value
};

}  // namespace troupe::record
