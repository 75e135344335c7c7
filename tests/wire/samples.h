// One valid frame of every message a client may send: the session kinds and
// every command and request subtype the schemas define (wire::body_rules()),
// each addressed to robot 0, index 0 of its interface. Every number in a
// body is set and nonzero, so that a test can find each one in the buffer
// (FlatBuffers leaves out a field equal to its default) and overwrite it in
// place. The fuzz targets' seed corpus and the value property tests start
// from these.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "wire/check.h"

namespace troupe::testing {

struct WireSample {
  std::string name;  // "position2d-command-1", "hello", ...
  std::vector<uint8_t> frame;
};

/// Session frames first, then one per row of wire::body_rules(), in order.
/// Requests carry seq 1000 + their index in the list.
std::vector<WireSample> wire_samples();

/// The body of one rule, built in `b`, every number set and in range (NONE
/// rules give a null offset).
flatbuffers::Offset<void> sample_body(flatbuffers::FlatBufferBuilder& b, wire::Body type);

}  // namespace troupe::testing
