// troupe-emulate-sick: a SICK LMS200 on a pseudo-terminal, for trying
// the sicklms200 driver (or any LMS2xx client) without a scanner. Prints
// the port's path on stdout, then runs until interrupted.
#include <cstdlib>
#include <memory>

#include "host-sim/emulators/serial_line/emulator_main.h"
#include "host-sim/emulators/sicklms200/sick_emulator.h"

int main(int argc, char** argv) {
  namespace emu = troupe::emulators;
  emu::SickEmulator::Config scanner;
  emu::EmulatorProgram p;
  p.name = "troupe-emulate-sick";
  p.synopsis = "[--startup-ms N]";
  p.about =
      "Emulates a SICK LMS200 laser scanner on a new pseudo-terminal and prints\n"
      "its path. It stands in a 20 x 6 m corridor, powers up at 9600 baud and\n"
      "waits for a driver to configure it.";
  p.flags_help = "  --startup-ms N   from a reset request to the power-on message (default 2000)\n";
  p.examples =
      "  troupe-emulate-sick --link laser-port\n"
      "  troupe emulate-sick --link laser-port --tear 0.05 --seed 3   # torn telegrams\n";
  p.bauds = {9600, 19200, 38400, 500000};
  p.flags = {{"--startup-ms", [&](const char* v) {
                char* end = nullptr;
                unsigned long ms = strtoul(v, &end, 10);
                if (end == v || *end != '\0') return std::string("--startup-ms needs a number of ms");
                scanner.startup_us = uint64_t(ms) * 1000;
                return std::string();
              }}};
  p.make = [&](const emu::EmulatorOptions& o) {
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
