// troupe-emulate-sick: a SICK LMS200 on a pseudo-terminal, for trying
// the sicklms200 driver (or any LMS2xx client) without a scanner. Prints
// the port's path on stdout, then runs until interrupted.
#include <cstdint>
#include <memory>

#include "host-sim/emulators/serial_line/emulator_main.h"
#include "host-sim/emulators/sicklms200/sick_emulator.h"
#include "wire/cli/args.h"

int main(int argc, char** argv) {
  namespace emu = troupe::emulators;
  emu::SickEmulator::Config scanner;
  emu::EmulatorProgram p;
  p.name = "troupe-emulate-sick";
  p.synopsis = "[--startup-ms N]";
  p.about =
      "Emulates a SICK LMS200 laser scanner on a new pseudo-terminal and prints\n"
      "its path. It stands in a 20 x 6 m corridor, powers up at 9600 baud and\n"
      "waits for a driver to configure it.\n";
  p.examples = {"troupe-emulate-sick --link laser-port",
                "troupe emulate-sick --link laser-port --tear 0.05 --seed 3   # torn telegrams"};
  p.bauds = {9600, 19200, 38400, 500000};
  uint64_t startup_ms = scanner.startup_us / 1000;
  p.add_flags = [&](CLI::App& app) {
    app.add_option("--startup-ms", startup_ms, "from a reset request to the power-on message (default 2000)")
        ->type_name("N")
        ->check(troupe::cli::at_least(0));
  };
  p.make = [&](const emu::EmulatorOptions& o) {
    scanner.startup_us = startup_ms * 1000;
    scanner.power_up_baud = o.baud;
    scanner.seed = o.seed;
    scanner.check_baud = o.check_baud;
    return std::make_unique<emu::SickEmulator>(scanner);
  };
  p.describe = [](const emu::EmulatorOptions& o) { return "LMS200 at " + std::to_string(o.baud) + " baud"; };
  // 2 ms: the line is paced in small steps (38400 baud is 4 bytes a ms).
  p.poll_ms = 2;
  return emu::emulator_main(argc, argv, p);
}
