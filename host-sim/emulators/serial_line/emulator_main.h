// The one main() of the serial-line emulator programs (troupe-emulate-p2os,
// troupe-emulate-sick): the flags every serial device shares (--link,
// --baud, faults, --seed, --no-baud-check), the device's own flags, then
// the device on a new pseudo-terminal, its path printed on stdout, stepped
// until SIGINT or SIGTERM. The command line is CLI11's, through
// wire/cli/args.h.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "host-sim/emulators/serial_line/line_faults.h"
#include "host-sim/emulators/serial_line/serial_emulator.h"

namespace CLI {
class App;
}

namespace troupe::emulators {

/// The flags every serial emulator takes.
struct EmulatorOptions {
  std::string link;
  /// The device's line speed at power-up, bit/s.
  uint32_t baud = 9600;
  FaultRates rates;
  uint64_t seed = 1;
  bool check_baud = true;
};

struct EmulatorProgram {
  /// "troupe-emulate-p2os": for messages.
  const char* name = "";
  /// What --help says beyond the common flags: the device's flags for the
  /// usage line ("[--model NAME]"), a description (whole lines), and
  /// examples, each a command line that runs the program.
  const char* synopsis = "";
  const char* about = "";
  std::vector<std::string> examples;
  /// The bauds the device speaks, bit/s; the first is the default.
  std::vector<uint32_t> bauds;
  /// Adds the device's own flags, with their help, to the command line.
  std::function<void(CLI::App&)> add_flags;
  /// Builds the device from the common options.
  std::function<std::unique_ptr<SerialEmulator>(const EmulatorOptions&)> make;
  /// The stderr line once the device is up, e.g. "LMS200 at 9600 baud".
  std::function<std::string(const EmulatorOptions&)> describe;
  /// How long one poll waits, ms: short enough to pace the line.
  int poll_ms = 5;
};

/// Parses `argv`, runs the device until a stop signal; the exit code.
int emulator_main(int argc, char** argv, const EmulatorProgram& program);

}  // namespace troupe::emulators
