#include "wire/frame.h"

#include <algorithm>
#include <cstring>

namespace troupe::wire {

FrameReader::FrameReader(uint32_t max_frame_bytes, size_t initial_bytes)
    : buf_(std::max<size_t>(initial_bytes, kPrefixBytes)), max_frame_(max_frame_bytes) {}

uint64_t FrameReader::pending_frame_bytes() const {
  if (end_ - begin_ < kPrefixBytes) return 0;
  return uint64_t{read_prefix(buf_.data() + begin_)} + kPrefixBytes;
}

std::span<uint8_t> FrameReader::write_space(size_t min_bytes) {
  if (begin_ == end_) begin_ = end_ = 0;
  size_t held = end_ - begin_;
  uint64_t frame = pending_frame_bytes();
  // Grow for an announced frame only when it is within the limit: a peer
  // must not make us allocate for a length it will never send.
  size_t missing = (frame > held && frame <= max_frame_) ? static_cast<size_t>(frame - held) : 0;
  size_t want = std::max(min_bytes, missing);
  if (buf_.size() - end_ < want && begin_ > 0) {
    std::memmove(buf_.data(), buf_.data() + begin_, held);
    begin_ = 0;
    end_ = held;
  }
  if (buf_.size() - end_ < want) buf_.resize(end_ + want);
  return {buf_.data() + end_, buf_.size() - end_};
}

void FrameReader::commit(size_t n) { end_ += n; }

std::span<const uint8_t> FrameReader::next() {
  if (too_large_ || end_ - begin_ < kPrefixBytes) return {};
  uint32_t len = read_prefix(buf_.data() + begin_);
  // 64-bit sum: on 32-bit boards a 4 GiB prefix plus 4 would wrap.
  if (uint64_t{len} + kPrefixBytes > max_frame_) {
    too_large_ = true;
    announced_ = len;
    return {};
  }
  size_t total = size_t{len} + kPrefixBytes;
  if (end_ - begin_ < total) return {};
  std::span<const uint8_t> frame(buf_.data() + begin_, total);
  begin_ += total;
  return frame;
}

const Message* verify_frame(std::span<const uint8_t> frame, const Limits& limits,
                            VerifyError* why) {
  auto fail = [why](VerifyError e) -> const Message* {
    if (why) *why = e;
    return nullptr;
  };
  // A frame needs its prefix plus a root offset at the very least.
  if (frame.size() < kPrefixBytes + sizeof(flatbuffers::uoffset_t)) return fail(VerifyError::Short);
  if (read_prefix(frame.data()) != frame.size() - kPrefixBytes) return fail(VerifyError::LengthMismatch);
  flatbuffers::Verifier verifier(frame.data(), frame.size(), limits.max_depth, limits.max_tables);
  if (!verifier.VerifySizePrefixedBuffer<Message>(nullptr)) return fail(VerifyError::Verifier);
  const Message* msg = flatbuffers::GetSizePrefixedRoot<Message>(frame.data());
  if (msg->header() == nullptr) return fail(VerifyError::NoHeader);
  if (why) *why = VerifyError::None;
  return msg;
}

const Header* peek_header(std::span<const uint8_t> frame) {
  if (frame.size() < kPrefixBytes + sizeof(flatbuffers::uoffset_t) ||
      read_prefix(frame.data()) != frame.size() - kPrefixBytes) {
    return nullptr;
  }
  // The first steps of the full verification, stopping after the header.
  flatbuffers::Verifier verifier(frame.data() + kPrefixBytes, frame.size() - kPrefixBytes, 1, 1);
  flatbuffers::uoffset_t root = verifier.VerifyOffset(0);
  if (root == 0) return nullptr;
  const uint8_t* at = frame.data() + kPrefixBytes + root;
  auto* table = reinterpret_cast<const flatbuffers::Table*>(at);
  if (!table->VerifyTableStart(verifier) || !table->VerifyField<Header>(verifier, Message::VT_HEADER, 4)) {
    return nullptr;
  }
  return reinterpret_cast<const Message*>(at)->header();
}

std::string_view verify_error_text(VerifyError e) {
  switch (e) {
    case VerifyError::None: return "ok";
    case VerifyError::Short: return "frame shorter than a FlatBuffer";
    case VerifyError::LengthMismatch: return "length prefix does not match the frame";
    case VerifyError::Verifier: return "FlatBuffers verifier refused the buffer";
    case VerifyError::NoHeader: return "message has no header";
  }
  return "unknown";
}

}  // namespace troupe::wire
