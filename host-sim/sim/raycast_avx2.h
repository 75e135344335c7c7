// The vector caster (raycast_avx2.cc, on x86-64 only), which
// StaticMap::cast_batch calls when the processor has AVX2 and FMA.
#pragma once

#include <cstdint>
#include <span>

#include "host-sim/sim/static_map.h"

namespace troupe::sim::detail {

// Where a map's cells are, for the vector caster: `codes` in blocks
// (StaticMap::index), block (bx, by) numbered by * pitch + bx - bias;
// `coarse` (a code per block) may be null on a dense map: then it is not
// used; `slots` is a sparse map's block table (null when dense). Rays stay
// within cells [x0, x1) x [y0, y1) (the window held).
struct CellStore {
  const uint8_t* codes;
  const uint8_t* coarse;
  const uint32_t* slots;
  int pitch;
  int bias;
  int x0, y0, x1, y1;
};
void cast_batch_avx2(const CellStore& map, Vec2 origin, double inv_res, double res,
                     std::span<const RayQuery> rays, uint8_t mask, float* out);
// The same on a sparse map.
void cast_batch_avx2_sparse(const CellStore& map, Vec2 origin, double inv_res, double res,
                            std::span<const RayQuery> rays, uint8_t mask, float* out);

}  // namespace troupe::sim::detail
