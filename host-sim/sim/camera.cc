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
  const size_t n = size_t(w) * size_t(h);
  st.rgb.resize(n * 3);
  st.depth.resize(n);
  const Pose at = compose(bodies[st.robot].pose, d.pose);
  const Vec2 o{at.x, at.y};
  // Pinhole intrinsics from the fields of view, principal point at the
  // image centre, shifted by the tilt.
  const double fx = 0.5 * w / std::tan(0.5 * d.hfov);
  const double fy = 0.5 * h / std::tan(0.5 * d.vfov);
  const double cx = 0.5 * w;
  const double cy = 0.5 * h + fy * std::tan(d.tilt);
  const double zc = d.z;

  // Per column: its horizontal ray, and k, the rows per metre of height at
  // one metre of horizontal distance (fy over the column's forward
  // component: its ray leaves the optical axis).
  ray_queries.clear();
  camera_k.resize(size_t(w));
  for (int u = 0; u < w; ++u) {
    const double b = std::atan2(cx - (u + 0.5), fx);
    const double a = at.a + b;
    ray_queries.push_back({o, {std::cos(a), std::sin(a)}, float(d.far)});
    camera_k[size_t(u)] = fy / std::cos(b);
  }

  // The floor and the sky, row by row (contiguous writes): a pixel below
  // the horizon sees the floor where its ray meets it within range. Its
  // ray climbs s = (cy - v) / k metres per horizontal metre, so it meets
  // the floor at zc / -s and its length is zc sqrt(1 + 1 / s^2).
  const uint8_t sky[3] = {uint8_t(kSkyColor >> 16), uint8_t(kSkyColor >> 8), uint8_t(kSkyColor)};
  const uint8_t ground[3] = {uint8_t(kFloorColor >> 16), uint8_t(kFloorColor >> 8), uint8_t(kFloorColor)};
  const float far = float(d.far), zcf = float(zc);
  for (int v = 0; v < h; ++v) {
    uint8_t* rgb = st.rgb.data() + size_t(v) * size_t(w) * 3;
    float* dep = st.depth.data() + size_t(v) * size_t(w);
    const float below = float((v + 0.5) - cy);  // > 0: below the horizon
    for (int u = 0; u < w; ++u) {
      float dist = kNoDepth;
      if (below > 0) {
        const float inv_s = float(camera_k[size_t(u)]) / below;
        const float len = zcf * std::sqrt(1 + inv_s * inv_s);
        if (len <= far) dist = len;
      }
      const uint8_t* c = dist <= far ? ground : sky;
      rgb[3 * u] = c[0];
      rgb[3 * u + 1] = c[1];
      rgb[3 * u + 2] = c[2];
      dep[u] = dist;
    }
  }

  // Robots that may be in the image: within range, and for each the
  // columns its bounding circle covers, so a column tests only those.
  candidates.clear();
  hash.query(o, d.far, [&](uint32_t j) {
    if (j != st.robot) candidates.push_back(j);
  });
  // In index order: spans at equal distances are then drawn in the same
  // order on every run, whatever order the hash gave them in.
  std::sort(candidates.begin(), candidates.end());
  camera_cols.clear();
  for (uint32_t j : candidates) {
    const Body& b = bodies[j];
    const double dx = b.pose.x - o.x, dy = b.pose.y - o.y, dist = std::hypot(dx, dy);
    if (dist - b.radius > d.far) continue;
    int u0 = 0, u1 = w - 1;
    if (dist > b.radius) {
      const double bearing = wrap_angle(std::atan2(dy, dx) - at.a);
      const double half = std::asin(b.radius / dist);
      const double lo = bearing - half, hi = bearing + half;  // rad, left positive
      if (hi <= -kPi / 2 || lo >= kPi / 2) continue;          // behind the camera
      // Column x = cx - fx tan(bearing): the left edge (hi) has the smaller x.
      const double x_left = hi >= kPi / 2 ? -1e9 : cx - fx * std::tan(hi);
      const double x_right = lo <= -kPi / 2 ? 1e9 : cx - fx * std::tan(lo);
      if (x_right < 0 || x_left > w) continue;
      u0 = int(std::max(0.0, std::floor(x_left - 1)));
      u1 = int(std::min(double(w - 1), std::ceil(x_right + 1)));
    }
    camera_cols.push_back({j, u0, u1});
  }

  wall_ranges.resize(size_t(w));
  map.cast_batch(ray_queries, StaticMap::kAnyMask, wall_ranges.data());
  const size_t rgb_stride = size_t(w) * 3;
  for (int u = 0; u < w; ++u) {
    const Vec2 dir = ray_queries[size_t(u)].dir;
    const double k = camera_k[size_t(u)];
    spans.clear();
    const double wall = wall_ranges[size_t(u)];
    if (wall < d.far) {
      const StaticInfo* hit = static_at(o + (wall + 0.5 * map.resolution()) * dir);
      spans.push_back({wall, hit ? hit->look.height : 1.0, hit ? hit->look.color : 0});
    }
    for (const CameraCandidate& c : camera_cols) {
      if (u < c.u0 || u > c.u1) continue;
      const double t = ray_robot(c.robot, o, dir);
      if (t >= 0 && t < wall && t < d.far) {
        spans.push_back({t, desc.robots[c.robot].look.height, desc.robots[c.robot].look.color});
      }
    }
    // Farthest first: nearer spans cover farther ones.
    std::stable_sort(spans.begin(), spans.end(), [](const Span& x, const Span& y) { return x.t > y.t; });
    uint8_t* rgb = st.rgb.data() + size_t(u) * 3;
    float* dep = st.depth.data() + u;
    for (const Span& sp : spans) {
      const double t = std::max(sp.t, 1e-6);
      const int top = row_at(cy - k * (sp.top - zc) / t, h);
      const int bottom = row_at(cy + k * zc / t, h);
      const uint8_t r = uint8_t(sp.color >> 16), g = uint8_t(sp.color >> 8), b = uint8_t(sp.color);
      for (int v = top; v < bottom; ++v) {
        const double s = (cy - (v + 0.5)) / k;  // height per horizontal metre
        const double len = t * std::sqrt(1 + s * s);
        // What lies nearer than near or beyond far (seen steeply) is not seen.
        if (len > d.far || len < d.near) continue;
        uint8_t* p = rgb + size_t(v) * rgb_stride;
        p[0] = r;
        p[1] = g;
        p[2] = b;
        dep[size_t(v) * size_t(w)] = float(len);
      }
    }
  }
  st.width = w;
  st.height = h;
  st.step = steps;
}

}  // namespace troupe::sim
