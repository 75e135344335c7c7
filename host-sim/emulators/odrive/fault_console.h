// Fault injection by typed commands, for trying a driver against the
// emulator by hand (troupe-emulate-odrive reads them from its standard input):
//
//   silent NODE on|off      the node stops sending and hearing (cable off)
//   error NODE BITS [keep]  sets axis error bits (hex or decimal), "keep": the
//                           cause stays until "clear"
//   clear NODE              the cause of a kept error is gone
//   reboot NODE             power cycle: IDLE, position count 0
//   drop P                  lose each frame with probability P in [0, 1]
//   garbage NODE N          sends N malformed frames from NODE's id
//   status                  one line per axis
#pragma once

#include <string>
#include <string_view>

#include "host-sim/emulators/odrive/odrive_emulator.h"

namespace troupe::emulators::odrive {

/// Applies one command line; returns what to print ("error: ..." for a bad
/// line, naming what was wrong).
std::string apply_fault_command(OdriveEmulator& emu, std::string_view line, uint64_t now_us);

/// One line describing an axis: state, error, velocity, position.
std::string axis_status(const Axis& axis);

}  // namespace troupe::emulators::odrive
