// A serial line driven from the node's event loop. libserial opens and
// configures the port (raw 8N1, no flow control, the baud asked for; see
// serial_device.h); its descriptor is then watched by the EventLoop, read
// whenever bytes are there and written through a bounded queue. Nothing here
// ever blocks.
//
// A port that fails (a USB adapter pulled out, an emulator's pty closed) is
// closed and reported to the listener from the loop, never from inside a
// call the driver made, so a driver never sees its state change under it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "drivers/serial_port/serial_device.h"
#include "runtime/event_loop.h"

namespace troupe::serial {

class SerialLink final : public FdHandler, public TimerHandler {
 public:
  class Listener {
   public:
    /// Bytes from the device, in order; valid during the call only.
    virtual void on_serial_bytes(std::span<const uint8_t> bytes) = 0;
    /// The device failed or vanished (`why` says how); the link is closed
    /// already and may be opened again.
    virtual void on_serial_lost(const std::string& why) = 0;

   protected:
    ~Listener() = default;
  };

  /// Bytes waiting for the port at most; more is dropped, as a full UART
  /// FIFO drops. Control packets are tens of bytes.
  static constexpr size_t kQueueBytes = 2048;

  explicit SerialLink(Listener& listener) : listener_(listener) {}
  ~SerialLink() { close(); }
  SerialLink(const SerialLink&) = delete;
  SerialLink& operator=(const SerialLink&) = delete;

  /// The loop that watches the port; before the first open().
  void attach(EventLoop& loop) { loop_ = &loop; }
  /// Opens `path` raw 8N1 at `baud` bit/s and starts watching it. On failure
  /// returns false with `error` naming the path and the reason.
  bool open(const std::string& path, uint32_t baud, std::string& error);
  /// Changes the line speed, bit/s. Bytes still queued are dropped: they
  /// were meant for the old speed.
  bool set_baud(uint32_t baud, std::string& error);
  /// Forgets bytes received but not yet read (stale replies after a baud
  /// change or a restart).
  void discard_input();
  /// Queues `bytes` for the device and writes what the port takes now.
  /// Returns false when the link is closed or the queue cannot take them
  /// all (then none are queued).
  bool send(std::span<const uint8_t> bytes);
  /// Closes the port; safe when the device has vanished, and when closed.
  void close();

  bool is_open() const { return device_.fd() >= 0; }
  /// Line speed, bit/s (0 when closed).
  uint32_t baud() const { return baud_; }
  const std::string& path() const { return path_; }
  size_t queued_bytes() const { return queue_size_ - queue_head_; }

  void on_fd(int fd, uint32_t events) override;
  void on_timer(TimerId id) override;

 private:
  void flush();
  void fail(const std::string& why);  // closes now, reports from the loop
  void want_write(bool on);

  EventLoop* loop_ = nullptr;
  Listener& listener_;
  SerialDevice device_;
  std::string path_;
  uint32_t session_ = 0;  // counts opens: a descriptor number may be reused
  uint32_t baud_ = 0;
  bool writing_ = false;
  uint8_t queue_[kQueueBytes];
  size_t queue_head_ = 0, queue_size_ = 0;
  TimerId lost_timer_ = 0;
  std::string lost_why_;
};

}  // namespace troupe::serial
