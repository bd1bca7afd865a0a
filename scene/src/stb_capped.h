// stb_image compiled into the loader, every allocation it makes counted against a cap per image. Debian's
// shared libstb (which tinygltf links) grows its buffers to whatever a stream asks for: a PNG whose pixel
// data inflates far past its header's image (a deflate bomb), a chunk that declares gigabytes. Here such an
// image fails when it would pass the cap, at no cost to images within it. The loader's texture decodes all go
// through this copy (tinygltf's own image loader is replaced, gltf_files.cpp).
#pragma once

#include <cstdint>
#include <vector>

namespace probebake::scene::detail {

struct StbImage {
  std::vector<unsigned char> pixels; // width x height x 4 components of `bits` each, row by row
  int width = 0, height = 0;
  int components = 0; // in the file (the pixels always hold 4)
  int bits = 8;       // 8, or 16 for 16-bit PNGs
};

enum class StbDecode { ok, over_cap, failed };

// Decodes `bytes` (any format stb reads) to RGBA, 16 bits per component when the file has them. over_cap:
// stb asked for more than `cap_bytes` in all at some moment; failed: anything else stb refused.
StbDecode decode_capped(const unsigned char* bytes, int size, std::uint64_t cap_bytes, StbImage& out);

} // namespace probebake::scene::detail
