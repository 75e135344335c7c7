// Steering by colour: the decision of the camera-seek example as a pure
// function of one Rgb8 image, so that it reads (and is tested) apart from
// the connection code in main.cc. It looks for the columns of the image that
// show the target colour, turns towards their centroid and drives until the
// target spans enough of the image's width.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace troupe::examples {

struct SeekParams {
  /// The colour sought, 0xRRGGBB, and how far each channel may stray from
  /// it (0..255) for a pixel to count as that colour.
  uint32_t target = 0xFF0000;
  int tolerance = 40;
  /// A column shows the target when at least this many of its pixels do
  /// (a speck of noise is not a target).
  int min_pixels = 2;
  /// Arrived once the target spans this fraction of the image's width.
  double arrive_fraction = 0.85;
  double speed = 0.4;        // m/s forward when the target is straight ahead
  double search_turn = 0.6;  // rad/s while the target is not in view
  double turn_gain = 1.5;    // rad/s per rad of bearing to the target
  double max_turn = 1.0;     // rad/s
};

/// An uncompressed Rgb8 image: `height` rows of `stride` bytes.
struct RgbView {
  const uint8_t* data = nullptr;
  unsigned width = 0, height = 0, stride = 0;  // px, px, bytes
};

enum class SeekPhase { Searching, Approaching, Arrived };

struct SeekDecision {
  SeekPhase phase = SeekPhase::Searching;
  double v = 0;  // m/s forward
  double w = 0;  // rad/s, positive turns left
  /// Fraction of the image's columns that show the target (0..1), and the
  /// target's bearing, rad (positive: to the left); 0 when not in view.
  double fraction = 0, bearing = 0;
};

inline bool near_colour(const uint8_t* px, uint32_t colour, int tolerance) {
  return std::abs(int(px[0]) - int((colour >> 16) & 0xFF)) <= tolerance &&
         std::abs(int(px[1]) - int((colour >> 8) & 0xFF)) <= tolerance &&
         std::abs(int(px[2]) - int(colour & 0xFF)) <= tolerance;
}

/// One decision from one image. `fx` and `cx` are the camera's focal length
/// and principal point in pixels (its Geometry): they turn a column into a
/// bearing.
inline SeekDecision seek_decide(const SeekParams& p, const RgbView& im, double fx, double cx) {
  SeekDecision d;
  unsigned columns = 0;
  double sum = 0;
  for (unsigned u = 0; u < im.width; ++u) {
    int hits = 0;
    for (unsigned v = 0; v < im.height && hits < p.min_pixels; ++v) {
      hits += near_colour(im.data + size_t(v) * im.stride + size_t(u) * 3, p.target, p.tolerance);
    }
    if (hits < p.min_pixels) continue;
    ++columns;
    sum += u + 0.5;  // the column's centre
  }
  if (columns == 0) {
    d.w = p.search_turn;  // turn on the spot until the target comes into view
    return d;
  }
  d.fraction = double(columns) / double(im.width);
  // Image x grows to the right, so a centroid left of cx is a bearing to the left.
  d.bearing = std::atan2(cx - sum / columns, fx);
  if (d.fraction >= p.arrive_fraction) {
    d.phase = SeekPhase::Arrived;
    return d;
  }
  d.phase = SeekPhase::Approaching;
  d.w = std::fmax(-p.max_turn, std::fmin(p.max_turn, p.turn_gain * d.bearing));
  // Full speed with the target ahead, none with it at the image's edge:
  // the robot turns towards it first rather than sweeping past.
  d.v = p.speed * std::fmax(0.0, 1.0 - std::fabs(d.bearing) / 0.4);
  return d;
}

}  // namespace troupe::examples
