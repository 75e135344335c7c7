// Writes one valid frame of every body type into a folder: the fuzzers'
// starting corpus, so they explore from real messages rather than from zero.
// Every message a client sends (tests/wire/samples.h), the data and replies
// a node sends, and the frames that once crashed something.
#include <cstdio>
#include <string>
#include <vector>

#include "tests/wire/samples.h"
#include "wire/writer.h"

using namespace troupe::wire;

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: fuzz_seeds DIR\n");
    return 2;
  }
  MessageWriter w;
  int written = 0;
  auto save = [&](const char* name, std::span<const uint8_t> frame) {
    std::string path = std::string(argv[1]) + "/" + name;
    FILE* f = fopen(path.c_str(), "wb");
    if (f == nullptr) return;
    const uint8_t cut = 7;  // the fuzzer reads this first byte as the chunk size
    fwrite(&cut, 1, 1, f);
    fwrite(frame.data(), 1, frame.size(), f);
    fclose(f);
    ++written;
  };
  Address pos(0, uint16_t(Interface::Position2d), 0);
  Address ranger(0, uint16_t(Interface::Ranger), 0);
  Pose2d p(1, 2, 3);
  {
    auto& b = w.start();
    Cov2d c(1, 0, 0, 1, 0, 1);
    auto body = CreatePosition2dState(b, &p, &p, true, &c);
    save("position2d", w.finish(make_header(pos, Kind::Data, 1, 1, 5), Body::Position2dState, body.Union()));
  }
  {
    auto& b = w.start();
    std::vector<uint16_t> r(181, 1234);
    std::vector<uint8_t> in(181, 9);
    auto body = CreateRangerScan(b, b.CreateVector(r), 0.001f, -1.57f, 0.0174f, 8, b.CreateVector(in));
    save("ranger", w.finish(make_header(ranger, Kind::Data, 1, 2, 5), Body::RangerScan, body.Union()));
  }
  {
    auto& b = w.start();
    Address a(0, 1, 0);
    std::vector<flatbuffers::Offset<DeviceInfo>> infos = {
        CreateDeviceInfo(b, &a, b.CreateString("r0"), b.CreateString("kinematic"))};
    auto body = CreateDeviceList(b, b.CreateVector(infos));
    save("devicelist", w.finish(make_header({}, Kind::DeviceList, 0, 3, 5), Body::DeviceList, body.Union()));
  }
  {
    auto& b = w.start();
    auto body = CreateHello(b, 1, b.CreateString("node"), 1 << 20, 0, 99);
    save("hello", w.finish(make_header({}, Kind::Hello, 0, 0, 5), Body::Hello, body.Union()));
  }
  {
    auto& b = w.start();
    std::vector<Blob> blobs = {Blob(0xff0000, 10, 1, 2, 0, 3, 0, 4, 1500, 1)};
    auto body = CreateBlobList(b, b.CreateVectorOfStructs(blobs), 80, 60);
    save("blobs", w.finish(make_header(Address(0, uint16_t(Interface::Blobfinder), 0), Kind::Data, 1, 4, 5),
                           Body::BlobList, body.Union()));
  }
  {
    auto& b = w.start();
    std::vector<Hypothesis> hyps = {Hypothesis(p, Cov2d(1, 0, 0, 1, 0, 1), 0.9f)};
    auto body = CreateLocalizeState(b, b.CreateVectorOfStructs(hyps), 0, 77);
    save("localize", w.finish(make_header(Address(0, uint16_t(Interface::Localize), 0), Kind::Data, 1, 5, 5),
                              Body::LocalizeState, body.Union()));
  }
  {
    auto& b = w.start();
    auto body = CreateError(b, ErrorCode::BadFrame, b.CreateString("why"));
    save("error", w.finish(make_header({}, Kind::Error, 0, 0, 5), Body::Error, body.Union()));
  }
  {
    auto& b = w.start();
    auto body = CreateSimPose(b, b.CreateString("r0"), &p);
    save("simpose", w.finish(make_header(Address(0, uint16_t(Interface::Simulation), 0), Kind::Request, 6, 6, 5),
                             Body::SimPose, body.Union()));
  }
  {
    auto& b = w.start();
    auto body = CreateSimGame(b, 1, 2, GamePhase::GoalPause, 3, b.CreateString("goal yellow"), 42);
    save("simgame", w.finish(make_header(Address(0, uint16_t(Interface::Simulation), 0), Kind::Data, 2, 9, 5),
                             Body::SimGame, body.Union()));
  }
  {
    auto& b = w.start();
    std::vector<flatbuffers::Offset<flatbuffers::String>> options = {b.CreateString("policy=block")};
    auto robot = b.CreateString("blue0");
    auto plugin = b.CreateString("goalkeeper");
    auto body = CreateSimPlayer(b, robot, plugin, b.CreateVector(options));
    save("simplayer", w.finish(make_header(Address(0, uint16_t(Interface::Simulation), 0), Kind::Request, 9, 10, 5),
                               Body::SimPlayer, body.Union()));
  }
  save("pull", w.empty(make_header(pos, Kind::Pull, 0, 7, 5)));
  {
    // Regression: a body offset without a body type. Valid for the verifier
    // (a NONE union is not followed); it once crashed the JSON printing of
    // whole messages (see wire/cli/format.cc).
    auto& b = w.start();
    auto body = CreateSwitch(b, true);
    Header h = make_header(pos, Kind::Request, 2, 8, 5);
    MessageBuilder mb(b);
    mb.add_header(&h);
    mb.add_body(body.Union());
    b.FinishSizePrefixed(mb.Finish());
    save("body-without-type", {b.GetBufferPointer(), b.GetSize()});
  }
  for (const troupe::testing::WireSample& sample : troupe::testing::wire_samples()) {
    save(("client-" + sample.name).c_str(), sample.frame);
  }
  // Regression: a Hello and a TimeSync whose body type is set but whose body
  // is absent (44 bytes): valid for the verifier; they crashed the node.
  for (Kind kind : {Kind::Hello, Kind::TimeSync}) {
    auto& b = w.start();
    Header h = make_header({}, kind, 0, 9, 5);
    MessageBuilder mb(b);
    mb.add_body_type(kind == Kind::Hello ? Body::Hello : Body::TimeSync);
    mb.add_header(&h);
    b.FinishSizePrefixed(mb.Finish());
    save(kind == Kind::Hello ? "hello-without-body" : "timesync-without-body", {b.GetBufferPointer(), b.GetSize()});
  }
  printf("%d seed frames in %s\n", written, argv[1]);
  return written > 0 ? 0 : 1;
}
