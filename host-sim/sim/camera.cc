// Cameras: a software rendering of the 2.5D world, one ray per image column.
// Each column's horizontal ray finds the first wall (the static grid's ray
// marcher) and every robot it crosses before it; each hit is a vertical
// span from the floor to the model's height, projected with the pinhole
// model. Spans are drawn farthest first, so nearer ones cover farther ones;
// the floor and the sky fill what no span covers. The depth image comes
// from the same pass. Limits: only the first wall along a column is drawn
// (a low wall hides the taller one behind it above its top: the sky shows
// there), and the floor is one colour.
#include <algorithm>
#include <cmath>

#include "host-sim/sim/engine.h"

namespace troupe::sim {
namespace {

constexpr uint32_t kFloorColor = 0x808080;
constexpr uint32_t kSkyColor = 0xB4D2F0;
constexpr float kNoDepth = INFINITY;

// Fills rows [from, to) of one column with a colour and the depth of a
// vertical surface (or the floor) at horizontal distance t.
struct Column {
  uint8_t* rgb;       // the column's top pixel
  float* depth;       // the column's top pixel
  size_t rgb_stride;  // bytes per row
  size_t depth_stride;

  void fill(int from, int to, uint32_t color, const float* ray_scale, float t) const {
    const uint8_t r = uint8_t(color >> 16), g = uint8_t(color >> 8), b = uint8_t(color);
    for (int v = from; v < to; ++v) {
      uint8_t* p = rgb + size_t(v) * rgb_stride;
      p[0] = r;
      p[1] = g;
      p[2] = b;
      depth[size_t(v) * depth_stride] = t * ray_scale[v];
    }
  }
};

// The first row whose centre is at or below image coordinate y (rows
// cover [v, v + 1)), clamped to the image.
int row_at(double y, int h) {
  return int(std::clamp(std::ceil(y - 0.5), 0.0, double(h)));
}

}  // namespace

void Engine::update_cameras() {
  for (uint32_t index = 0; index < cameras.size(); ++index) {
    if (cameras[index].wanted) render_camera(index);
  }
}

void Engine::render_camera(uint32_t index) {
  CameraState& st = cameras[index];
  const CameraDesc& d = desc.robots[st.robot].cameras[index - info[st.robot].cameras.first];
  const int w = d.width, h = d.height;
  st.rgb.resize(size_t(w) * size_t(h) * 3);
  st.depth.resize(size_t(w) * size_t(h));
  const Pose at = compose(bodies[st.robot].pose, d.pose);
  const Vec2 o{at.x, at.y};
  // Pinhole intrinsics from the fields of view, principal point at the
  // image centre, shifted by the tilt.
  const double fx = 0.5 * w / std::tan(0.5 * d.hfov);
  const double fy = 0.5 * h / std::tan(0.5 * d.vfov);
  const double cx = 0.5 * w;
  const double cy = 0.5 * h + fy * std::tan(d.tilt);
  const double zc = d.z;
  candidates.clear();
  hash.query(o, d.far, [&](uint32_t j) {
    if (j != st.robot) candidates.push_back(j);
  });
  // Robots in index order: spans of equal distance are then drawn in the
  // same order on every run, whatever order the hash gave them in.
  std::sort(candidates.begin(), candidates.end());
  ray_queries.clear();
  for (int u = 0; u < w; ++u) {
    const double a = at.a + std::atan2(cx - (u + 0.5), fx);
    ray_queries.push_back({o, {std::cos(a), std::sin(a)}, float(d.far)});
  }
  wall_ranges.resize(size_t(w));
  map.cast_batch(ray_queries, StaticMap::kAnyMask, wall_ranges.data());
  std::vector<float>& ray_scale = camera_ray_scale;
  ray_scale.resize(size_t(h));
  const size_t rgb_stride = size_t(w) * 3, depth_stride = size_t(w);
  for (int u = 0; u < w; ++u) {
    const Vec2 dir = ray_queries[size_t(u)].dir;
    // Rows per metre of height at one metre of horizontal distance: fy over
    // the column's forward component (its ray leaves the optical axis).
    const double k = fy / std::cos(std::atan2(cx - (u + 0.5), fx));
    for (int v = 0; v < h; ++v) {
      const double s = (cy - (v + 0.5)) / k;  // height per horizontal metre
      ray_scale[size_t(v)] = float(std::sqrt(1 + s * s));
    }
    const Column col{st.rgb.data() + size_t(u) * 3, st.depth.data() + u, rgb_stride, depth_stride};
    // Sky above the horizon, floor below it, up to the far range.
    const int horizon = row_at(cy, h);
    for (int v = 0; v < horizon; ++v) {
      col.fill(v, v + 1, kSkyColor, ray_scale.data(), kNoDepth);
    }
    for (int v = horizon; v < h; ++v) {
      const double t = zc * k / ((v + 0.5) - cy);  // where the pixel's ray meets the floor
      const bool seen = t * ray_scale[size_t(v)] <= d.far;
      col.fill(v, v + 1, seen ? kFloorColor : kSkyColor, ray_scale.data(), seen ? float(t) : kNoDepth);
    }
    spans.clear();
    const double wall = wall_ranges[size_t(u)];
    if (wall < d.far) {
      const StaticInfo* hit = static_at(o + (wall + 0.5 * map.resolution()) * dir);
      spans.push_back({wall, hit ? hit->look.height : 1.0, hit ? hit->look.color : 0});
    }
    for (uint32_t j : candidates) {
      const double t = ray_robot(j, o, dir);
      if (t >= 0 && t < wall && t < d.far) spans.push_back({t, desc.robots[j].look.height, desc.robots[j].look.color});
    }
    std::stable_sort(spans.begin(), spans.end(), [](const Span& x, const Span& y) { return x.t > y.t; });
    for (const Span& sp : spans) {
      const double t = std::max(sp.t, 1e-6);
      const int top = row_at(cy - k * (sp.top - zc) / t, h);
      const int bottom = row_at(cy + k * zc / t, h);
      if (top >= bottom) continue;
      // Parts of the span beyond the far range (seen steeply) or nearer
      // than the near range stay as they were: the camera does not see them.
      int from = top, to = bottom;
      while (from < to && (t * ray_scale[size_t(from)] > d.far || t * ray_scale[size_t(from)] < d.near)) ++from;
      while (to > from && (t * ray_scale[size_t(to - 1)] > d.far || t * ray_scale[size_t(to - 1)] < d.near)) --to;
      col.fill(from, to, sp.color, ray_scale.data(), float(t));
    }
  }
  st.step = steps;
}

}  // namespace troupe::sim
