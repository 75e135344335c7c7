// The obstacles that never move, as one occupancy grid with a distance field
// folded into it: a byte per cell that either says what occupies the cell or,
// for a free cell, how far the nearest occupied cell is. Rays march through
// open space in steps of that distance (range_libc's ray marching) and walk
// cell by cell (Amanatides-Woo) only near obstacles, so a ray costs a few
// lookups instead of one per cell, and finds exactly the cell a plain per-cell
// walk finds.
//
// The cells are stored in blocks of 8 x 8 (64 bytes, one cache line each),
// blocks in rows: a ray's next few cells, in whatever direction it goes,
// are mostly in the line it is already reading, where a row-major layout
// puts every row in a line of its own. A map of a large swarm (tens of
// megabytes) does not fit in the caches, so lines read are what a ray
// costs there.
//
// A map too large to hold every cell (a campus at 0.02 m: 1.75 billion
// cells) is sparse: a table gives each block its place in a pool, and only
// the blocks that hold or border an obstacle (the coarse level below 3
// cells of clearance) have one of their own. Every other block shares one
// of 256 uniform blocks: a block inside a building the all-solid one, a
// block in open space the one holding its coarse code, a march step just
// as safe from any of its cells. Rays read exactly the cells and steps
// they read on the dense map with its coarse level.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "host-sim/sim/desc.h"
#include "host-sim/sim/geometry.h"
#include "host-sim/sim/huge_page_allocator.h"

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
  /// A sparse map's pool starts with one block of each code.
  static constexpr uint32_t kUniformBlocks = 256;

  /// An empty grid covering [lo, hi] (world frame, m) at `resolution` m,
  /// sparse or dense as `storage` says (Auto: sparse from
  /// kSparseFromCells cells on; beyond 2^30 cells always sparse, since a
  /// dense map's cells are found by 32-bit offsets). At most kMaxCells.
  ///
  /// With a `window` ([lo, hi] corners, world frame, m) only the cells
  /// within it are held, on the same grid: a process of a divided world
  /// holds its own region of a large map. Dense, the window's blocks are
  /// stored and nothing else (the size rules above count the window's
  /// cells); sparse, no block the fills leave empty is stored. Rays,
  /// clearances and overlaps read the window only, as if the grid ended at
  /// its edges: the caller keeps every query inside it.
  void reset(Vec2 lo, Vec2 hi, double resolution, MapStorage storage = MapStorage::Auto,
             const Vec2* window = nullptr);

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
  /// Whether cast_batch() looks at the coarse level first (see coarse_).
  /// finish() turns it on for maps larger than kCoarseFromCells; tests and
  /// benchmarks may force it either way (the results are the same). A
  /// sparse map always reads it.
  void set_coarse(bool on) { use_coarse_ = on || sparse(); }
  bool coarse() const { return use_coarse_; }
  /// A block (a coarse cell, a cache line of cells) is kTile x kTile cells.
  static constexpr int kTileShift = 3;
  static constexpr int kTile = 1 << kTileShift;
  /// Where cell (ix, iy) is stored: its block's place (the block itself
  /// when dense), then its row in the block.
  size_t index(int ix, int iy) const {
    size_t block = block_number(ix >> kTileShift, iy >> kTileShift);
    if (!slots_.empty()) block = slots_[block];
    return (block << (2 * kTileShift)) + size_t((iy & (kTile - 1)) << kTileShift) + size_t(ix & (kTile - 1));
  }
  /// Block (bx, by)'s number: its place in the coarse level, and in the
  /// cells (dense) or the block table (sparse). Blocks in rows of
  /// block_pitch(), less block_bias() (a dense window stores its own
  /// blocks only).
  size_t block_number(int bx, int by) const { return size_t(ptrdiff_t(by) * pitch_ + bx - bias_); }
  int block_pitch() const { return pitch_; }
  ptrdiff_t block_bias() const { return bias_; }
  /// The cells held, inclusive: the whole grid unless reset() was given a
  /// window.
  int window_x0() const { return wx0_; }
  int window_y0() const { return wy0_; }
  int window_x1() const { return wx1_; }
  int window_y1() const { return wy1_; }
  /// True when reset() was given a window smaller than the grid.
  bool windowed() const { return wx0_ > 0 || wy0_ > 0 || wx1_ < w_ - 1 || wy1_ < h_ - 1; }
  /// Maps from this many cells on (4 MiB, about a core's share of the
  /// mid-level cache) read the coarse level first.
  static constexpr size_t kCoarseFromCells = size_t(4) << 20;
  /// Maps from this many cells on (128 MiB dense, twice that while the
  /// distance field is computed) are sparse unless told otherwise.
  static constexpr size_t kSparseFromCells = size_t(1) << 27;
  /// The largest grid, in cells (whole blocks): 2^26 blocks, whose table
  /// and coarse level alone take 320 MiB.
  static constexpr size_t kMaxCells = size_t(1) << 32;
  /// True when only the blocks near obstacles are stored.
  bool sparse() const { return !slots_.empty(); }

  /// Starts loading the cells within `r` (m) of `p` (world) into the
  /// cache, for a cast from there soon after. At most 3 x 3 blocks.
  void prefetch(Vec2 p, double r) const;

  /// True when the polygon (world frame) overlaps a cell whose code is in
  /// `mask`.
  bool overlaps(std::span<const Vec2> polygon, uint8_t mask = kObstacleMask) const;
  /// True when the segment touches a cell whose code is in `mask`.
  bool segment_hits(Vec2 a, Vec2 b, uint8_t mask = kObstacleMask) const;

  /// A lower bound on the distance from `p` to any occupied cell, m (0 inside
  /// one; large outside the grid's reach). With the coarse level, the
  /// block's bound when that is more than `enough` m (the map is not read).
  double clearance(Vec2 p, double enough = 1e300) const;

  int width() const { return w_; }
  int height() const { return h_; }
  double resolution() const { return res_; }
  /// World position of the grid's corner (cell 0, 0 starts there), m.
  Vec2 origin() const { return origin_; }
  uint8_t code(int ix, int iy) const { return codes_[index(ix, iy)]; }
  bool occupied(int ix, int iy) const { return code(ix, iy) <= kBarrier; }
  /// Some cell is an obstacle (a world whose walls are all rigid bodies
  /// has none: its moves need no test against the grid).
  bool has_obstacles() const { return has_obstacles_; }
  /// True when block (bx, by), cells [kTile bx, kTile bx + kTile) on each
  /// axis, holds no occupied cell; false before finish(). Lets a walk over
  /// every cell (a snapshot) pass a campus's open ground a block at a time.
  bool block_free(int bx, int by) const {
    // Blocks outside a window hold nothing this map knows of.
    if (bx < wx0_ >> kTileShift || bx > wx1_ >> kTileShift || by < wy0_ >> kTileShift ||
        by > wy1_ >> kTileShift)
      return !coarse_.empty();
    return !coarse_.empty() && coarse_[block_number(bx, by)] > kBarrier;
  }
  /// Bytes held.
  size_t memory_bytes() const {
    return codes_.capacity() + coarse_.capacity() + slots_.capacity() * sizeof(uint32_t);
  }

 private:
  // A cell's code once `add` (bit 1: stops robots, bit 2: seen by rangers)
  // is combined into it.
  static uint8_t combined(uint8_t code, uint8_t add);
  // A free cell's code at `d2` cells^2 from the nearest occupied cell centre.
  static uint8_t distance_code(double d2);
  void mark(int ix, int iy, uint8_t add);
  // The dense map's distance field, and the sparse map's (static_map_sparse.cc).
  void finish_dense();
  void finish_sparse();
  // Sparse: fills cells [ix0, ix1] x [iy0, iy1] a block at a time; whole
  // blocks stay uniform.
  void fill_box_sparse(int ix0, int iy0, int ix1, int iy1, uint8_t add);
  // Sparse: the block's own cells, copied from its uniform block first if it
  // had none. Invalidates pointers into codes_.
  uint8_t* writable_block(size_t block);
  // Sparse: gives a block back to the pool if its cells are all alike.
  void release_if_uniform(size_t block);
  // The window (inclusive cells) from its corners in the world, m.
  void set_window(Vec2 lo, Vec2 hi);
  // Clips the ray to the window: [t0, t1) in cells. False when it misses.
  bool clip(float ox, float oy, float dx, float dy, float& t0, float& t1) const;

  int w_ = 0, h_ = 0;
  double res_ = 0.02, inv_res_ = 50;
  Vec2 origin_;
  // The cells held (reset's window), inclusive: the whole grid unless
  // told otherwise. Fills mark nothing outside, rays stop at its edges.
  int wx0_ = 0, wy0_ = 0, wx1_ = 0, wy1_ = 0;
  // Blocks per row of stored blocks, and the number of the first stored
  // block (block_number): blocks_w_ and 0 but for a dense window.
  int pitch_ = 1;
  ptrdiff_t bias_ = 0;
  std::vector<uint8_t, HugePageAllocator<uint8_t>> codes_;
  // The coarse level: per kTile x kTile block of cells, the smallest code
  // in it (an occupied code when the block holds an obstacle). Its march
  // step is safe from anywhere in the block, as a cell's is from anywhere
  // in the cell, and it is 64 times smaller than the map: on a map that
  // outgrows the caches, open space is crossed by reading this cached
  // array, and the map itself is read only near obstacles.
  std::vector<uint8_t> coarse_;
  // Sparse only: per block, its place in codes_ (in blocks). Places below
  // kUniformBlocks are the shared uniform blocks, place c all of code c.
  // Read at random by rays near obstacles, so in huge pages too.
  std::vector<uint32_t, HugePageAllocator<uint32_t>> slots_;
  // Sparse, while filling: places given back, to be reused.
  std::vector<uint32_t> free_slots_;
  int blocks_w_ = 1;  // blocks per row of blocks
  int blocks_h_ = 1;
  bool use_coarse_ = false;
  bool per_cell_ = false;
  bool has_obstacles_ = false;
};

}  // namespace troupe::sim
