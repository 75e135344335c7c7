#include "drivers/replay/replay_driver.h"

#include <algorithm>

#include "runtime/log.h"
#include "runtime/node.h"
#include "runtime/node_config.h"
#include "wire/image.h"

namespace troupe::drivers::replay {
namespace {

// How often a replay waiting for readers looks whether they came, us.
constexpr uint64_t kReaderCheckUs = 20000;

// The key of a recorded reply: a device and the request's subtype.
uint64_t reply_key(const wire::Address& addr, uint8_t subtype) {
  return wire::address_key(addr) * 256 + subtype;
}

// A play time in loop-clock us at `speed`, saturated far beyond any run.
uint64_t scaled_us(uint64_t play_us, double speed) {
  const double us = double(play_us) / speed;
  return us < 1e18 ? uint64_t(us) : uint64_t(1e18);
}

}  // namespace

ReplayDriver::ReplayDriver(Options options)
    : options_(std::move(options)), configured_(true), clock_(options_.max_gap_us) {}

bool ReplayDriver::setup(Node& node, const DriverSetup& setup, std::string& error) {
  if (!configured_) {
    OptionsView<drivers::replay::Options> opt(setup);
    options_.path = opt->file() ? opt->file()->str() : std::string();
    options_.speed = opt->speed();
    options_.loop = opt->loop();
    options_.wait_for_readers = opt->wait_for_readers();
    if (options_.path.empty()) {
      error = "option \"file\" (the troupe log) is missing";
      return false;
    }
  }
  if (!(options_.speed > 0)) {
    error = "the replay speed must be > 0";
    return false;
  }
  if (!copier_.ok()) {
    error = "the embedded message schema does not verify (a build problem)";
    return false;
  }
  for (DeviceId id : setup.provides) devices_[wire::address_key(node.address(id))] = id;
  if (!reader_.open(options_.path, error)) return false;
  read_replies();
  if (options_.wait_for_readers) {
    waiting_ = true;
    timer_ = node.loop().start_timer(kReaderCheckUs, kReaderCheckUs, this);
    if (timer_ == 0) {
      error = "no timer left";
      return false;
    }
    return true;
  }
  begin_pass();
  return true;
}

void ReplayDriver::read_replies() {
  record::LogRecord r;
  while (reader_.next(r)) {
    const wire::Header& h = *r.message->header();
    if (h.kind() != wire::Kind::Ack || devices_.count(wire::address_key(h.addr())) == 0) continue;
    // A recording that asked twice (a reconnection) keeps its first answer.
    replies_.try_emplace(reply_key(h.addr(), h.subtype()), r.frame.begin(), r.frame.end());
  }
  reader_.rewind();
}

void ReplayDriver::on_request(DeviceId device, const wire::Message& request, RequestToken token) {
  auto it = replies_.find(reply_key(node_->address(device), request.header()->subtype()));
  if (it == replies_.end()) return Driver::on_request(device, request, token);
  const wire::Message& reply = *wire::trusted_message(it->second);  // verified when read_replies() read it
  if (reply.body_type() != wire::Body::NONE && !copier_.can_copy(reply.body_type())) {
    return Driver::on_request(device, request, token);
  }
  auto& b = node_->begin();
  flatbuffers::Offset<void> body = copier_.copy(b, reply);
  node_->ack(token, reply.body_type(), body);
}

void ReplayDriver::shutdown() {
  if (timer_ != 0) node_->loop().cancel_timer(timer_);
  timer_ = 0;
}

void ReplayDriver::on_timer(TimerId) {
  if (!waiting_) {
    timer_ = 0;
    if (restart_) {
      restart_ = false;
      return begin_pass();
    }
    play_due();
    return;
  }
  bool all = std::all_of(devices_.begin(), devices_.end(),
                         [&](const auto& d) { return node_->has_readers(d.second); });
  if (!all) return;
  node_->loop().cancel_timer(timer_);
  timer_ = 0;
  waiting_ = false;
  begin_pass();
}

void ReplayDriver::begin_pass() {
  ++passes_;
  reader_.rewind();
  clock_.restart();
  has_current_ = read_data();
  if (!has_current_) {
    finished_ = true;  // nothing to play (or nothing more: an empty pass would loop forever)
    return;
  }
  pass_start_us_ = node_->loop().now_us();
  last_play_us_ = 0;
  pass_frames_ = 0;
  play_due();
}

bool ReplayDriver::read_data() {
  while (reader_.next(current_)) {
    if (current_.message->header()->kind() != wire::Kind::Data) continue;
    bool jumped = false;
    current_play_us_ = clock_.next(current_.time_us, jumped);
    // Logged in the first pass only.
    if (jumped && passes_ == 1 && log_this_one(jumps_)) {
      log_warn(
          "%s: byte %llu: the record time jumps to %.6f s; playing on at once (a pause over %.0f s or "
          "a step back is not kept; %llu such jumps so far)",
          options_.path.c_str(), static_cast<unsigned long long>(current_.offset),
          double(current_.time_us) * 1e-6, double(options_.max_gap_us) * 1e-6,
          static_cast<unsigned long long>(jumps_));
    }
    return true;
  }
  return false;
}

void ReplayDriver::play_due() {
  for (;;) {
    if (!has_current_) {
      if (!options_.loop) {
        finished_ = true;
        return;
      }
      // The next pass starts one mean frame interval later, as the next
      // frame would have: never at once, so a pass is never re-entered.
      uint64_t gap_us = pass_frames_ > 1 ? scaled_us(last_play_us_ / (pass_frames_ - 1), options_.speed) : 0;
      restart_ = true;
      timer_ = node_->loop().start_timer(std::max<uint64_t>(gap_us, 1000), 0, this);
      return;
    }
    uint64_t due = pass_start_us_ + scaled_us(current_play_us_, options_.speed);
    uint64_t now = node_->loop().now_us();
    if (due > now) {
      timer_ = node_->loop().start_timer(due - now, 0, this);
      return;
    }
    publish(current_);
    ++pass_frames_;
    last_play_us_ = current_play_us_;
    has_current_ = read_data();
  }
}

void ReplayDriver::publish(const record::LogRecord& record) {
  const wire::Message& msg = *record.message;
  const wire::Header& h = *msg.header();
  auto it = devices_.find(wire::address_key(h.addr()));
  if (it == devices_.end()) return;  // data of a device the log's list does not name
  if (msg.body_type() != wire::Body::NONE && !copier_.can_copy(msg.body_type())) {
    if (!warned_unknown_) {
      log_warn("%s: byte %llu: a body type this build does not know (%u); skipping such frames",
               options_.path.c_str(), static_cast<unsigned long long>(record.offset),
               unsigned(msg.body_type()));
      warned_unknown_ = true;
    }
    return;
  }
  std::string why;
  if (const wire::CameraImage* image = msg.body_as_CameraImage();
      image && !wire::image_complete(*image, why)) {
    // Served, it would hand a client a buffer shorter than the image it
    // describes; the images after it are whole and play.
    if (log_this_one(incomplete_images_)) {
      log_warn("%s: byte %llu: %s: skipping this image (%llu such so far)", options_.path.c_str(),
               static_cast<unsigned long long>(record.offset), why.c_str(),
               static_cast<unsigned long long>(incomplete_images_));
    }
    return;
  }
  auto& b = node_->begin();
  flatbuffers::Offset<void> body = copier_.copy(b, msg);
  node_->publish_at(it->second, h.subtype(), msg.body_type(), body, wire::time_us(h));
  ++published_;
}

extern const DriverEntry kEntry;
const DriverEntry kEntry{"replay", []() -> Driver* { return new ReplayDriver; }};

}  // namespace troupe::drivers::replay
