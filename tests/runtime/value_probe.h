// Tools of the value property tests: every number of a sample frame found
// through the protocol's reflection schema (message.bfbs, what `troupe`
// prints JSON with), so a new field in a schema is probed without editing a
// test; and one exchange with a node over a raw connection, reporting the
// answer a frame got.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "tests/runtime/node_fixture.h"

namespace troupe::testing {

/// A number inside a frame's body.
struct ValueSite {
  std::string field;  // as wire::Refusal names it: "vel.x", "steps"
  size_t offset = 0;  // byte offset in the frame
  enum class Type { Float, Unsigned, Enum } type = Type::Float;
  size_t bytes = 4;
};

/// Every number of the frame's body: float fields, floats of struct fields
/// (one level, as Pose2d and Cov2d are), unsigned integers and enums. Fails
/// the test when a field is left out of the frame (a sample must set all).
std::vector<ValueSite> value_sites(std::span<const uint8_t> frame);

/// A copy of `frame` with the value at `site` replaced.
std::vector<uint8_t> with_float(std::span<const uint8_t> frame, const ValueSite& site, float value);
std::vector<uint8_t> with_unsigned(std::span<const uint8_t> frame, const ValueSite& site, uint64_t value);

/// What a frame sent to a node got back.
struct Answer {
  bool ok = false;  // the exchange completed (a reply or, for a command, none)
  bool replied = false;
  wire::Kind kind = wire::Kind::Invalid;
  wire::ErrorCode code = wire::ErrorCode::Unknown;
  uint32_t seq = 0;
  std::string text;
};

/// Sends `frame` with its seq replaced by `seq`. A command is followed by a
/// DeviceList round trip (commands are answered only when refused); other
/// kinds wait for the reply with that seq.
Answer exchange(RawConnection& raw, std::span<const uint8_t> frame, uint32_t seq);

}  // namespace troupe::testing
