// What the allocation cap costs a texture's decode: the loader's own stb (scene/src/stb_capped.h, the header
// read and every allocation counted against the loader's cap) against Debian's libstb on the same bytes, RGBA8 images of a few sizes (a gradient with
// noise, stb's own encoder), both to RGBA, median of the runs.
//
// Usage: probebake-bench-png [--runs N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <random>
#include <vector>

#include <stb_image.h>
#include <stb_image_write.h>

#include "bench_args.h"
#include "stb_capped.h"

namespace {

std::vector<unsigned char> encode(int side) {
  std::vector<unsigned char> rgba(std::size_t(side) * std::size_t(side) * 4);
  std::mt19937 random(7);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      unsigned char* p = &rgba[(std::size_t(y) * std::size_t(side) + std::size_t(x)) * 4];
      const unsigned noise = random() % 16;
      p[0] = static_cast<unsigned char>(x * 255 / side + noise),
      p[1] = static_cast<unsigned char>(y * 255 / side + noise);
      p[2] = static_cast<unsigned char>(128 + noise), p[3] = 255;
    }
  std::vector<unsigned char> png;
  stbi_write_png_to_func(
      [](void* out, void* data, int size) {
        auto* bytes = static_cast<std::vector<unsigned char>*>(out);
        bytes->insert(bytes->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
      },
      &png, side, side, 4, rgba.data(), side * 4);
  return png;
}

template <class F>
double median_ms(int runs, F&& f) {
  std::vector<double> ms;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

} // namespace

int main(int argc, char** argv) {
  const std::optional<int> parsed_runs = probebake::bench::parse_runs(argc, argv, 1, 9);
  if (!parsed_runs) return std::fprintf(stderr, "usage: probebake-bench-png [--runs N]\n"), 1;
  const int runs = *parsed_runs;
  std::printf("| side | PNG bytes | loader's stb, capped, ms | libstb ms | ratio |\n|--:|--:|--:|--:|--:|\n");
  for (int side : {512, 1024, 2048, 4096}) {
    const std::vector<unsigned char> png = encode(side);
    bool ok = true;
    const double capped = median_ms(runs, [&] {
      probebake::scene::detail::StbHeader header;
      probebake::scene::detail::StbImage image;
      ok = probebake::scene::detail::read_stb_header(png.data(), int(png.size()), header) &&
           probebake::scene::detail::decode_capped(png.data(), int(png.size()), header,
                                                   probebake::scene::detail::stb_decode_cap(header, int(png.size())),
                                                   image) == probebake::scene::detail::StbDecode::ok &&
           ok;
    });
    const double libstb = median_ms(runs, [&] {
      int w = 0, h = 0, n = 0;
      stbi_image_free(stbi_load_from_memory(png.data(), int(png.size()), &w, &h, &n, 4));
    });
    if (!ok) return std::fprintf(stderr, "the capped decode refused a valid PNG\n"), 1;
    std::printf("| %d | %zu | %.2f | %.2f | %.2f |\n", side, png.size(), capped, libstb, capped / libstb);
  }
  return 0;
}
