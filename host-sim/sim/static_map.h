// The obstacles that never move, as one occupancy grid with a distance field
// folded into it: a byte per cell that either says what occupies the cell or,
// for a free cell, how far the nearest occupied cell is. Rays march through
// open space in steps of that distance (range_libc's ray marching) and walk
// cell by cell (Amanatides-Woo) only near obstacles, so a ray costs a few
// lookups instead of one per cell, and finds exactly the cell a plain per-cell
// walk finds.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host-sim/sim/geometry.h"

namespace troupe::sim {

/// One ray for StaticMap::cast_batch.
struct RayQuery {
  Vec2 origin;      // world, m
  Vec2 dir;         // unit
  float max_range;  // m
};

class StaticMap {
 public:
  /// What a cell holds. Codes 0..2 are occupied cells; a free cell holds
  /// kFreeBase + floor(distance to the nearest occupied cell centre, in
  /// cells), saturating at 255.
  static constexpr uint8_t kSolid = 0;    // stops robots, seen by rangers
  static constexpr uint8_t kVisible = 1;  // seen by rangers only
  static constexpr uint8_t kBarrier = 2;  // stops robots only
  static constexpr uint8_t kFreeBase = 2;
  static constexpr uint8_t kFree = 255;

  /// Which occupied codes count as a hit (bit = code).
  static constexpr uint8_t kRangerMask = (1u << kSolid) | (1u << kVisible);
  static constexpr uint8_t kObstacleMask = (1u << kSolid) | (1u << kBarrier);
  static constexpr uint8_t kAnyMask = kRangerMask | kObstacleMask;

  /// An empty grid covering [lo, hi] (world frame, m) at `resolution` m.
  void reset(Vec2 lo, Vec2 hi, double resolution);

  /// Marks the cells a polygon (world frame) overlaps. `obstacle` and
  /// `visible` say what it is; overlapping marks combine.
  void fill_polygon(std::span<const Vec2> polygon, bool obstacle, bool visible);
  /// The same for an axis-aligned box, faster (bitmap runs).
  void fill_box(Vec2 lo, Vec2 hi, bool obstacle, bool visible);
  /// Computes the distance field. Call after the last fill, before casting.
  void finish();

  /// Distance along the ray from `origin` in direction `dir` (unit) to the
  /// first cell whose code is in `mask`, m; `max_range` when none is nearer.
  float cast(Vec2 origin, Vec2 dir, float max_range, uint8_t mask = kRangerMask) const;
  /// Many rays at once (a laser's beams): out[i] gets ray i's distance, m.
  /// Same results as cast(), faster: several rays are in flight together.
  void cast_batch(std::span<const RayQuery> rays, uint8_t mask, float* out) const;
  /// The same by a plain cell-by-cell walk: the baseline the benchmark and
  /// the tests compare `cast` against.
  float cast_per_cell(Vec2 origin, Vec2 dir, float max_range, uint8_t mask = kRangerMask) const;
  /// Benchmarks only: makes cast() and cast_batch() walk every cell, so a
  /// whole simulation can be timed against the per-cell baseline.
  void set_per_cell(bool on) { per_cell_ = on; }

  /// True when the polygon (world frame) overlaps a cell whose code is in
  /// `mask`.
  bool overlaps(std::span<const Vec2> polygon, uint8_t mask = kObstacleMask) const;
  /// True when the segment touches a cell whose code is in `mask`.
  bool segment_hits(Vec2 a, Vec2 b, uint8_t mask = kObstacleMask) const;

  /// A lower bound on the distance from `p` to any occupied cell, m (0 inside
  /// one; large outside the grid's reach).
  double clearance(Vec2 p) const;

  int width() const { return w_; }
  int height() const { return h_; }
  double resolution() const { return res_; }
  /// World position of the grid's corner (cell 0, 0 starts there), m.
  Vec2 origin() const { return origin_; }
  uint8_t code(int ix, int iy) const { return codes_[size_t(iy) * size_t(w_) + size_t(ix)]; }
  bool occupied(int ix, int iy) const { return code(ix, iy) <= kBarrier; }
  /// Bytes held.
  size_t memory_bytes() const { return codes_.capacity(); }

 private:
  void mark(size_t index, bool obstacle, bool visible);
  // Clips the ray to the grid: [t0, t1) in cells. False when it misses.
  bool clip(float ox, float oy, float dx, float dy, float& t0, float& t1) const;

  int w_ = 0, h_ = 0;
  double res_ = 0.02, inv_res_ = 50;
  Vec2 origin_;
  std::vector<uint8_t> codes_;
  bool per_cell_ = false;
};

}  // namespace troupe::sim
