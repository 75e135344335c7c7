#include "host-sim/sim_control/kicker_state.h"

namespace troupe::sim {

void publish_kicker_state(Node& node, DeviceId device, bool ready) {
  auto& b = node.begin();
  const wire::ActuatorMode mode = ready ? wire::ActuatorMode::Ready : wire::ActuatorMode::Kicking;
  auto body = wire::CreateActuatorState(b, mode, 0.0f, 0, 0);
  node.publish(device, uint8_t(wire::ActuatorDataSub::State), wire::Body::ActuatorState, body.Union());
}

}  // namespace troupe::sim
