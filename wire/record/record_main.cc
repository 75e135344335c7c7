// troupe-record (`troupe record`): writes the data of devices of a node, as
// received and with receive times, to a troupe log.
#include <signal.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "wire/address.h"
#include "wire/log.h"
#include "wire/record/recorder.h"
#include "wire/stop_signals.h"

namespace {

const char kUsage[] =
    "usage: troupe record HOST[:PORT] ADDR... -o FILE [--duration S] [--count N]\n"
    "\n"
    "Records the data of the given devices, frame by frame as the node sends it and\n"
    "with the time each frame arrived, into FILE: a troupe log that `troupe play`\n"
    "serves again. Stops after --duration seconds, after --count frames, or on\n"
    "Ctrl-C. A lost connection is re-established and the recording goes on.\n"
    "ADDR is [ROBOT/]INTERFACE:INDEX, e.g. position2d:0 or r3/ranger:1.\n"
    "\n"
    "  -o, --output FILE  the log to write (replaced if it exists)\n"
    "  --duration S       stop after S seconds\n"
    "  --count N          stop after N data frames\n"
    "  --timeout S        wait this long for the node to connect and reply (default 3)\n"
    "  --log-level LEVEL  error, warn, info (default) or debug\n"
    "\n"
    "examples:\n"
    "  troupe record localhost position2d:0 ranger:0 -o run1.trl\n"
    "  troupe record robot7.local:6670 r0/ranger:1 -o laser.trl --duration 60\n"
    "  troupe record localhost position2d:0 -o ten.trl --count 10\n";

int usage_error(const std::string& message) {
  fprintf(stderr, "troupe record: %s (see: troupe record --help)\n", message.c_str());
  return 2;
}

bool parse_number(const char* text, double min, double& out) {
  char* end = nullptr;
  out = strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(out) && out >= min;
}

}  // namespace

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-record");
  signal(SIGPIPE, SIG_IGN);
  troupe::record::RecordOptions options;
  std::string host;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&](const char*& out) {
      if (i + 1 >= argc) return false;
      out = argv[++i];
      return true;
    };
    const char* v = nullptr;
    double d = 0;
    if (a == "-h" || a == "--help") {
      fputs(kUsage, stdout);
      return 0;
    } else if (a == "-o" || a == "--output") {
      if (!value(v)) return usage_error(a + " needs a file name");
      options.output = v;
    } else if (a == "--duration") {
      if (!value(v) || !parse_number(v, 0, d) || d <= 0) return usage_error("--duration needs seconds > 0");
      options.duration_s = d;
    } else if (a == "--count") {
      if (!value(v) || !parse_number(v, 1, d) || d != std::floor(d))
        return usage_error("--count needs a whole number >= 1");
      options.max_frames = uint64_t(d);
    } else if (a == "--timeout") {
      if (!value(v) || !parse_number(v, 0, d) || d <= 0 || d > 3600)
        return usage_error("--timeout needs seconds in (0, 3600]");
      options.timeout_ms = int(d * 1000);
    } else if (a == "--log-level") {
      troupe::LogLevel level{};
      if (!value(v) || !troupe::parse_log_level(v, level))
        return usage_error("--log-level needs error, warn, info or debug");
      troupe::set_log_level(level);
    } else if (a.size() > 1 && a[0] == '-') {
      return usage_error("unknown option '" + a + "'");
    } else if (host.empty()) {
      host = a;
    } else {
      options.devices.push_back(a);
    }
  }
  if (host.empty()) return usage_error("missing HOST");
  if (options.devices.empty()) return usage_error("missing ADDR: which devices to record");
  if (options.output.empty()) return usage_error("missing -o FILE");
  std::string error;
  troupe::wire::HostPort hp;
  if (!troupe::wire::parse_host(host, hp, error)) return usage_error(error);
  for (const std::string& spec : options.devices) {
    troupe::wire::DeviceSpec parsed;
    if (!troupe::wire::parse_device(spec, parsed, error)) return usage_error(error);
  }
  options.host = hp.host;
  options.port = hp.port;

  troupe::StopSignals stop;
  troupe::record::Recorder recorder(options);
  if (!recorder.start(error)) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  troupe::log_info("recording %zu device(s) of %s:%u to %s; Ctrl-C stops", options.devices.size(),
                   options.host.c_str(), unsigned(options.port), options.output.c_str());
  bool ok = recorder.run(stop.fd(), error);
  if (const char* sig = stop.take()) troupe::log_info("%s: stopping", sig);
  if (!ok) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }
  troupe::log_info("recorded %llu frames in %.1f s (%.1f KiB) to %s",
                   static_cast<unsigned long long>(recorder.frames()), recorder.elapsed_s(),
                   double(recorder.bytes()) / 1024.0, options.output.c_str());
  return 0;
}
