#include "runtime/node.h"

#include <algorithm>
#include <cstdio>

#include "runtime/clock.h"
#include "runtime/log.h"
#include "runtime/server.h"
#include "wire/address.h"
#include "wire/check.h"

namespace troupe {

using wire::Body;
using wire::ErrorCode;
using wire::Kind;

void Driver::on_request(DeviceId /*device*/, const wire::Message& request, RequestToken token) {
  char why[64];
  snprintf(why, sizeof why, "request subtype %u is not supported", unsigned(request.header()->subtype()));
  node_->nack(token, ErrorCode::Unsupported, why);
}

Node::Node(Options options)
    : options_(std::move(options)),
      loop_(options_.max_timers),
      server_(std::make_unique<Server>(*this)),
      pending_(options_.max_pending_requests) {}

Node::~Node() { shutdown(); }

uint64_t Node::now_us() const { return clock_ ? clock_(clock_ctx_) : monotonic_us(); }

void Node::set_clock(uint64_t (*clock_us)(void*), void* ctx) {
  clock_ = clock_us;
  clock_ctx_ = ctx;
}

DeviceId Node::add_device(const wire::Address& addr, Driver* driver, std::string_view driver_name,
                          std::string_view robot_name) {
  uint64_t key = wire::address_key(addr);
  if (by_address_.count(key) != 0) return kNoDevice;
  DeviceId id = DeviceId(devices_.size());
  Device& dev = devices_.emplace_back();
  dev.addr = addr;
  dev.driver = driver;
  dev.driver_name = driver_name;
  dev.robot_name = robot_name;
  by_address_.emplace(key, id);
  return id;
}

bool Node::add_driver(std::unique_ptr<Driver> driver, const DriverSetup& setup, std::string& error,
                      SetupFailure* failure) {
  driver->node_ = this;
  if (!driver->setup(*this, setup, error)) {
    if (failure != nullptr) *failure = driver->setup_failure_;
    return false;
  }
  drivers_.push_back(std::move(driver));
  return true;
}

bool Node::start(std::string& error) {
  if (!loop_.ok()) {
    error = "cannot create the event loop";
    return false;
  }
  pending_commands_.reserve(devices_.size());
  return server_->start(error);
}

uint16_t Node::port() const { return server_->port(); }
std::string Node::listen_text() const { return server_->listen_text(); }

void Node::poll(int64_t max_wait_us) {
  loop_.run_once(max_wait_us);
  deliver_commands();
}

void Node::run() {
  while (!loop_.stopped()) poll(-1);
}

void Node::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  for (auto it = drivers_.rbegin(); it != drivers_.rend(); ++it) (*it)->shutdown();
  server_->close_all();
}

DeviceId Node::find_device(const wire::Address& addr) const {
  auto it = by_address_.find(wire::address_key(addr));
  return it == by_address_.end() ? kNoDevice : it->second;
}

const wire::Address& Node::address(DeviceId device) const { return devices_[device].addr; }

bool Node::has_readers(DeviceId device) const {
  const Device& dev = devices_[device];
  return !dev.readers.empty() || !dev.subscribers.empty();
}

bool Node::has_readers(DeviceId device, wire::ImageCompression compression) const {
  const Device& dev = devices_[device];
  if (compression == wire::ImageCompression::None && !dev.subscribers.empty()) return true;
  return std::any_of(dev.readers.begin(), dev.readers.end(),
                     [compression](const Reader& r) { return r.compression == uint8_t(compression); });
}

void Node::forget_data(DeviceId device) {
  for (DataSlot& slot : devices_[device].slots) slot.frame.clear();  // keeps the capacity
}

void Node::subscribe(DeviceId source, Driver* driver) {
  std::vector<Driver*>& subs = devices_[source].subscribers;
  if (std::find(subs.begin(), subs.end(), driver) == subs.end()) subs.push_back(driver);
}

Node::Reader* Node::find_reader(Device& dev, uint32_t client) {
  for (Reader& r : dev.readers) {
    if (r.client == client) return &r;
  }
  return nullptr;
}

int Node::slot_for(Device& dev, uint8_t subtype, uint8_t compression) {
  for (int i = 0; i < kDataSlots; ++i) {
    const DataSlot& s = dev.slots[i];
    if (s.subtype == subtype && s.compression == compression && !s.frame.empty()) return i;
  }
  int slot = kDataSlots - 1;  // more data subtypes than slots: the last slot is shared by the extras
  for (int i = 0; i < kDataSlots; ++i) {
    if (dev.slots[i].frame.empty()) {
      slot = i;
      break;
    }
  }
  dev.slots[slot].subtype = subtype;
  dev.slots[slot].compression = compression;
  return slot;
}

void Node::publish_at(DeviceId device, uint8_t subtype, Body type, flatbuffers::Offset<void> body,
                      uint64_t time_us) {
  publish_to(device, kEveryReader, subtype, type, body, time_us);
}

void Node::publish_packed(DeviceId device, wire::ImageCompression compression, uint8_t subtype, Body type,
                          flatbuffers::Offset<void> body) {
  publish_to(device, uint8_t(compression), subtype, type, body, now_us());
}

void Node::publish_to(DeviceId device, uint8_t compression, uint8_t subtype, Body type,
                      flatbuffers::Offset<void> body, uint64_t time_us) {
  Device& dev = devices_[device];
  auto frame = writer_.finish(wire::make_header(dev.addr, Kind::Data, subtype, ++dev.seq, time_us), type, body);
  int slot = slot_for(dev, subtype, compression);
  // assign() reuses the slot's capacity: no allocation once it has held a
  // sample of this size.
  dev.slots[slot].frame.assign(frame.begin(), frame.end());
  const std::vector<uint8_t>& stored = dev.slots[slot].frame;
  for (const Reader& r : dev.readers) {
    if (r.delivery == uint8_t(wire::Delivery::Push) && r.wants(dev.slots[slot])) {
      server_->push_data(r.client, device, slot, stored);
    }
  }
  if (!dev.subscribers.empty() && compression != uint8_t(wire::ImageCompression::Png)) {
    const wire::Message* msg = wire::trusted_message(stored);
    for (Driver* d : dev.subscribers) d->on_data(device, *msg);
  }
}

void Node::send_hello(uint32_t client) {
  auto& b = reply_writer_.start();
  auto body = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString(options_.name),
                                options_.limits.max_frame_bytes, 0, now_us());
  server_->send_reliable(client, reply_writer_.finish(wire::make_header({}, Kind::Hello, 0, 0, now_us()),
                                                      Body::Hello, body.Union()));
}

void Node::reply_status(uint32_t client, const wire::Header& to, Kind kind, ErrorCode code,
                        std::string_view text) {
  auto& b = reply_writer_.start();
  flatbuffers::Offset<void> body = 0;
  Body type = Body::NONE;
  if (kind != Kind::Ack) {
    body = wire::CreateError(b, code, b.CreateString(text.data(), text.size())).Union();
    type = Body::Error;
  }
  server_->send_reliable(
      client, reply_writer_.finish(wire::make_header(to.addr(), kind, to.subtype(), to.seq(), now_us()), type, body));
}

void Node::route(uint32_t client, const wire::Message& msg, std::span<const uint8_t> frame) {
  const wire::Header& h = *msg.header();
  const Kind kind = h.kind();
  const Body body = msg.body_type();

  if (kind == Kind::Invalid || uint8_t(kind) > uint8_t(Kind::MAX)) {
    char text[48];
    snprintf(text, sizeof text, "unknown message kind %u", unsigned(kind));
    return reply_status(client, h, Kind::Nack, ErrorCode::Unsupported, text);
  }
  if (!wire::is_known_body(body)) {
    // A newer peer's body: refuse politely, keep the connection.
    char text[48];
    snprintf(text, sizeof text, "unknown body type %u", unsigned(body));
    return reply_status(client, h, Kind::Nack, ErrorCode::Unsupported, text);
  }
  if (!wire::body_fits(kind, h.addr().iface(), body)) {
    char text[128];
    snprintf(text, sizeof text, "a %s message for %s cannot carry body %s",
             std::string(wire::kind_name(kind)).c_str(),
             std::string(wire::interface_name(h.addr().iface())).c_str(), wire::EnumNameBody(body));
    log_warn("client %u: %s", client, text);
    return server_->close_with_error(client, ErrorCode::BadBody, text, &h);
  }
  if (kind == Kind::Data || kind == Kind::Ack || kind == Kind::Nack || kind == Kind::Error) {
    char text[64];
    snprintf(text, sizeof text, "clients do not send %s messages", std::string(wire::kind_name(kind)).c_str());
    return server_->close_with_error(client, ErrorCode::BadBody, text, &h);
  }
  // Everything a handler below reads is there and within its range: this is
  // the one place that checks it (wire/check.h).
  wire::Refusal why;
  if (!wire::check_message(msg, why)) {
    log_warn("client %u: %s %s refused: %s", client, std::string(wire::kind_name(kind)).c_str(),
             wire::format_address(h.addr()).c_str(), why.text);
    // A session message that cannot be read breaks the session; a device's
    // message gets its answer, and the connection goes on.
    if (kind == Kind::Hello || kind == Kind::TimeSync || kind == Kind::DeviceList) {
      return server_->close_with_error(client, why.code, why.text, &h);
    }
    return reply_status(client, h, Kind::Nack, why.code, why.text);
  }

  // Anything answered is answered after the commands sent before it reached
  // their drivers: a reply then tells the client its commands are in effect.
  // Commands back to back are still collapsed to the newest.
  if (kind != Kind::Command && !pending_commands_.empty()) deliver_commands();

  switch (kind) {
    case Kind::Hello: return server_->handle_hello(client, msg);
    case Kind::DeviceList: return send_device_list(client, msg);
    case Kind::TimeSync: return send_time_sync(client, msg);
    default: break;
  }

  DeviceId dev = find_device(h.addr());
  if (dev == kNoDevice) {
    std::string text = "no such device " + wire::format_address(h.addr());
    return reply_status(client, h, Kind::Nack, ErrorCode::NoSuchDevice, text);
  }
  switch (kind) {
    case Kind::Open: return handle_open(client, dev, msg);
    case Kind::Close: return handle_close(client, dev, msg);
    case Kind::Pull:
      if (!permitted(client, dev, msg, Right::Read)) return;
      return handle_pull(client, dev, msg);
    case Kind::Command:
      if (!permitted(client, dev, msg, Right::Command)) return;
      return handle_command(client, dev, msg, frame);
    case Kind::Request:
      if (!permitted(client, dev, msg, Right::Request)) return;
      return handle_request(client, dev, msg);
    default: return;
  }
}

bool Node::permitted(uint32_t client, DeviceId id, const wire::Message& msg, Right right, Right or_else) {
  if (!kSessionsMayBeSecure) return true;  // no rights without secure sessions
  const Rights* rights = server_->clients_[client].rights.get();
  const Device& dev = devices_[id];
  std::string refusal;
  if (rights == nullptr || rights->permits(right, dev.addr, dev.robot_name, refusal)) return true;
  if (or_else != right && rights->allows(or_else, dev.addr, dev.robot_name)) return true;
  reply_status(client, *msg.header(), Kind::Nack, ErrorCode::Forbidden, refusal);
  return false;
}

void Node::handle_open(uint32_t client, DeviceId id, const wire::Message& msg) {
  Device& dev = devices_[id];
  const wire::Open* open = msg.body_as_Open();
  auto access = open ? open->access() : wire::Access::All;
  auto delivery = open ? open->delivery() : wire::Delivery::Push;
  const uint8_t compression = open ? uint8_t(open->compression()) : 0;
  // Opening to read needs the right to read; opening only to write needs
  // the right to command or to request (each is checked again as it comes).
  const bool reads = uint8_t(access) & uint8_t(wire::Access::Read);
  if (reads ? !permitted(client, id, msg, Right::Read) : !permitted(client, id, msg, Right::Command, Right::Request)) {
    return;
  }
  Reader* r = find_reader(dev, client);
  const bool new_packing = reads && dev.driver != nullptr &&
                           std::none_of(dev.readers.begin(), dev.readers.end(), [&](const Reader& o) {
                             return o.client != client && o.compression == compression;
                           });
  if (r == nullptr) {
    // Before the reader is added: what the driver publishes now is stored
    // and reaches the reader below, once, after the Ack.
    if (!has_readers(id) && reads && dev.driver != nullptr) {
      dev.driver->on_read_start(id);
    }
    if (new_packing) dev.driver->on_packing_start(id, wire::ImageCompression(compression));
    dev.readers.push_back(Reader{client, uint8_t(delivery), 0, uint8_t(access), compression});
    r = &dev.readers.back();
    auto& c = server_->clients_[client];
    c.opened.push_back(id);
    c.dirty.reserve(c.opened.size());  // each opened device is dirty at most once
  } else {
    if (new_packing && r->compression != compression) {
      dev.driver->on_packing_start(id, wire::ImageCompression(compression));
    }
    r->delivery = uint8_t(delivery);
    r->access = uint8_t(access);
    r->compression = compression;
  }
  reply_status(client, *msg.header(), Kind::Ack);
  // A new reader gets the current state at once rather than at the next
  // sample, which may be long in coming for slow devices.
  if (reads && delivery == wire::Delivery::Push) {
    for (int slot = 0; slot < kDataSlots; ++slot) {
      if (!dev.slots[slot].frame.empty() && r->wants(dev.slots[slot])) {
        server_->push_data(client, id, slot, dev.slots[slot].frame);
      }
    }
  }
}

void Node::handle_close(uint32_t client, DeviceId id, const wire::Message& msg) {
  Device& dev = devices_[id];
  std::erase_if(dev.readers, [client](const Reader& r) { return r.client == client; });
  std::erase(server_->clients_[client].opened, id);
  reply_status(client, *msg.header(), Kind::Ack);
}

void Node::handle_pull(uint32_t client, DeviceId id, const wire::Message& msg) {
  Device& dev = devices_[id];
  // A client that pulls without having opened the device gets raw data.
  const Reader* r = find_reader(dev, client);
  const Reader raw{client, 0};
  for (int slot = 0; slot < kDataSlots; ++slot) {
    if (dev.slots[slot].frame.empty() || !(r ? r : &raw)->wants(dev.slots[slot])) continue;
    if (!server_->send_reliable(client, dev.slots[slot].frame)) return;
  }
  // The Ack marks the end of the batch for the client.
  reply_status(client, *msg.header(), Kind::Ack);
}

void Node::handle_command(uint32_t client, DeviceId id, const wire::Message& msg,
                          std::span<const uint8_t> frame) {
  Device& dev = devices_[id];
  if (const Reader* r = find_reader(dev, client); r && !(r->access & uint8_t(wire::Access::Write))) {
    return reply_status(client, *msg.header(), Kind::Nack, ErrorCode::Denied,
                        "device opened read-only by this client");
  }
  // Newest wins: overwrite whatever command is still waiting.
  dev.command.assign(frame.begin(), frame.end());
  if (!dev.command_pending) {
    dev.command_pending = true;
    pending_commands_.push_back(id);
  }
}

void Node::deliver_commands() {
  // Index loop: a driver's on_command may not add commands, but stay safe.
  for (size_t i = 0; i < pending_commands_.size(); ++i) {
    Device& dev = devices_[pending_commands_[i]];
    dev.command_pending = false;
    if (dev.driver) dev.driver->on_command(pending_commands_[i], *wire::trusted_message(dev.command));
  }
  pending_commands_.clear();
}

void Node::handle_request(uint32_t client, DeviceId id, const wire::Message& msg) {
  const wire::Header& h = *msg.header();
  Device& dev = devices_[id];
  if (const Reader* r = find_reader(dev, client); r && !(r->access & uint8_t(wire::Access::Write))) {
    return reply_status(client, h, Kind::Nack, ErrorCode::Denied, "device opened read-only by this client");
  }
  uint32_t slot = 0;
  if (dev.driver == nullptr || !claim_request_slot(slot)) {
    return reply_status(client, h, Kind::Nack, ErrorCode::DeviceFailed,
                        dev.driver ? "too many requests pending" : "device has no driver");
  }
  Pending& p = pending_[slot];
  p.active = true;
  p.requester = nullptr;
  p.client = client;
  p.client_generation = server_->generation(client);
  p.device = id;
  p.subtype = h.subtype();
  p.seq = h.seq();
  p.deadline_us = now_us() + uint64_t(options_.request_timeout_ms) * 1000u;
  arm_request_timer();
  dev.driver->on_request(id, msg, RequestToken{slot, p.generation});
}

bool Node::claim_request_slot(uint32_t& slot) {
  slot = 0;
  while (slot < pending_.size() && pending_[slot].active) ++slot;
  return slot < pending_.size();
}

bool Node::request(DeviceId id, uint8_t subtype, uint32_t seq, Body type, flatbuffers::Offset<void> body,
                   Driver* from) {
  Device& dev = devices_[id];
  uint32_t slot = 0;
  if (dev.driver == nullptr || from == nullptr || !claim_request_slot(slot)) return false;
  // A copy: the target builds its reply in writer_, where this request is.
  auto built = writer_.finish(wire::make_header(dev.addr, Kind::Request, subtype, seq, now_us()), type, body);
  std::vector<uint8_t> frame(built.begin(), built.end());
  Pending& p = pending_[slot];
  p.active = true;
  p.requester = from;
  p.client = 0;
  p.client_generation = 0;
  p.device = id;
  p.subtype = subtype;
  p.seq = seq;
  p.deadline_us = now_us() + uint64_t(options_.request_timeout_ms) * 1000u;
  uint32_t generation = p.generation;
  arm_request_timer();
  dev.driver->on_request(id, *wire::trusted_message(frame), RequestToken{slot, generation});
  return true;
}

void Node::reply_to_driver(Pending& p, std::span<const uint8_t> frame) {
  // A copy, so the requester may build its next request while reading this.
  std::vector<uint8_t> copy(frame.begin(), frame.end());
  Driver* to = p.requester;
  p.requester = nullptr;
  to->on_reply(p.device, *wire::trusted_message(copy));
}

DeviceId Node::request_device(RequestToken token) const {
  if (token.slot >= pending_.size()) return kNoDevice;
  const Pending& p = pending_[token.slot];
  return p.active && p.generation == token.generation ? p.device : kNoDevice;
}

void Node::ack(RequestToken token, Body type, flatbuffers::Offset<void> body) {
  if (request_device(token) == kNoDevice) return;  // already answered (timeout)
  Pending& p = pending_[token.slot];
  p.active = false;
  ++p.generation;
  if (p.requester == nullptr && !server_->alive(p.client, p.client_generation)) return;
  auto frame =
      writer_.finish(wire::make_header(devices_[p.device].addr, Kind::Ack, p.subtype, p.seq, now_us()), type, body);
  if (p.requester != nullptr) return reply_to_driver(p, frame);
  server_->send_reliable(p.client, frame);
}

void Node::nack(RequestToken token, ErrorCode code, std::string_view why) {
  if (request_device(token) == kNoDevice) return;
  Pending& p = pending_[token.slot];
  p.active = false;
  ++p.generation;
  if (p.requester != nullptr) {
    auto& b = reply_writer_.start();
    auto body = wire::CreateError(b, code, b.CreateString(why.data(), why.size()));
    auto frame = reply_writer_.finish(
        wire::make_header(devices_[p.device].addr, Kind::Nack, p.subtype, p.seq, now_us()), Body::Error,
        body.Union());
    return reply_to_driver(p, frame);
  }
  if (!server_->alive(p.client, p.client_generation)) return;
  wire::Header to = wire::make_header(devices_[p.device].addr, Kind::Nack, p.subtype, p.seq, 0);
  reply_status(p.client, to, Kind::Nack, code, why);
}

void Node::arm_request_timer() {
  uint64_t earliest = UINT64_MAX;
  for (const Pending& p : pending_) {
    if (p.active) earliest = std::min(earliest, p.deadline_us);
  }
  if (earliest == UINT64_MAX || (request_timer_ != 0 && request_timer_deadline_ <= earliest)) return;
  if (request_timer_ != 0) loop_.cancel_timer(request_timer_);
  uint64_t now = now_us();
  request_timer_ = loop_.start_timer(earliest > now ? earliest - now : 0, 0, this);
  request_timer_deadline_ = earliest;
}

void Node::on_timer(TimerId id) {
  if (id != request_timer_) return;
  request_timer_ = 0;
  uint64_t now = now_us();
  for (uint32_t slot = 0; slot < pending_.size(); ++slot) {
    Pending& p = pending_[slot];
    if (p.active && p.deadline_us <= now) {
      char text[64];
      snprintf(text, sizeof text, "no reply from the driver within %u ms", options_.request_timeout_ms);
      log_warn("%s: %s", wire::format_address(devices_[p.device].addr).c_str(), text);
      nack(RequestToken{slot, p.generation}, ErrorCode::Timeout, text);
    }
  }
  arm_request_timer();
}

void Node::send_device_list(uint32_t client, const wire::Message& msg) {
  auto& b = reply_writer_.start();
  std::vector<flatbuffers::Offset<wire::DeviceInfo>> infos;
  infos.reserve(devices_.size());
  for (const Device& dev : devices_) {
    // Strings first, in a fixed order: as two arguments of one call their
    // order would be up to the compiler, and so would the frame's bytes.
    auto robot = b.CreateString(dev.robot_name);
    auto driver = b.CreateString(dev.driver_name);
    infos.push_back(wire::CreateDeviceInfo(b, &dev.addr, robot, driver));
  }
  auto body = wire::CreateDeviceList(b, b.CreateVector(infos));
  const wire::Header& h = *msg.header();
  server_->send_reliable(
      client, reply_writer_.finish(wire::make_header(h.addr(), Kind::DeviceList, h.subtype(), h.seq(), now_us()),
                                   Body::DeviceList, body.Union()));
}

void Node::send_time_sync(uint32_t client, const wire::Message& msg) {
  uint64_t received = now_us();
  auto& b = reply_writer_.start();
  const wire::TimeSync* ask = msg.body_as_TimeSync();  // present: checked by route()
  auto body = wire::CreateTimeSync(b, ask->client_send_us(), received, now_us());
  const wire::Header& h = *msg.header();
  server_->send_reliable(client, reply_writer_.finish(wire::make_header(h.addr(), Kind::TimeSync, h.subtype(), h.seq(), now_us()),
                                                      Body::TimeSync, body.Union()));
}

void Node::forget_client(uint32_t client) {
  for (DeviceId id : server_->clients_[client].opened) {
    std::erase_if(devices_[id].readers, [client](const Reader& r) { return r.client == client; });
  }
  server_->clients_[client].opened.clear();
}

}  // namespace troupe
