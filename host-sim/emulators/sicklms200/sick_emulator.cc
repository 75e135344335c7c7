#include "host-sim/emulators/sicklms200/sick_emulator.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace troupe::emulators {

namespace sick = drivers::sicklms200;

namespace {

constexpr double kCentidegreeToRad = 3.14159265358979323846 / 18000.0;
constexpr uint8_t kPassword[] = {'S', 'I', 'C', 'K', '_', 'L', 'M', 'S'};
// A partial telegram is dropped after this long without a byte, us.
constexpr uint64_t kTelegramGapUs = 50'000;
// Mode change replies: done, refused (wrong password), not supported.
constexpr uint8_t kModeOk = 0, kModeBadPassword = 1, kModeUnsupported = 2;

bool valid_variant(uint16_t width, uint16_t res) {
  if (width == 180) return res == 50 || res == 100;
  if (width == 100) return res == 25 || res == 50 || res == 100;
  return false;
}

}  // namespace

SickEmulator::SickEmulator(Config config, SickWorld* world)
    : SerialEmulator(config.seed, config.check_baud),
      config_(std::move(config)),
      world_(world ? world : &default_world_),
      baud_(config_.power_up_baud),
      width_deg_(config_.width_deg),
      resolution_cdeg_(config_.resolution_cdeg) {
  config_block_[sick::kConfigUnits] = uint8_t(config_.units);
}

void SickEmulator::power_cycle() {
  mode_ = Mode::Monitor;
  baud_ = config_.power_up_baud;
  pending_baud_ = 0;
  queue_head_ = queue_size_ = 0;
  scanner_.reset();
}

void SickEmulator::on_heard(std::span<const uint8_t> bytes) {
  uint32_t bad = scanner_.bad_crcs();
  sick::scan_telegrams(scanner_, bytes, [this](std::span<const uint8_t> body) { obey(body); });
  // A telegram that framed but failed its CRC is answered NACK.
  if (scanner_.bad_crcs() != bad && mode_ != Mode::Starting) send_byte(sick::kNack);
}

void SickEmulator::on_stale_partial() {
  sick::expire_telegrams(scanner_, [this](std::span<const uint8_t> body) { obey(body); });
}

void SickEmulator::step(uint64_t now_us) {
  if (!started_) {
    started_ = true;
    last_step_us_ = now_us;
  }
  now_us_ = now_us;
  listen(now_us, kTelegramGapUs);
  drain(now_us);
  if (mode_ == Mode::Starting && now_us >= ready_at_us_ && queue_size_ == queue_head_) {
    // Restarted: at its power-up speed, it says what it is.
    power_cycle();
    reply(sick::kPowerOnReply, {reinterpret_cast<const uint8_t*>(config_.type.data()), config_.type.size()});
  }
  const bool streaming = mode_ == Mode::Continuous || mode_ == Mode::MeanValues;
  if (streaming && queue_size_ == queue_head_ && pending_baud_ == 0 && now_us >= next_scan_us_) {
    send_scan();
    // Keep the scanner's own rhythm; after an idle spell, start it afresh.
    // A mean over N scans takes N scan periods.
    uint64_t period = uint64_t(1e6 / config_.max_scan_rate_hz) * (mode_ == Mode::MeanValues ? mean_samples_ : 1);
    next_scan_us_ = next_scan_us_ + period > now_us ? next_scan_us_ + period : now_us + period;
  }
}

void SickEmulator::drain(uint64_t now_us) {
  // A UART sends baud / 10 bytes a second (8N1: ten bits a byte).
  credit_bytes_ += double(now_us - last_step_us_) * 1e-6 * baud_ / 10.0;
  last_step_us_ = now_us;
  size_t queued = queue_size_ - queue_head_;
  if (queued == 0) {
    credit_bytes_ = std::min(credit_bytes_, 1.0);  // an idle line saves up nothing
    if (pending_baud_ != 0) {
      baud_ = pending_baud_;
      pending_baud_ = 0;
    }
    return;
  }
  size_t n = std::min(queued, size_t(credit_bytes_));
  if (n == 0) return;
  credit_bytes_ -= double(n);
  uint8_t* out = queue_ + queue_head_;
  garble_if_mismatched({out, n});
  // What the pty does not take is lost, as bytes nobody reads are.
  write_line({out, n});
  queue_head_ += n;
  if (queue_head_ == queue_size_) queue_head_ = queue_size_ = 0;
}

void SickEmulator::queue(std::span<const uint8_t> bytes) {
  if (queue_head_ > 0) {
    memmove(queue_, queue_ + queue_head_, queue_size_ - queue_head_);
    queue_size_ -= queue_head_;
    queue_head_ = 0;
  }
  size_t n = std::min(bytes.size(), kQueueBytes - queue_size_);
  memcpy(queue_ + queue_size_, bytes.data(), n);
  queue_size_ += n;
}

void SickEmulator::send_byte(uint8_t b) {
  if (b == sick::kNack) ++nacks_sent_;
  queue({&b, 1});
}

void SickEmulator::reply(uint8_t code, std::span<const uint8_t> data) {
  sick::Telegram t;
  if (!sick::make_reply(code, data, 0, t)) return;
  uint8_t out[sick::kMaxTelegramBytes];
  if (code != sick::kPowerOnReply) send_byte(sick::kAck);
  queue({out, through_faults(t.view(), out)});
}

void SickEmulator::obey(std::span<const uint8_t> body) {
  if (mode_ == Mode::Starting) return;  // deaf while it restarts
  const uint8_t code = body[0];
  std::span<const uint8_t> data = body.subspan(1);
  switch (sick::Request(code)) {
    case sick::Request::Reset:
      reply(sick::kResetReply, {});
      mode_ = Mode::Starting;
      ready_at_us_ = now_us_ + config_.startup_us;
      return;
    case sick::Request::ModeChange:
      return mode_change(data);
    case sick::Request::OneScan:
      if (mode_ == Mode::Installation) break;
      send_byte(sick::kAck);
      return send_scan();
    case sick::Request::Status:
      return send_status();
    case sick::Request::Errors:
      return reply(sick::reply_code(sick::Request::Errors), {});  // none logged
    case sick::Request::Type:
      return reply(sick::reply_code(sick::Request::Type),
                   {reinterpret_cast<const uint8_t*>(config_.type.data()), config_.type.size()});
    case sick::Request::Variant: {
      if (data.size() != 4) break;
      uint16_t width = uint16_t(data[0] | (data[1] << 8)), res = uint16_t(data[2] | (data[3] << 8));
      bool ok = valid_variant(width, res);
      if (ok) {
        width_deg_ = width;
        resolution_cdeg_ = res;
      }
      const uint8_t answer[5] = {uint8_t(ok ? 1 : 0), uint8_t(width_deg_ & 0xFF), uint8_t(width_deg_ >> 8),
                                 uint8_t(resolution_cdeg_ & 0xFF), uint8_t(resolution_cdeg_ >> 8)};
      return reply(sick::reply_code(sick::Request::Variant), answer);
    }
    case sick::Request::ReadConfig:
      return reply(sick::reply_code(sick::Request::ReadConfig), config_block_);
    case sick::Request::WriteConfig: {
      // The configuration is written only in configuration mode, as the
      // listing's 32 bytes or later firmware's 34.
      if (mode_ != Mode::Installation || (data.size() != 32 && data.size() != sick::kConfigBytes)) break;
      bool ok = data[sick::kConfigUnits] <= uint8_t(Units::Decimetres);
      if (ok) std::copy(data.begin(), data.end(), config_block_);
      uint8_t answer[1 + sick::kConfigBytes] = {uint8_t(ok ? 1 : 0)};
      std::copy_n(config_block_, data.size(), answer + 1);
      return reply(sick::reply_code(sick::Request::WriteConfig), {answer, 1 + data.size()});
    }
  }
  send_byte(sick::kNack);
}

void SickEmulator::mode_change(std::span<const uint8_t> data) {
  uint8_t result = kModeOk;
  if (data.empty()) {
    result = kModeUnsupported;
  } else {
    switch (sick::Mode(data[0])) {
      case sick::Mode::Config:
        if (data.size() == 1 + sizeof kPassword && std::equal(data.begin() + 1, data.end(), kPassword)) {
          mode_ = Mode::Installation;
        } else {
          result = kModeBadPassword;
        }
        break;
      case sick::Mode::Baud9600:
        pending_baud_ = 9600;
        break;
      case sick::Mode::Baud19200:
        pending_baud_ = 19200;
        break;
      case sick::Mode::Baud38400:
        pending_baud_ = 38400;
        break;
      case sick::Mode::Baud500000:
        pending_baud_ = 500000;
        break;
      case sick::Mode::Continuous:
        mode_ = Mode::Continuous;
        break;
      case sick::Mode::StopContinuous:
        mode_ = Mode::Monitor;
        break;
      case sick::Mode::MeanValues:
        if (data.size() == 2 && data[1] >= 2 && data[1] <= 250) {
          mode_ = Mode::MeanValues;
          mean_samples_ = data[1];
        } else {
          result = kModeUnsupported;
        }
        break;
      default:
        result = kModeUnsupported;
        break;
    }
  }
  const uint8_t answer[1] = {result};
  reply(sick::reply_code(sick::Request::ModeChange), answer);
}

void SickEmulator::send_scan() {
  size_t count = size_t(width_deg_) * 100 / resolution_cdeg_ + 1;
  float ranges_m[sick::kMaxScanValues];
  double first = -double(width_deg_) * 50 * kCentidegreeToRad;
  world_->measure(first, resolution_cdeg_ * kCentidegreeToRad, {ranges_m, count});
  Units units = this->units();
  double per_metre = units == Units::Millimetres ? 1000.0 : units == Units::Centimetres ? 100.0 : 10.0;
  for (size_t i = 0; i < count; ++i) {
    double v = std::round(double(ranges_m[i]) * per_metre);
    last_scan_[i] = v >= sick::kNoReturn || !std::isfinite(v) ? sick::kNoReturn : uint16_t(std::max(v, 0.0));
  }
  last_count_ = count;
  // A mean-values telegram leads with its sample count; the world holds
  // still between the samples of one mean, so the mean is the scan.
  const bool mean = mode_ == Mode::MeanValues;
  uint8_t data[3 + 2 * sick::kMaxScanValues] = {mean_samples_};
  size_t size = sick::write_scan({last_scan_, count}, units, {data + (mean ? 1 : 0), sizeof data - 1});
  sick::Telegram t;
  if (size == 0 || !sick::make_reply(mean ? sick::kMeanScanReply : sick::kScanReply,
                                     {data, size + (mean ? 1 : 0)}, 0, t))
    return;
  uint8_t out[sick::kMaxTelegramBytes];
  queue({out, through_faults(t.view(), out)});
  ++scans_sent_;
}

void SickEmulator::send_status() {
  // The status block as sicktoolbox reads it (data offsets; its payload
  // offsets are one more): software version 0-6, operating mode 7, status
  // 8 (0: fine), variant 17, measuring mode 101, scan angle 106-107 and
  // resolution 108-109 (LE16, degrees and 1/100 degree), restart mode 110,
  // the line's baud 115-116, permanent baud 118, address 119, units 121,
  // laser on 122, boot version 123-129.
  uint8_t b[sick::kStatusBytes] = {};
  auto le16 = [&](size_t at, uint16_t v) {
    b[at] = uint8_t(v & 0xFF);
    b[at + 1] = uint8_t(v >> 8);
  };
  std::string version = (config_.version + "       ").substr(0, 7);
  std::copy(version.begin(), version.end(), b);
  b[7] = uint8_t(mode_);
  b[101] = config_block_[5];  // measuring mode, as configured
  le16(106, width_deg_);
  le16(108, resolution_cdeg_);
  // The baud as the listing codes it: 0x8000 | d, with d the divider of
  // the scanner's 1 MHz UART clock, baud = 1 MHz / (d + 1) (0x8001 500 kBd,
  // 0x8019 38400, 0x8033 19200, 0x8067 9600).
  le16(115, uint16_t(0x8000 | (1'000'000 / baud_ - 1)));
  // 1: the scanner keeps its baud over a power cycle (0: back to 9600).
  b[118] = config_.power_up_baud != 9600;
  b[121] = config_block_[sick::kConfigUnits];
  b[122] = 1;
  std::copy(version.begin(), version.end(), b + 123);
  reply(sick::reply_code(sick::Request::Status), b);
}

}  // namespace troupe::emulators
