// Framing: a frame is a u32 little-endian length followed by that many bytes
// of FlatBuffer (FlatBuffers' size-prefixed form). FrameReader cuts a byte
// stream into frames; verify_frame() checks one before anything reads it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "wire/message.h"

namespace troupe::wire {

inline constexpr uint32_t kPrefixBytes = 4;

/// Bounds applied to every inbound frame.
struct Limits {
  /// Largest frame accepted, bytes including the prefix. A length prefix
  /// announcing more is refused before any buffer grows for it.
  uint32_t max_frame_bytes = 1u << 20;
  /// Deepest nesting of tables and vectors the verifier follows.
  uint32_t max_depth = 16;
  /// Most tables the verifier visits in one frame.
  uint32_t max_tables = 20000;
};

/// Reads the length prefix at `p` (4 bytes, little-endian).
inline uint32_t read_prefix(const uint8_t* p) {
  return uint32_t{p[0]} | (uint32_t{p[1]} << 8) | (uint32_t{p[2]} << 16) | (uint32_t{p[3]} << 24);
}

/// Cuts a byte stream into frames. Copes with frames split across reads and
/// several frames in one read. Memory grows only to the largest frame seen,
/// never beyond `max_frame_bytes`.
class FrameReader {
 public:
  explicit FrameReader(uint32_t max_frame_bytes, size_t initial_bytes = 4096);

  /// Space for the next read: at least `min_bytes` (or what the frame being
  /// assembled still needs), after compacting consumed bytes away.
  std::span<uint8_t> write_space(size_t min_bytes = 1024);
  /// Records that `n` bytes were written into write_space().
  void commit(size_t n);

  /// The next whole frame (prefix included), or an empty span when more
  /// bytes are needed or the stream is broken (see too_large()).
  std::span<const uint8_t> next();

  /// The stream announced a frame over the limit; it cannot be resynced.
  bool too_large() const { return too_large_; }
  /// The announced length of the oversized frame, bytes after the prefix.
  uint32_t announced_bytes() const { return announced_; }
  /// Bytes held that do not yet form a whole frame (a truncated frame when
  /// the stream ends).
  size_t pending_bytes() const { return end_ - begin_; }
  /// The size the frame being assembled will have, or 0 before its prefix.
  uint64_t pending_frame_bytes() const;

 private:
  std::vector<uint8_t> buf_;
  size_t begin_ = 0;  // first unconsumed byte
  size_t end_ = 0;    // one past the last byte written
  uint32_t max_frame_;
  uint32_t announced_ = 0;
  bool too_large_ = false;
};

/// Why verify_frame() refused a frame.
enum class VerifyError { None, Short, LengthMismatch, Verifier, NoHeader };

/// Checks a whole frame (prefix included) with the FlatBuffers Verifier under
/// `limits`; returns the message, or nullptr and sets `why`. Nothing in the
/// frame is read before this returns non-null.
const Message* verify_frame(std::span<const uint8_t> frame, const Limits& limits,
                            VerifyError* why = nullptr);

std::string_view verify_error_text(VerifyError e);

/// The header of a frame verify_frame() refused, when the root table and the
/// header in it are sound by themselves (the body may be what is broken), so
/// that the Error answering it can echo its address, subtype and seq;
/// nullptr otherwise.
const Header* peek_header(std::span<const uint8_t> frame);

/// The message of a frame this process built itself (no verification).
inline const Message* trusted_message(std::span<const uint8_t> frame) {
  return flatbuffers::GetSizePrefixedRoot<Message>(frame.data());
}

}  // namespace troupe::wire
