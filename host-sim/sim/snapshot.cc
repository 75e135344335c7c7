#include "host-sim/sim/snapshot.h"

#include <algorithm>
#include <cmath>

#include "host-sim/sim/static_map.h"

namespace troupe::sim {
namespace {

struct Canvas {
  world::RgbImage& img;
  Vec2 lo;       // world corner at the image's bottom-left, m
  double scale;  // px/m

  // Image rows grow downwards; world y grows upwards.
  double px(double x) const { return (x - lo.x) * scale; }
  double py(double y) const { return img.height - (y - lo.y) * scale; }

  void put(int x, int y, uint32_t rgb) {
    if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
    uint8_t* p = &img.pixels[(size_t(y) * size_t(img.width) + size_t(x)) * 3];
    p[0] = uint8_t(rgb >> 16);
    p[1] = uint8_t(rgb >> 8);
    p[2] = uint8_t(rgb);
  }

  void line(Vec2 a, Vec2 b, uint32_t rgb) {
    double x0 = px(a.x), y0 = py(a.y), x1 = px(b.x), y1 = py(b.y);
    int n = int(std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0)))) + 1;
    n = std::min(n, 100000);
    for (int i = 0; i <= n; ++i) {
      double t = double(i) / n;
      put(int(std::floor(x0 + t * (x1 - x0))), int(std::floor(y0 + t * (y1 - y0))), rgb);
    }
  }

  void fill(const std::vector<Vec2>& poly, uint32_t rgb) {
    if (poly.size() < 3) return;
    double ymin = 1e300, ymax = -1e300;
    for (Vec2 p : poly) {
      ymin = std::min(ymin, py(p.y));
      ymax = std::max(ymax, py(p.y));
    }
    std::vector<double> xs;
    for (int y = std::max(0, int(ymin)); y <= std::min(img.height - 1, int(ymax)); ++y) {
      const double yc = y + 0.5;
      xs.clear();
      for (size_t i = 0, n = poly.size(); i < n; ++i) {
        double ya = py(poly[i].y), yb = py(poly[(i + 1) % n].y);
        double xa = px(poly[i].x), xb = px(poly[(i + 1) % n].x);
        if ((ya > yc) != (yb > yc)) xs.push_back(xa + (yc - ya) / (yb - ya) * (xb - xa));
      }
      std::sort(xs.begin(), xs.end());
      for (size_t k = 0; k + 1 < xs.size(); k += 2) {
        for (int x = std::max(0, int(std::ceil(xs[k] - 0.5)));
             x <= std::min(img.width - 1, int(xs[k + 1] - 0.5)); ++x) {
          put(x, y, rgb);
        }
      }
    }
  }
};

uint32_t darker(uint32_t rgb) {
  return (rgb >> 1) & 0x7F7F7F;
}

}  // namespace

world::RgbImage render(const World& w, const SnapshotOptions& opt) {
  const StaticMap& map = w.map();
  const double res = map.resolution();
  Vec2 lo = map.origin(), hi = {lo.x + map.width() * res, lo.y + map.height() * res};
  for (RobotId i = 0; i < w.robot_count(); ++i) {
    const Pose& p = w.state(i).pose;
    lo = {std::min(lo.x, p.x - 1), std::min(lo.y, p.y - 1)};
    hi = {std::max(hi.x, p.x + 1), std::max(hi.y, p.y + 1)};
  }
  const double span = std::max(hi.x - lo.x, hi.y - lo.y);
  double scale = opt.scale;
  if (scale <= 0) {
    scale = opt.max_pixels / span;
    if (w.desc().window.scale > 0) scale = std::min(scale, w.desc().window.scale);
  }
  world::RgbImage img;
  img.resize(std::max(1, int(std::ceil((hi.x - lo.x) * scale))),
             std::max(1, int(std::ceil((hi.y - lo.y) * scale))));
  Canvas c{img, lo, scale};

  // Obstacles: each occupied cell paints the pixels it covers (at least one).
  for (int iy = 0; iy < map.height(); ++iy) {
    for (int ix = 0; ix < map.width(); ++ix) {
      if (ix % StaticMap::kTile == 0 && map.block_free(ix / StaticMap::kTile, iy / StaticMap::kTile)) {
        ix += StaticMap::kTile - 1;  // the whole block is free
        continue;
      }
      if (!map.occupied(ix, iy)) continue;
      const double x = map.origin().x + ix * res, y = map.origin().y + iy * res;
      const uint32_t col = map.code(ix, iy) == StaticMap::kBarrier ? 0x9090C0 : 0x404040;
      int x0 = int(c.px(x)), x1 = std::max(x0, int(std::ceil(c.px(x + res))) - 1);
      int y1 = int(c.py(y)), y0 = std::min(y1, int(std::ceil(c.py(y + res))));
      for (int yy = y0; yy <= y1; ++yy) {
        for (int xx = x0; xx <= x1; ++xx) c.put(xx, yy, col);
      }
    }
  }
  if (opt.beams) {
    for (RobotId i = 0; i < w.robot_count(); ++i) {
      const IndexRange rr = w.robot(i).rangers;
      for (uint32_t k = rr.first; k < rr.first + rr.count; ++k) {
        RangerView v = w.ranger(k);
        if (v.step == UINT64_MAX) continue;
        std::vector<Pose> beams = w.ranger_beams(k);
        for (size_t b = 0; b < beams.size() && b < v.ranges.size(); ++b) {
          const Pose& o = beams[b];
          c.line({o.x, o.y}, {o.x + v.ranges[b] * std::cos(o.a), o.y + v.ranges[b] * std::sin(o.a)},
                 0x70C070);
        }
      }
    }
  }
  for (RobotId i = 0; i < w.robot_count(); ++i) {
    const uint32_t col = w.desc().robots[i].look.color;
    for (const auto& poly : w.outline(i)) {
      c.fill(poly, col);
      for (size_t k = 0; k < poly.size(); ++k) c.line(poly[k], poly[(k + 1) % poly.size()], darker(col));
    }
    const Pose& p = w.state(i).pose;
    const double nose = std::max(0.1, 0.6 * std::hypot(w.desc().robots[i].size.x, w.desc().robots[i].size.y));
    c.line({p.x, p.y}, {p.x + nose * std::cos(p.a), p.y + nose * std::sin(p.a)}, 0x000000);
  }
  return img;
}

bool write_snapshot(const World& world, const std::string& path, std::string& error,
                    const SnapshotOptions& options) {
  return world::write_png(path, render(world, options), error);
}

}  // namespace troupe::sim
