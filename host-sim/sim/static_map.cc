#include "host-sim/sim/static_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "host-sim/sim/row_distance.h"

namespace troupe::sim {
namespace {

// Slack that keeps a shape touching a cell's edge from marking the cell.
constexpr double kEdgeSlack = 1e-6;

// Bits of an occupied code: 1 = stops robots, 2 = seen by rangers.
uint8_t bits_of(uint8_t code) {
  switch (code) {
    case StaticMap::kSolid:
      return 3;
    case StaticMap::kVisible:
      return 2;
    case StaticMap::kBarrier:
      return 1;
    default:
      return 0;
  }
}

uint8_t code_of(uint8_t bits) {
  return bits == 3 ? StaticMap::kSolid : bits == 2 ? StaticMap::kVisible : StaticMap::kBarrier;
}

}  // namespace

uint8_t StaticMap::distance_code(double d2) {
  const double d = std::floor(std::sqrt(d2) + 1e-9);
  return uint8_t(kFreeBase + std::min(d, 253.0));
}

uint8_t StaticMap::combined(uint8_t code, uint8_t add) {
  return add == 0 ? code : code_of(uint8_t(bits_of(code) | add));
}

void StaticMap::reset(Vec2 lo, Vec2 hi, double resolution, MapStorage storage, const Vec2* window) {
  res_ = resolution;
  inv_res_ = 1.0 / resolution;
  has_obstacles_ = false;
  origin_ = lo;
  w_ = std::max(1, int(std::ceil((hi.x - lo.x) * inv_res_)));
  h_ = std::max(1, int(std::ceil((hi.y - lo.y) * inv_res_)));
  wx0_ = wy0_ = 0;
  wx1_ = w_ - 1;
  wy1_ = h_ - 1;
  if (window) set_window(window[0], window[1]);
  // Whole blocks (the cells past the grid's edges stay free and are never
  // reached), and four bytes more: the vector caster reads a cell as the
  // low byte of a 32-bit load.
  blocks_w_ = (w_ + kTile - 1) >> kTileShift;
  blocks_h_ = (h_ + kTile - 1) >> kTileShift;
  const int bx0 = wx0_ >> kTileShift, by0 = wy0_ >> kTileShift;
  const size_t held_w = size_t((wx1_ >> kTileShift) - bx0 + 1),
               held_h = size_t((wy1_ >> kTileShift) - by0 + 1);
  const size_t held = held_w * held_h;
  constexpr size_t kBlockCells = size_t(1) << (2 * kTileShift);
  // A dense map's cells are found by 32-bit offsets: beyond 2^30 cells it
  // is sparse whatever was asked.
  const bool sparse = storage == MapStorage::Sparse ||
                      (storage == MapStorage::Auto && held * kBlockCells >= kSparseFromCells) ||
                      held * kBlockCells > (size_t(1) << 30);
  // Fresh storage: a map built again as a window gives back what the
  // whole map held.
  decltype(codes_)().swap(codes_);
  decltype(coarse_)().swap(coarse_);
  decltype(slots_)().swap(slots_);
  free_slots_.clear();
  use_coarse_ = false;
  if (!sparse) {
    pitch_ = int(held_w);
    bias_ = ptrdiff_t(by0) * pitch_ + bx0;
    codes_.assign((held << (2 * kTileShift)) + 4, kFree);
    return;
  }
  // Every block starts as the uniform free block.
  pitch_ = blocks_w_;
  bias_ = 0;
  const size_t blocks = size_t(blocks_w_) * size_t(blocks_h_);
  slots_.assign(blocks, kFree);
  codes_.resize(kUniformBlocks * kBlockCells);
  for (uint32_t c = 0; c < kUniformBlocks; ++c)
    std::fill_n(codes_.begin() + std::ptrdiff_t(c * kBlockCells), kBlockCells, uint8_t(c));
}

void StaticMap::mark(int ix, int iy, uint8_t add) {
  if (add == 0) return;
  uint8_t* cell = &codes_[index(ix, iy)];
  const uint8_t code = combined(*cell, add);
  if (code == *cell) return;  // already so: a shared block stays shared
  if (sparse()) {
    const size_t block = block_number(ix >> kTileShift, iy >> kTileShift);
    if (slots_[block] < kUniformBlocks)
      cell = writable_block(block) + size_t((iy & (kTile - 1)) << kTileShift) + size_t(ix & (kTile - 1));
  }
  *cell = code;
}

void StaticMap::fill_box(Vec2 lo, Vec2 hi, bool obstacle, bool visible) {
  has_obstacles_ = has_obstacles_ || obstacle;
  double x0 = (lo.x - origin_.x) * inv_res_, x1 = (hi.x - origin_.x) * inv_res_;
  double y0 = (lo.y - origin_.y) * inv_res_, y1 = (hi.y - origin_.y) * inv_res_;
  int ix0 = int(std::floor(x0 + kEdgeSlack)), ix1 = int(std::ceil(x1 - kEdgeSlack)) - 1;
  int iy0 = int(std::floor(y0 + kEdgeSlack)), iy1 = int(std::ceil(y1 - kEdgeSlack)) - 1;
  // A box thinner than a cell still marks the cell it lies in.
  if (ix1 < ix0) ix0 = ix1 = int(std::floor(0.5 * (x0 + x1)));
  if (iy1 < iy0) iy0 = iy1 = int(std::floor(0.5 * (y0 + y1)));
  ix0 = std::max(ix0, wx0_);
  iy0 = std::max(iy0, wy0_);
  ix1 = std::min(ix1, wx1_);
  iy1 = std::min(iy1, wy1_);
  const uint8_t add = uint8_t((obstacle ? 1 : 0) | (visible ? 2 : 0));
  if (sparse()) return fill_box_sparse(ix0, iy0, ix1, iy1, add);
  for (int iy = iy0; iy <= iy1; ++iy) {
    for (int ix = ix0; ix <= ix1; ++ix) mark(ix, iy, add);
  }
}

void StaticMap::fill_polygon(std::span<const Vec2> poly, bool obstacle, bool visible) {
  has_obstacles_ = has_obstacles_ || obstacle;
  const size_t n = poly.size();
  const uint8_t add = uint8_t((obstacle ? 1 : 0) | (visible ? 2 : 0));
  if (n == 0 || add == 0) return;
  std::vector<Vec2> c(n);
  double ymin = 1e300, ymax = -1e300;
  for (size_t i = 0; i < n; ++i) {
    c[i] = {(poly[i].x - origin_.x) * inv_res_, (poly[i].y - origin_.y) * inv_res_};
    ymin = std::min(ymin, c[i].y);
    ymax = std::max(ymax, c[i].y);
  }
  auto mark_span = [&](int iy, double xa, double xb) {
    int ix0 = std::max(wx0_, int(std::floor(xa + kEdgeSlack)));
    int ix1 = std::min(wx1_, std::max(int(std::ceil(xb - kEdgeSlack)) - 1, int(std::floor(xa + kEdgeSlack))));
    for (int ix = ix0; ix <= ix1; ++ix) mark(ix, iy, add);
  };
  int row0 = std::max(wy0_, int(std::floor(ymin + kEdgeSlack)));
  int row1 = std::min(wy1_, int(std::ceil(ymax - kEdgeSlack)) - 1);
  const bool flat = ymax - ymin < 2 * kEdgeSlack;  // a line along x, or a point
  if (row1 < row0 && ymin >= wy0_ && ymin < wy1_ + 1) row0 = row1 = int(std::floor(ymin));
  std::vector<double> xs;
  for (int iy = row0; iy <= row1; ++iy) {
    const double y0 = iy + kEdgeSlack, y1 = iy + 1 - kEdgeSlack;
    // The outline: every cell of this row an edge passes through.
    for (size_t i = 0; i < n; ++i) {
      Vec2 a = c[i], b = c[(i + 1) % n];
      if (a.y == b.y) {
        if (flat || (a.y >= y0 && a.y <= y1)) {
          mark_span(iy, std::min(a.x, b.x), std::max(a.x, b.x));
        }
        continue;
      }
      double ta = (y0 - a.y) / (b.y - a.y), tb = (y1 - a.y) / (b.y - a.y);
      double lo = std::max(0.0, std::min(ta, tb)), hi = std::min(1.0, std::max(ta, tb));
      if (lo > hi) continue;
      double xa = a.x + lo * (b.x - a.x), xb = a.x + hi * (b.x - a.x);
      mark_span(iy, std::min(xa, xb), std::max(xa, xb));
    }
    // The inside: cells whose centre is in the polygon (even-odd).
    const double yc = iy + 0.5;
    xs.clear();
    for (size_t i = 0; i < n; ++i) {
      Vec2 a = c[i], b = c[(i + 1) % n];
      if ((a.y > yc) != (b.y > yc)) xs.push_back(a.x + (yc - a.y) / (b.y - a.y) * (b.x - a.x));
    }
    std::sort(xs.begin(), xs.end());
    for (size_t k = 0; k + 1 < xs.size(); k += 2) {
      int ix0 = std::max(wx0_, int(std::ceil(xs[k] - 0.5)));
      int ix1 = std::min(wx1_, int(std::floor(xs[k + 1] - 0.5)));
      for (int ix = ix0; ix <= ix1; ++ix) mark(ix, iy, add);
    }
  }
  // A rotated bitmap is a polygon per run of pixels: give back the blocks
  // they have filled whole, or a building's inside would keep its cells.
  if (sparse() && row0 <= row1) {
    double xmin = 1e300, xmax = -1e300;
    for (const Vec2& p : c) {
      xmin = std::min(xmin, p.x);
      xmax = std::max(xmax, p.x);
    }
    const int bx0 = int(std::clamp(std::floor(xmin), 0.0, double(w_ - 1))) >> kTileShift;
    const int bx1 = int(std::clamp(std::floor(xmax), 0.0, double(w_ - 1))) >> kTileShift;
    for (int by = row0 >> kTileShift; by <= row1 >> kTileShift; ++by) {
      for (int bx = bx0; bx <= bx1; ++bx) release_if_uniform(size_t(by) * size_t(blocks_w_) + size_t(bx));
    }
  }
}

void StaticMap::set_window(Vec2 lo, Vec2 hi) {
  auto cell = [](double v, double o, double inv) { return std::floor((v - o) * inv); };
  wx0_ = int(std::clamp(cell(lo.x, origin_.x, inv_res_), 0.0, double(w_ - 1)));
  wy0_ = int(std::clamp(cell(lo.y, origin_.y, inv_res_), 0.0, double(h_ - 1)));
  wx1_ = int(std::clamp(cell(hi.x, origin_.x, inv_res_), double(wx0_), double(w_ - 1)));
  wy1_ = int(std::clamp(cell(hi.y, origin_.y, inv_res_), double(wy0_), double(h_ - 1)));
}

void StaticMap::finish() {
  if (sparse()) {
    finish_sparse();
  } else {
    finish_dense();
  }
}

void StaticMap::finish_dense() {
  // Exact Euclidean distance transform (Felzenszwalb-Huttenlocher): a
  // vertical pass in two row-order sweeps, then the lower envelope of
  // parabolas along each row. Distances beyond 253 cells saturate. Over
  // the cells held (a window's obstacles are all it knows of).
  const int x0 = wx0_, y0 = wy0_;
  const size_t w = size_t(wx1_ - wx0_ + 1), h = size_t(wy1_ - wy0_ + 1);
  std::vector<uint8_t> g(w * h);
  for (size_t y = 0; y < h; ++y) {
    uint8_t* gr = &g[y * w];
    const uint8_t* above = y > 0 ? &g[(y - 1) * w] : nullptr;
    for (size_t x = 0; x < w; ++x) {
      gr[x] = code(x0 + int(x), y0 + int(y)) <= kBarrier
                  ? 0
                  : (above ? uint8_t(std::min(255, above[x] + 1)) : 255);
    }
  }
  for (size_t y = h - 1; y-- > 0;) {
    uint8_t* gr = &g[y * w];
    const uint8_t* below = &g[(y + 1) * w];
    for (size_t x = 0; x < w; ++x) gr[x] = uint8_t(std::min<int>(gr[x], below[x] + 1));
  }
  std::vector<double> f(w);
  RowDistance row;
  for (size_t y = 0; y < h; ++y) {
    const uint8_t* gr = &g[y * w];
    for (size_t x = 0; x < w; ++x) f[x] = double(gr[x]) * double(gr[x]);
    row.build(f.data(), int(w));
    for (int q = 0; q < int(w); ++q) {
      const double d2 = row.at(q);
      uint8_t& cell = codes_[index(x0 + q, y0 + int(y))];
      if (cell > kBarrier) cell = distance_code(d2);
    }
  }
  // The coarse level: a byte per block held, four bytes longer for the
  // vector caster's loads.
  constexpr size_t kBlockCells = size_t(1) << (2 * kTileShift);
  const size_t blocks = (codes_.size() - 4) / kBlockCells;
  coarse_.assign(blocks + 4, kFree);
  for (size_t b = 0; b < blocks; ++b) {
    const uint8_t* cells = &codes_[b * kBlockCells];
    coarse_[b] = *std::min_element(cells, cells + kBlockCells);
  }
  // Whether it is read follows the whole grid's size, held or not: a
  // window reads the steps the whole map would.
  use_coarse_ = size_t(w_) * size_t(h_) >= kCoarseFromCells;
}

void StaticMap::prefetch(Vec2 p, double r) const {
  const double u = (p.x - origin_.x) * inv_res_, v = (p.y - origin_.y) * inv_res_, ru = r * inv_res_;
  if (!(u - ru >= wx0_ && v - ru >= wy0_ && u + ru < wx1_ + 1 && v + ru < wy1_ + 1))
    return;  // near the edge: not worth it
  const int bx0 = int(u - ru) >> kTileShift, bx1 = std::min(int(u + ru) >> kTileShift, bx0 + 2);
  const int by0 = int(v - ru) >> kTileShift, by1 = std::min(int(v + ru) >> kTileShift, by0 + 2);
  // A sparse block's cells are found through its table entry: loading the
  // entry now would wait for it, so only the entry is fetched.
  const uint8_t* cells = sparse() ? reinterpret_cast<const uint8_t*>(slots_.data()) : codes_.data();
  const int shift = sparse() ? 2 : 2 * kTileShift;  // bytes per block: 4 (an entry) or 64 (its cells)
  for (int by = by0; by <= by1; ++by) {
    for (int bx = bx0; bx <= bx1; ++bx) {
      const size_t block = block_number(bx, by);
      if (use_coarse_) __builtin_prefetch(&coarse_[block]);
      __builtin_prefetch(cells + (block << shift));
    }
  }
}

bool StaticMap::overlaps(std::span<const Vec2> poly, uint8_t mask) const {
  if (poly.empty()) return false;
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (Vec2 p : poly) {
    xmin = std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  int ix0 = std::max(wx0_, int(std::floor((xmin - origin_.x) * inv_res_)));
  int ix1 = std::min(wx1_, int(std::floor((xmax - origin_.x) * inv_res_)));
  int iy0 = std::max(wy0_, int(std::floor((ymin - origin_.y) * inv_res_)));
  int iy1 = std::min(wy1_, int(std::floor((ymax - origin_.y) * inv_res_)));
  for (int iy = iy0; iy <= iy1; ++iy) {
    for (int ix = ix0; ix <= ix1; ++ix) {
      uint8_t c = code(ix, iy);
      if (c > kBarrier || !((mask >> c) & 1u)) continue;
      Vec2 lo{origin_.x + ix * res_, origin_.y + iy * res_};
      if (polygon_overlaps_box(poly, lo, {lo.x + res_, lo.y + res_})) return true;
    }
  }
  return false;
}

bool StaticMap::segment_hits(Vec2 a, Vec2 b, uint8_t mask) const {
  Vec2 d = b - a;
  double len = length(d);
  if (len < 1e-12) {
    int ix = int(std::floor((a.x - origin_.x) * inv_res_)),
        iy = int(std::floor((a.y - origin_.y) * inv_res_));
    if (ix < wx0_ || iy < wy0_ || ix > wx1_ || iy > wy1_) return false;
    uint8_t c = code(ix, iy);
    return c <= kBarrier && ((mask >> c) & 1u);
  }
  return cast(a, (1.0 / len) * d, float(len), mask) < float(len);
}

double StaticMap::clearance(Vec2 p, double enough) const {
  double u = (p.x - origin_.x) * inv_res_, v = (p.y - origin_.y) * inv_res_;
  const double u0 = wx0_, v0 = wy0_, u1 = wx1_ + 1, v1 = wy1_ + 1;
  if (u < u0 || v < v0 || u >= u1 || v >= v1) {
    double ex = std::max({0.0, u0 - u, u - u1}), ey = std::max({0.0, v0 - v, v - v1});
    return std::hypot(ex, ey) * res_;
  }
  // A block's code is its smallest cell's: the same bound holds anywhere in
  // the block.
  if (use_coarse_) {
    const uint8_t b = coarse_[block_number(int(u) >> kTileShift, int(v) >> kTileShift)];
    const double bound = std::max(0.0, (double(b) - kFreeBase - 1.4143) * res_);
    if (bound > enough) return bound;
  }
  uint8_t c = code(int(u), int(v));
  if (c <= kBarrier) return 0;
  return std::max(0.0, (double(c) - kFreeBase - 1.4143) * res_);
}

}  // namespace troupe::sim
