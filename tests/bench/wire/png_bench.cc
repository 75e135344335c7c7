// What encoding a camera image as PNG costs the sender, against what
// building the raw image's frame costs (the baseline every image pays):
// CPU time per 320x240 Rgb8 image, the median of repeats, for a flat-shaded
// scene as the simulator renders and for noise (the worst case for deflate).
//
//   build/host-release/tests/bench/wire/png_bench [--repeats 7] [--images 20]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>

#include "runtime/random.h"
#include "tests/bench/wire/sizes.h"
#include "wire/png.h"
#include "wire/writer.h"

namespace {

double cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Median over `repeats` of the CPU time of `images` runs of `work`, us per run.
template <typename Work>
double median_us(int repeats, int images, Work work) {
  std::vector<double> per_image;
  for (int r = 0; r < repeats; ++r) {
    const double start = cpu_s();
    for (int i = 0; i < images; ++i) work();
    per_image.push_back((cpu_s() - start) / images * 1e6);
  }
  std::sort(per_image.begin(), per_image.end());
  return per_image[per_image.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace troupe;
  int repeats = 7, images = 20;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--repeats")) repeats = std::max(1, atoi(argv[i + 1]));
    if (!strcmp(argv[i], "--images")) images = std::max(1, atoi(argv[i + 1]));
  }
  const std::vector<uint8_t> flat = wire::sizes::flat_scene_320x240();
  std::vector<uint8_t> noise(flat.size());
  const Random random(1);
  for (size_t i = 0; i < noise.size(); ++i) noise[i] = uint8_t(random.bits(0, i));

  wire::MessageWriter writer;
  size_t frame_bytes = 0;
  auto raw_frame = [&](const std::vector<uint8_t>& pixels, wire::ImageCompression packing, uint32_t stride) {
    auto& b = writer.start();
    auto body = wire::CreateCameraImage(b, 320, 240, wire::PixelFormat::Rgb8, stride, packing,
                                        b.CreateVector(pixels));
    frame_bytes =
        writer.finish(wire::make_header({}, wire::Kind::Data, 1, 1, 0), wire::Body::CameraImage, body.Union())
            .size();
  };
  printf("| image (320x240 Rgb8) | raw frame (us) | PNG encode + frame (us) | PNG / raw | PNG bytes |\n");
  printf("|---|---:|---:|---:|---:|\n");
  const std::pair<const char*, const std::vector<uint8_t>*> images_of[] = {{"flat-shaded scene", &flat},
                                                                           {"noise", &noise}};
  for (const auto& [name, pixels] : images_of) {
    const double raw_us =
        median_us(repeats, images, [&] { raw_frame(*pixels, wire::ImageCompression::None, 960); });
    std::vector<uint8_t> png;
    std::string why;
    const double png_us = median_us(repeats, images, [&] {
      if (!wire::encode_png({320, 240, wire::PixelFormat::Rgb8, 960, *pixels}, png, why)) {
        fprintf(stderr, "png_bench: %s\n", why.c_str());
        exit(1);
      }
      raw_frame(png, wire::ImageCompression::Png, 0);
    });
    printf("| %s | %.0f | %.0f | %.1f | %zu |\n", name, raw_us, png_us, png_us / raw_us, png.size());
  }
  printf("\nmedian of %d repeats of %d images each, process CPU time\n", repeats, images);
  return 0;
}
