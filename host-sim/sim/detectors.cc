// Blobfinders (colour blobs in a scan line), fiducial finders (landmark ids
// with range and bearing, behind nothing), and bumpers (segments touching
// obstacles).
#include <algorithm>
#include <cmath>

#include "host-sim/sim/engine.h"

namespace troupe::sim {
namespace {

constexpr uint32_t kNoColor = 0xFFFFFFFFu;

bool segment_meets_polygon(Vec2 a, Vec2 b, std::span<const Vec2> poly) {
  for (size_t i = 0, n = poly.size(); i < n; ++i) {
    if (segments_intersect(a, b, poly[i], poly[(i + 1) % n])) return true;
  }
  return !poly.empty() && point_in_polygon(a, poly);
}

}  // namespace

void Engine::update_blobfinders() {
  std::vector<uint32_t> colors;
  std::vector<double> dists;
  for (uint32_t index = 0; index < blobfinders.size(); ++index) {
    BlobState& st = blobfinders[index];
    if (!due(st)) continue;
    const BlobfinderDesc& d = desc.robots[st.robot].blobfinders[index - info[st.robot].blobfinders.first];
    const Pose at = compose(bodies[st.robot].pose, d.pose);
    const Vec2 o{at.x, at.y};
    candidates.clear();
    hash.query(o, d.range, [&](uint32_t j) {
      if (j != st.robot) candidates.push_back(j);
    });
    // One ray per image column, right to left across the field of view.
    const int w = std::max(1, d.width);
    colors.assign(size_t(w), kNoColor);
    dists.assign(size_t(w), d.range);
    // The walls for every column at once, then the robots.
    ray_queries.clear();
    for (int s = 0; s < w; ++s) {
      const double a = at.a + d.pan - d.fov / 2 + d.fov * (s + 0.5) / w;
      ray_queries.push_back({o, {std::cos(a), std::sin(a)}, float(d.range)});
    }
    wall_ranges.resize(size_t(w));
    map.cast_batch(ray_queries, StaticMap::kAnyMask, wall_ranges.data());
    for (int s = 0; s < w; ++s) {
      const Vec2 dir = ray_queries[size_t(s)].dir;
      double best = wall_ranges[size_t(s)];
      uint32_t color = kNoColor;
      if (best < d.range) {
        const StaticInfo* hit = static_at(o + (best + 0.5 * map.resolution()) * dir);
        if (hit && hit->look.blob) color = hit->look.color;
      }
      for (uint32_t j : candidates) {
        const double t = ray_robot(j, o, dir);
        if (t >= 0 && t < best) {
          best = t;
          const Appearance& look = desc.robots[j].look;
          color = look.blob ? look.color : kNoColor;
        }
      }
      colors[size_t(s)] = color;
      dists[size_t(s)] = best;
    }
    // Runs of one colour are blobs; image x grows to the right, i.e. against
    // the bearing.
    st.blobs.clear();
    const int h = std::max(1, d.height);
    const double rad_per_px = d.fov / w;
    for (int s = 0; s < w;) {
      const uint32_t c = colors[size_t(s)];
      int e = s;
      double sum = 0;
      while (e < w && colors[size_t(e)] == c) sum += dists[size_t(e++)];
      if (c != kNoColor) {
        uint32_t channel = 0;
        bool tracked = d.colors.empty();
        for (uint32_t k = 0; k < d.colors.size() && !tracked; ++k) {
          if ((d.colors[k] & 0xFFFFFF) == (c & 0xFFFFFF)) {
            tracked = true;
            channel = k;
          }
        }
        if (tracked) {
          Blob b;
          b.color = c;
          b.channel = channel;
          b.range = sum / (e - s);
          b.left = w - e;
          b.right = w - 1 - s;
          // The blob's height from a nominal 0.6 m target (Stage's), square pixels.
          const double half = std::atan2(0.3, std::max(b.range, 1e-3)) / rad_per_px;
          b.top = std::clamp(int(std::lround(h / 2.0 - half)), 0, h - 1);
          b.bottom = std::clamp(int(std::lround(h / 2.0 + half)), 0, h - 1);
          b.x = 0.5 * (b.left + b.right);
          b.y = 0.5 * (b.top + b.bottom);
          b.area = uint32_t((b.right - b.left + 1) * (b.bottom - b.top + 1));
          st.blobs.push_back(b);
        }
      }
      s = e;
    }
    st.step = steps;
  }
}

void Engine::update_fiducials() {
  for (uint32_t index = 0; index < fiducials.size(); ++index) {
    FiducialState& st = fiducials[index];
    if (!due(st)) continue;
    const FiducialDesc& d = desc.robots[st.robot].fiducials[index - info[st.robot].fiducials.first];
    const Pose at = compose(bodies[st.robot].pose, d.pose);
    const Vec2 o{at.x, at.y};
    candidates.clear();
    hash.query(o, d.range_max, [&](uint32_t j) {
      if (j != st.robot) candidates.push_back(j);
    });
    std::sort(candidates.begin(), candidates.end());  // readings in robot order
    st.readings.clear();
    auto consider = [&](const Pose& target, int id, int key, int robot, double size) {
      if (id == 0 || key != d.key) return;
      const double dx = target.x - o.x, dy = target.y - o.y, range = std::hypot(dx, dy);
      if (range > d.range_max || range < 1e-9) return;
      const double bearing = wrap_angle(std::atan2(dy, dx) - at.a);
      if (std::fabs(bearing) > d.fov / 2) return;
      const Vec2 dir{dx / range, dy / range};
      // Line of sight: nothing between the sensor and the landmark's surface.
      double surface = range;
      if (robot >= 0) {
        const double t = ray_robot(RobotId(robot), o, dir);
        if (t >= 0) surface = t;
      } else {
        surface = std::max(0.0, range - size - map.resolution());
      }
      // The cells rangers' beams stop at (kRangerMask), so walls that only
      // show in the grid (a RoboCup field's rigid barrier and goals, which
      // the physics stops robots at) hide landmarks as they stop beams.
      if (map.cast(o, dir, float(range), StaticMap::kRangerMask) < surface) return;
      for (uint32_t k : candidates) {
        if (int(k) == robot || !bodies[k].ranger_visible) continue;
        const double t = ray_robot(k, o, dir);
        if (t >= 0 && t < surface) return;
      }
      FiducialReading r;
      r.id = range <= d.range_max_id ? id : -1;
      r.range = std::max(range, d.range_min);
      r.bearing = bearing;
      r.pose = relative(at, target);
      st.readings.push_back(r);
    };
    for (uint32_t j : candidates) {
      const Appearance& look = desc.robots[j].look;
      consider(bodies[j].pose, look.fiducial_id, look.fiducial_key, int(j), bodies[j].radius);
    }
    for (const StaticInfo& s : statics) {
      const double size = 0.5 * std::hypot(s.hi.x - s.lo.x, s.hi.y - s.lo.y);
      consider(s.pose, s.look.fiducial_id, s.look.fiducial_key, -1, size);
    }
    st.step = steps;
  }
}

void Engine::update_bumpers() {
  for (uint32_t index = 0; index < bumpers.size(); ++index) {
    BumperState& st = bumpers[index];
    if (!due(st)) continue;
    const BumperDesc& d = desc.robots[st.robot].bumpers[index - info[st.robot].bumpers.first];
    const Body& self = bodies[st.robot];
    // A robot stopped by a collision presses where it tried to go.
    const Pose at = self.stalled ? self.blocked_at : self.pose;
    st.pressed = 0;
    for (size_t k = 0; k < d.segments.size() && k < 32; ++k) {
      const Pose c = compose(at, compose(d.pose, d.segments[k].pose));
      const double h = d.segments[k].length / 2;
      const Vec2 a = transform(c, {0, -h}), b = transform(c, {0, h});
      bool hit = map.segment_hits(a, b, StaticMap::kObstacleMask);
      if (!hit) {
        hash.query({c.x, c.y}, h, [&](uint32_t j) {
          if (hit || j == st.robot || !bodies[j].obstacle) return;
          outline(j, bodies[j].pose, scratch_verts, scratch_polys);
          for (const PolyRef& p : scratch_polys) {
            if (segment_meets_polygon(a, b, {scratch_verts.data() + p.first, p.count})) hit = true;
          }
        });
      }
      if (hit) st.pressed |= 1u << k;
    }
    st.step = steps;
  }
}

}  // namespace troupe::sim
