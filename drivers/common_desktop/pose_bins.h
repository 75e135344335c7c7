// A histogram over poses (x, y, heading) for KLD sampling and clustering:
// each pose maps to one 64-bit bin key.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "drivers/common_desktop/pose2.h"

namespace troupe::desktop {

class PoseBins {
 public:
  /// Bin sides: m, rad.
  PoseBins(double bin_xy, double bin_a)
      : xy_(bin_xy), a_(bin_a), heading_bins_(std::max<int64_t>(1, int64_t(std::ceil(2 * kPi / bin_a)))) {}

  struct Index {
    int64_t ix, iy, ia;
  };
  Index index(const Pose2& p) const {
    int64_t ia = int64_t(std::floor((wrap_angle(p.a) + kPi) / a_));
    return {int64_t(std::floor(p.x / xy_)), int64_t(std::floor(p.y / xy_)), ia % heading_bins_};
  }
  /// 21 bits per axis: positions within +-1e6 bins (500 km at 0.5 m).
  uint64_t key(const Index& i) const {
    int64_t ia = ((i.ia % heading_bins_) + heading_bins_) % heading_bins_;
    return (uint64_t(i.ix + (1 << 20)) & 0x1FFFFF) << 42 | (uint64_t(i.iy + (1 << 20)) & 0x1FFFFF) << 21 |
           uint64_t(ia);
  }
  uint64_t key(const Pose2& p) const { return key(index(p)); }
  int64_t heading_bins() const { return heading_bins_; }

 private:
  double xy_, a_;
  int64_t heading_bins_;
};

}  // namespace troupe::desktop
