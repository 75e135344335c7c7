// The benchmark's worlds: a synthetic office floor (rooms, doors, pillars)
// as a bitmap, robot placement in its free space, and world files that load
// through the same path as any user's.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host-sim/sim/desc.h"
#include "host-sim/world/png_image.h"

namespace troupe::bench {

/// An office floor `width_m` x `height_m` at `m_per_px`: outer walls, rooms
/// about 10 x 7.5 m with 1.5 m doors, and scattered pillars. Dark = wall.
world::GrayImage office(double width_m, double height_m, double m_per_px, uint64_t seed);

/// A campus-like site as a `width_px` x `height_px` image, for Stage's
/// large.world layout (the SFU campus bitmap on a 1,000 x 700 m
/// floorplan): city blocks between roads, each a solid building, a
/// building with rooms off a corridor, a walled yard or open lawn; trees
/// scattered over the open ground; a fence round the site. Dark = obstacle.
world::GrayImage campus(int width_px, int height_px, uint64_t seed);

/// `count` poses (world frame, the image centred on the origin) with at
/// least `clear_m` of free floor around each and `spacing_m` between any
/// two. Fewer when the floor is full.
std::vector<sim::Pose> place(const world::GrayImage& map, double m_per_px, size_t count, double clear_m,
                             double spacing_m, uint64_t seed);

/// A small robot: a 0.25 m square with a ring of 12 sonars (2 m, every
/// 30 degrees), driven by `ctrl`.
sim::RobotDesc ring_robot(const std::string& name, const sim::Pose& pose, const std::string& ctrl);

/// The same robot as world-file text (a define), for worlds written to disk.
std::string ring_robot_define();

/// A scratch folder, removed on destruction.
class Scratch {
 public:
  Scratch();
  ~Scratch();
  std::string path(const std::string& name) const { return root_ + "/" + name; }
  std::string write(const std::string& name, const std::string& text) const;

 private:
  std::string root_;
};

}  // namespace troupe::bench
