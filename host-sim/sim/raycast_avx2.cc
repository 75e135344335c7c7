// Ray casting with AVX2: four rays step together in one set of registers,
// every step the same instructions without branches (look the cell up by a
// gather; a far-from-obstacles cell gives its march step, a near one the
// step to the next cell boundary plus a hair). On a large map a lane first
// reads its block's code in the small coarse level and reads the map only
// when the block is near an obstacle; on a sparse map it then finds the
// block's cells through the block table, one gather more for those lanes
// only (a template argument: the dense map's loop is as it was). Built with
// -mavx2 -mfma and used only when the processor has both
// (StaticMap::cast_batch checks).
//
// Doubles throughout: the hair (1e-6 cell) must move a position across a
// cell boundary even 100,000 cells from the grid's corner.
#include "host-sim/sim/raycast_avx2.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace troupe::sim::detail {

namespace {
constexpr double kHair = 1e-6;  // cells past a boundary
constexpr double kEdgeMargin = 1e-3;
constexpr uint8_t kMarchFrom = StaticMap::kFreeBase + 3;  // march when >= 3 cells clear
constexpr int kShift = StaticMap::kTileShift;
constexpr int kLow = StaticMap::kTile - 1;  // a cell's place in its block

template <bool kSparse>
void cast_lanes(const CellStore& map, Vec2 origin, double inv_res, double res, std::span<const RayQuery> rays,
                uint8_t mask, float* out) {
  const uint8_t* codes = map.codes;
  const uint8_t* coarse = map.coarse;
  const uint32_t* slots = map.slots;
  const ptrdiff_t pitch = map.pitch, bias = map.bias;
  constexpr int kGroups = 4;  // groups of four rays: their chains overlap (3 or 5: slower)
  constexpr int kLanes = 4 * kGroups;
  alignas(32) double ox[kLanes], oy[kLanes], dx[kLanes], dy[kLanes], inv_x[kLanes], inv_y[kLanes];
  alignas(32) double wall_x[kLanes], wall_y[kLanes], t[kLanes], t_end[kLanes], big_x[kLanes], big_y[kLanes];
  int index[kLanes];
  const double lo_x = map.x0, lo_y = map.y0, inner_x = map.x1 - kEdgeMargin, inner_y = map.y1 - kEdgeMargin;
  size_t next = 0;
  int active = 0;
  double shared_ox = -1, shared_oy = -1, shared_t = 0;
  // A cell's code for marching: its block's when the block is clear.
  auto step_code = [&](size_t x, size_t y) {
    const size_t block = size_t(ptrdiff_t(y >> kShift) * pitch + ptrdiff_t(x >> kShift) - bias);
    if (coarse && coarse[block] >= kMarchFrom) return coarse[block];
    const size_t stored = kSparse ? size_t(slots[block]) : block;
    return codes[(stored << (2 * kShift)) + ((y & kLow) << kShift) + (x & kLow)];
  };

  // Loads the next ray that clipping does not settle into lane k, or parks
  // the lane on the window's first cell going nowhere.
  // Inlined: a call per ray costs a fifth of the caster's instructions.
  auto start = [&](int k) __attribute__((always_inline)) {
    while (next < rays.size()) {
      const RayQuery& q = rays[next];
      const int i = int(next++);
      const double x = (q.origin.x - origin.x) * inv_res, y = (q.origin.y - origin.y) * inv_res;
      double t0 = 0, t1 = q.max_range * inv_res;
      for (int axis = 0; axis < 2; ++axis) {
        const double o = axis == 0 ? x : y, d = axis == 0 ? q.dir.x : q.dir.y, lo = axis == 0 ? lo_x : lo_y,
                     hi = axis == 0 ? inner_x : inner_y;
        if (d == 0) {
          if (o < lo || o >= hi) t1 = -1;
          continue;
        }
        double a = (lo - o) / d, b = (hi - o) / d;
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
      }
      if (!(t0 < t1)) {
        out[i] = q.max_range;
        continue;
      }
      if (t0 == 0) {
        // Rays of a fan share their origin and its cell's free radius.
        if (x != shared_ox || y != shared_oy) {
          shared_ox = x;
          shared_oy = y;
          const uint8_t c = step_code(size_t(x), size_t(y));
          shared_t = c >= kMarchFrom ? double(c - StaticMap::kFreeBase) - 1.5 : 0.0;
        }
        t0 = std::min(shared_t, t1);
      }
      ox[k] = x;
      oy[k] = y;
      dx[k] = q.dir.x;
      dy[k] = q.dir.y;
      t[k] = t0;
      t_end[k] = t1;
      inv_x[k] = q.dir.x != 0 ? 1.0 / q.dir.x : 0.0;
      inv_y[k] = q.dir.y != 0 ? 1.0 / q.dir.y : 0.0;
      wall_x[k] = q.dir.x > 0 ? 1.0 : 0.0;
      wall_y[k] = q.dir.y > 0 ? 1.0 : 0.0;
      // A direction without an x component never reaches an x boundary;
      // nor does one whose x moves less than a hair over the whole ray:
      // from a position on a boundary, a step of a hair would not move it
      // off in doubles, and it would step a hair at a time (seconds for a
      // beam at 90 degrees from a robot on a cell's edge).
      big_x[k] = std::fabs(q.dir.x) * t1 > kHair ? 0.0 : 1e300;
      big_y[k] = std::fabs(q.dir.y) * t1 > kHair ? 0.0 : 1e300;
      index[k] = i;
      return true;
    }
    ox[k] = lo_x;
    oy[k] = lo_y;
    dx[k] = dy[k] = inv_x[k] = inv_y[k] = wall_x[k] = wall_y[k] = 0;
    big_x[k] = big_y[k] = 0;
    t[k] = 0;
    t_end[k] = 1e300;
    index[k] = -1;
    return false;
  };
  for (int k = 0; k < kLanes; ++k) active += start(k) ? 1 : 0;

  const __m128i byte = _mm_set1_epi32(0xFF), three = _mm_set1_epi32(3), low = _mm_set1_epi32(kLow);
  const __m128i one = _mm_set1_epi32(1);
  const __m256d far_from = _mm256_set1_pd(StaticMap::kFreeBase + 2.5);  // codes >= 5 march
  const __m128i maskv = _mm_set1_epi32(mask);
  const __m256d hair = _mm256_set1_pd(kHair), slack = _mm256_set1_pd(StaticMap::kFreeBase + 1.5);
  // A window's bias is folded into the addresses the gathers add their
  // offsets to (only ever read at a cell of the window), so a step pays
  // nothing for it. A sparse map's cells are found through its table.
  auto before = [](const void* p, ptrdiff_t bytes) {
    return reinterpret_cast<const int*>(reinterpret_cast<uintptr_t>(p) - uintptr_t(bytes));
  };
  const int* base = before(codes, kSparse ? 0 : bias << (2 * kShift));
  const int* coarse_base = before(coarse, bias);
  const int* slots_base = before(slots, bias * ptrdiff_t(sizeof(uint32_t)));
  const __m128i blocks_width = _mm_set1_epi32(map.pitch);
  const __m128i march_from = _mm_set1_epi32(kMarchFrom);
  struct Group {
    __m256d ox, oy, dx, dy, ix, iy, wx, wy, t, te, bx, by, live;
    __m256d fin, hit;  // lanes that ended, and of those, the ones that hit
  };
  auto load = [&](int g) {
    const int o = 4 * g;
    Group v;
    v.ox = _mm256_load_pd(ox + o);
    v.oy = _mm256_load_pd(oy + o);
    v.dx = _mm256_load_pd(dx + o);
    v.dy = _mm256_load_pd(dy + o);
    v.ix = _mm256_load_pd(inv_x + o);
    v.iy = _mm256_load_pd(inv_y + o);
    v.wx = _mm256_load_pd(wall_x + o);
    v.wy = _mm256_load_pd(wall_y + o);
    v.t = _mm256_load_pd(t + o);
    v.te = _mm256_load_pd(t_end + o);
    v.bx = _mm256_load_pd(big_x + o);
    v.by = _mm256_load_pd(big_y + o);
    // Parked lanes never end (their results would go nowhere).
    v.live = _mm256_castsi256_pd(_mm256_set_epi64x(index[o + 3] >= 0 ? -1 : 0, index[o + 2] >= 0 ? -1 : 0,
                                                   index[o + 1] >= 0 ? -1 : 0, index[o] >= 0 ? -1 : 0));
    v.fin = v.hit = _mm256_setzero_pd();
    return v;
  };
  // One step of four rays. Lanes that ended stay put (a hit at its entry
  // distance, a miss at its last position inside the grid) until the
  // group's lanes are refilled. Returns the lanes ended so far.
  auto step = [&](Group& v) {
    const __m256d px = _mm256_add_pd(v.ox, _mm256_mul_pd(v.t, v.dx));
    const __m256d py = _mm256_add_pd(v.oy, _mm256_mul_pd(v.t, v.dy));
    const __m128i ix = _mm256_cvttpd_epi32(px), iy = _mm256_cvttpd_epi32(py);
    // The cell's place: its block, then its row and column in the block.
    const __m128i block =
        _mm_add_epi32(_mm_mullo_epi32(_mm_srli_epi32(iy, kShift), blocks_width), _mm_srli_epi32(ix, kShift));
    const __m128i inner =
        _mm_add_epi32(_mm_slli_epi32(_mm_and_si128(iy, low), kShift), _mm_and_si128(ix, low));
    __m128i c;
    if constexpr (kSparse) {
      // As below, but a near lane's cells are where its block's table
      // entry says: 64-bit offsets, since the pool may pass 2 GiB.
      const __m128i b = _mm_and_si128(_mm_i32gather_epi32(coarse_base, block, 1), byte);
      const __m128i near = _mm_cmplt_epi32(b, march_from);
      const __m128i slot = _mm_mask_i32gather_epi32(_mm_setzero_si128(), slots_base, block, near, 4);
      const __m256i at = _mm256_add_epi64(_mm256_slli_epi64(_mm256_cvtepu32_epi64(slot), 2 * kShift),
                                          _mm256_cvtepu32_epi64(inner));
      c = _mm_and_si128(_mm256_mask_i64gather_epi32(b, base, at, near, 1), byte);
    } else {
      const __m128i cell = _mm_add_epi32(_mm_slli_epi32(block, 2 * kShift), inner);
      if (coarse) {
        // Lanes whose block is clear march on the block's code; only the
        // others read the map (a masked gather loads nothing for the rest).
        const __m128i b = _mm_and_si128(_mm_i32gather_epi32(coarse_base, block, 1), byte);
        const __m128i near = _mm_cmplt_epi32(b, march_from);
        c = _mm_and_si128(_mm_mask_i32gather_epi32(b, base, cell, near, 1), byte);
      } else {
        c = _mm_and_si128(_mm_i32gather_epi32(base, cell, 1), byte);
      }
    }
    const __m256d cf = _mm256_cvtepi32_pd(c);
    // Hit: an occupied code (0..2) whose bit is in the mask. The two common
    // masks are one compare.
    __m256d hit;
    if (mask == StaticMap::kRangerMask) {
      hit = _mm256_cmp_pd(cf, _mm256_set1_pd(1.5), _CMP_LT_OQ);
    } else if (mask == StaticMap::kAnyMask) {
      hit = _mm256_cmp_pd(cf, _mm256_set1_pd(2.5), _CMP_LT_OQ);
    } else {
      const __m128i in_mask = _mm_and_si128(
          _mm_cmplt_epi32(c, three), _mm_cmpeq_epi32(_mm_and_si128(_mm_srlv_epi32(maskv, c), one), one));
      hit = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(in_mask));
    }
    // March where the cell is far from obstacles, else walk to the next cell
    // boundary (min over x and y) plus a hair.
    const __m256d fx = _mm256_cvtepi32_pd(ix), fy = _mm256_cvtepi32_pd(iy);
    const __m256d tx = _mm256_add_pd(_mm256_mul_pd(_mm256_sub_pd(_mm256_add_pd(fx, v.wx), px), v.ix), v.bx);
    const __m256d ty = _mm256_add_pd(_mm256_mul_pd(_mm256_sub_pd(_mm256_add_pd(fy, v.wy), py), v.iy), v.by);
    const __m256d walk = _mm256_add_pd(_mm256_min_pd(tx, ty), hair);
    const __m256d march = _mm256_sub_pd(cf, slack);
    const __m256d far = _mm256_cmp_pd(cf, far_from, _CMP_GT_OQ);
    const __m256d hit_d = _mm256_andnot_pd(v.fin, hit);
    const __m256d next_t = _mm256_add_pd(v.t, _mm256_blendv_pd(walk, march, far));
    const __m256d over = _mm256_cmp_pd(next_t, v.te, _CMP_GE_OQ);
    const __m256d stay = _mm256_or_pd(_mm256_or_pd(v.fin, hit_d), over);
    v.t = _mm256_blendv_pd(next_t, v.t, stay);
    v.hit = _mm256_or_pd(v.hit, hit_d);
    v.fin = _mm256_or_pd(v.fin, _mm256_and_pd(v.live, _mm256_or_pd(hit_d, over)));
    return _mm256_movemask_pd(v.fin);
  };
  while (active > 0) {
    Group g[kGroups];
    int live = 0;
    for (int i = 0; i < kGroups; ++i) {
      g[i] = load(i);
      live |= _mm256_movemask_pd(g[i].live) << (4 * i);
    }
    // Step the groups until three quarters of the lanes (or all) have
    // ended, then refill those: reloading the registers for every ended ray
    // costs more than letting a few lanes idle (a half measured 8% slower
    // on simple.world). Groups with no ray at all (a batch smaller than
    // the lanes, as a sonar ring's) are not stepped.
    const int want = std::min(std::max(1, __builtin_popcount(unsigned(live))), 3 * kLanes / 4);
    int done = 0;
    do {
      done = 0;
      for (int i = 0; i < kGroups; ++i) {
        if ((live >> (4 * i)) & 0xF) done |= step(g[i]) << (4 * i);
      }
    } while (__builtin_popcount(unsigned(done)) < want);
    int hits = 0;
    for (int i = 0; i < kGroups; ++i) {
      _mm256_store_pd(t + 4 * i, g[i].t);
      hits |= _mm256_movemask_pd(g[i].hit) << (4 * i);
    }
    for (int k = 0; k < kLanes; ++k) {
      if (!((done >> k) & 1) || index[k] < 0) continue;
      out[index[k]] = (hits >> k) & 1 ? float(t[k] * res) : rays[size_t(index[k])].max_range;
      if (!start(k)) --active;
    }
  }
}

}  // namespace

void cast_batch_avx2(const CellStore& map, Vec2 origin, double inv_res, double res,
                     std::span<const RayQuery> rays, uint8_t mask, float* out) {
  cast_lanes<false>(map, origin, inv_res, res, rays, mask, out);
}

void cast_batch_avx2_sparse(const CellStore& map, Vec2 origin, double inv_res, double res,
                            std::span<const RayQuery> rays, uint8_t mask, float* out) {
  cast_lanes<true>(map, origin, inv_res, res, rays, mask, out);
}

}  // namespace troupe::sim::detail
