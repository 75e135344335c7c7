// How a kicker's state goes on the wire (actuator interface,
// wire/schemas/actuator.fbs): Ready at rest, Kicking while it fires or
// recovers. One encoding for a RoboCup robot's kicker (robocup/serve) and a
// Stage robot's (troupe_sim).
#pragma once

#include "runtime/node.h"

namespace troupe::sim {

/// Publishes the kicker's state on `device`.
void publish_kicker_state(Node& node, DeviceId device, bool ready);

}  // namespace troupe::sim
