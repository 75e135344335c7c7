// troupe-record (`troupe record`): writes the data of devices of a node, as
// received and with receive times, to a troupe log.
#include <signal.h>

#include <cstdio>
#include <string>

#include "wire/address.h"
#include "wire/cli/args.h"
#include "wire/log.h"
#include "wire/noise/client_keys.h"
#include "wire/noise/noise_transport.h"
#include "wire/record/recorder.h"
#include "wire/stop_signals.h"

int main(int argc, char** argv) {
  troupe::set_log_program("troupe-record");
  signal(SIGPIPE, SIG_IGN);
  troupe::record::RecordOptions options;
  std::string host;
  troupe::wire::noise::ClientKeys keys;
  double duration_s = 0, timeout_s = 3;
  auto app = troupe::cli::make_app(
      "troupe record",
      {"troupe record HOST[:PORT] ADDR... -o FILE [--duration S] [--count N]",
       "Records the data of the given devices, frame by frame as the node sends it and\n"
       "with the time each frame arrived, into FILE: a troupe log that `troupe play`\n"
       "serves again. Stops after --duration seconds, after --count frames, or on\n"
       "Ctrl-C. A lost connection is re-established and the recording goes on.\n"
       "A camera's images are recorded as it sends them, with its answers to Geometry\n"
       "and GetConfig, which play gives back.\n"
       "ADDR is [ROBOT/]INTERFACE:INDEX, e.g. position2d:0 or r3/ranger:1.\n",
       {"troupe record localhost position2d:0 ranger:0 -o run1.trl",
        "troupe record robot7.local:6670 r0/ranger:1 -o laser.trl --duration 60",
        "troupe record localhost position2d:0 -o ten.trl --count 10",
        "troupe record localhost cam/camera:0 -o images.trl --duration 5 --image-compression none",
        "troupe record robot7.local r0/ranger:0 -o laser.trl --identity laptop --node-key robot7.pub"}});
  app->add_option("HOST", host, "HOST[:PORT]");
  app->add_option("ADDR", options.devices, "the devices to record");
  app->add_option("-o,--output", options.output, "the log to write (replaced if it exists)")->type_name("FILE");
  app->add_option("--duration", duration_s, "stop after S seconds")->type_name("S")->check(troupe::cli::above(0));
  app->add_option("--count", options.max_frames, "stop after N data frames")
      ->type_name("N")
      ->check(troupe::cli::at_least(1));
  app->add_option("--timeout", timeout_s, "wait this long for the node to connect and reply (default 3)")
      ->type_name("S")
      ->check(troupe::cli::above(0) & troupe::cli::at_most(3600));
  std::string compression = "none";
  app->add_option("--image-compression", compression,
                  "how cameras are asked to pack images: none (raw rows, the default) or png")
      ->type_name("none|png")
      ->check(CLI::IsMember({"none", "png"}));
  troupe::cli::add_secure_session(*app, keys);
  troupe::cli::add_log_level(*app);
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  auto usage_error = [&](const std::string& message) { return troupe::cli::usage_error(*app, message); };
  if (host.empty()) return usage_error("missing HOST");
  if (options.devices.empty()) return usage_error("missing ADDR: which devices to record");
  if (options.output.empty()) return usage_error("missing -o FILE");
  // troupe-sim's cameras encode PNG themselves; a camera that packs nothing
  // (a board's v4l2 driver) sends raw rows whatever was asked, and those are
  // recorded as they came.
  options.image_compression =
      compression == "png" ? troupe::wire::ImageCompression::Png : troupe::wire::ImageCompression::None;
  options.duration_s = duration_s;
  options.timeout_ms = int(timeout_s * 1000);
  std::string error;
  troupe::wire::HostPort hp;
  if (!troupe::wire::parse_host(host, hp, error)) return usage_error(error);
  for (const std::string& spec : options.devices) {
    troupe::wire::DeviceSpec parsed;
    if (!troupe::wire::parse_device(spec, parsed, error)) return usage_error(error);
  }
  options.host = hp.host;
  options.port = hp.port;
  options.transport = troupe::wire::noise::client_transport(keys, hp.host, hp.port, error);
  if (!error.empty()) {
    troupe::log_error("%s", error.c_str());
    return 1;
  }

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
