#include "drivers/sicklms200/sick_protocol.h"

#include <algorithm>
#include <cstring>

namespace troupe::drivers::sicklms200 {
namespace {

constexpr uint8_t kPassword[] = {'S', 'I', 'C', 'K', '_', 'L', 'M', 'S'};

bool frame(uint8_t address, std::span<const uint8_t> body, Telegram& out) {
  if (body.empty() || body.size() + kFrameBytes > kMaxTelegramBytes) return false;
  out.bytes[0] = kStx;
  out.bytes[1] = address;
  out.bytes[2] = uint8_t(body.size() & 0xFF);
  out.bytes[3] = uint8_t(body.size() >> 8);
  memcpy(out.bytes.data() + 4, body.data(), body.size());
  uint16_t crc = crc16({out.bytes.data(), 4 + body.size()});
  out.bytes[4 + body.size()] = uint8_t(crc & 0xFF);
  out.bytes[5 + body.size()] = uint8_t(crc >> 8);
  out.size = body.size() + kFrameBytes;
  return true;
}

}  // namespace

uint16_t crc16(std::span<const uint8_t> bytes) {
  uint16_t crc = 0;
  uint8_t prev = 0;
  for (uint8_t b : bytes) {
    crc = (crc & 0x8000) ? uint16_t(((crc & 0x7FFF) << 1) ^ 0x8005) : uint16_t(crc << 1);
    crc ^= uint16_t(b | (prev << 8));
    prev = b;
  }
  return crc;
}

bool make_request(std::span<const uint8_t> body, Telegram& out) {
  return frame(kHostAddress, body, out);
}

bool make_reply(uint8_t code, std::span<const uint8_t> data, uint8_t status, Telegram& out) {
  uint8_t body[kMaxTelegramBytes];
  if (data.size() + 2 + kFrameBytes > kMaxTelegramBytes) return false;
  body[0] = code;
  if (!data.empty()) memcpy(body + 1, data.data(), data.size());
  body[1 + data.size()] = status;
  return frame(kReplyAddress, {body, data.size() + 2}, out);
}

Telegram mode_change(Mode mode) {
  Telegram t;
  const uint8_t body[2] = {uint8_t(Request::ModeChange), uint8_t(mode)};
  make_request(body, t);
  return t;
}

bool mode_for_baud(uint32_t baud, Mode& out) {
  switch (baud) {
    case 9600:
      out = Mode::Baud9600;
      return true;
    case 19200:
      out = Mode::Baud19200;
      return true;
    case 38400:
      out = Mode::Baud38400;
      return true;
    case 500000:
      out = Mode::Baud500000;
      return true;
    default:
      return false;
  }
}

bool baud_change(uint32_t baud, Telegram& out) {
  Mode mode{};
  if (!mode_for_baud(baud, mode)) return false;
  out = mode_change(mode);
  return true;
}

Telegram enter_config() {
  uint8_t body[2 + sizeof kPassword] = {uint8_t(Request::ModeChange), uint8_t(Mode::Config)};
  memcpy(body + 2, kPassword, sizeof kPassword);
  Telegram t;
  make_request(body, t);
  return t;
}

Telegram variant(uint16_t width_deg, uint16_t resolution_cdeg) {
  const uint8_t body[5] = {uint8_t(Request::Variant), uint8_t(width_deg & 0xFF), uint8_t(width_deg >> 8),
                           uint8_t(resolution_cdeg & 0xFF), uint8_t(resolution_cdeg >> 8)};
  Telegram t;
  make_request(body, t);
  return t;
}

Telegram simple(Request request) {
  const uint8_t body[1] = {uint8_t(request)};
  Telegram t;
  make_request(body, t);
  return t;
}

Telegram write_config(std::span<const uint8_t> config) {
  uint8_t body[1 + kConfigBytes] = {uint8_t(Request::WriteConfig)};
  size_t n = std::min(config.size(), kConfigBytes);
  memcpy(body + 1, config.data(), n);
  Telegram t;
  make_request({body, 1 + n}, t);
  return t;
}

void TelegramScanner::drop_front(size_t n) {
  n = std::min(n, size_);
  memmove(buf_, buf_ + n, size_ - n);
  size_ -= n;
}

bool TelegramScanner::scan(std::span<const uint8_t>& body) {
  for (;;) {
    size_t start = 0;
    while (start < size_ && buf_[start] != kStx) {
      if (buf_[start] == kNack) ++nacks_;
      ++start;
    }
    if (start > 0) {
      skipped_ += uint32_t(start);
      drop_front(start);
    }
    if (size_ < 2) return false;
    if (buf_[1] != address_) {
      ++skipped_;
      drop_front(1);
      continue;
    }
    if (size_ < 4) return false;
    size_t len = size_t(buf_[2]) | (size_t(buf_[3]) << 8);
    if (len == 0 || len + kFrameBytes > kMaxTelegramBytes) {
      ++skipped_;
      drop_front(1);
      continue;
    }
    if (size_ < len + kFrameBytes) return false;
    uint16_t crc = uint16_t(buf_[4 + len] | (buf_[5 + len] << 8));
    if (crc16({buf_, 4 + len}) != crc) {
      ++bad_crcs_;
      drop_front(1);
      continue;
    }
    ++telegrams_;
    body = {buf_ + 4, len};
    consume_ = len + kFrameBytes;
    return true;
  }
}

size_t TelegramScanner::feed(std::span<const uint8_t> in, std::span<const uint8_t>& body) {
  body = {};
  if (consume_ > 0) {
    drop_front(consume_);
    consume_ = 0;
    if (scan(body)) return 0;
  }
  size_t used = 0;
  while (used < in.size()) {
    size_t take = std::min(in.size() - used, kMaxTelegramBytes - size_);
    memcpy(buf_ + size_, in.data() + used, take);
    size_ += take;
    used += take;
    if (scan(body)) {
      // Bytes after the telegram copied in but not looked at go back to
      // the caller, who feeds them again.
      size_t give_back = std::min(size_ - consume_, take);
      size_ -= give_back;
      return used - give_back;
    }
  }
  return used;
}

bool TelegramScanner::expire(std::span<const uint8_t>& body) {
  if (consume_ > 0) {
    drop_front(consume_);
    consume_ = 0;
  }
  while (size_ > 0) {
    if (scan(body)) return true;
    ++skipped_;
    drop_front(1);
  }
  return false;
}

bool split_reply(std::span<const uint8_t> body, Reply& out) {
  if (body.size() < 2) return false;
  out.code = body[0];
  out.data = body.subspan(1, body.size() - 2);
  out.status = body.back();
  return true;
}

bool parse_scan(std::span<const uint8_t> data, Scan& out, const char** why) {
  auto fail = [why](const char* text) {
    if (why) *why = text;
    return false;
  };
  if (data.size() < 2) return fail("scan shorter than its count");
  size_t count = size_t(data[0]) | (size_t(data[1] & 0x3F) << 8);
  if (count > kMaxScanValues) return fail("scan count over 401 values");
  if (2 + 2 * count > data.size()) return fail("scan count overruns the telegram");
  out.count = uint16_t(count);
  out.units = Units(data[1] >> 6);
  for (size_t i = 0; i < count; ++i) {
    out.ranges[i] = uint16_t((data[2 + 2 * i] | (data[3 + 2 * i] << 8)) & 0x1FFF);
  }
  return true;
}

size_t write_scan(std::span<const uint16_t> ranges, Units units, std::span<uint8_t> out) {
  size_t size = 2 + 2 * ranges.size();
  if (ranges.size() > kMaxScanValues || size > out.size()) return 0;
  out[0] = uint8_t(ranges.size() & 0xFF);
  out[1] = uint8_t(((ranges.size() >> 8) & 0x3F) | (uint8_t(units) << 6));
  for (size_t i = 0; i < ranges.size(); ++i) {
    uint16_t v = std::min<uint16_t>(ranges[i], kNoReturn);
    out[2 + 2 * i] = uint8_t(v & 0xFF);
    out[3 + 2 * i] = uint8_t(v >> 8);
  }
  return size;
}

}  // namespace troupe::drivers::sicklms200
