// The sparse map: filled a box at a time (a box that covers a whole block
// leaves it shared), then its distance field computed without ever holding
// the grid: the coarse level row of blocks by row of blocks, exact, and the
// cells of each block the casters will read from the obstacles around it.
// The codes are those the dense map computes, cell for cell and block for
// block (tests/sim/sparse_map_test.cc compares them).
#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>

#include "host-sim/sim/row_distance.h"
#include "host-sim/sim/static_map.h"

namespace troupe::sim {
namespace {

constexpr int kShift = StaticMap::kTileShift;
constexpr int kTile = StaticMap::kTile;
constexpr size_t kBlockCells = size_t(1) << (2 * kShift);
// The casters read a block's cells when its coarse code is below this.
constexpr uint8_t kMarchFrom = StaticMap::kFreeBase + 3;
// Vertical distances are capped where the dense field caps them (a byte):
// past it every code saturates anyway.
constexpr int kFar = 255;
// Block rows whose vertical distances upwards are found in one sweep, and
// the rows above them that sweep starts from (kFar cells).
constexpr int kBand = 64;
constexpr int kReach = (kFar + kTile) / kTile;
// A stored block's cells are all within 13 cells of an obstacle (one of
// them is within 3, the others at most 7 sqrt(2) further), so the blocks
// two around it hold every obstacle that sets their codes.
constexpr int kApron = 2;
constexpr int kNear = 13;

// Bit i: cell i of the block (row i / 8, column i % 8) is occupied.
uint64_t occupancy_of(const uint8_t* cells) {
  uint64_t m = 0;
  for (size_t i = 0; i < kBlockCells; ++i) m |= uint64_t(cells[i] <= StaticMap::kBarrier) << i;
  return m;
}

// The rows of column c (0..7) of a block's occupancy, a bit per row.
uint64_t column_bits(uint64_t occupancy, int c) {
  return (occupancy >> c) & 0x0101010101010101ull;
}
int lowest_row(uint64_t column) {
  return std::countr_zero(column) >> kShift;
}
int highest_row(uint64_t column) {
  return (63 - std::countl_zero(column)) >> kShift;
}

}  // namespace

uint8_t* StaticMap::writable_block(size_t block) {
  uint32_t& slot = slots_[block];
  if (slot >= kUniformBlocks) return &codes_[size_t(slot) << (2 * kShift)];
  const uint8_t code = uint8_t(slot);
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = uint32_t(codes_.size() / kBlockCells);
    codes_.resize(codes_.size() + kBlockCells);
  }
  uint8_t* cells = &codes_[size_t(slot) << (2 * kShift)];
  std::fill_n(cells, kBlockCells, code);
  return cells;
}

void StaticMap::release_if_uniform(size_t block) {
  const uint32_t slot = slots_[block];
  if (slot < kUniformBlocks) return;
  const uint8_t* cells = &codes_[size_t(slot) << (2 * kShift)];
  if (!std::all_of(cells, cells + kBlockCells, [&](uint8_t c) { return c == cells[0]; })) return;
  free_slots_.push_back(slot);
  slots_[block] = cells[0];
}

void StaticMap::fill_box_sparse(int ix0, int iy0, int ix1, int iy1, uint8_t add) {
  for (int by = iy0 >> kShift; by <= iy1 >> kShift; ++by) {
    const int y0 = std::max(iy0, by << kShift), y1 = std::min(iy1, (by << kShift) + kTile - 1);
    for (int bx = ix0 >> kShift; bx <= ix1 >> kShift; ++bx) {
      const int x0 = std::max(ix0, bx << kShift), x1 = std::min(ix1, (bx << kShift) + kTile - 1);
      const size_t block = size_t(by) * size_t(blocks_w_) + size_t(bx);
      const uint32_t slot = slots_[block];
      if (slot < kUniformBlocks) {
        const uint8_t code = combined(uint8_t(slot), add);
        if (code == slot) continue;  // already so
        if (x1 - x0 == kTile - 1 && y1 - y0 == kTile - 1) {
          slots_[block] = code;  // the whole block: it stays shared
          continue;
        }
      }
      uint8_t* cells = writable_block(block);
      for (int y = y0; y <= y1; ++y) {
        uint8_t* row = cells + ((y & (kTile - 1)) << kShift);
        for (int x = x0; x <= x1; ++x) row[x & (kTile - 1)] = combined(row[x & (kTile - 1)], add);
      }
      // Runs of a bitmap's rows complete a block a piece at a time.
      release_if_uniform(block);
    }
  }
}

void StaticMap::finish_sparse() {
  const size_t blocks = slots_.size(), places = codes_.size() / kBlockCells;
  const size_t bw = size_t(blocks_w_);
  // Per place in the pool: its occupied cells and its smallest code.
  std::vector<uint64_t> occupancy(places);
  std::vector<uint8_t> lowest(places);
  for (size_t p = 0; p < places; ++p) {
    const uint8_t* cells = &codes_[p * kBlockCells];
    occupancy[p] = occupancy_of(cells);
    lowest[p] = *std::min_element(cells, cells + kBlockCells);
  }
  auto block_occupancy = [&](size_t by, size_t bx) { return occupancy[slots_[by * bw + bx]]; };

  // The coarse level, exact: the smallest code of a block is its occupied
  // cells' smallest, or the distance from its nearest obstacle, found as
  // the dense field finds a cell's (each column's vertical distance, then
  // the envelope along the row) with a row of blocks for a row of cells.
  coarse_.assign(blocks + 4, kFree);
  const int w = w_;
  const size_t columns = size_t(w_);
  std::vector<int> below(columns, INT_MIN / 2);  // highest occupied row under the block row
  std::vector<int> next_up(columns);             // lowest occupied row above it
  std::vector<uint8_t> above(size_t(kBand) * columns);
  std::vector<double> f(columns);
  std::vector<int> vertical(columns);
  RowDistance row;
  // Calls fn(x, column bits) for every column of block row `by` with an
  // occupied cell.
  auto occupied_columns = [&](int by, auto&& fn) {
    for (size_t bx = 0; bx < bw; ++bx) {
      const uint64_t m = block_occupancy(size_t(by), bx);
      if (m == 0) continue;
      for (int c = 0; c < kTile; ++c) {
        if (const uint64_t col = column_bits(m, c)) fn(int(bx << kShift) + c, col);
      }
    }
  };
  for (int band = 0; band < blocks_h_; band += kBand) {
    const int end = std::min(blocks_h_, band + kBand);
    std::fill(next_up.begin(), next_up.end(), INT_MAX / 2);
    for (int by = std::min(blocks_h_ - 1, end - 1 + kReach); by >= band; --by) {
      if (by < end) {
        const int y1 = std::min(h_ - 1, (by << kShift) + kTile - 1);
        uint8_t* up = &above[size_t(by - band) * size_t(w)];
        for (int x = 0; x < w; ++x) up[x] = uint8_t(std::min(kFar, next_up[size_t(x)] - y1));
      }
      occupied_columns(by,
                       [&](int x, uint64_t col) { next_up[size_t(x)] = (by << kShift) + lowest_row(col); });
    }
    for (int by = band; by < end; ++by) {
      const int y0 = by << kShift;
      const uint8_t* up = &above[size_t(by - band) * size_t(w)];
      bool near = false;
      for (int x = 0; x < w; ++x) {
        vertical[size_t(x)] = std::min({kFar, y0 - below[size_t(x)], int(up[x])});
        near |= vertical[size_t(x)] < kFar;
      }
      occupied_columns(by, [&](int x, uint64_t col) {
        vertical[size_t(x)] = 0;
        below[size_t(x)] = y0 + highest_row(col);
        near = true;
      });
      uint8_t* out = &coarse_[size_t(by) * bw];
      if (near) {
        for (int x = 0; x < w; ++x) f[size_t(x)] = double(vertical[size_t(x)]) * vertical[size_t(x)];
        row.build(f.data(), w);
      }
      for (size_t bx = 0; bx < bw; ++bx) {
        const uint32_t slot = slots_[size_t(by) * bw + bx];
        if (occupancy[slot] != 0) {
          out[bx] = lowest[slot];
        } else if (near) {
          double d2 = 1e300;
          for (int x = int(bx << kShift); x < std::min(w, int(bx << kShift) + kTile); ++x)
            d2 = std::min(d2, row.at(x));
          out[bx] = distance_code(d2);
        }
      }
    }
  }

  // The blocks the casters read (below kMarchFrom) keep cells of their own
  // in a new pool, in block order; all-occupied ones stay shared, and the
  // rest become the uniform block of their coarse code.
  size_t stored = 0;
  for (size_t b = 0; b < blocks; ++b) {
    stored += coarse_[b] < kMarchFrom && !(slots_[b] < kUniformBlocks && slots_[b] <= kBarrier);
  }
  std::vector<uint8_t, HugePageAllocator<uint8_t>> pool((kUniformBlocks + stored) * kBlockCells + 4, kFree);
  std::copy_n(codes_.begin(), kUniformBlocks * kBlockCells, pool.begin());
  // The occupancy of the five block rows around the one being rewritten,
  // read before their table entries change.
  constexpr int kRows = 2 * kApron + 1;
  std::vector<uint64_t> ring(size_t(kRows) * (bw + 2 * kApron));
  auto ring_row = [&](int by) { return &ring[size_t((by + kRows) % kRows) * (bw + 2 * kApron) + kApron]; };
  auto load_row = [&](int by) {
    uint64_t* r = ring_row(by);
    for (size_t bx = 0; bx < bw; ++bx) r[bx] = by < blocks_h_ ? block_occupancy(size_t(by), bx) : 0;
  };
  for (int by = 0; by < kApron; ++by) load_row(by);
  uint32_t next = kUniformBlocks;
  for (int by = 0; by < blocks_h_; ++by) {
    load_row(by + kApron);  // rows under the first stay as the ring starts: empty
    for (size_t bx = 0; bx < bw; ++bx) {
      const size_t b = size_t(by) * bw + bx;
      uint32_t& slot = slots_[b];
      if (coarse_[b] >= kMarchFrom) {
        slot = coarse_[b];
        continue;
      }
      if (slot < kUniformBlocks && slot <= kBarrier) continue;
      uint8_t* cells = &pool[size_t(next) * kBlockCells];
      std::copy_n(&codes_[size_t(slot) * kBlockCells], kBlockCells, cells);
      slot = next++;
      // The obstacles around, a row of 40 cells a bit each: bit 16 + c is
      // column c of this block, row 16 + r row r.
      uint64_t window[kRows * kTile] = {};
      for (int dy = -kApron; dy <= kApron; ++dy) {
        const uint64_t* r = ring_row(by + dy);
        for (int dx = -kApron; dx <= kApron; ++dx) {
          const uint64_t m = r[ptrdiff_t(bx) + dx];
          for (int k = 0; m != 0 && k < kTile; ++k) {
            window[(dy + kApron) * kTile + k] |= ((m >> (k * kTile)) & 0xFF) << ((dx + kApron) * kTile);
          }
        }
      }
      // Per window row, each of this block's columns' distance to the
      // row's nearest obstacle (64: none in the window).
      int across[kRows * kTile][kTile];
      for (int wr = 0; wr < kRows * kTile; ++wr) {
        for (int c = 0; c < kTile; ++c) {
          const int at = kApron * kTile + c;
          const uint64_t right = window[wr] >> at, left = window[wr] << (63 - at);
          across[wr][c] = std::min(right ? std::countr_zero(right) : 64, left ? std::countl_zero(left) : 64);
        }
      }
      // Codes by squared distance, as distance_code gives them (a sixth of
      // the load went to its square roots).
      static const std::array<uint8_t, kNear* kNear + 64 * 64 + 1> kCodeOf = [] {
        std::array<uint8_t, kNear * kNear + 64 * 64 + 1> t{};
        for (size_t d2 = 0; d2 < t.size(); ++d2) t[d2] = distance_code(double(d2));
        return t;
      }();
      for (int r = 0; r < kTile && (by << kShift) + r < h_; ++r) {
        for (int c = 0; c < kTile && int(bx << kShift) + c < w; ++c) {
          uint8_t& cell = cells[(r << kShift) + c];
          if (cell <= kBarrier) continue;
          int d2 = INT_MAX;
          for (int dy = -kNear; dy <= kNear; ++dy) {
            const int a = across[kApron * kTile + r + dy][c];
            d2 = std::min(d2, dy * dy + a * a);
          }
          cell = kCodeOf[size_t(d2)];
        }
      }
    }
  }
  codes_.swap(pool);
  free_slots_ = {};
  use_coarse_ = true;
}

}  // namespace troupe::sim
