#include "host-sim/sim_control/sim_requests.h"

#include <cmath>

namespace troupe::sim {
namespace {

using wire::ErrorCode;

constexpr const char* kNoGame = "this world has no game and no player plugins (RoboCup worlds have)";

bool finite(const wire::Pose2d& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.a());
}

void pose_request(Node& node, const wire::Message& req, bool set, RequestToken token, SimulationModels& models) {
  const wire::SimPose* body = req.body_as_SimPose();
  const flatbuffers::String* name = set ? (body ? body->name() : nullptr)
                                        : (req.body_as_SimModel() ? req.body_as_SimModel()->name() : nullptr);
  if (name == nullptr) return node.nack(token, ErrorCode::BadArgument, "needs a model name");
  const std::string model = name->str();
  std::string error;
  if (set) {
    const wire::Pose2d* p = body->pose();
    if (p == nullptr || !finite(*p)) return node.nack(token, ErrorCode::BadArgument, "needs a finite pose");
    const wire::Pose2d* v = body->velocity();
    if (v && !finite(*v)) return node.nack(token, ErrorCode::BadArgument, "needs a finite velocity");
    const geometry::Pose2 velocity = v ? geometry::Pose2{v->x(), v->y(), v->a()} : geometry::Pose2{};
    if (!models.set_pose(model, {p->x(), p->y(), p->a()}, v ? &velocity : nullptr, error)) {
      return node.nack(token, ErrorCode::BadArgument, error);
    }
    return node.ack(token);
  }
  geometry::Pose2 pose, velocity;
  bool has_velocity = false;
  if (!models.get_pose(model, pose, has_velocity, velocity, error)) {
    return node.nack(token, ErrorCode::BadArgument, error);
  }
  auto& b = node.begin();
  const wire::Pose2d p(float(pose.x), float(pose.y), float(pose.a));
  const wire::Pose2d v(float(velocity.x), float(velocity.y), float(velocity.a));
  auto reply = wire::CreateSimPose(b, b.CreateString(model), &p, has_velocity ? &v : nullptr);
  node.ack(token, wire::Body::SimPose, reply.Union());
}

void player_request(Node& node, const wire::Message& req, RequestToken token, SimulationModels& models) {
  std::string error;
  if (wire::SimulationReqSub(req.header()->subtype()) == wire::SimulationReqSub::StopPlayer) {
    const wire::SimModel* m = req.body_as_SimModel();
    if (m == nullptr || m->name() == nullptr) return node.nack(token, ErrorCode::BadArgument, "needs a robot name");
    if (!models.stop_player(m->name()->str(), error)) return node.nack(token, ErrorCode::BadArgument, error);
    return node.ack(token);
  }
  const wire::SimPlayer* p = req.body_as_SimPlayer();
  if (p == nullptr || p->robot() == nullptr || p->plugin() == nullptr) {
    return node.nack(token, ErrorCode::BadArgument, "needs a robot and a plugin name");
  }
  std::vector<std::pair<std::string, std::string>> options;
  if (p->options()) {
    for (const flatbuffers::String* kv : *p->options()) {
      const std::string text = kv ? kv->str() : std::string();
      const size_t eq = text.find('=');
      if (eq == std::string::npos || eq == 0) {
        return node.nack(token, ErrorCode::BadArgument, "option '" + text + "': expected key=value");
      }
      options.emplace_back(text.substr(0, eq), text.substr(eq + 1));
    }
  }
  if (!models.start_player(p->robot()->str(), p->plugin()->str(), options, error)) {
    return node.nack(token, ErrorCode::BadArgument, error);
  }
  node.ack(token);
}

}  // namespace

bool SimulationModels::start_player(const std::string&, const std::string&,
                                    const std::vector<std::pair<std::string, std::string>>&, std::string& error) {
  error = kNoGame;
  return false;
}

bool SimulationModels::stop_player(const std::string&, std::string& error) {
  error = kNoGame;
  return false;
}

bool SimulationModels::game(flatbuffers::FlatBufferBuilder&, flatbuffers::Offset<wire::SimGame>&) {
  return false;
}

void answer_simulation_request(Node& node, SimControl& control, const wire::Message& req, RequestToken token,
                               SimulationModels& models) {
  using Sub = wire::SimulationReqSub;
  switch (Sub(req.header()->subtype())) {
    case Sub::Pause:
    case Sub::Resume:
    case Sub::GetClock:
    case Sub::Step:
    case Sub::SetSpeed:
      return answer_clock_request(node, control, req, token, [&models] { return models.now(); });
    case Sub::GetPose:
    case Sub::SetPose:
      return pose_request(node, req, Sub(req.header()->subtype()) == Sub::SetPose, token, models);
    case Sub::Reset:
      if (control.reset) control.reset();
      return ack_clock(node, control, token, models.now());
    case Sub::StartPlayer:
    case Sub::StopPlayer:
      return player_request(node, req, token, models);
    case Sub::GetGame: {
      auto& b = node.begin();
      flatbuffers::Offset<wire::SimGame> game;
      if (!models.game(b, game)) return node.nack(token, ErrorCode::Unsupported, kNoGame);
      return node.ack(token, wire::Body::SimGame, game.Union());
    }
    case Sub::Models: {
      auto& b = node.begin();
      auto list = models.models(b);
      return node.ack(token, wire::Body::SimModelList, list.Union());
    }
  }
  node.nack(token, ErrorCode::Unsupported, "unknown simulation request");
}

}  // namespace troupe::sim
