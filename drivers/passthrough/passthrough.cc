#include "drivers/passthrough/passthrough.h"

#include <cstdio>

#include "runtime/log.h"
#include "runtime/node.h"
#include "wire/body_copy.h"
#include "wire/noise/client_keys.h"
#include "wire/noise/key_file.h"
#include "wire/noise/noise_transport.h"

namespace troupe::drivers::passthrough {
namespace {

constexpr size_t kMaxInFlight = 64;              // forwarded requests awaiting the remote
constexpr uint64_t kStatusPeriodUs = 1'000'000;  // the status device repeats itself

uint64_t seconds_to_us(float s) {
  return s > 0 ? uint64_t(double(s) * 1e6) : 0;
}

// The keys `identity` and `node_key` name, files relative to the config's
// folder (a node key may be 64 hex digits instead).
wire::noise::ClientKeys client_keys(const OptionsView<Options>& opt, const DriverSetup& setup) {
  wire::noise::ClientKeys keys;
  if (opt->identity() != nullptr) keys.identity = config_relative(setup.config_path, opt->identity()->str());
  if (opt->node_key() != nullptr) {
    wire::noise::Key key;
    const std::string text = opt->node_key()->str();
    keys.node_key = wire::noise::parse_key_hex(text, key) ? text : config_relative(setup.config_path, text);
  }
  return keys;
}

}  // namespace

bool Passthrough::setup(Node& node, const DriverSetup& setup, std::string& error) {
  name_ = setup.name;
  OptionsView<Options> opt(setup);
  std::vector<DeviceId> forwarded(setup.provides.begin(), setup.provides.end());
  if (!forwarded.empty() && node.address(forwarded.back()).iface() == uint16_t(wire::Interface::Opaque)) {
    status_ = forwarded.back();
    forwarded.pop_back();
  }
  if (forwarded.empty()) {
    error = "passthrough provides no device to forward";
    return false;
  }
  const auto* remote = opt->remote();
  if (remote != nullptr && remote->size() != 0 && remote->size() != forwarded.size()) {
    error = "remote names " + std::to_string(remote->size()) + " devices but provides has " +
            std::to_string(forwarded.size()) + " to serve them";
    return false;
  }
  for (size_t i = 0; i < forwarded.size(); ++i) {
    Forwarded f;
    f.local = forwarded[i];
    if (remote != nullptr && remote->size() != 0) {
      std::string why;
      if (!wire::parse_device(remote->Get(uint32_t(i))->string_view(), f.spec, why)) {
        error = "remote[" + std::to_string(i) + "]: " + why;
        return false;
      }
    } else {
      const wire::Address& a = node.address(f.local);
      f.spec.robot = std::to_string(a.robot());
      f.spec.iface = wire::Interface(a.iface());
      f.spec.index = a.index();
    }
    if (uint16_t(f.spec.iface) != node.address(f.local).iface()) {
      error = "remote[" + std::to_string(i) + "] is a " +
              std::string(wire::interface_name(uint16_t(f.spec.iface))) + " but provides[" +
              std::to_string(i) + "] a " + std::string(wire::interface_name(node.address(f.local).iface()));
      return false;
    }
    devices_.push_back(std::move(f));
  }
  if (!(opt->backoff_min() > 0) || opt->backoff_max() < opt->backoff_min() || !(opt->connect_timeout() > 0) ||
      !(opt->idle_timeout() > 0)) {
    error = "backoff_min, connect_timeout and idle_timeout must be > 0 s and backoff_max >= backoff_min";
    return false;
  }
  if (opt->host() == nullptr || opt->host()->size() == 0) {
    error = "host is required: the remote node's address";
    return false;
  }
  LinkOptions lo;
  lo.host = opt->host()->str();
  lo.port = opt->port();
  lo.client_name = "passthrough " + node.options().name;
  lo.backoff_min_us = seconds_to_us(opt->backoff_min());
  lo.backoff_max_us = seconds_to_us(opt->backoff_max());
  lo.connect_timeout_us = seconds_to_us(opt->connect_timeout());
  lo.idle_timeout_us = seconds_to_us(opt->idle_timeout());
  lo.limits = node.options().limits;
  const wire::noise::ClientKeys keys = client_keys(opt, setup);
  if (keys.identity.empty() && !keys.node_key.empty()) {
    error = "node_key without identity: a secure session needs this node's secret key file as well";
    return false;
  }
  lo.transport = wire::noise::client_transport(keys, lo.host, lo.port, error);
  if (!error.empty()) return false;
  in_flight_.resize(kMaxInFlight);
  node_ = &node;
  since_us_ = node.loop().now_us();
  link_ = std::make_unique<RemoteLink>(node.loop(), *this);
  if (!link_->start(lo, error)) return false;
  if (status_ != kNoDevice) {
    status_timer_ = node.loop().start_timer(0, kStatusPeriodUs, this);
    if (status_timer_ == 0) {
      error = "no timer left";
      return false;
    }
  }
  log_info("%s: serving %zu devices of %s%s", name_.c_str(), devices_.size(), link_->remote_text().c_str(),
           lo.transport ? " through a secure session" : "");
  return true;
}

void Passthrough::shutdown() {
  if (link_) link_->stop();
}

Passthrough::Forwarded* Passthrough::by_local(DeviceId device) {
  for (Forwarded& f : devices_) {
    if (f.local == device) return &f;
  }
  return nullptr;
}

Passthrough::Forwarded* Passthrough::by_remote(const wire::Address& addr) {
  for (Forwarded& f : devices_) {
    if (f.remote == addr) return &f;
  }
  return nullptr;
}

void Passthrough::on_link_up() {
  opened_ = false;
  list_seq_ = link_->next_seq();
  link_->send(writer_.empty(wire::make_header({}, wire::Kind::DeviceList, 0, list_seq_, node_->now_us())));
  publish_status();
}

void Passthrough::on_link_down(const std::string& why) {
  bool was_open = opened_;
  opened_ = false;
  for (Forwarded& f : devices_) f.command_pending = false;  // stale by the time the remote is back
  fail_requests("connection to " + link_->remote_text() + " lost: " + why);
  if (was_open) {
    since_us_ = node_->loop().now_us();
    log_warn("%s: %s; reconnecting", name_.c_str(), why.c_str());
  } else if (why != logged_error_) {
    log_info("%s: %s; retrying", name_.c_str(), why.c_str());
  }
  logged_error_ = why;
  publish_status();
}

bool Passthrough::resolve_devices(const wire::Message& msg) {
  const wire::DeviceList* list = msg.body_as_DeviceList();
  for (Forwarded& f : devices_) {
    int robot = wire::robot_number(f.spec.robot);
    bool found = false;
    if (list != nullptr && list->devices() != nullptr) {
      for (const wire::DeviceInfo* d : *list->devices()) {
        if (d->addr() == nullptr || d->addr()->iface() != uint16_t(f.spec.iface) ||
            d->addr()->index() != f.spec.index)
          continue;
        bool robot_matches =
            robot >= 0 ? d->addr()->robot() == robot
                       : d->robot_name() != nullptr && d->robot_name()->string_view() == f.spec.robot;
        if (robot_matches) {
          f.remote = *d->addr();
          found = true;
          break;
        }
      }
    }
    if (!found) {
      wire::Address local = node_->address(f.local);
      std::string spec = (f.spec.robot.empty() ? "" : f.spec.robot + "/") +
                         std::string(wire::interface_name(uint16_t(f.spec.iface))) + ":" +
                         std::to_string(f.spec.index);
      link_->close("remote " + link_->remote_text() + " has no device " + spec + " (for local " +
                   wire::format_address(local) + ")");
      return false;
    }
  }
  return true;
}

void Passthrough::on_remote_frame(const wire::Message& msg) {
  const wire::Header& h = *msg.header();
  switch (h.kind()) {
    case wire::Kind::DeviceList: {
      if (h.seq() != list_seq_ || opened_ || !resolve_devices(msg)) return;
      for (const Forwarded& f : devices_) {
        auto& b = writer_.start();
        auto open = wire::CreateOpen(b, wire::Access::All, wire::Delivery::Push);
        link_->send(writer_.finish(
            wire::make_header(f.remote, wire::Kind::Open, 0, link_->next_seq(), node_->now_us()),
            wire::Body::Open, open.Union()));
      }
      opened_ = true;
      since_us_ = node_->loop().now_us();
      log_info("%s: connected to %s (connection %u)", name_.c_str(), link_->remote_text().c_str(),
               link_->connections());
      logged_error_.clear();
      publish_status();
      return;
    }
    case wire::Kind::Data: {
      Forwarded* f = by_remote(h.addr());
      if (f == nullptr || !opened_) return;
      auto& b = node_->begin();
      flatbuffers::Offset<void> body = wire::body_copier().copy(b, msg);
      wire::Body type = body.IsNull() ? wire::Body::NONE : msg.body_type();
      node_->publish(f->local, h.subtype(), type, body, wire::time_us(h));
      return;
    }
    case wire::Kind::Ack:
    case wire::Kind::Nack:
      return forward_reply(msg);
    default:
      return;
  }
}

void Passthrough::forward_reply(const wire::Message& reply) {
  const wire::Header& h = *reply.header();
  for (InFlight& r : in_flight_) {
    if (!r.active || r.remote_seq != h.seq()) continue;
    r.active = false;
    if (h.kind() == wire::Kind::Ack) {
      auto& b = node_->begin();
      flatbuffers::Offset<void> body = wire::body_copier().copy(b, reply);
      node_->ack(r.token, body.IsNull() ? wire::Body::NONE : reply.body_type(), body);
    } else {
      const wire::Error* e = reply.body_as_Error();
      node_->nack(r.token, e ? e->code() : wire::ErrorCode::Unknown,
                  e && e->text() ? e->text()->string_view() : std::string_view("refused by the remote"));
    }
    return;
  }
  // Not a forwarded request: the reply to one of our Opens. A refused Open
  // leaves that device without data; say so.
  if (h.kind() == wire::Kind::Nack) {
    const wire::Error* e = reply.body_as_Error();
    log_warn("%s: %s refused %s: %s", name_.c_str(), link_->remote_text().c_str(),
             wire::format_address(h.addr()).c_str(), e && e->text() ? e->text()->c_str() : "no reason given");
  }
}

void Passthrough::on_command(DeviceId device, const wire::Message& command) {
  Forwarded* f = by_local(device);
  if (f == nullptr) return;
  if (!opened_) {
    log_debug("%s: command for %s dropped: %s is not connected", name_.c_str(),
              wire::format_address(node_->address(device)).c_str(), link_->remote_text().c_str());
    return;
  }
  auto& b = writer_.start();
  flatbuffers::Offset<void> body = wire::body_copier().copy(b, command);
  const wire::Header& h = *command.header();
  std::span<const uint8_t> frame = writer_.finish(
      wire::make_header(f->remote, wire::Kind::Command, h.subtype(), link_->next_seq(), wire::time_us(h)),
      body.IsNull() ? wire::Body::NONE : command.body_type(), body);
  f->command.assign(frame.begin(), frame.end());
  f->command_pending = true;
  send_commands();
}

void Passthrough::send_commands() {
  // Only into an empty queue: while the remote lags, a newer command replaces
  // the one waiting here instead of queueing behind it.
  for (Forwarded& f : devices_) {
    if (!f.command_pending || !link_->idle() || !opened_) continue;
    f.command_pending = false;
    link_->send(f.command);
  }
}

void Passthrough::on_link_writable() {
  send_commands();
}

void Passthrough::on_request(DeviceId device, const wire::Message& request, RequestToken token) {
  if (device == status_) {
    std::string text = status_text();
    auto& b = node_->begin();
    auto body = wire::CreateOpaqueBytes(
        b, b.CreateVector(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    return node_->ack(token, wire::Body::OpaqueBytes, body.Union());
  }
  Forwarded* f = by_local(device);
  if (f == nullptr) return node_->nack(token, wire::ErrorCode::NoSuchDevice, "not a forwarded device");
  if (!opened_) {
    std::string why = "remote " + link_->remote_text() + " not connected" +
                      (link_->last_error().empty() ? std::string() : ": " + link_->last_error());
    return node_->nack(token, wire::ErrorCode::DeviceFailed, why);
  }
  InFlight* slot = nullptr;
  for (InFlight& r : in_flight_) {
    // A request the node already answered (Timeout) frees its slot: the
    // remote's late reply then finds nothing and is dropped.
    if (!r.active || node_->request_device(r.token) == kNoDevice) {
      slot = &r;
      break;
    }
  }
  if (slot == nullptr) {
    return node_->nack(token, wire::ErrorCode::DeviceFailed, "too many requests waiting for the remote");
  }
  auto& b = writer_.start();
  flatbuffers::Offset<void> body = wire::body_copier().copy(b, request);
  const wire::Header& h = *request.header();
  uint32_t seq = link_->next_seq();
  std::span<const uint8_t> frame =
      writer_.finish(wire::make_header(f->remote, wire::Kind::Request, h.subtype(), seq, wire::time_us(h)),
                     body.IsNull() ? wire::Body::NONE : request.body_type(), body);
  *slot = InFlight{true, seq, token};
  if (!link_->send(frame)) {
    // send() failing closed the link, which already answered the slot.
    if (slot->active) {
      slot->active = false;
      node_->nack(token, wire::ErrorCode::DeviceFailed, "connection to the remote lost");
    }
  }
}

void Passthrough::fail_requests(const std::string& why) {
  for (InFlight& r : in_flight_) {
    if (!r.active) continue;
    r.active = false;
    node_->nack(r.token, wire::ErrorCode::DeviceFailed, why);
  }
}

std::string Passthrough::status_text() const {
  // Hand-written JSON: a fixed, flat object the CLI prints as text.
  std::string err;
  for (char c : link_->last_error()) {
    if (c == '"' || c == '\\') err += '\\';
    err += c;
  }
  const char* state = opened_ ? "connected" : "reconnecting";
  double since_s = double(node_->loop().now_us() - since_us_) * 1e-6;
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "{\"remote\":\"%s\",\"state\":\"%s\",\"link\":\"%s\",\"for_s\":%.1f,\"connections\":%u,",
                link_->remote_text().c_str(), state, wire::link_state_name(link_->state()), since_s,
                link_->connections());
  return std::string(buf) + "\"last_error\":\"" + err + "\"}";
}

void Passthrough::publish_status() {
  if (status_ == kNoDevice) return;
  std::string text = status_text();
  auto& b = node_->begin();
  auto body =
      wire::CreateOpaqueBytes(b, b.CreateVector(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
  node_->publish(status_, uint8_t(wire::OpaqueSub::Bytes), wire::Body::OpaqueBytes, body.Union());
}

void Passthrough::on_timer(TimerId id) {
  if (id == status_timer_) publish_status();
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"passthrough", []() -> Driver* { return new Passthrough; }};

}  // namespace troupe::drivers::passthrough
