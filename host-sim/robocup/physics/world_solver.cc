// Contacts and impulses: which bodies touch, the sequential-impulse solver
// that gives them restitution and friction, and the push that separates
// bodies found overlapping.
#include <algorithm>

#include "host-sim/robocup/physics/world.h"

namespace troupe::robocup {

bool World::may_touch(const Body& a, const Body& b) const {
  if (!a.alive || !b.alive || (a.inv_mass == 0 && b.inv_mass == 0)) return false;
  const Vec2 slop{def_.contact_slop, def_.contact_slop};
  return Aabb{a.box.lo - slop, a.box.hi + slop}.overlaps(b.box);
}

void World::find_contacts(std::vector<Contact>& out) const {
  out.clear();
  for (uint32_t i = 0; i < bodies_.size(); ++i) {
    for (uint32_t j = i + 1; j < bodies_.size(); ++j) {
      const Body& a = bodies_[i];
      const Body& b = bodies_[j];
      if (!may_touch(a, b)) continue;
      for (size_t si = 0; si < a.placed.size(); ++si) {
        for (size_t sj = 0; sj < b.placed.size(); ++sj) {
          if (!heights_overlap(a.shapes[si], b.shapes[sj])) continue;
          const Separation s = separation(a.placed[si], b.placed[sj]);
          if (s.distance >= def_.contact_slop) continue;
          Contact c;
          c.a = i;
          c.b = j;
          c.normal = s.normal;
          c.count = s.point_count;
          c.points[0] = s.points[0];
          c.points[1] = s.points[1];
          out.push_back(c);
        }
      }
    }
  }
}

void World::solve(std::vector<Contact>& contacts) {
  const double e = def_.restitution, f = def_.friction;
  for (Contact& c : contacts) {
    const Body& a = bodies_[c.a];
    const Body& b = bodies_[c.b];
    const Vec2 n = c.normal, t = perp(n);
    for (int k = 0; k < c.count; ++k) {
      ContactPoint& p = c.cp[k];
      p = {};
      p.ra = c.points[k] - com_world(a);
      p.rb = c.points[k] - com_world(b);
      const double rna = cross(p.ra, n), rnb = cross(p.rb, n);
      const double rta = cross(p.ra, t), rtb = cross(p.rb, t);
      const double kn = a.inv_mass + b.inv_mass + a.inv_inertia * rna * rna + b.inv_inertia * rnb * rnb;
      const double kt = a.inv_mass + b.inv_mass + a.inv_inertia * rta * rta + b.inv_inertia * rtb * rtb;
      p.normal_mass = kn > 0 ? 1 / kn : 0;
      p.tangent_mass = kt > 0 ? 1 / kt : 0;
      const Vec2 dv = (b.v + cross(b.w, p.rb)) - (a.v + cross(a.w, p.ra));
      const double vn = dot(dv, n);
      p.approach = -vn;
      // Restitution: the ratio of normal relative speeds after/before.
      p.target_vn = vn < -def_.restitution_threshold ? -e * vn : 0;
    }
  }
  auto push = [this](Contact& c, ContactPoint& p, Vec2 impulse) {
    Body& a = bodies_[c.a];
    Body& b = bodies_[c.b];
    a.v -= impulse * a.inv_mass;
    a.w -= cross(p.ra, impulse) * a.inv_inertia;
    b.v += impulse * b.inv_mass;
    b.w += cross(p.rb, impulse) * b.inv_inertia;
  };
  auto relative = [this](const Contact& c, const ContactPoint& p) {
    const Body& a = bodies_[c.a];
    const Body& b = bodies_[c.b];
    return (b.v + cross(b.w, p.rb)) - (a.v + cross(a.w, p.ra));
  };
  auto normal_passes = [&](int passes) {
    for (int pass = 0; pass < passes; ++pass) {
      double largest = 0;
      for (Contact& c : contacts) {
        for (int k = 0; k < c.count; ++k) {
          ContactPoint& p = c.cp[k];
          // Accumulated normal impulse never pulls the bodies together.
          const double vn = dot(relative(c, p), c.normal);
          const double total = std::max(0.0, p.normal_impulse + (p.target_vn - vn) * p.normal_mass);
          const double dj = total - p.normal_impulse;
          p.normal_impulse = total;
          push(c, p, c.normal * dj);
          largest = std::max(largest, std::fabs(dj));
        }
      }
      if (largest < 1e-12) break;
    }
  };
  normal_passes(def_.solver_passes);
  // Friction: the fraction f of the tangential impulse that would stop the
  // slip of the contact point, on contacts that press. f = 0 applies none
  // (frictionless), f = 1 stops the slip (sticky). Never adds energy.
  if (f > 0) {
    for (Contact& c : contacts) {
      const Vec2 t = perp(c.normal);
      for (int k = 0; k < c.count; ++k) {
        ContactPoint& p = c.cp[k];
        if (p.normal_impulse <= 0) continue;
        p.tangent_impulse = -f * dot(relative(c, p), t) * p.tangent_mass;
        push(c, p, t * p.tangent_impulse);
      }
    }
    // Friction can turn a contact's motion back into it.
    normal_passes(def_.solver_passes);
  }
  for (const Contact& c : contacts) {
    for (int k = 0; k < c.count; ++k) {
      const ContactPoint& p = c.cp[k];
      if (p.normal_impulse <= 0) continue;
      events_.push_back({{c.a, bodies_[c.a].generation},
                         {c.b, bodies_[c.b].generation},
                         c.points[k],
                         c.normal,
                         p.normal_impulse,
                         p.approach});
    }
  }
}

void World::resolve_overlaps() {
  constexpr int kPasses = 4;
  const double tolerance = def_.contact_slop * 0.1;
  for (int pass = 0; pass < kPasses; ++pass) {
    bool moved = false;
    for (uint32_t i = 0; i < bodies_.size(); ++i) {
      for (uint32_t j = i + 1; j < bodies_.size(); ++j) {
        Body& a = bodies_[i];
        Body& b = bodies_[j];
        if (!may_touch(a, b)) continue;
        for (size_t si = 0; si < a.placed.size(); ++si) {
          for (size_t sj = 0; sj < b.placed.size(); ++sj) {
            if (!heights_overlap(a.shapes[si], b.shapes[sj])) continue;
            const Separation s = separation(a.placed[si], b.placed[sj]);
            if (s.distance > -tolerance) continue;
            // Back into the touching band, shared by inverse mass.
            const double depth = -s.distance + def_.contact_slop * 0.25;
            const double share = a.inv_mass + b.inv_mass;
            const Vec2 da = s.normal * (-depth * a.inv_mass / share);
            const Vec2 db = s.normal * (depth * b.inv_mass / share);
            a.pose.x += da.x;
            a.pose.y += da.y;
            b.pose.x += db.x;
            b.pose.y += db.y;
            place_body(a);
            place_body(b);
            moved = true;
          }
        }
      }
    }
    if (!moved) break;
  }
}

}  // namespace troupe::robocup
