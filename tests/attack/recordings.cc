#include "tests/attack/recordings.h"

#include "wire/record/log_file.h"
#include "wire/writer.h"

namespace troupe::attack {

bool write_recording(const std::string& path, const std::vector<uint64_t>& times_us, std::string& error) {
  record::LogWriter log;
  if (!log.open(path, 1700000000000000ull, error)) return false;
  wire::MessageWriter w;
  const wire::Address pos(0, uint16_t(wire::Interface::Position2d), 0);
  {
    auto& b = w.start();
    auto hello = wire::CreateHello(b, wire::kProtocolVersion, b.CreateString("recorded"), 1u << 20);
    if (!log.write(
            0, w.finish(wire::make_header({}, wire::Kind::Hello, 0, 0, 0), wire::Body::Hello, hello.Union()),
            error))
      return false;
  }
  {
    auto& b = w.start();
    auto info = wire::CreateDeviceInfo(b, &pos, b.CreateString(""), b.CreateString("kinematic"));
    auto list = wire::CreateDeviceList(b, b.CreateVector(&info, 1));
    if (!log.write(0,
                   w.finish(wire::make_header({}, wire::Kind::DeviceList, 0, 1, 0), wire::Body::DeviceList,
                            list.Union()),
                   error))
      return false;
  }
  uint32_t seq = 0;
  for (uint64_t t : times_us) {
    auto& b = w.start();
    const wire::Pose2d pose(0.01f * float(seq), 0, 0);
    auto state = wire::CreatePosition2dState(b, &pose);
    auto frame = w.finish(wire::make_header(pos, wire::Kind::Data, 1, ++seq, t), wire::Body::Position2dState,
                          state.Union());
    if (!log.write(t, frame, error)) return false;
  }
  return log.close(error);
}

std::vector<uint64_t> steady_times(int n, uint64_t period_us) {
  std::vector<uint64_t> t;
  for (int i = 0; i < n; ++i) t.push_back(uint64_t(i) * period_us);
  return t;
}

}  // namespace troupe::attack
