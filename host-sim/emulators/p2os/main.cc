// troupe-emulate-p2os: a Pioneer robot on a pseudo-terminal, for trying the
// p2os driver (or any P2OS client) without a robot. Prints the port's path
// on stdout, then runs until interrupted.
#include <memory>

#include "host-sim/emulators/p2os/pioneer_emulator.h"
#include "host-sim/emulators/serial_line/emulator_main.h"

namespace {

const char kUsage[] =
    "usage: troupe-emulate-p2os [--link PATH] [--model NAME] [--baud N] [--name TEXT]\n"
    "                           [--flip P] [--drop P] [--tear P] [--seed N] [--no-baud-check]\n"
    "\n"
    "Emulates a Pioneer robot (P2OS firmware) on a new pseudo-terminal and\n"
    "prints its path. A p2os driver (or ARIA) opens that path (or PATH, a\n"
    "symbolic link made to it) as its serial port.\n"
    "\n"
    "  --link PATH      also make PATH a symbolic link to the port\n"
    "  --model NAME     robot subclass: p3dx-sh (default) or p3dx\n"
    "  --baud N         the robot's line speed, bit/s (default 9600)\n"
    "  --name TEXT      robot name reported in the handshake\n"
    "  --flip P         per byte sent: probability a bit flips\n"
    "  --drop P         per byte sent: probability it is lost\n"
    "  --tear P         per packet sent: probability it is cut short\n"
    "  --seed N         seed of the fault generator (default 1)\n"
    "  --no-baud-check  talk whatever speed the driver's end is set to\n"
    "\n"
    "examples:\n"
    "  troupe-emulate-p2os --link pioneer-port --baud 38400\n"
    "  troupe emulate-p2os --link pioneer-port --drop 0.01 --seed 7   # a noisy cable\n";

}  // namespace

int main(int argc, char** argv) {
  using troupe::emulators::EmulatorOptions;
  using troupe::emulators::PioneerEmulator;
  PioneerEmulator::Config config;
  troupe::emulators::EmulatorProgram program;
  program.name = "troupe-emulate-p2os";
  program.usage = kUsage;
  program.bauds = {9600, 19200, 38400, 57600, 115200};
  program.flags = {
      {"--model",
       [&](const char* v) {
         config.model = v;
         if (troupe::drivers::p2os::find_robot(config.model) == nullptr) {
           fprintf(stderr, "troupe-emulate-p2os: note: '%s' is no known model; reporting it with p3dx-sh units\n",
                   v);
         }
         return std::string();
       }},
      {"--name", [&](const char* v) {
         config.name = v;
         return std::string();
       }}};
  program.make = [&](const EmulatorOptions& o) {
    config.baud = o.baud;
    config.seed = o.seed;
    config.check_baud = o.check_baud;
    return std::make_unique<PioneerEmulator>(config);
  };
  program.describe = [&](const EmulatorOptions& o) {
    return config.model + " robot '" + config.name + "' at " + std::to_string(o.baud) + " baud";
  };
  program.poll_ms = 5;
  return troupe::emulators::emulator_main(argc, argv, program);
}
