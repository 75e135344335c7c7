#include "host-sim/sim_control/sim_control.h"

#include <cmath>

namespace troupe::sim {
namespace {

// One Step request runs at most this many steps: with start_steps the loop
// serves every client meanwhile, and the request's deadline (the node's
// request timeout) ends it anyway, but the number stays bounded either way.
constexpr uint32_t kMaxStepsAtOnce = 1000000;

}  // namespace

void ack_clock(Node& node, const SimControl& control, RequestToken token, SimTime now) {
  auto& b = node.begin();
  auto body = wire::CreateSimClock(b, uint64_t(std::llround(now.time_s * 1e6)), now.steps, control.paused,
                                   float(control.speed), float(control.real_time_factor));
  node.ack(token, wire::Body::SimClock, body.Union());
}

void answer_clock_request(Node& node, SimControl& control, const wire::Message& req, RequestToken token,
                          const std::function<SimTime()>& clock) {
  using Sub = wire::SimulationReqSub;
  switch (Sub(req.header()->subtype())) {
    case Sub::Pause:
      control.paused = true;
      break;
    case Sub::Resume:
      control.paused = false;
      break;
    case Sub::GetClock:
      break;
    case Sub::Step: {
      const wire::SimStep* s = req.body_as_SimStep();
      const uint32_t n = s ? s->steps() : 1;
      if (n > kMaxStepsAtOnce)
        return node.nack(token, wire::ErrorCode::BadArgument, "at most 1000000 steps at once");
      if (control.start_steps) return control.start_steps(n, token);
      if (control.step) control.step(n);
      break;
    }
    case Sub::SetSpeed: {
      const wire::SimSpeed* s = req.body_as_SimSpeed();
      if (s == nullptr || !(s->speed() >= 0) || !std::isfinite(s->speed())) {
        return node.nack(token, wire::ErrorCode::BadArgument, "speed must be >= 0 (0: as fast as possible)");
      }
      control.speed = s->speed();
      break;
    }
    default:
      return node.nack(token, wire::ErrorCode::Unsupported, "not a clock request");
  }
  ack_clock(node, control, token, clock());
}

}  // namespace troupe::sim
