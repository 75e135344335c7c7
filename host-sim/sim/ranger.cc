// The ranger model (sonar rings, IR, lasers). Each beam is cast through the
// static grid; then the robots in its way lower its range. Two ways find
// them, to the same result bit for bit. Where few robots stand within a
// ranger's reach, each is tested only against the beams its bounding circle
// can cross (an angular interval per robot), and only where it could be
// nearer than the wall already found. In a crowd that is a few hundred
// robots per ranger, so there each beam walks the per-step robot layer
// instead (robot_layer.h), nearest cells first, and stops behind the first
// robot it meets: its cost no longer grows with the robots around it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "host-sim/sim/engine.h"

namespace troupe::sim {
namespace {

// std::hypot(dx, dy) <= limit (all in m), the same answer at a fraction of
// the cost: the squares settle it wherever they are clearly on one side
// (their rounding is a few parts in 1e16), hypot only within 1e-12 of the
// edge (and for NaN, which no comparison settles).
bool within(double dx, double dy, double limit) {
  const double d2 = dx * dx + dy * dy, l2 = limit * limit;
  if (d2 < l2 * (1 - 1e-12)) return true;
  if (d2 > l2 * (1 + 1e-12)) return false;
  return std::hypot(dx, dy) <= limit;
}

// atan2(y, x), rad, to within 1e-5 rad (Abramowitz and Stegun 4.4.49 on
// [0, 1], then the octant), at a fraction of atan2's cost: it only chooses
// which of a fan's beams a robot's circle may cross, with kBearingSlack to
// spare, and the exact test settles each of them.
double bearing(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y), lo = std::min(ax, ay), hi = std::max(ax, ay);
  if (hi == 0) return 0;
  const double z = lo / hi, z2 = z * z;
  double a = z * (0.9998660 + z2 * (-0.3302995 + z2 * (0.1801410 + z2 * (-0.0851330 + z2 * 0.0208351))));
  if (ay > ax) a = 0.5 * kPi - a;
  if (x < 0) a = kPi - a;
  return y < 0 ? -a : a;
}

// rad added to each side of a robot's bearings before choosing the beams
// it may cross: ten times bearing()'s error, so every beam the exact
// bearing would choose is chosen (a few more are tested in vain).
constexpr double kBearingSlack = 1e-4;

// An angle (rad) within a turn or so of [-pi, pi] brought into it without
// std::remainder's cost; wrap_angle for anything farther.
double wrap_near(double a) {
  if (std::fabs(a) > 3 * kPi) return wrap_angle(a);
  return a > kPi ? a - 2 * kPi : (a < -kPi ? a + 2 * kPi : a);
}

// A beam index from a real one, clamped before the conversion.
int index_at(double v, int lo, int hi) {
  return int(std::clamp(v, double(lo) - 1, double(hi) + 1));
}

}  // namespace

double Engine::ray_robot(RobotId j, Vec2 origin, Vec2 dir) const {
  const double a = bodies[j].pose.a;
  return ray_robot(j, {std::cos(a), std::sin(a)}, origin, dir);
}

namespace {

// A world vector (m) in the frame of a robot whose heading's cosine and sine
// are `turn`, where its outline is stored. One expression for every caller,
// so each gets the same doubles.
Vec2 into_frame(Vec2 turn, Vec2 v) {
  return {turn.x * v.x + turn.y * v.y, -turn.y * v.x + turn.x * v.y};
}

}  // namespace

double Engine::ray_robot(RobotId j, Vec2 turn, Vec2 origin, Vec2 dir) const {
  const Body& b = bodies[j];
  const Vec2 o = into_frame(turn, origin - Vec2{b.pose.x, b.pose.y}), d = into_frame(turn, dir);
  double best = -1;
  for (uint32_t k = 0; k < b.poly_count; ++k) {
    const PolyRef& p = polys[b.poly_first + k];
    double t = ray_polygon(o, d, {verts.data() + p.first, p.count});
    if (t >= 0 && (best < 0 || t < best)) best = t;
  }
  return best;
}

namespace {

// m a polygon must lie inside another, and a ray's origin outside it, for
// the inner one to be skipped: far above the rounding of any ray's t.
constexpr double kNestMargin = 1e-6;

// Signed distance (m) of p from the line through edge [a, b] of a convex
// polygon of orientation `turning` (+1 counter-clockwise, -1 clockwise):
// positive inside.
double inside_by(Vec2 a, Vec2 b, double turning, Vec2 p) {
  return turning * cross(b - a, p - a) / length(b - a);
}

// inside_by(a, b, turning, p) < -kNestMargin, without its division.
bool outside_edge(Vec2 a, Vec2 b, double turning, Vec2 p) {
  const double c = turning * cross(b - a, p - a);
  return c < 0 && c * c > kNestMargin * kNestMargin * length_squared(b - a);
}

// +1 or -1 when the polygon is strictly convex, counter-clockwise or
// clockwise; 0 otherwise.
double convex_turning(std::span<const Vec2> poly) {
  const size_t n = poly.size();
  if (n < 3) return 0;
  int pos = 0, neg = 0;
  for (size_t i = 0; i < n; ++i) {
    const double c = cross(poly[(i + 1) % n] - poly[i], poly[(i + 2) % n] - poly[(i + 1) % n]);
    pos += c > 0;
    neg += c < 0;
  }
  return pos == int(n) ? 1.0 : (neg == int(n) ? -1.0 : 0.0);
}

}  // namespace

void Engine::nest_outlines() {
  // Outlines never change once built, so each polygon is looked at once.
  const size_t from = poly_within.size();
  poly_within.resize(polys.size(), {-1, 0});
  for (const Body& b : bodies) {
    const uint32_t end = b.poly_first + b.poly_count;
    if (end <= from) continue;
    for (uint32_t k = std::max<uint32_t>(b.poly_first, uint32_t(from)); k < end; ++k) {
      const std::span<const Vec2> inner{verts.data() + polys[k].first, polys[k].count};
      for (uint32_t m = b.poly_first; m < end && poly_within[k].outer < 0; ++m) {
        const std::span<const Vec2> outer{verts.data() + polys[m].first, polys[m].count};
        const double turning = m == k ? 0 : convex_turning(outer);
        if (turning == 0) continue;
        bool inside = !inner.empty();
        for (size_t e = 0; e < outer.size() && inside; ++e) {
          for (Vec2 p : inner) {
            inside = inside && inside_by(outer[e], outer[(e + 1) % outer.size()], turning, p) > kNestMargin;
          }
        }
        if (inside) poly_within[k] = {int32_t(m), turning};
      }
    }
  }
}

void Engine::seen_from(RobotId j, Vec2 turn, Vec2 origin, SeenOutline& seen) {
  if (poly_within.size() != polys.size()) nest_outlines();
  const Body& b = bodies[j];
  seen.o = into_frame(turn, origin - Vec2{b.pose.x, b.pose.y});
  seen.turn = turn;
  seen.rel.clear();
  seen.skip.clear();
  for (uint32_t k = 0; k < b.poly_count; ++k) {
    const PolyRef& p = polys[b.poly_first + k];
    for (uint32_t v = p.first; v < p.first + p.count; ++v) seen.rel.push_back(verts[v] - seen.o);
    // A polygon inside a convex one, seen from outside that: every ray
    // meets the outer one first, at least kNestMargin nearer, so the inner
    // one cannot be the nearest hit and need not be tested.
    bool skip = false;
    if (const Nest n = poly_within[b.poly_first + k]; n.outer >= 0) {
      const PolyRef& m = polys[uint32_t(n.outer)];
      for (uint32_t e = 0; e < m.count && !skip; ++e) {
        const Vec2 a = verts[m.first + e], c = verts[m.first + (e + 1 == m.count ? 0 : e + 1)];
        skip = outside_edge(a, c, n.turning, seen.o);
      }
    }
    seen.skip.push_back(skip);
  }
}

double Engine::ray_robot(RobotId j, const SeenOutline& seen, Vec2 dir) const {
  // ray_robot's loop, the origin's part done once.
  const Body& b = bodies[j];
  const Vec2 d = into_frame(seen.turn, dir);
  double best = -1;
  const Vec2* rel = seen.rel.data();
  for (uint32_t k = 0; k < b.poly_count; ++k) {
    const PolyRef& p = polys[b.poly_first + k];
    if (!seen.skip[k]) {
      double t = ray_polygon(seen.o, d, {verts.data() + p.first, p.count}, rel);
      if (t >= 0 && (best < 0 || t < best)) best = t;
    }
    rel += p.count;
  }
  return best;
}

const StaticInfo* Engine::static_at(Vec2 p) const {
  // The grid fills every cell a polygon touches, so a hit point may lie up
  // to a cell outside the model's box (thin walls): boxes grow by a cell.
  const double pad = map.resolution();
  const StaticInfo* best = nullptr;
  for (const StaticInfo& s : statics) {
    if (p.x < s.lo.x - pad || p.x > s.hi.x + pad || p.y < s.lo.y - pad || p.y > s.hi.y + pad) continue;
    if (!best || s.area < best->area) best = &s;
  }
  return best;
}

void Engine::prefetch_rangers(const SpatialHash::Item& item) const {
  const IndexRange r = robot_rangers[item.index];
  for (uint32_t k = r.first; k < r.first + r.count; ++k) __builtin_prefetch(&rangers[k]);
  __builtin_prefetch(&bodies[item.index]);
  map.prefetch({item.x, item.y}, item.r);
}

void Engine::update_rangers() {
  // Robot by robot in the hash's cell order, so consecutive rays read
  // nearby parts of the grid (a large map does not fit in cache). Each
  // ranger's result depends only on the world, not on this order.
  //
  // The robots' own records are stored by robot number, so in this order
  // each is a fresh cache miss on a large swarm: they are fetched a few
  // robots ahead (the robot numbers themselves further ahead still), so
  // their latency overlaps the rays of the robots before them.
  constexpr size_t kAhead = 4;
  const std::span<const SpatialHash::Item> order = hash.order();
  robot_layer_fresh = false;
  ray_queries.clear();
  transducer_poses.clear();
  ranger_batch.clear();
  for (size_t n = 0; n < order.size(); ++n) {
    if (n + 2 * kAhead < order.size()) __builtin_prefetch(&robot_rangers[order[n + 2 * kAhead].index]);
    if (n + kAhead < order.size()) prefetch_rangers(order[n + kAhead]);
    const IndexRange r = robot_rangers[order[n].index];
    for (uint32_t k = r.first; k < r.first + r.count; ++k) {
      if (due(rangers[k])) queue_ranger(k);
    }
  }
  cast_ranger_batch();
}

void Engine::beams_meet_candidates(const RangerState& rs, std::span<const RayQuery> queries,
                                   std::span<const Pose> poses, float* out, float* inten) {
  // Robots that may cross a beam, tested only on the beams they can cross
  // and only where they could be nearer than what the beam already hit.
  // From the hash's copies of the robots' circles (which hold each robot
  // over this step's move): no robot data is touched to filter.
  ranger_candidates.clear();
  const double sx = bodies[rs.robot].pose.x, sy = bodies[rs.robot].pose.y;
  hash.query_items({sx, sy}, rs.reach, [&](const SpatialHash::Item& it) {
    if (it.index == rs.robot || !(it.flags & kHashRangerVisible)) return;
    const double r = double(it.r) + 1e-3;  // covers the float rounding of the copy
    if (within(it.x - sx, it.y - sy, rs.reach + r))
      ranger_candidates.push_back({it.index, it.x, it.y, r, {std::numeric_limits<double>::quiet_NaN(), 0}});
  });
  for (uint32_t t = rs.transducer_first;
       t < rs.transducer_first + rs.transducer_count && !ranger_candidates.empty(); ++t) {
    const Transducer& td = transducers[t];
    const uint32_t first = td.beam_offset, n = td.samples;
    const Pose& org = poses[t - rs.transducer_first];
    const Vec2 o{org.x, org.y};
    for (Candidate& cand : ranger_candidates) {
      const double dx = cand.x - o.x, dy = cand.y - o.y;
      bool seen = false;  // seen_outline holds the robot seen from o
      // Lowers beam s of the transducer to the robot, where it is nearer.
      // Nearer than `near`, nothing of the robot is: beams that stopped at
      // a wall before it cannot see it.
      auto test = [&](int s, double near) {
        const RayQuery& q = queries[first + uint32_t(s)];
        float& r = out[first + uint32_t(s)];
        if (near >= r) return;
        if (std::isnan(cand.turn.x)) {
          const double a = bodies[cand.index].pose.a;
          cand.turn = {std::cos(a), std::sin(a)};
        }
        if (!seen) {
          seen_from(cand.index, cand.turn, q.origin, seen_outline);
          seen = true;
        }
        const double hit = ray_robot(cand.index, seen_outline, q.dir);
        if (hit >= 0 && hit < r) {
          r = float(hit);
          inten[first + uint32_t(s)] = bodies[cand.index].ranger_return;
        }
      };
      if (n == 1) {
        // One beam: does it pass within the robot's circle, ahead of what it hit?
        const Vec2 d = queries[first].dir;
        const double along = d.x * dx + d.y * dy, across = d.x * dy - d.y * dx;
        if (std::fabs(across) > cand.r || along + cand.r < 0 || along - cand.r >= out[first]) continue;
        test(0, along - cand.r);  // no nearer than the circle's nearest point along the beam
        continue;
      }
      // (sqrt, not hypot: it only bounds where and how near the robot can
      // be, and the circles are padded far beyond its rounding.)
      const double dist = std::sqrt(dx * dx + dy * dy);
      if (dist - cand.r >= td.range_max) continue;
      const double near = dist - cand.r;
      const double half =
          (dist > cand.r ? std::asin(cand.r / dist) : kPi) + 0.5 * td.noise_angle + kBearingSlack;
      if (!(half < kPi && td.incr > 0)) {
        for (int s = 0; s < int(n); ++s) test(s, near);
        continue;
      }
      const int last = int(n) - 1;
      // Bearing from the first beam; the fan is centred on the heading.
      const double rel = wrap_near(bearing(dy, dx) - org.a) - td.start;
      // The beams the robot's bearings span, and the same a turn either
      // way: a robot behind a wide fan, or close behind any fan, spans
      // beams at both of its ends.
      for (int k = -1; k <= 1; ++k) {
        const double at = rel + k * 2 * kPi;
        const int lo = std::max(0, index_at(std::ceil((at - half) / td.incr), 0, last));
        const int hi = std::min(last, index_at(std::floor((at + half) / td.incr), 0, last));
        for (int s = lo; s <= hi; ++s) test(s, near);
      }
    }
  }
}

namespace {

// How far (m) beyond the nearest robot hit a beam still looks: hits within a
// float's rounding of each other are settled in the hash's order, as the
// candidates' loop settles them, so every way gives the same float.
double tie_margin(double t) {
  return 1e-6 * std::max(1.0, t);
}

}  // namespace

void Engine::layer_hits_first(std::span<RayQuery> queries) {
  if (!robot_layer_fresh) {
    robot_layer.build(hash, kHashRangerVisible);
    robot_turns.resize(bodies.size());
    for (const SpatialHash::Item& it : hash.order()) {
      const double a = bodies[it.index].pose.a;
      robot_turns[it.index] = {std::cos(a), std::sin(a)};
    }
    robot_stamps.resize(bodies.size());
    robot_layer_fresh = true;
  }
  robot_hits.clear();
  beam_hits.clear();
  beam_ends.clear();
  Vec2 clear_at{std::numeric_limits<double>::quiet_NaN(), 0};
  double clear = 0;  // m free of walls around clear_at
  for (RayQuery& q : queries) {
    beam_hits.push_back(uint32_t(robot_hits.size()));
    beam_ends.push_back(0);
    if (++beam_stamp == 0) {  // wrapped: forget every stamp
      std::fill(robot_stamps.begin(), robot_stamps.end(), 0u);
      beam_stamp = 1;
    }
    const size_t first = robot_hits.size();
    const double range = q.max_range;  // only hits below it count
    double best = range, limit = range;
    robot_layer.walk(q.origin, q.dir, range, [&](std::span<const RobotLayer::Entry> cell, double) {
      for (const RobotLayer::Entry& e : cell) {
        if (e.index == self_robot) continue;
        const double dx = e.x - q.origin.x, dy = e.y - q.origin.y;
        const double along = q.dir.x * dx + q.dir.y * dy, across = q.dir.x * dy - q.dir.y * dx;
        if (std::fabs(across) > e.r || along + e.r < 0 || along - e.r >= limit) continue;
        if (robot_stamps[e.index] == beam_stamp) continue;
        robot_stamps[e.index] = beam_stamp;
        const double hit = ray_robot(e.index, robot_turns[e.index], q.origin, q.dir);
        if (hit < 0 || !(hit < range)) continue;
        robot_hits.push_back({e.order, e.index, hit});
        best = std::min(best, hit);
        limit = std::min(range, best + tie_margin(best));
      }
      return limit;
    });
    if (robot_hits.size() == first) continue;
    // Only the near ties matter: farther hits cannot be what the
    // candidates' loop ends with.
    size_t kept = first;
    for (size_t h = first; h < robot_hits.size(); ++h) {
      if (robot_hits[h].t <= limit) robot_hits[kept++] = robot_hits[h];
    }
    robot_hits.resize(kept);
    // The walls matter only before the nearest robot: the cast stops a
    // little beyond it (past every near tie), and finds any wall before
    // that where the full cast would (the march is the same up to there).
    const double reach = best + 3 * tie_margin(best);
    if (reach >= range) continue;
    // Nearer than the distance field's bound around the beam's origin, no
    // wall is: the cast is not needed at all (its range 0 ends it at once),
    // and its end is the beam's (a transducer's beams share their origin).
    if (!(q.origin.x == clear_at.x && q.origin.y == clear_at.y)) {
      clear_at = q.origin;
      clear = map.clearance(q.origin);
    }
    if (reach < clear) {
      beam_ends.back() = float(reach);
      q.max_range = 0;
    } else {
      q.max_range = float(reach);
    }
  }
  beam_hits.push_back(uint32_t(robot_hits.size()));
}

void Engine::settle_layer_hits(float* out, float* inten) {
  for (uint32_t b = 0; b + 1 < beam_hits.size(); ++b) {
    if (beam_ends[b] > 0) out[b] = beam_ends[b];  // not cast: no wall before this
    const auto first = robot_hits.begin() + beam_hits[b], last = robot_hits.begin() + beam_hits[b + 1];
    // Lowered in the hash's order, as the candidates' loop lowers them, from
    // the wall's range (or, past the shortened cast's end, its end: beyond
    // every near tie, as the full cast's wall is).
    if (last - first > 1) {
      std::sort(first, last, [](const RobotHit& x, const RobotHit& y) { return x.order < y.order; });
    }
    for (auto h = first; h != last; ++h) {
      if (h->t < out[b]) {
        out[b] = float(h->t);
        inten[b] = bodies[h->robot].ranger_return;
      }
    }
  }
}

void Engine::beams_meet_every(const RangerState& rs, std::span<const RayQuery> queries, float* out,
                              float* inten) {
  for (const SpatialHash::Item& it : hash.order()) {
    if (it.index == rs.robot || !(it.flags & kHashRangerVisible)) continue;
    for (uint32_t b = 0; b < rs.beam_count; ++b) {
      const double hit = ray_robot(it.index, queries[b].origin, queries[b].dir);
      if (hit >= 0 && hit < out[b]) {
        out[b] = float(hit);
        inten[b] = bodies[it.index].ranger_return;
      }
    }
  }
}

bool Engine::aim_ranger(uint32_t index) {
  RangerState& rs = rangers[index];
  const Body& self = bodies[rs.robot];
  const uint64_t angle_stream = Random::stream(uint64_t(RandomKind::RangerAngle), index, steps);

  // Every beam of the ranger, appended to the batch's queries. Directions
  // are the robot-frame ones turned by the robot's heading.
  const double hc = std::cos(self.pose.a), hs = std::sin(self.pose.a);
  auto turn = [hc, hs](Vec2 v) { return Vec2{hc * v.x - hs * v.y, hs * v.x + hc * v.y}; };
  for (uint32_t t = rs.transducer_first; t < rs.transducer_first + rs.transducer_count; ++t) {
    const Transducer& td = transducers[t];
    const Vec2 o = Vec2{self.pose.x, self.pose.y} + turn({td.pose.x, td.pose.y});
    const Pose org{o.x, o.y, self.pose.a + td.pose.a};
    transducer_poses.push_back(org);
    if (td.noise_angle > 0) {
      const double a0 = org.a + td.start;
      for (uint32_t s = 0; s < td.samples; ++s) {
        const double a =
            a0 + td.incr * s +
            0.5 * td.noise_angle * random.symmetric(angle_stream, rs.beam_first + td.beam_offset + s);
        ray_queries.push_back({o, {std::cos(a), std::sin(a)}, td.range_max});
      }
      continue;
    }
    Vec2 dir = turn(td.first_dir);
    const double c = td.incr_rot.x, sn = td.incr_rot.y;
    for (uint32_t s = 0; s < td.samples; ++s) {
      ray_queries.push_back({o, dir, td.range_max});
      dir = {c * dir.x - sn * dir.y, sn * dir.x + c * dir.y};
    }
  }
  // Robots in the beams. The candidates' cost grows with the robots within
  // the ranger's reach times its transducers (each robot is placed among
  // each transducer's beams), the layer's with its beams: the layer pays off
  // from about this many robots per beam of a transducer, measured on the
  // crowd, packed and cave rows. The robots are those counted at the
  // ranger's last update (robots move little in a step), so the common case
  // of few robots pays nothing to choose.
  constexpr size_t kLayerFrom = 24;
  return ranger_robots == World::RangerRobots::Layer ||
         (ranger_robots == World::RangerRobots::Auto &&
          size_t(rs.robots_near) * rs.transducer_count >= kLayerFrom * rs.beam_count);
}

void Engine::queue_ranger(uint32_t index) {
  const PendingRanger p{index, uint32_t(ray_queries.size()), uint32_t(transducer_poses.size())};
  if (!aim_ranger(index)) {
    ranger_batch.push_back(p);
    if (ray_queries.size() >= kRangerBatchRays) cast_ranger_batch();
    return;
  }
  // The layer finds the robots first, so the walls are cast only up to
  // them: this ranger's rays are cast now, on their own, and leave the batch.
  RangerState& rs = rangers[index];
  const std::span<RayQuery> queries{ray_queries.data() + p.query_first, rs.beam_count};
  self_robot = rs.robot;
  layer_hits_first(queries);
  // Counted by the hash's cells (a few more than the candidates' circles
  // would keep, which favours staying with the layer).
  const Body& self = bodies[rs.robot];
  rs.robots_near = uint32_t(hash.count_items({self.pose.x, self.pose.y}, rs.reach));
  map.cast_batch(queries, StaticMap::kRangerMask, ranges.data() + rs.beam_first);
  finish_ranger(p, true);
  ray_queries.resize(p.query_first);
  transducer_poses.resize(p.pose_first);
}

void Engine::cast_ranger_batch() {
  // One cast for the rays of several robots: the caster's lanes stay full
  // and its cache misses overlap, where one ranger's few rays (a sonar
  // ring's 12) fill the lanes once and then drain them.
  batch_ranges.resize(ray_queries.size());
  map.cast_batch(ray_queries, StaticMap::kRangerMask, batch_ranges.data());
  for (const PendingRanger& p : ranger_batch) {
    const RangerState& rs = rangers[p.ranger];
    std::copy_n(batch_ranges.data() + p.query_first, rs.beam_count, ranges.data() + rs.beam_first);
    finish_ranger(p, false);
  }
  ranger_batch.clear();
  ray_queries.clear();
  transducer_poses.clear();
}

void Engine::finish_ranger(const PendingRanger& p, bool layer) {
  RangerState& rs = rangers[p.ranger];
  float* const out = ranges.data() + rs.beam_first;
  float* const inten = intensities.data() + rs.beam_first;
  const std::span<const RayQuery> queries{ray_queries.data() + p.query_first, rs.beam_count};
  const std::span<const Pose> poses{transducer_poses.data() + p.pose_first, rs.transducer_count};
  const uint64_t noise_stream = Random::stream(uint64_t(RandomKind::RangerNoise), p.ranger, steps);
  const uint64_t gauss_stream = Random::stream(uint64_t(RandomKind::RangerGauss), p.ranger, steps);

  const bool one_static = statics.size() == 1;
  const float static_return = one_static ? float(std::max(0.0, statics[0].look.ranger_return)) : 1.0f;
  for (uint32_t b = 0; b < rs.beam_count; ++b) {
    inten[b] = 0;
    if (out[b] >= queries[b].max_range) continue;
    if (one_static) {
      inten[b] = static_return;
    } else {
      const RayQuery& q = queries[b];
      const StaticInfo* hit = static_at(q.origin + (out[b] + 0.5 * map.resolution()) * q.dir);
      inten[b] = hit ? float(std::max(0.0, hit->look.ranger_return)) : 1.0f;
    }
  }

  if (layer) {
    settle_layer_hits(out, inten);
  } else if (ranger_robots == World::RangerRobots::Every) {
    beams_meet_every(rs, queries, out, inten);
  } else {
    beams_meet_candidates(rs, queries, poses, out, inten);
    rs.robots_near = uint32_t(ranger_candidates.size());
  }

  // Noise on returns, then the sensor's limits.
  for (uint32_t t = rs.transducer_first; t < rs.transducer_first + rs.transducer_count; ++t) {
    const Transducer& td = transducers[t];
    float* r = out + td.beam_offset;
    const uint64_t beam = rs.beam_first + td.beam_offset;  // world-wide index: the noise counter
    if (td.noise_prop <= 0 && td.noise_sd <= 0) {
      // No noise: only the limits (the loop below does the same, slower).
      for (uint32_t s = 0; s < td.samples; ++s) r[s] = std::max(std::min(r[s], td.range_max), td.range_min);
      continue;
    }
    for (uint32_t s = 0; s < td.samples; ++s) {
      if (r[s] < td.range_max) {
        double v = r[s];
        if (td.noise_prop > 0) v += v * td.noise_prop * random.symmetric(noise_stream, beam + s);
        if (td.noise_sd > 0) v += td.noise_sd * random.gaussian(gauss_stream, beam + s);
        r[s] = float(std::clamp(v, double(td.range_min), double(td.range_max)));
      } else {
        r[s] = td.range_max;
      }
      r[s] = std::max(r[s], td.range_min);
    }
  }
  rs.step = steps;
}

}  // namespace troupe::sim
