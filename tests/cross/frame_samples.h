// Frames with known contents, built the same way on every target. A
// big-endian (powerpc) build and the little-endian host each write them and
// each read what the other wrote: the wire format must not depend on the
// byte order of the machine that built a frame.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace troupe::cross {

/// Appends the sample frames, size-prefixed as on the wire, to `out`.
void write_samples(std::vector<uint8_t>& out);

/// How many frames write_samples() writes.
int sample_count();

/// Cuts `bytes` into frames, verifies each and compares every field with
/// the samples. Returns "" when all match, else what differs: the frame's
/// index and byte offset, the field, the value read and the one expected.
std::string check_samples(std::span<const uint8_t> bytes);

}  // namespace troupe::cross
