// What every serial driver's connection does apart from its protocol: open
// the port (and keep trying, with backoff, while it is not there), probe a
// list of bauds, time each protocol step, and lose the port cleanly (close,
// log once, reopen later). A driver embeds one SerialSession and keeps only
// its own protocol states; the session calls it back from the node's loop:
//
//   opened  -> on_session_open()        the driver starts its handshake at
//                                       probe_baud(0)
//   bytes   -> on_session_bytes(bytes)
//   50 ms   -> on_session_tick(now_us)  while the port is open
//   lost    -> on_session_down()        the port is closed; it reopens
//                                       by itself after the backoff
//
// Nothing blocks; the session owns one timer (its tick) and the SerialLink.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "drivers/serial_port/serial_link.h"
#include "runtime/event_loop.h"

namespace troupe::serial {

class SerialSession final : private SerialLink::Listener, private TimerHandler {
 public:
  class Listener {
   public:
    /// The port is open at bauds()[0]; start the handshake.
    virtual void on_session_open() = 0;
    /// Bytes from the device, valid during the call.
    virtual void on_session_bytes(std::span<const uint8_t> bytes) = 0;
    /// Every tick while the port is open; `now_us` is the loop's clock.
    virtual void on_session_tick(uint64_t now_us) = 0;
    /// The port was lost or could not be opened; it is closed now.
    virtual void on_session_down() = 0;

   protected:
    ~Listener() = default;
  };

  /// How often the session ticks, us.
  static constexpr uint64_t kTickUs = 50'000;
  /// Most bauds a driver probes.
  static constexpr size_t kMaxBauds = 8;

  struct Options {
    /// The driver instance's name, for log lines.
    std::string name;
    /// The serial device, e.g. "/dev/ttyS0".
    std::string port;
    /// Bauds to probe, bit/s, in order (at most kMaxBauds).
    std::span<const uint32_t> bauds;
    /// Reopen backoff: first delay and the most it doubles to, us.
    uint64_t reopen_min_us = 0, reopen_max_us = 0;
  };

  explicit SerialSession(Listener& listener) : listener_(listener), link_(*this) {}
  ~SerialSession() { stop(); }
  SerialSession(const SerialSession&) = delete;
  SerialSession& operator=(const SerialSession&) = delete;

  /// Starts the tick and tries the port at once (a device not there yet
  /// is no failure: the session keeps trying). False with `error` when no
  /// timer is left or the options are impossible.
  bool start(EventLoop& loop, const Options& options, std::string& error);
  /// Stops the tick and closes the port, without calling back.
  void stop();

  /// Queues bytes for the device; false (and a debug line) when the link
  /// is closed or its queue is full.
  bool send(std::span<const uint8_t> bytes);
  /// Switches the line to bauds()[index] (when it is not there already) and
  /// forgets stale input. False when the port refused; the session is then
  /// lost already.
  bool probe_baud(size_t index);
  /// Switches the line to `baud` (the device changed speed on request);
  /// false when refused, the session lost already.
  bool set_baud(uint32_t baud);
  /// The baud at `index` is tried first from now on (it answered).
  void prefer(size_t index);
  /// The same by value; a baud not in the list is ignored.
  void prefer_baud(uint32_t baud);
  /// The bauds to probe, in the current order.
  std::span<const uint32_t> bauds() const { return {bauds_, baud_count_}; }
  /// "9600, 38400 or 500000", for messages.
  std::string bauds_text() const;

  /// The connection works: the next loss waits reopen_min_us again.
  void connected() { backoff_us_ = reopen_min_us_; }
  /// Closes the port and reopens it after `delay_us` (0: the current
  /// backoff); logs `why` and calls on_session_down().
  void lose(const std::string& why, uint64_t delay_us = 0);
  /// The longest backoff, us: the wait after a device that answered but
  /// cannot be used.
  uint64_t reopen_max_us() const { return reopen_max_us_; }

  /// Deadlines for the protocol's steps, on the loop's clock.
  void arm(uint64_t timeout_us) { deadline_us_ = now_us() + timeout_us; }
  bool expired() const { return now_us() >= deadline_us_; }
  uint64_t now_us() const { return loop_->now_us(); }

  bool is_open() const { return link_.is_open(); }
  uint32_t baud() const { return link_.baud(); }
  const std::string& port() const { return port_; }
  const std::string& name() const { return name_; }
  SerialLink& link() { return link_; }

 private:
  void on_serial_bytes(std::span<const uint8_t> bytes) override;
  void on_serial_lost(const std::string& why) override;
  void on_timer(TimerId id) override;
  void try_open();

  Listener& listener_;
  SerialLink link_;
  EventLoop* loop_ = nullptr;
  std::string name_, port_;
  uint32_t bauds_[kMaxBauds] = {};
  size_t baud_count_ = 0;
  uint64_t reopen_min_us_ = 0, reopen_max_us_ = 0, backoff_us_ = 0;
  uint64_t reopen_at_us_ = 0, deadline_us_ = 0;
  bool open_failed_logged_ = false;
  TimerId tick_ = 0;
};

}  // namespace troupe::serial
