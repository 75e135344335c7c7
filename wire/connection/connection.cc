#include "wire/connection/connection.h"

#include <algorithm>

#include "wire/connection/transport.h"

namespace troupe::wire {
namespace {

std::string error_text(const Message& msg) {
  const Error* e = msg.body_as_Error();
  if (e == nullptr) return "no reason given";
  std::string text = e->text() ? e->text()->str() : std::string();
  return text.empty() ? std::string(EnumNameErrorCode(e->code())) : text;
}

std::string ms_text(uint64_t us) {
  return std::to_string(us / 1000) + " ms";
}

bool established(LinkState s) {
  return s == LinkState::Handshake || s == LinkState::Up;
}

}  // namespace

const char* link_state_name(LinkState s) {
  switch (s) {
    case LinkState::Idle: return "idle";
    case LinkState::Waiting: return "waiting";
    case LinkState::Connecting: return "connecting";
    case LinkState::Handshake: return "handshake";
    case LinkState::Up: return "up";
  }
  return "?";
}

Connection::Connection(ConnectionOptions options, Transport* transport)
    : options_(std::move(options)), transport_(transport), reader_(options_.limits.max_frame_bytes) {}

Connection::~Connection() = default;

void Connection::set_state(LinkState s, uint64_t now_us) {
  if (s == state_) return;
  state_ = s;
  since_us_ = now_us;
}

uint32_t Connection::next_seq() {
  if (++seq_ == 0) ++seq_;  // 0 means "none" to peers and to this class
  return seq_;
}

// ---- Connecting ---------------------------------------------------------------

void Connection::start(uint64_t now_us) {
  now_us_ = std::max(now_us_, now_us);
  if (state_ != LinkState::Idle && state_ != LinkState::Waiting) return;
  running_ = true;
  begin_attempt(now_us);
}

void Connection::stop() {
  for (uint32_t i = 0; i < candidates_.size(); ++i) {
    if (candidates_[i].attempt == Attempt::InFlight) actions_.push_back({ActionKind::Abandon, i});
  }
  if (established(state_)) actions_.push_back({ActionKind::Close, 0});
  candidates_.clear();
  in_flight_ = 0;
  resolving_ = false;
  running_ = false;
  reset_session();
  downs_.clear();
  down_head_ = 0;
  state_ = LinkState::Idle;
}

void Connection::begin_attempt(uint64_t now_us) {
  candidates_.clear();
  in_flight_ = 0;
  stagger_at_us_ = kNoDeadline;
  retry_at_us_ = kNoDeadline;
  attempt_deadline_us_ = options_.connect_timeout_us ? now_us + options_.connect_timeout_us : kNoDeadline;
  resolving_ = true;
  set_state(LinkState::Connecting, now_us);
  actions_.push_back({ActionKind::Resolve, 0});
}

void Connection::resolved(uint64_t now_us, std::vector<std::string> candidates) {
  now_us_ = std::max(now_us_, now_us);
  if (state_ != LinkState::Connecting || !resolving_) return;
  resolving_ = false;
  if (candidates.empty()) return fail_attempt(now_us, "no address for " + options_.target);
  for (std::string& name : candidates) candidates_.push_back({std::move(name), Attempt::NotStarted, {}});
  start_next_candidate(now_us);
}

void Connection::resolve_failed(uint64_t now_us, std::string why) {
  now_us_ = std::max(now_us_, now_us);
  if (state_ != LinkState::Connecting || !resolving_) return;
  resolving_ = false;
  fail_attempt(now_us, why);
}

bool Connection::start_next_candidate(uint64_t now_us) {
  for (uint32_t i = 0; i < candidates_.size(); ++i) {
    if (candidates_[i].attempt != Attempt::NotStarted) continue;
    candidates_[i].attempt = Attempt::InFlight;
    ++in_flight_;
    actions_.push_back({ActionKind::Connect, i});
    stagger_at_us_ = now_us + options_.attempt_delay_us;
    return true;
  }
  stagger_at_us_ = kNoDeadline;
  return false;
}

void Connection::attempt_failed(uint64_t now_us, uint32_t candidate, std::string_view why) {
  now_us_ = std::max(now_us_, now_us);
  if (state_ != LinkState::Connecting || candidate >= candidates_.size() ||
      candidates_[candidate].attempt != Attempt::InFlight) {
    return;
  }
  candidates_[candidate].attempt = Attempt::Failed;
  candidates_[candidate].why = why;
  --in_flight_;
  // RFC 8305: a failed attempt starts the next address at once.
  if (!start_next_candidate(now_us) && in_flight_ == 0) fail_attempt(now_us, connect_error());
}

void Connection::attempt_connected(uint64_t now_us, uint32_t candidate) {
  now_us_ = std::max(now_us_, now_us);
  if (state_ != LinkState::Connecting || candidate >= candidates_.size() ||
      candidates_[candidate].attempt != Attempt::InFlight) {
    actions_.push_back({ActionKind::Abandon, candidate});  // late: another attempt won
    return;
  }
  for (uint32_t i = 0; i < candidates_.size(); ++i) {
    if (i != candidate && candidates_[i].attempt == Attempt::InFlight) actions_.push_back({ActionKind::Abandon, i});
  }
  candidates_.clear();
  in_flight_ = 0;
  stagger_at_us_ = kNoDeadline;
  transport_up(now_us);
}

std::string Connection::connect_error() const {
  // One reason when every address gave the same, else each address's.
  bool same = std::all_of(candidates_.begin(), candidates_.end(),
                          [&](const Candidate& c) { return c.why == candidates_.front().why; });
  std::string text = "cannot connect to " + options_.target + ": ";
  if (same) return text + candidates_.front().why;
  for (size_t i = 0; i < candidates_.size(); ++i) {
    text += (i ? "; " : "") + candidates_[i].name + ": " + candidates_[i].why;
  }
  return text;
}

void Connection::fail_attempt(uint64_t now_us, const std::string& why) {
  for (uint32_t i = 0; i < candidates_.size(); ++i) {
    if (candidates_[i].attempt == Attempt::InFlight) actions_.push_back({ActionKind::Abandon, i});
  }
  candidates_.clear();
  in_flight_ = 0;
  resolving_ = false;
  end(now_us, why);
}

// ---- Established ---------------------------------------------------------------

void Connection::reset_session() {
  // The frame reader is kept until the next transport: the frame of the
  // event the owner is handling may live in it while a send() overflows.
  out_.clear();
  out_head_ = 0;
  wire_out_.clear();
  wire_head_ = 0;
  closing_ = false;
  hello_sent_ = false;
  ping_outstanding_ = false;
  ping_seq_ = 0;
  sync_seq_ = 0;
  clock_synced_ = false;
  stagger_at_us_ = kNoDeadline;
}

void Connection::transport_up(uint64_t now_us) {
  // Frames the owner queued while connecting survive into the new session.
  std::vector<uint8_t> queued(out_.begin() + long(out_head_), out_.end());
  reset_session();
  out_ = std::move(queued);
  reader_ = FrameReader(options_.limits.max_frame_bytes);
  last_rx_us_ = now_us;
  set_state(LinkState::Handshake, now_us);
  if (transport_ != nullptr) {
    transport_->begin(wire_out_);
    if (!transport_->ready()) return;  // its handshake first; Hello after it
  }
  send_prologue(now_us);
}

void Connection::send_prologue(uint64_t now_us) {
  // Hello (and the first TimeSync) go before what the owner queued.
  std::vector<uint8_t> queued(out_.begin() + long(out_head_), out_.end());
  out_.clear();
  out_head_ = 0;
  auto& b = writer_.start();
  auto hello = CreateHello(b, kProtocolVersion, b.CreateString(options_.name), options_.limits.max_frame_bytes,
                           options_.udp_port, now_us);
  queue_bytes(writer_.finish(make_header({}, Kind::Hello, 0, 0, now_us), Body::Hello, hello.Union()));
  if (options_.sync_clock) {
    sync_seq_ = next_seq();
    auto& t = writer_.start();
    auto sync = CreateTimeSync(t, now_us, 0, 0);
    queue_bytes(writer_.finish(make_header({}, Kind::TimeSync, 0, sync_seq_, now_us), Body::TimeSync,
                               sync.Union()));
  }
  queue_bytes(queued);
  hello_sent_ = true;
  seal_pending();
}

bool Connection::transport_ready() const {
  return transport_ == nullptr || transport_->ready();
}

void Connection::queue_bytes(std::span<const uint8_t> bytes) {
  // Compact when the sent half dominates, so the buffer stays at the size
  // the traffic needs instead of growing with everything ever sent.
  if (out_head_ > 0 && out_head_ >= out_.size() / 2) {
    out_.erase(out_.begin(), out_.begin() + long(out_head_));
    out_head_ = 0;
  }
  out_.insert(out_.end(), bytes.begin(), bytes.end());
}

void Connection::seal_pending() {
  if (transport_ == nullptr || !transport_->ready() || !hello_sent_ || out_head_ == out_.size()) return;
  if (wire_head_ > 0 && wire_head_ >= wire_out_.size() / 2) {
    wire_out_.erase(wire_out_.begin(), wire_out_.begin() + long(wire_head_));
    wire_head_ = 0;
  }
  transport_->outbound({out_.data() + out_head_, out_.size() - out_head_}, wire_out_);
  out_.clear();
  out_head_ = 0;
}

std::span<uint8_t> Connection::read_space(size_t min_bytes) {
  if (transport_ == nullptr) return reader_.write_space(min_bytes);
  if (raw_in_.size() < min_bytes) raw_in_.resize(min_bytes);
  return raw_in_;
}

void Connection::received(uint64_t now_us, size_t n) {
  now_us_ = std::max(now_us_, now_us);
  if (!established(state_) || closing_ || n == 0) return;
  last_rx_us_ = now_us;
  ping_outstanding_ = false;
  if (transport_ == nullptr) {
    reader_.commit(n);
    return;
  }
  std::string why;
  if (!transport_->inbound({raw_in_.data(), n}, reader_, wire_out_, why)) {
    return drop(now_us, "bad bytes from " + options_.peer + ": " + why);
  }
  if (transport_->ready() && !hello_sent_) send_prologue(now_us);
}

void Connection::transport_closed(uint64_t now_us, std::string_view why) {
  now_us_ = std::max(now_us_, now_us);
  if (!established(state_) || closing_) return;
  closing_ = true;
  closed_at_us_ = now_us;
  close_why_ = why.empty() ? options_.peer + " closed the connection"
                           : "connection to " + options_.target + " lost: " + std::string(why);
  // A secure node answers nothing to a handshake it refuses: say what that
  // can mean.
  if (why.empty() && transport_ != nullptr && !transport_->ready()) {
    close_why_ += " during the secure handshake: it does not accept our key, does not hold the key we know for it, "
                  "or does not speak secure sessions";
  }
}

std::span<const uint8_t> Connection::output() const {
  if (!established(state_) || closing_) return {};
  if (transport_ != nullptr) return {wire_out_.data() + wire_head_, wire_out_.size() - wire_head_};
  return {out_.data() + out_head_, out_.size() - out_head_};
}

void Connection::consumed(size_t n) {
  std::vector<uint8_t>& buf = transport_ != nullptr ? wire_out_ : out_;
  size_t& head = transport_ != nullptr ? wire_head_ : out_head_;
  head = std::min(head + n, buf.size());
  if (head == buf.size()) {
    buf.clear();
    head = 0;
  }
}

bool Connection::send(std::span<const uint8_t> frame) {
  if (state_ != LinkState::Connecting && !established(state_)) return false;
  if (closing_) return false;
  size_t pending = (out_.size() - out_head_) + (wire_out_.size() - wire_head_);
  if (options_.max_output_bytes != 0 && pending + frame.size() > options_.max_output_bytes) {
    if (established(state_)) {
      drop(now_us_, options_.peer + " does not read (" + std::to_string(pending) + " bytes queued)");
    }
    return false;
  }
  queue_bytes(frame);
  seal_pending();
  return true;
}

uint32_t Connection::request_time_sync(uint64_t now_us) {
  now_us_ = std::max(now_us_, now_us);
  if (state_ != LinkState::Up || closing_) return 0;
  sync_seq_ = next_seq();
  auto& b = writer_.start();
  auto sync = CreateTimeSync(b, now_us, 0, 0);
  queue_bytes(writer_.finish(make_header({}, Kind::TimeSync, 0, sync_seq_, now_us), Body::TimeSync, sync.Union()));
  seal_pending();
  return sync_seq_;
}

// ---- Ending ---------------------------------------------------------------------

void Connection::close(uint64_t now_us, std::string why) {
  now_us_ = std::max(now_us_, now_us);
  if (state_ == LinkState::Connecting) return fail_attempt(now_us, why);
  if (established(state_)) drop(now_us, why);
}

void Connection::drop(uint64_t now_us, const std::string& why) {
  actions_.push_back({ActionKind::Close, 0});
  end(now_us, why);
}

void Connection::end(uint64_t now_us, const std::string& why) {
  error_ = why;
  downs_.push_back(why);
  reset_session();
  attempt_deadline_us_ = kNoDeadline;
  if (running_ && options_.reconnect) {
    backoff_us_ = backoff_us_ == 0 ? options_.backoff_min_us : std::min(backoff_us_ * 2, options_.backoff_max_us);
    retry_at_us_ = now_us + backoff_us_;
    set_state(LinkState::Waiting, now_us);
  } else {
    running_ = false;
    set_state(LinkState::Idle, now_us);
  }
}

// ---- Time -------------------------------------------------------------------------

void Connection::tick(uint64_t now_us) {
  now_us_ = std::max(now_us_, now_us);
  switch (state_) {
    case LinkState::Idle:
      return;
    case LinkState::Waiting:
      if (now_us >= retry_at_us_) begin_attempt(now_us);
      return;
    case LinkState::Connecting:
      if (now_us >= attempt_deadline_us_) {
        return fail_attempt(now_us, "no connection with " + options_.target + " within " +
                                        ms_text(options_.connect_timeout_us));
      }
      if (!resolving_ && now_us >= stagger_at_us_ && in_flight_ < kMaxAttemptsInFlight) {
        start_next_candidate(now_us);
      }
      return;
    case LinkState::Handshake:
      if (!closing_ && now_us >= attempt_deadline_us_) {
        drop(now_us, "no handshake with " + options_.target + " within " + ms_text(options_.connect_timeout_us));
      }
      return;
    case LinkState::Up:
      if (closing_ || options_.keepalive_us == 0) return;
      if (ping_outstanding_) {
        if (now_us >= ping_sent_us_ + options_.keepalive_timeout_us) {
          drop(now_us, options_.peer + " silent for " + ms_text(now_us - last_rx_us_));
        }
      } else if (now_us >= last_rx_us_ + options_.keepalive_us) {
        // A TimeSync is the cheapest message every node answers: its reply
        // proves the peer alive when no data flows.
        ping_seq_ = next_seq();
        ping_sent_us_ = now_us;
        ping_outstanding_ = true;
        auto& b = writer_.start();
        auto sync = CreateTimeSync(b, now_us, 0, 0);
        queue_bytes(writer_.finish(make_header({}, Kind::TimeSync, 0, ping_seq_, now_us), Body::TimeSync,
                                   sync.Union()));
        seal_pending();
      }
      return;
  }
}

uint64_t Connection::next_deadline_us() const {
  switch (state_) {
    case LinkState::Idle:
      return kNoDeadline;
    case LinkState::Waiting:
      return retry_at_us_;
    case LinkState::Connecting: {
      bool untried = std::any_of(candidates_.begin(), candidates_.end(),
                                 [](const Candidate& c) { return c.attempt == Attempt::NotStarted; });
      bool stagger = !resolving_ && untried && in_flight_ < kMaxAttemptsInFlight;
      return std::min(attempt_deadline_us_, stagger ? stagger_at_us_ : kNoDeadline);
    }
    case LinkState::Handshake:
      return closing_ ? kNoDeadline : attempt_deadline_us_;
    case LinkState::Up:
      if (closing_ || options_.keepalive_us == 0) return kNoDeadline;
      return ping_outstanding_ ? ping_sent_us_ + options_.keepalive_timeout_us : last_rx_us_ + options_.keepalive_us;
  }
  return kNoDeadline;
}

Action Connection::next_action() {
  if (action_head_ == actions_.size()) return {};
  Action a = actions_[action_head_++];
  if (action_head_ == actions_.size()) {
    actions_.clear();
    action_head_ = 0;
  }
  return a;
}

// ---- Frames in ------------------------------------------------------------------

Event Connection::next_event() {
  for (;;) {
    if (down_head_ < downs_.size()) {
      event_text_ = std::move(downs_[down_head_++]);
      if (down_head_ == downs_.size()) {
        downs_.clear();
        down_head_ = 0;
      }
      return {EventKind::Down, {}, nullptr, event_text_};
    }
    if (!established(state_)) return {};
    std::span<const uint8_t> frame = transport_ready() ? reader_.next() : std::span<const uint8_t>();
    if (frame.empty()) {
      if (reader_.too_large()) {
        drop(now_us_, options_.peer + " sent a frame over the limit (" + std::to_string(reader_.announced_bytes()) +
                          " bytes)");
        continue;
      }
      if (!closing_) return {};
      std::string why = close_why_;
      if (reader_.pending_bytes() > 0) why += " inside a frame";
      end(closed_at_us_, why);  // the socket is closed already
      continue;
    }
    Event event;
    if (on_frame(frame, event)) return event;
  }
}

bool Connection::on_frame(std::span<const uint8_t> frame, Event& out) {
  VerifyError why{};
  const Message* msg = verify_frame(frame, options_.limits, &why);
  if (msg == nullptr) {
    drop(now_us_, "bad frame from " + options_.peer + ": " + std::string(verify_error_text(why)));
    return false;
  }
  const Header& h = *msg->header();
  if (h.kind() == Kind::Error) {
    // A node sends Error last and then closes; say what it said.
    drop(now_us_, options_.peer + " closed the connection: " + error_text(*msg));
    return false;
  }
  if (h.kind() == Kind::Hello) {
    if (state_ == LinkState::Up) return false;  // a repeated Hello changes nothing
    const Hello* hello = msg->body_as_Hello();
    if (hello == nullptr) {
      drop(now_us_, options_.peer + " sent a Hello without its body");
      return false;
    }
    if (hello->protocol_version() != kProtocolVersion) {
      drop(now_us_, options_.peer + " speaks protocol " + std::to_string(hello->protocol_version()) +
                        ", this client " + std::to_string(kProtocolVersion));
      return false;
    }
    peer_name_ = hello->name() ? hello->name()->str() : std::string();
    set_state(LinkState::Up, last_rx_us_);
    backoff_us_ = 0;
    ++connections_;
    out = {EventKind::Up, frame, msg, {}};
    return true;
  }
  if (state_ != LinkState::Up) {
    drop(now_us_, options_.peer + " sent " + std::string(kind_name(h.kind())) + " before its Hello");
    return false;
  }
  if (h.kind() == Kind::TimeSync) {
    if (h.seq() == ping_seq_ && ping_seq_ != 0) return false;  // the keep-alive's reply: arriving was its job
    if (h.seq() == sync_seq_ && sync_seq_ != 0) {
      if (const TimeSync* t = msg->body_as_TimeSync()) {
        int64_t t0 = int64_t(t->client_send_us()), t1 = int64_t(t->node_recv_us());
        int64_t t2 = int64_t(t->node_send_us()), t3 = int64_t(last_rx_us_);
        clock_offset_us_ = ((t1 - t0) + (t2 - t3)) / 2;
        clock_synced_ = true;
      }
      out = {EventKind::Synced, frame, msg, {}};
      return true;
    }
  }
  out = {EventKind::Frame, frame, msg, {}};
  return true;
}

}  // namespace troupe::wire
