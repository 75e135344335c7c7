// Cameras: a software rendering of the 2.5D world from horizontal rays of
// the static grid's ray marcher. Each ray finds the first wall and every
// robot it crosses before it; each hit is a vertical span from the floor to
// the model's height. The floor is painted (FloorDesc: a colour and marks,
// such as a RoboCup field's lines) and the sky fills what nothing covers.
// The depth image comes from the same pass. Two projections:
//  - pinhole: one ray per image column; spans are projected with the
//    pinhole model, farthest first, so nearer ones cover farther ones;
//  - omni (an isometric mirror): one ray per pixel of the image's rim, all
//    around; each pixel follows its ray down to the ground point its radius
//    maps to (or up, in the outer ring) and takes the first span it meets.
// Limits: only the first wall along a ray is drawn (a low wall hides the
// taller one behind it above its top: the sky shows there).
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "host-sim/sim/engine.h"

namespace troupe::sim {
namespace {

constexpr uint32_t kSkyColor = 0xB4D2F0;
constexpr float kNoDepth = INFINITY;

// The first row whose centre is at or below image coordinate y (rows
// cover [v, v + 1)), clamped to the image.
int row_at(double y, int h) {
  return int(std::clamp(std::ceil(y - 0.5), 0.0, double(h)));
}

void put(uint8_t* p, uint32_t color) {
  p[0] = uint8_t(color >> 16);
  p[1] = uint8_t(color >> 8);
  p[2] = uint8_t(color);
}

}  // namespace

uint32_t floor_color(const FloorDesc& floor, Vec2 p) {
  // Squared distances, so the test per mark takes no square root (this runs
  // for every floor pixel).
  uint32_t color = floor.color;
  for (const FloorMark& m : floor.marks) {
    const double half = 0.5 * m.width;
    bool on;
    if (m.radius > 0) {
      const double d2 = length_squared(p - m.a), inner = std::max(0.0, m.radius - half);
      on = d2 >= inner * inner && d2 <= (m.radius + half) * (m.radius + half);
    } else {
      const Vec2 ab = m.b - m.a;
      const double l2 = dot(ab, ab);
      const double f = l2 > 0 ? std::clamp(dot(p - m.a, ab) / l2, 0.0, 1.0) : 0.0;
      on = length_squared(p - (m.a + f * ab)) <= half * half;
    }
    if (on) color = m.color;
  }
  return color;
}

void Engine::camera_sights(RobotId own, const Pose& at, double far) {
  const Vec2 o{at.x, at.y};
  candidates.clear();
  hash.query(o, far, [&](uint32_t j) {
    if (j != own) candidates.push_back(j);
  });
  // In index order: spans at equal distances are then drawn in the same
  // order on every run, whatever order the hash gave them in.
  std::sort(candidates.begin(), candidates.end());
  sights.clear();
  for (uint32_t j : candidates) {
    const Body& b = bodies[j];
    const double dx = b.pose.x - o.x, dy = b.pose.y - o.y, dist = std::hypot(dx, dy);
    if (dist - b.radius > far) continue;
    if (dist <= b.radius) {
      sights.push_back({j, 0, 0, true});
    } else {
      sights.push_back({j, wrap_angle(std::atan2(dy, dx) - at.a), std::asin(b.radius / dist), false});
    }
  }
}

void Engine::ray_spans(Vec2 o, Vec2 dir, double wall, double far, int ray, int rays) {
  spans.clear();
  if (wall < far) {
    const StaticInfo* hit = static_at(o + (wall + 0.5 * map.resolution()) * dir);
    spans.push_back({wall, hit ? hit->look.height : 1.0, hit ? hit->look.color : 0});
  }
  for (const CameraCandidate& c : camera_cols) {
    if (((ray - c.u0) % rays + rays) % rays > c.u1 - c.u0) continue;
    const double t = ray_robot(c.robot, o, dir);
    if (t >= 0 && t < wall && t < far) {
      spans.push_back({t, desc.robots[c.robot].look.height, desc.robots[c.robot].look.color});
    }
  }
}

void Engine::update_cameras() {
  for (uint32_t index = 0; index < cameras.size(); ++index) {
    if (!due(cameras[index])) continue;
    render_camera(index);
    add_camera_noise(index);
  }
}

void Engine::add_camera_noise(uint32_t index) {
  CameraState& st = cameras[index];
  const CameraDesc& d = desc.robots[st.robot].cameras[index - info[st.robot].cameras.first];
  if (d.color_noise <= 0 && d.depth_noise <= 0) return;
  const bool omni = d.projection == CameraProjection::Omni;
  const uint64_t stream = Random::stream(uint64_t(RandomKind::CameraNoise), index, steps);
  const size_t n = size_t(st.width) * size_t(st.height);
  for (size_t px = 0; px < n; ++px) {
    // Beyond an omni mirror's rim no light reaches the sensor: it stays
    // black, as on a real F2000 camera.
    if (omni && omni_pixels[px].ray < 0) continue;
    // Four counters per pixel (red, green, blue, depth), so every value has
    // its own numbers whichever of the two noises is on.
    const uint64_t counter = 4 * uint64_t(px);
    if (d.color_noise > 0) {
      uint8_t* c = st.rgb.data() + 3 * px;
      for (int k = 0; k < 3; ++k) {
        const double v = c[k] + d.color_noise * random.gaussian(stream, counter + uint64_t(k));
        c[k] = uint8_t(std::clamp(std::lround(v), 0l, 255l));
      }
    }
    // A pixel that saw nothing within range has no depth to blur; a noisy
    // depth never goes below 0.
    float& z = st.depth[px];
    if (d.depth_noise > 0 && std::isfinite(z))
      z = std::max(0.0f, float(z + d.depth_noise * random.gaussian(stream, counter + 3)));
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
  st.width = w;
  st.height = h;
  st.step = steps;
  if (d.projection == CameraProjection::Omni) {
    render_omni(st, d, at);
    return;
  }
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
  // the floor zc / -s horizontal metres away and its length is
  // zc sqrt(1 + 1 / s^2).
  // An unpainted floor is one colour: its loop stays as lean as the sky's
  // (this fill is a good part of a pinhole image's cost).
  const uint8_t sky[3] = {uint8_t(kSkyColor >> 16), uint8_t(kSkyColor >> 8), uint8_t(kSkyColor)};
  const uint32_t plain = desc.floor.color;
  const uint8_t ground[3] = {uint8_t(plain >> 16), uint8_t(plain >> 8), uint8_t(plain)};
  const float far = float(d.far), zcf = float(zc);
  auto fill = [&](auto painted) {
    for (int v = 0; v < h; ++v) {
      uint8_t* rgb = st.rgb.data() + size_t(v) * size_t(w) * 3;
      float* dep = st.depth.data() + size_t(v) * size_t(w);
      const float below = float((v + 0.5) - cy);  // > 0: below the horizon
      for (int u = 0; u < w; ++u) {
        float dist = kNoDepth;
        float inv_s = 0;
        if (below > 0) {
          inv_s = float(camera_k[size_t(u)]) / below;
          const float len = zcf * std::sqrt(1 + inv_s * inv_s);
          if (len <= far) dist = len;
        }
        if constexpr (decltype(painted)::value) {
          put(rgb + 3 * u, dist <= far
                               ? floor_color(desc.floor, o + double(zcf * inv_s) * ray_queries[size_t(u)].dir)
                               : kSkyColor);
        } else {
          const uint8_t* c = dist <= far ? ground : sky;
          rgb[3 * u] = c[0];
          rgb[3 * u + 1] = c[1];
          rgb[3 * u + 2] = c[2];
        }
        dep[u] = dist;
      }
    }
  };
  if (desc.floor.marks.empty()) {
    fill(std::false_type{});
  } else {
    fill(std::true_type{});
  }

  // Robots that may be in the image: within range, and for each the
  // columns its bounding circle covers, so a column tests only those.
  camera_sights(st.robot, at, d.far);
  camera_cols.clear();
  for (const CameraSight& c : sights) {
    int u0 = 0, u1 = w - 1;
    if (!c.around) {
      const double lo = c.bearing - c.half, hi = c.bearing + c.half;  // rad, left positive
      if (hi <= -kPi / 2 || lo >= kPi / 2) continue;                  // behind the camera
      // Column x = cx - fx tan(bearing): the left edge (hi) has the smaller x.
      const double x_left = hi >= kPi / 2 ? -1e9 : cx - fx * std::tan(hi);
      const double x_right = lo <= -kPi / 2 ? 1e9 : cx - fx * std::tan(lo);
      if (x_right < 0 || x_left > w) continue;
      u0 = int(std::max(0.0, std::floor(x_left - 1)));
      u1 = int(std::min(double(w - 1), std::ceil(x_right + 1)));
    }
    camera_cols.push_back({c.robot, u0, u1});
  }

  wall_ranges.resize(size_t(w));
  map.cast_batch(ray_queries, StaticMap::kAnyMask, wall_ranges.data());
  const size_t rgb_stride = size_t(w) * 3;
  for (int u = 0; u < w; ++u) {
    const Vec2 dir = ray_queries[size_t(u)].dir;
    const double k = camera_k[size_t(u)];
    ray_spans(o, dir, wall_ranges[size_t(u)], d.far, u, w);
    // Farthest first: nearer spans cover farther ones.
    std::stable_sort(spans.begin(), spans.end(), [](const Span& x, const Span& y) { return x.t > y.t; });
    uint8_t* rgb = st.rgb.data() + size_t(u) * 3;
    float* dep = st.depth.data() + u;
    for (const Span& sp : spans) {
      const double t = std::max(sp.t, 1e-6);
      const int top = row_at(cy - k * (sp.top - zc) / t, h);
      const int bottom = row_at(cy + k * zc / t, h);
      for (int v = top; v < bottom; ++v) {
        const double s = (cy - (v + 0.5)) / k;  // height per horizontal metre
        const double len = t * std::sqrt(1 + s * s);
        // What lies nearer than near or beyond far (seen steeply) is not seen.
        if (len > d.far || len < d.near) continue;
        put(rgb + size_t(v) * rgb_stride, sp.color);
        dep[size_t(v) * size_t(w)] = float(len);
      }
    }
  }
}

void Engine::render_omni(CameraState& st, const CameraDesc& d, const Pose& at) {
  const int w = d.width, h = d.height;
  const size_t n_px = size_t(w) * size_t(h);
  const Vec2 o{at.x, at.y};
  const double zc = d.z;
  const double rim = 0.5 * std::min(w, h);  // px: the mirror's edge

  // One ray per pixel of the rim, counter-clockwise from the camera's
  // forward: ray i looks at bearing 2 pi i / n.
  const int n = std::max(8, int(std::ceil(2 * kPi * rim)));
  const double per_ray = 2 * kPi / n;  // rad
  ray_queries.clear();
  for (int i = 0; i < n; ++i) {
    const double a = at.a + per_ray * i;
    ray_queries.push_back({o, {std::cos(a), std::sin(a)}, float(d.far)});
  }
  wall_ranges.resize(size_t(n));
  map.cast_batch(ray_queries, StaticMap::kAnyMask, wall_ranges.data());

  // Robots in range, with the rays their bounding circles cover: u0..u1,
  // counted on from u0 around the circle (u0 may be negative).
  camera_sights(st.robot, at, d.far);
  camera_cols.clear();
  for (const CameraSight& c : sights) {
    int u0 = 0, u1 = n - 1;
    if (!c.around) {
      u0 = int(std::floor((c.bearing - c.half) / per_ray)) - 1;
      u1 = std::min(u0 + n - 1, int(std::ceil((c.bearing + c.half) / per_ray)) + 1);
    }
    camera_cols.push_back({c.robot, u0, u1});
  }

  // Each ray's spans, nearest first.
  omni_spans.clear();
  omni_first.assign(size_t(n) + 1, 0);
  for (int i = 0; i < n; ++i) {
    ray_spans(o, ray_queries[size_t(i)].dir, wall_ranges[size_t(i)], d.far, i, n);
    std::stable_sort(spans.begin(), spans.end(), [](const Span& x, const Span& y) { return x.t < y.t; });
    omni_spans.insert(omni_spans.end(), spans.begin(), spans.end());
    omni_first[size_t(i) + 1] = uint32_t(omni_spans.size());
  }

  omni_map(d, n);
  for (size_t px = 0; px < n_px; ++px) {
    const OmniPixel& p = omni_pixels[px];
    uint32_t color = 0;  // beyond the mirror's rim: black
    float dist = kNoDepth;
    if (p.ray >= 0) {
      const double s = p.rise, stretch = p.stretch;
      color = kSkyColor;
      bool seen = false;
      for (uint32_t k = omni_first[size_t(p.ray)]; k < omni_first[size_t(p.ray) + 1]; ++k) {
        const Span& sp = omni_spans[k];
        const double z = zc + s * sp.t, len = sp.t * stretch;
        if (len > d.far) break;
        if (z < 0 || z > sp.top || len < d.near) continue;
        color = sp.color;
        dist = float(len);
        seen = true;
        break;
      }
      if (!seen && s < 0) {
        const double g = -zc / s, len = g * stretch;  // m: horizontal, along the ray
        if (len <= d.far) {
          color = floor_color(desc.floor, o + g * ray_queries[size_t(p.ray)].dir);
          dist = float(len);
        }
      }
    }
    put(st.rgb.data() + 3 * px, color);
    st.depth[px] = dist;
  }
}

void Engine::omni_map(const CameraDesc& d, int n) {
  const std::array<double, 7> key = {double(d.width), double(d.height), d.z,      d.mirror_range,
                                     d.mirror_ground, d.mirror_top,     double(n)};
  if (key == omni_pixels_for && !omni_pixels.empty()) return;
  omni_pixels_for = key;
  const int w = d.width, h = d.height;
  omni_pixels.resize(size_t(w) * size_t(h));
  const double cx = 0.5 * w, cy = 0.5 * h, zc = d.z;
  const double rim = 0.5 * std::min(w, h);      // px: the mirror's edge
  const double ground = d.mirror_ground * rim;  // px: the ground ring's edge
  // Elevation of a ray meeting the floor at mirror_range: where the outer
  // ring starts, so the image is continuous across the ring's edge.
  const double low = -std::atan2(zc, d.mirror_range);
  const double per_ray = 2 * kPi / n;  // rad
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      OmniPixel& p = omni_pixels[size_t(v) * size_t(w) + size_t(u)];
      const double x = u + 0.5 - cx, y = v + 0.5 - cy;  // px right of and below the centre
      const double r = std::hypot(x, y);
      if (r > rim) {
        p = {-1, 0, 0};
        continue;
      }
      // In the ground ring the ray meets the floor r / ground * mirror_range
      // away; beyond it, its elevation grows linearly with r.
      const double s = r <= ground ? -zc / std::max(r / ground * d.mirror_range, 1e-9)
                                   : std::tan(low + (r - ground) / (rim - ground) * (d.mirror_top - low));
      // Forward is up, left is left: the bearing left of forward.
      int ray = int(std::lround(std::atan2(-x, -y) / per_ray));
      if (ray < 0) ray += n;
      if (ray >= n) ray -= n;
      p = {ray, float(s), float(std::sqrt(1 + s * s))};
    }
  }
}

}  // namespace troupe::sim
