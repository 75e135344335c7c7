#include "wire/client/proxy.h"

namespace troupe::client {

Proxy::Proxy(Client& client, const wire::Address& addr) : client_(&client), addr_(addr) {}

void Proxy::attach(wire::Access access, wire::Delivery delivery, wire::ImageCompression compression) {
  client_->add_proxy(this);
  open_ = client_->open(addr_, access, delivery, compression);
}

Proxy::~Proxy() {
  if (client_ != nullptr) client_->remove_proxy(this);
}

void Proxy::receive(const wire::Message& msg) {
  time_us_ = wire::time_us(*msg.header());
  seq_ = msg.header()->seq();
  ++samples_;
  fresh_ = true;
  update(msg);
}

Reply Proxy::request(uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body, int timeout_ms) {
  return client_->request(addr_, subtype, type, body, timeout_ms);
}

bool Proxy::command(uint8_t subtype, wire::Body type, flatbuffers::Offset<void> body) {
  return client_->command(addr_, subtype, type, body);
}

}  // namespace troupe::client
