// Copies a message body, whatever its type, from a received frame into a
// builder. The passthrough forwards bodies it does not interpret (a scan, a
// map tile, a reply to any request), so it copies them by the protocol's own
// binary schema (embedded at build time): a body type added to the schema
// later is forwarded without a change here.
#pragma once

#include <flatbuffers/flatbuffers.h>

#include "wire/message.h"

namespace troupe::drivers::passthrough {

/// Copies `msg`'s body into `fbb` (which must have no table open). Returns
/// a null offset when the message has no body or its type is unknown to
/// this build; check with is_known_body() first to tell the two apart.
/// `msg` must come from a verified frame.
flatbuffers::Offset<void> copy_body(flatbuffers::FlatBufferBuilder& fbb, const wire::Message& msg);

}  // namespace troupe::drivers::passthrough
