// stb_image compiled into the loader, every allocation it makes counted against a cap per image. Debian's
// shared libstb (which tinygltf links) grows its buffers to whatever a stream asks for: a PNG whose pixel
// data inflates far past its header's image (a deflate bomb), a chunk that declares gigabytes. Here such an
// image fails when it would pass the cap, at no cost to images within it. The loader's texture decodes all go
// through this copy (tinygltf's own image loader is replaced, gltf_files.cpp).
#pragma once

#include <cstdint>
#include <vector>

namespace probebake::scene::detail {

// What an image's header says, read before any pixel is decoded.
struct StbHeader {
  int width = 0, height = 0;
  bool wide = false; // 16 bits per component (PNG)
};

struct StbImage {
  std::vector<unsigned char> pixels; // width x height x 4 components of 8 bits, or 16 when the header is wide
  int width = 0, height = 0;
};

enum class StbDecode { ok, over_cap, failed };

// The header of `bytes` (any format stb reads); false when stb knows no such format.
bool read_stb_header(const unsigned char* bytes, int size, StbHeader& out);

// What stb holds at most while it decodes an image within its header: the compressed data (grown by
// doubling), the decompressed rows, the file's pixels and their RGBA copy, and 1 MiB of tables.
std::uint64_t stb_decode_cap(const StbHeader& header, int size);

// Decodes `bytes` to RGBA, 16 bits per component when `header` is wide. over_cap: stb asked for more than
// `cap_bytes` in all at some moment; failed: anything else stb refused.
StbDecode decode_capped(const unsigned char* bytes, int size, const StbHeader& header, std::uint64_t cap_bytes,
                        StbImage& out);

} // namespace probebake::scene::detail
