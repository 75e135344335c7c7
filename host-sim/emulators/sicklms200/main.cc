// troupe-emulate-sicklms200: a SICK LMS200 on a pseudo-terminal, for trying
// the sicklms200 driver (or any LMS2xx client) without a scanner. Prints
// the port's path on stdout, then runs until interrupted.
#include <memory>

#include "host-sim/emulators/serial_line/emulator_main.h"
#include "host-sim/emulators/sicklms200/sick_emulator.h"

namespace {

const char kUsage[] =
    "usage: troupe-emulate-sicklms200 [--link PATH] [--baud N] [--startup-ms N] [--flip P]\n"
    "                                 [--drop P] [--tear P] [--seed N] [--no-baud-check]\n"
    "\n"
    "Emulates a SICK LMS200 laser scanner on a new pseudo-terminal and prints\n"
    "its path. It stands in a 20 x 6 m corridor, powers up at 9600 baud and\n"
    "waits for a driver to configure it.\n"
    "\n"
    "  --link PATH      also make PATH a symbolic link to the port\n"
    "  --baud N         the speed it powers up at, bit/s (default 9600)\n"
    "  --startup-ms N   from a reset request to the power-on message (default 2000)\n"
    "  --flip P         per byte sent: probability a bit flips\n"
    "  --drop P         per byte sent: probability it is lost\n"
    "  --tear P         per telegram sent: probability it is cut short\n"
    "  --seed N         seed of the fault generator (default 1)\n"
    "  --no-baud-check  talk whatever speed the driver's end is set to\n"
    "\n"
    "examples:\n"
    "  troupe-emulate-sicklms200 --link laser-port\n"
    "  troupe emulate-sicklms200 --link laser-port --tear 0.05 --seed 3   # torn telegrams\n";

}  // namespace

int main(int argc, char** argv) {
  using troupe::emulators::EmulatorOptions;
  using troupe::emulators::SickEmulator;
  SickEmulator::Config config;
  troupe::emulators::EmulatorProgram program;
  program.name = "troupe-emulate-sicklms200";
  program.usage = kUsage;
  program.bauds = {9600, 19200, 38400, 500000};
  program.flags = {{"--startup-ms", [&](const char* v) {
                      char* end = nullptr;
                      unsigned long ms = strtoul(v, &end, 10);
                      if (end == v || *end != '\0') return std::string("--startup-ms needs a number of ms");
                      config.startup_us = uint64_t(ms) * 1000;
                      return std::string();
                    }}};
  program.make = [&](const EmulatorOptions& o) {
    config.power_up_baud = o.baud;
    config.seed = o.seed;
    config.check_baud = o.check_baud;
    return std::make_unique<SickEmulator>(config);
  };
  program.describe = [](const EmulatorOptions& o) { return "LMS200 at " + std::to_string(o.baud) + " baud"; };
  // 2 ms: the line is paced in small steps (38400 baud is 4 bytes a ms).
  program.poll_ms = 2;
  return troupe::emulators::emulator_main(argc, argv, program);
}
