#include "drivers/serial_port/serial_session.h"

#include <algorithm>

#include "runtime/log.h"

namespace troupe::serial {

bool SerialSession::start(EventLoop& loop, const Options& options, std::string& error) {
  if (options.bauds.empty() || options.bauds.size() > kMaxBauds) {
    error = "between 1 and " + std::to_string(kMaxBauds) + " bauds to probe";
    return false;
  }
  if (options.reopen_min_us == 0 || options.reopen_max_us < options.reopen_min_us) {
    error = "options \"reopen_min_ms\" must be > 0 and \"reopen_max_ms\" at least as large";
    return false;
  }
  loop_ = &loop;
  name_ = options.name;
  port_ = options.port;
  baud_count_ = options.bauds.size();
  std::copy(options.bauds.begin(), options.bauds.end(), bauds_);
  reopen_min_us_ = backoff_us_ = options.reopen_min_us;
  reopen_max_us_ = options.reopen_max_us;
  link_.attach(loop);
  tick_ = loop.start_timer(kTickUs, kTickUs, this);
  if (tick_ == 0) {
    error = "no timer left";
    return false;
  }
  try_open();
  return true;
}

void SerialSession::stop() {
  if (tick_ != 0) loop_->cancel_timer(tick_);
  tick_ = 0;
  link_.close();
}

void SerialSession::try_open() {
  std::string error;
  if (!link_.open(port_, bauds_[0], error)) {
    reopen_at_us_ = now_us() + backoff_us_;
    // The first failure is worth a warning; repeats of the same only at
    // debug level, or a missing device fills the log.
    if (!open_failed_logged_) {
      log_warn("%s: %s; trying again every %u ms or less", name_.c_str(), error.c_str(),
               unsigned(reopen_max_us_ / 1000));
      open_failed_logged_ = true;
    } else {
      log_debug("%s: %s", name_.c_str(), error.c_str());
    }
    backoff_us_ = std::min(backoff_us_ * 2, reopen_max_us_);
    return listener_.on_session_down();
  }
  log_info("%s: opened %s", name_.c_str(), port_.c_str());
  open_failed_logged_ = false;
  listener_.on_session_open();
}

bool SerialSession::send(std::span<const uint8_t> bytes) {
  if (link_.send(bytes)) return true;
  log_debug("%s: output queue full or port closed; %zu bytes dropped", name_.c_str(), bytes.size());
  return false;
}

bool SerialSession::probe_baud(size_t index) {
  if (!set_baud(bauds_[index])) return false;
  link_.discard_input();
  return true;
}

bool SerialSession::set_baud(uint32_t baud) {
  std::string error;
  if (link_.baud() == baud || link_.set_baud(baud, error)) return true;
  lose(error);
  return false;
}

void SerialSession::prefer(size_t index) {
  if (index < baud_count_) std::rotate(bauds_, bauds_ + index, bauds_ + index + 1);
}

void SerialSession::prefer_baud(uint32_t baud) {
  prefer(size_t(std::find(bauds_, bauds_ + baud_count_, baud) - bauds_));
}

std::string SerialSession::bauds_text() const {
  std::string text;
  for (size_t i = 0; i < baud_count_; ++i) {
    text += (i == 0 ? "" : i + 1 == baud_count_ ? " or " : ", ") + std::to_string(bauds_[i]);
  }
  return text;
}

void SerialSession::lose(const std::string& why, uint64_t delay_us) {
  if (delay_us == 0) delay_us = backoff_us_;
  link_.close();
  reopen_at_us_ = now_us() + delay_us;
  backoff_us_ = std::min(std::max(delay_us, reopen_min_us_) * 2, reopen_max_us_);
  log_warn("%s: %s; reopening %s in %u ms", name_.c_str(), why.c_str(), port_.c_str(),
           unsigned(delay_us / 1000));
  listener_.on_session_down();
}

void SerialSession::on_serial_bytes(std::span<const uint8_t> bytes) {
  listener_.on_session_bytes(bytes);
}

void SerialSession::on_serial_lost(const std::string& why) {
  lose(port_ + ": " + why);
}

void SerialSession::on_timer(TimerId id) {
  if (id != tick_) return;
  if (!link_.is_open()) {
    if (now_us() >= reopen_at_us_) try_open();
    return;
  }
  listener_.on_session_tick(now_us());
}

}  // namespace troupe::serial
