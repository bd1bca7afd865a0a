#include "stb_capped.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace probebake::scene::detail {
namespace {

// The allocation count of the decode running on this thread: stb is called with one image at a time.
struct Allowance {
  std::uint64_t cap = 0, used = 0;
  bool over = false;
};
thread_local Allowance t_allowance;

constexpr std::size_t kHeader = alignof(std::max_align_t); // each block's size, before it

void* capped_malloc(std::size_t size) {
  Allowance& a = t_allowance;
  if (size > a.cap - a.used) return a.over = true, nullptr;
  if (size > SIZE_MAX - kHeader) return nullptr;
  auto* block = static_cast<unsigned char*>(std::malloc(size + kHeader));
  if (block == nullptr) return nullptr;
  std::memcpy(block, &size, sizeof(size));
  a.used += size;
  return block + kHeader;
}

void capped_free(void* p) {
  if (p == nullptr) return;
  unsigned char* block = static_cast<unsigned char*>(p) - kHeader;
  std::size_t size = 0;
  std::memcpy(&size, block, sizeof(size));
  t_allowance.used -= size;
  std::free(block);
}

void* capped_realloc(void* p, std::size_t size) {
  if (p == nullptr) return capped_malloc(size);
  unsigned char* block = static_cast<unsigned char*>(p) - kHeader;
  std::size_t old = 0;
  std::memcpy(&old, block, sizeof(old));
  Allowance& a = t_allowance;
  if (size > old && size - old > a.cap - a.used) return a.over = true, nullptr;
  if (size > SIZE_MAX - kHeader) return nullptr;
  auto* grown = static_cast<unsigned char*>(std::realloc(block, size + kHeader));
  if (grown == nullptr) return nullptr;
  std::memcpy(grown, &size, sizeof(size));
  a.used = a.used - old + size;
  return grown + kHeader;
}

} // namespace
} // namespace probebake::scene::detail

// stb's own code, static in this file so that it never clashes with libstb's.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO
#define STBI_MALLOC(size) probebake::scene::detail::capped_malloc(size)
#define STBI_REALLOC(p, size) probebake::scene::detail::capped_realloc(p, size)
#define STBI_FREE(p) probebake::scene::detail::capped_free(p)
#include <stb_image.h>

namespace probebake::scene::detail {

namespace {

std::uint64_t pixel_bytes(const StbHeader& header) { return 4u * (header.wide ? 2u : 1u); }

} // namespace

bool read_stb_header(const unsigned char* bytes, int size, StbHeader& out) {
  t_allowance = {2u * std::uint64_t(std::max(size, 0)) + (1u << 20), 0, false}; // the parser's own state
  int components = 0;
  if (stbi_info_from_memory(bytes, size, &out.width, &out.height, &components) == 0) return false;
  out.wide = stbi_is_16_bit_from_memory(bytes, size) != 0;
  return true;
}

std::uint64_t stb_decode_cap(const StbHeader& header, int size) {
  return 2u * std::uint64_t(std::max(size, 0)) +
         4u * std::uint64_t(header.width) * std::uint64_t(header.height) * pixel_bytes(header) + (1u << 20);
}

StbDecode decode_capped(const unsigned char* bytes, int size, const StbHeader& header, std::uint64_t cap_bytes,
                        StbImage& out) {
  t_allowance = {cap_bytes, 0, false};
  int width = 0, height = 0, components = 0;
  void* pixels = header.wide
                     ? static_cast<void*>(stbi_load_16_from_memory(bytes, size, &width, &height, &components, 4))
                     : static_cast<void*>(stbi_load_from_memory(bytes, size, &width, &height, &components, 4));
  const bool over = t_allowance.over;
  if (pixels == nullptr || width < 1 || height < 1) {
    stbi_image_free(pixels);
    return over ? StbDecode::over_cap : StbDecode::failed;
  }
  const std::size_t bytes_out = std::size_t(width) * std::size_t(height) * std::size_t(pixel_bytes(header));
  out.pixels.assign(static_cast<unsigned char*>(pixels), static_cast<unsigned char*>(pixels) + bytes_out);
  stbi_image_free(pixels);
  out.width = width, out.height = height;
  return StbDecode::ok;
}

} // namespace probebake::scene::detail
