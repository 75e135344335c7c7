#include "tests/bench/sim/arena.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace troupe::bench {
namespace {

void fill(world::GrayImage& img, int x0, int y0, int x1, int y1, uint8_t v) {
  x0 = std::max(0, x0);
  y0 = std::max(0, y0);
  x1 = std::min(img.width, x1);
  y1 = std::min(img.height, y1);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) img.pixels[size_t(y) * size_t(img.width) + size_t(x)] = v;
  }
}

}  // namespace

world::GrayImage office(double width_m, double height_m, double m_per_px, uint64_t seed) {
  std::mt19937_64 rng(seed);
  world::GrayImage img;
  img.width = int(std::lround(width_m / m_per_px));
  img.height = int(std::lround(height_m / m_per_px));
  img.pixels.assign(size_t(img.width) * size_t(img.height), 255);
  const int wall = std::max(1, int(std::lround(0.1 / m_per_px)));
  const int door = int(std::lround(1.5 / m_per_px));
  const int room_x = int(std::lround(10.0 / m_per_px)), room_y = int(std::lround(7.5 / m_per_px));
  // Outer walls.
  fill(img, 0, 0, img.width, wall, 0);
  fill(img, 0, img.height - wall, img.width, img.height, 0);
  fill(img, 0, 0, wall, img.height, 0);
  fill(img, img.width - wall, 0, img.width, img.height, 0);
  // Room walls along x and y, each segment with a door at a seeded place.
  for (int y = room_y; y < img.height - room_y / 2; y += room_y) {
    for (int x = 0; x < img.width; x += room_x) {
      const int d = x + wall + int(rng() % uint64_t(std::max(1, room_x - door - 2 * wall)));
      fill(img, x, y, d, y + wall, 0);
      fill(img, d + door, y, x + room_x, y + wall, 0);
    }
  }
  for (int x = room_x; x < img.width - room_x / 2; x += room_x) {
    for (int y = 0; y < img.height; y += room_y) {
      const int d = y + wall + int(rng() % uint64_t(std::max(1, room_y - door - 2 * wall)));
      fill(img, x, y, x + wall, d, 0);
      fill(img, x, d + door, x + wall, y + room_y, 0);
    }
  }
  // A pillar (0.3 m) every ~25 square metres.
  const int pillar = std::max(1, int(std::lround(0.3 / m_per_px)));
  const size_t pillars = size_t(width_m * height_m / 25);
  for (size_t i = 0; i < pillars; ++i) {
    const int x = int(rng() % uint64_t(img.width)), y = int(rng() % uint64_t(img.height));
    fill(img, x, y, x + pillar, y + pillar, 0);
  }
  return img;
}

world::GrayImage campus(int width_px, int height_px, uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto between = [&](int lo, int hi) { return hi <= lo ? lo : lo + int(rng() % uint64_t(hi - lo + 1)); };
  world::GrayImage img;
  img.width = width_px;
  img.height = height_px;
  img.pixels.assign(size_t(width_px) * size_t(height_px), 255);
  // The site's fence.
  fill(img, 0, 0, width_px, 1, 0);
  fill(img, 0, height_px - 1, width_px, height_px, 0);
  fill(img, 0, 0, 1, height_px, 0);
  fill(img, width_px - 1, 0, width_px, height_px, 0);
  // Rooms off a corridor along a building's long side (x here), each with
  // a door onto it; walls a pixel thick.
  auto hollow = [&](int x0, int y0, int x1, int y1) {
    const int mid = (y0 + y1) / 2, half = between(2, 4);
    fill(img, x0, y0, x1, y0 + 1, 0);
    fill(img, x0, y1 - 1, x1, y1, 0);
    fill(img, x0, y0, x0 + 1, y1, 0);
    fill(img, x1 - 1, y0, x1, y1, 0);
    fill(img, x0, mid - half, x0 + 1, mid + half, 255);  // entrances at both ends
    fill(img, x1 - 1, mid - half, x1, mid + half, 255);
    fill(img, x0, mid - half - 1, x1, mid - half, 0);  // the corridor's walls
    fill(img, x0, mid + half, x1, mid + half + 1, 0);
    for (int x = x0 + between(12, 24); x < x1 - 8; x += between(12, 24)) {
      fill(img, x, y0, x + 1, mid - half, 0);  // the walls between rooms
      fill(img, x, mid + half, x + 1, y1, 0);
      fill(img, x - 4, mid - half - 1, x - 2, mid - half, 255);  // their doors
      fill(img, x - 4, mid + half, x - 2, mid + half + 1, 255);
    }
  };
  // City blocks between roads 10 to 20 px wide; each a solid building (an
  // L of two wings), a building with rooms, a walled yard, or open lawn.
  for (int y = between(10, 30); y < height_px - 60;) {
    const int block_h = between(100, 220);
    for (int x = between(10, 30); x < width_px - 60;) {
      const int block_w = between(120, 260);
      const int x1 = std::min(x + block_w, width_px - 10), y1 = std::min(y + block_h, height_px - 10);
      const int inset = between(6, 20);
      switch (rng() % 8) {
        case 0:
        case 1:
        case 2: {
          const int cx = between(x + inset + 20, x1 - inset - 20),
                    cy = between(y + inset + 20, y1 - inset - 20);
          fill(img, x + inset, y + inset, x1 - inset, cy, 0);
          fill(img, x + inset, cy, cx, y1 - inset, 0);
          break;
        }
        case 3:
        case 4:
        case 5:
          hollow(x + inset, y + inset, x1 - inset, y1 - inset);
          break;
        case 6:
          fill(img, x + inset, y + inset, x1 - inset, y + inset + 1, 0);
          fill(img, x + inset, y1 - inset - 1, x1 - inset, y1 - inset, 0);
          fill(img, x + inset, y + inset, x + inset + 1, y1 - inset - 8, 0);  // a gate in the west wall
          fill(img, x1 - inset - 1, y + inset, x1 - inset, y1 - inset, 0);
          break;
        default:
          break;
      }
      x += block_w + between(20, 40);
    }
    y += block_h + between(20, 40);
  }
  // Trees and lamp posts: a pixel or two, one per ~400 m^2 at 0.5 m a
  // pixel, on free ground.
  const size_t trees = size_t(width_px) * size_t(height_px) / 1600;
  for (size_t i = 0; i < trees; ++i) {
    const int x = between(2, width_px - 4), y = between(2, height_px - 4), r = between(1, 2);
    if (img.at(x, y) == 255) fill(img, x, y, x + r, y + r, 0);
  }
  return img;
}

std::vector<sim::Pose> place(const world::GrayImage& map, double m_per_px, size_t count, double clear_m,
                             double spacing_m, uint64_t seed) {
  std::mt19937_64 rng(seed);
  // A prefix sum of dark pixels answers "is this square free" in O(1).
  const size_t W = size_t(map.width) + 1;
  std::vector<uint32_t> sum(W * (size_t(map.height) + 1), 0);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      sum[size_t(y + 1) * W + size_t(x + 1)] =
          sum[size_t(y) * W + size_t(x + 1)] + sum[size_t(y + 1) * W + size_t(x)] -
          sum[size_t(y) * W + size_t(x)] + (map.at(x, y) <= 127 ? 1u : 0u);
    }
  }
  const int r = int(std::ceil(clear_m / m_per_px));
  auto free_at = [&](int x, int y) {
    if (x - r < 0 || y - r < 0 || x + r + 1 > map.width || y + r + 1 > map.height) return false;
    const size_t x0 = size_t(x - r), y0 = size_t(y - r), x1 = size_t(x + r + 1), y1 = size_t(y + r + 1);
    return sum[y1 * W + x1] - sum[y0 * W + x1] - sum[y1 * W + x0] + sum[y0 * W + x0] == 0;
  };
  // Spacing through a coarse grid of cells `spacing_m` wide.
  const double cell = spacing_m;
  const double w_m = map.width * m_per_px, h_m = map.height * m_per_px;
  const int gx = int(w_m / cell) + 1, gy = int(h_m / cell) + 1;
  std::vector<std::vector<sim::Pose>> grid(size_t(gx) * size_t(gy));
  std::vector<sim::Pose> out;
  std::uniform_real_distribution<double> ang(-3.14159, 3.14159);
  for (size_t tries = 0; out.size() < count && tries < count * 200; ++tries) {
    const int px = int(rng() % uint64_t(map.width)), py = int(rng() % uint64_t(map.height));
    if (!free_at(px, py)) continue;
    const sim::Pose p{(px + 0.5) * m_per_px - w_m / 2, h_m / 2 - (py + 0.5) * m_per_px, ang(rng)};
    const int cx = int((p.x + w_m / 2) / cell), cy = int((p.y + h_m / 2) / cell);
    bool ok = true;
    for (int yy = std::max(0, cy - 1); yy <= std::min(gy - 1, cy + 1) && ok; ++yy) {
      for (int xx = std::max(0, cx - 1); xx <= std::min(gx - 1, cx + 1) && ok; ++xx) {
        for (const sim::Pose& q : grid[size_t(yy) * size_t(gx) + size_t(xx)]) {
          if (std::hypot(q.x - p.x, q.y - p.y) < spacing_m) ok = false;
        }
      }
    }
    if (!ok) continue;
    grid[size_t(cy) * size_t(gx) + size_t(cx)].push_back(p);
    out.push_back(p);
  }
  return out;
}

sim::RobotDesc ring_robot(const std::string& name, const sim::Pose& pose, const std::string& ctrl) {
  sim::RobotDesc r;
  r.name = name;
  r.pose = pose;
  r.size = {0.25, 0.25};
  r.polygons = {{{-0.125, -0.125}, {0.125, -0.125}, {0.125, 0.125}, {-0.125, 0.125}}};
  r.velocity[0] = {-0.5, 0.5};
  r.velocity[2] = {-1.57, 1.57};
  sim::RangerDesc ring;
  ring.name = "sonar";
  for (int i = 0; i < 12; ++i) {
    sim::TransducerDesc t;
    const double a = i * sim::kPi / 6;
    t.pose = {0.125 * std::cos(a), 0.125 * std::sin(a), a};
    t.range_max = 2.0;
    t.fov = 15 * sim::kPi / 180;
    t.samples = 1;
    ring.transducers.push_back(t);
  }
  r.rangers.push_back(ring);
  r.ctrl = ctrl;
  return r;
}

std::string ring_robot_define() {
  std::string s = "define ring12 ranger (\n";
  for (int i = 0; i < 12; ++i) {
    const double a = i * 30.0, rad = a * sim::kPi / 180;
    char line[160];
    std::snprintf(line, sizeof line,
                  "  sensor ( pose [ %.4f %.4f 0 %.1f ] range [ 0 2 ] fov 15 samples 1 )\n",
                  0.125 * std::cos(rad), 0.125 * std::sin(rad), a);
    s += line;
  }
  s += ")\n";
  s += "define smallbot position ( size [ 0.25 0.25 0.2 ] velocity_bounds [ -0.5 0.5 0 0 0 0 -90 90 ] ring12 "
       "( ) )\n";
  return s;
}

Scratch::Scratch() {
  std::string pattern = (std::filesystem::temp_directory_path() / "troupe-bench-XXXXXX").string();
  root_ = mkdtemp(pattern.data()) ? pattern : std::string(".");
}

Scratch::~Scratch() {
  std::error_code ec;
  std::filesystem::remove_all(root_, ec);
}

std::string Scratch::write(const std::string& name, const std::string& text) const {
  std::ofstream(path(name), std::ios::binary) << text;
  return path(name);
}

}  // namespace troupe::bench
