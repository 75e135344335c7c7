// sim_bench: the troupe-sim performance table. Each row runs in a child
// process of its own, so its peak memory is its own. Speeds are simulated
// seconds per CPU second of the one thread that runs the simulation (the
// machine may be shared; CPU time does not count time spent waiting for the
// processor), medians over repeats, with wall-clock figures beside them and
// the same world timed with per-cell ray casting as an in-run baseline. The
// Stage column is given, not measured: the figure the project was given for
// Stage 4.3 on this kind of machine, a constant of each row.
//
//   sim_bench [simple] [crowd] [packed] [cave] [scale] [rays] [campus] [scale100k] [--repeats N] [--quick]
//   sim_bench --write-campus DIR     (the campus row's world, for troupe-sim)
//   sim_bench --write-scale DIR [--robots N]   (the scale rows' world, N robots)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "tests/bench/sim/rows.h"
#include "wire/cli/args.h"

namespace {

using troupe::bench::Settings;
using troupe::bench::Summary;

struct Row {
  const char* name;
  bool (*run)(const Settings&, Summary&);
};

constexpr Row kRows[] = {
    {"simple", troupe::bench::row_simple}, {"crowd", troupe::bench::row_crowd},
    {"packed", troupe::bench::row_packed}, {"cave", troupe::bench::row_cave},
    {"scale", troupe::bench::row_scale},   {"rays", troupe::bench::row_rays},
    {"campus", troupe::bench::row_campus}, {"scale100k", troupe::bench::row_scale100k},
};

// The child's summary travels back through a pipe as one text line.
void send(int fd, const Summary& s, long peak_kb) {
  char line[512];
  int n =
      std::snprintf(line, sizeof line, "%s\t%s\t%.6g\t%.6g\t%.6g\t%.6g\t%.6g\t%ld\t%.6g\n", s.row.c_str(),
                    s.what.c_str(), s.rtf, s.rtf_wall, s.baseline_rtf, s.stage, s.target, peak_kb, s.load_s);
  if (n > 0 && write(fd, line, size_t(n)) < 0) std::perror("write");
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  std::vector<std::string> names;
  bool quick = false;
  std::string campus_dir, scale_dir;
  int scale_robots = 100000;
  auto app = troupe::cli::make_app(
      "sim_bench",
      {"sim_bench [simple] [crowd] [packed] [cave] [scale] [rays] [campus] [scale100k] [--repeats N] "
       "[--quick]",
       "The simulator's performance table: the named rows, or all of them.\n",
       {"sim_bench --repeats 3", "sim_bench simple crowd --quick", "sim_bench --write-campus /tmp/campus",
        "sim_bench --write-scale /tmp/scale --robots 100000"}});
  app->add_option("ROW", names, "rows to run")
      ->check(CLI::IsMember({"simple", "crowd", "packed", "cave", "scale", "rays", "campus", "scale100k"}));
  const std::map<std::string, troupe::sim::MapStorage> storages = {
      {"auto", troupe::sim::MapStorage::Auto},
      {"dense", troupe::sim::MapStorage::Dense},
      {"sparse", troupe::sim::MapStorage::Sparse}};
  app->add_option("--map", settings.storage,
                  "how static maps keep their cells: auto (sparse from 128 Mi cells), dense or sparse")
      ->transform(CLI::CheckedTransformer(storages, CLI::ignore_case))
      ->type_name("auto|dense|sparse");
  app->add_option("--write-campus", campus_dir,
                  "write the campus row's world (campus.world, campus.png) into DIR and exit")
      ->type_name("DIR");
  app->add_option("--write-scale", scale_dir,
                  "write the scale rows' world (office.world, office.png: 8.4 m^2 of office per robot) into "
                  "DIR and exit")
      ->type_name("DIR");
  app->add_option("--robots", scale_robots, "robots in the world --write-scale writes (default 100000)")
      ->type_name("N")
      ->check(CLI::Range(1, 1000000));
  app->add_option("--repeats", settings.repeats, "timed chunks per row; medians are reported (default 5)")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  app->add_flag("--quick", quick, "a tenth of the steps, 3 repeats: a short look");
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  if (!campus_dir.empty() || !scale_dir.empty()) {
    std::string err;
    std::error_code made;  // a folder that cannot be made fails at the first file, with its reason
    std::filesystem::create_directories(campus_dir.empty() ? scale_dir : campus_dir, made);
    const std::string path = campus_dir.empty()
                                 ? troupe::bench::write_scale_world(scale_dir, scale_robots, err)
                                 : troupe::bench::write_campus(campus_dir, err);
    if (path.empty()) {
      std::fprintf(stderr, "sim_bench: %s\n", err.c_str());
      return 1;
    }
    std::printf("%s\n", path.c_str());
    return 0;
  }
  if (quick) {
    settings.scale = 0.1;
    settings.repeats = 3;
  }
  std::vector<const Row*> rows;
  for (const std::string& name : names) {
    for (const Row& r : kRows) {
      if (name == r.name) rows.push_back(&r);
    }
  }
  if (rows.empty()) {
    for (const Row& r : kRows) rows.push_back(&r);
  }
  std::vector<std::string> lines;
  for (const Row* row : rows) {
    int fds[2];
    if (pipe(fds) != 0) return 1;
    std::fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
      close(fds[0]);
      Summary s;
      bool ok = row->run(settings, s);
      std::fflush(stdout);
      rusage ru{};
      getrusage(RUSAGE_SELF, &ru);
      if (ok) send(fds[1], s, ru.ru_maxrss);
      _exit(ok ? 0 : 3);
    }
    close(fds[1]);
    std::string text;
    char buf[512];
    ssize_t n;
    while ((n = read(fds[0], buf, sizeof buf)) > 0) text.append(buf, size_t(n));
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (!text.empty()) lines.push_back(text);
  }
  std::printf("\n%-13s %-60s %11s %11s %9s %8s %8s %8s %9s %7s\n", "row", "work", "sim s/CPU s", "sim s/wall",
              "per-cell", "x cells", "Stage", "x Stage", "peak MB", "load s");
  std::printf("%-13s %-60s %11s %11s %9s %8s %8s %8s\n", "", "", "", "", "", "", "given", "given");
  for (const std::string& l : lines) {
    char row[64], what[256];
    double rtf, wall, base, stage, target, load_s;
    long kb;
    if (std::sscanf(l.c_str(), "%63[^\t]\t%255[^\t]\t%lf\t%lf\t%lf\t%lf\t%lf\t%ld\t%lf", row, what, &rtf,
                    &wall, &base, &stage, &target, &kb, &load_s) != 9) {
      continue;
    }
    if (std::string(row) == "rays") {
      std::printf("%-13s %-60s %9.2f M %11s %7.2f M %7.2fx %8s %8s %9.1f   (rays per CPU second)\n", row,
                  what, rtf, "", base, base > 0 ? rtf / base : 0, "", "", kb / 1024.0);
      continue;
    }
    char load[16] = "";
    if (load_s > 0) std::snprintf(load, sizeof load, "%.1f", load_s);
    char goal[32] = "";  // rows without a target say none
    if (target > 0) std::snprintf(goal, sizeof goal, "   target %.0f", target);
    const int digits = rtf < 10 ? 2 : 0;  // slower than 10x real time: hundredths say something
    std::printf("%-13s %-60s %11.*f %11.*f %9.0f %7.2fx %8.0f %7.1fx %9.1f %7s%s\n", row, what, digits, rtf,
                digits, wall, base, base > 0 ? rtf / base : 0, stage, stage > 0 ? rtf / stage : 0,
                kb / 1024.0, load, goal);
  }
  std::printf(
      "\nStage: given, not measured in this run: the figure the project was given for Stage 4.3 on\n"
      "this kind of machine (one core, headless, fastest mode); x Stage divides by it.\n");
  return 0;
}
