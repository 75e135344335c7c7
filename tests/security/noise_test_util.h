// What the secure-session tests share: hex, and two NoiseTransports joined
// in memory (bytes handed from one to the other as a socket would).
#pragma once

#include <string>
#include <vector>

#include "wire/frame.h"
#include "wire/noise/noise_transport.h"

namespace troupe::testing {

std::vector<uint8_t> from_hex(const std::string& hex);
std::string to_hex(std::span<const uint8_t> bytes);

/// A frame as the frame reader cuts them: the u32 prefix, then `body_bytes`
/// bytes of a pattern set by `seed`.
std::vector<uint8_t> test_frame(size_t body_bytes, uint8_t seed);

/// Splits a stream of length-prefixed Noise messages into the messages
/// (prefix included), to replay, reorder or alter them one by one.
std::vector<std::vector<uint8_t>> split_messages(std::span<const uint8_t> stream);

}  // namespace troupe::testing
