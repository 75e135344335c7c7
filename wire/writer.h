// Building frames. One MessageWriter is reused for every message a component
// sends: after the first few messages its buffer has the size it needs and
// building allocates nothing.
#pragma once

#include <span>

#include "wire/message.h"

namespace troupe::wire {

class MessageWriter {
 public:
  explicit MessageWriter(size_t initial_bytes = 1024) : fbb_(initial_bytes) {}

  /// Forgets the previous message; build the body with builder() next.
  flatbuffers::FlatBufferBuilder& start() {
    fbb_.Clear();
    started_ = true;
    return fbb_;
  }
  flatbuffers::FlatBufferBuilder& builder() { return fbb_; }

  /// Completes the message begun with start(): its header and body (built in
  /// builder() since start()). Returns the frame, prefix included; it stays
  /// valid until the next start().
  std::span<const uint8_t> finish(const Header& header, Body type = Body::NONE,
                                  flatbuffers::Offset<void> body = 0) {
    // Without start() the builder still holds the previous, finished message
    // and the new one would be appended to it. A body needs start() (it was
    // built after it); a bodiless message can start here.
    FLATBUFFERS_ASSERT(started_ || body.IsNull());
    if (!started_) fbb_.Clear();
    started_ = false;
    // Fields go in this order on purpose: the builder lays them out back to
    // front, and with the one-byte union type first the table needs no
    // padding before the next object. 4 bytes less on most frames
    // (measured: tests/bench/wire/wire_sizes).
    MessageBuilder mb(fbb_);
    mb.add_body_type(type);
    mb.add_header(&header);
    mb.add_body(body);
    fbb_.FinishSizePrefixed(mb.Finish());
    return frame();
  }

  /// A message without a body (Close, Pull, requests without arguments).
  std::span<const uint8_t> empty(const Header& header) { return finish(header); }

  std::span<const uint8_t> frame() const { return {fbb_.GetBufferPointer(), fbb_.GetSize()}; }

 private:
  flatbuffers::FlatBufferBuilder fbb_;
  bool started_ = false;
};

}  // namespace troupe::wire
