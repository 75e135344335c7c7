// The rows of the simulator's performance table, one function each. Every
// row prints its own detail and returns its summary line.
#pragma once

#include <string>

#include "host-sim/sim/desc.h"

namespace troupe::bench {

struct Settings {
  int repeats = 5;                                  // timed chunks per row; medians are reported
  double scale = 1.0;                               // multiplies the steps per chunk (0.1 for a quick look)
  bool baseline = true;                             // also time one chunk with per-cell ray casting
  sim::MapStorage storage = sim::MapStorage::Auto;  // how static maps keep their cells
};

struct Summary {
  std::string row;
  std::string what;
  double rtf = 0;           // median simulated seconds per CPU second
  double rtf_wall = 0;      // the same per wall second
  double baseline_rtf = 0;  // per-cell ray casting, same world, same run
  double stage = 0;         // Stage 4.3's figure for this row: given (the issue's), not measured
  double target = 0;        // the target
  double load_s = 0;        // wall time to load the world file, s (rows that load one)
};

/// Each returns false when it cannot run (missing data), after saying why.
bool row_simple(const Settings& s, Summary& out);
bool row_crowd(const Settings& s, Summary& out);
bool row_packed(const Settings& s, Summary& out);
bool row_cave(const Settings& s, Summary& out);
bool row_scale(const Settings& s, Summary& out);
bool row_rays(const Settings& s, Summary& out);
bool row_campus(const Settings& s, Summary& out);
bool row_scale100k(const Settings& s, Summary& out);

/// Writes the campus row's world (campus.world and its bitmap campus.png)
/// into `dir`; its path, or "" with `err` set.
std::string write_campus(const std::string& dir, std::string& err);

/// Writes the scale rows' world for `robots` robots (office.world and its
/// bitmap office.png) into `dir`: the same density (8.4 m^2 of office per
/// robot), robots and sensors as the scale row. Its path, or "" with `err`.
std::string write_scale_world(const std::string& dir, int robots, std::string& err);

}  // namespace troupe::bench
