#include "tests/device_harness/wire_client.h"

namespace troupe::testing {

namespace {

wire::ConnectionOptions test_connection_options() {
  wire::ConnectionOptions o;
  o.name = "test-client";
  o.reconnect = false;
  o.sync_clock = false;
  return o;
}

}  // namespace

bool WireClient::connect(uint16_t port, std::string& error) {
  wire::ConnectionOptions o = test_connection_options();
  o.target = "127.0.0.1:" + std::to_string(port);
  link_ = std::make_unique<wire::SocketLink>("127.0.0.1", port, o);
  // The kernel completes a loopback connect from the listen backlog, so the
  // transport opens before the node (in this same thread) has accepted;
  // frames sent now go out after our Hello.
  return link_->open_transport(2000, error);
}

void WireClient::send(std::span<const uint8_t> frame) {
  if (!link_->send(frame)) closed_ = true;
}

void WireClient::open(const wire::Address& addr) {
  auto& b = writer_.start();
  auto body = wire::CreateOpen(b, wire::Access::All, wire::Delivery::Push);
  send(writer_.finish(wire::make_header(addr, wire::Kind::Open, 0, next_seq(), 0), wire::Body::Open,
                      body.Union()));
}

void WireClient::send_vel(const wire::Address& addr, float v, float w) {
  auto& b = writer_.start();
  wire::Pose2d vel(v, 0, w);
  auto body = wire::CreatePosition2dVel(b, &vel);
  send(writer_.finish(
      wire::make_header(addr, wire::Kind::Command, uint8_t(wire::Position2dCmdSub::Vel), next_seq(), 0),
      wire::Body::Position2dVel, body.Union()));
}

uint32_t WireClient::request(const wire::Address& addr, uint8_t subtype, wire::Body type,
                             flatbuffers::Offset<void> body) {
  uint32_t seq = next_seq();
  send(writer_.finish(wire::make_header(addr, wire::Kind::Request, subtype, seq, 0), type, body));
  return seq;
}

uint32_t WireClient::request_switch(const wire::Address& addr, uint8_t subtype, bool on) {
  auto& b = begin();
  auto body = wire::CreateSwitch(b, on);
  return request(addr, subtype, wire::Body::Switch, body.Union());
}

void WireClient::poll() {
  if (!link_ || closed_) return;
  link_->wait(0);
  for (wire::Event e = link_->next_event(); e.kind != wire::EventKind::None; e = link_->next_event()) {
    if (e.kind == wire::EventKind::Down) closed_ = true;
    if (e.kind != wire::EventKind::Frame) continue;
    const wire::Header& h = *e.message->header();
    if (h.kind() == wire::Kind::Data) {
      Log& log = data_[wire::address_key(h.addr())];
      ++log.count;
      log.last.assign(e.frame.begin(), e.frame.end());
    } else if (h.kind() == wire::Kind::Ack || h.kind() == wire::Kind::Nack) {
      replies_[h.seq()].assign(e.frame.begin(), e.frame.end());
    }
  }
}

uint32_t WireClient::count(const wire::Address& addr) const {
  auto it = data_.find(wire::address_key(addr));
  return it == data_.end() ? 0 : it->second.count;
}

const wire::Message* WireClient::last(const wire::Address& addr) const {
  auto it = data_.find(wire::address_key(addr));
  return it == data_.end() ? nullptr : wire::trusted_message(it->second.last);
}

const wire::Message* WireClient::reply(uint32_t seq) const {
  auto it = replies_.find(seq);
  return it == replies_.end() ? nullptr : wire::trusted_message(it->second);
}

}  // namespace troupe::testing
