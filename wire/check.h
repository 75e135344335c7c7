// What a message must hold before anything reads it, beyond what the
// FlatBuffers verifier proves. The verifier accepts an absent table (a union
// type with no body behind it, a struct field left out); a handler that
// reads it then follows a null pointer. And it knows nothing of values: a
// NaN velocity is a valid float. check_message() adds both: the body the
// message's kind and subtype call for, the fields its handler reads, and
// every value within the range its schema documents (wire/README.md, "Valid
// values"). The node runs it on every frame a client sends, before routing
// (runtime/node.cc); a client runs it on what it is about to send, to refuse
// a bad value with a clear message before any node sees it.
#pragma once

#include <cstdint>
#include <span>

#include "wire/message.h"

namespace troupe::wire {

/// Limits shared by many fields; each schema field names the one it uses.
/// |x| and |y| of a pose, and any other position, m.
inline constexpr float kMaxCoordinate = 1e6f;
/// |a| of a pose, rad (handlers take it modulo 2 pi).
inline constexpr float kMaxAngle = 1000.0f;
/// |speed| of any linear velocity, m/s.
inline constexpr float kMaxSpeed = 1000.0f;
/// |turn rate| of any angular velocity, rad/s.
inline constexpr float kMaxTurnRate = 1000.0f;
/// |covariance entry|, m^2, m*rad or rad^2 (diagonal entries >= 0).
inline constexpr float kMaxVariance = 1e12f;
/// Ranger configuration: |angle| rad (2 pi), ranges m, frequency Hz.
inline constexpr float kMaxScanAngle = 6.2831855f;
inline constexpr float kMaxFrequency = 1e6f;
/// Simulation: steps in one Step request, and the largest speed factor.
inline constexpr uint32_t kMaxSteps = 1000000;
inline constexpr float kMaxSimSpeed = 1e6f;
/// Cells in one map tile (512 x 512: 64 KiB packed).
inline constexpr uint32_t kMaxTileCells = 512 * 512;
/// Camera configuration: image width and height, px, and images per
/// second, Hz. The side is a sanity bound, not a promise: an image must
/// also fit the frame limit to be sent.
inline constexpr uint32_t kMaxImageSide = 4096;
inline constexpr float kMaxImageRate = 1000.0f;
/// Smallest Hello.max_frame_bytes a peer may announce (0: not announced),
/// bytes: below it not even an Error with its text fits.
inline constexpr uint32_t kMinFrameBytes = 1024;

/// The body a command or request calls for.
struct BodyRule {
  Interface iface;
  Kind kind;  // Command or Request
  uint8_t subtype;
  Body body;      // NONE: the message carries no body
  bool required;  // false: the body may be left out (its defaults apply)
};

/// Every command and request subtype the schemas define, one row each.
std::span<const BodyRule> body_rules();

/// Why check_message() refused a message.
struct Refusal {
  /// BadBody: the body, or a field its handler reads, is missing, or the
  /// body is not the one the subtype takes. BadValue: a value outside its
  /// range. Unsupported: a command subtype its interface does not define.
  ErrorCode code = ErrorCode::Unknown;
  /// The offending field as the schema spells it ("vel.x"), "body" for the
  /// whole body, empty for the subtype.
  char field[32] = {};
  /// What is wrong and what is allowed, for the reply's text.
  char text[160] = {};
};

/// Checks a message that verify_frame() accepted and whose body fits its
/// kind and interface (body_fits()). True when every rule holds; otherwise
/// false with `why`.
bool check_message(const Message& msg, Refusal& why);

}  // namespace troupe::wire
