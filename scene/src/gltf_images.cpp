// Texture images: WebP (EXT_texture_webp) through libwebp, PNG/JPEG/BMP/GIF/... through stb, compiled into the
// loader with its allocations capped (stb_capped.h; tinygltf's own image loader is replaced). Dimensions are
// read from the header and checked and the pixels charged to the memory budget before anything is decoded;
// the decode may then allocate a few times the image's pixels, no more. An image that cannot be decoded
// (unknown format, KTX2/Basis, corrupt data, too large) is not an error here: it is recorded, left empty, and
// its textures fall back to the material's factors (select_texture_images warns once per texture).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include <fmt/core.h>
#include <tiny_gltf.h>
#include <webp/decode.h>

#include "gltf_internal.h"
#include "stb_capped.h"

namespace probebake::scene::detail {
namespace {

constexpr int kMaxImageSide = 16384; // larger textures are not decoded: probes only need an average colour

bool starts_with(const unsigned char* bytes, int size, const char* magic, int offset = 0) {
  const int n = int(std::strlen(magic));
  return size >= offset + n && std::memcmp(bytes + offset, magic, std::size_t(n)) == 0;
}

bool is_webp(const unsigned char* bytes, int size) {
  return starts_with(bytes, size, "RIFF") && starts_with(bytes, size, "WEBP", 8);
}

bool is_ktx2(const unsigned char* bytes, int size) { return starts_with(bytes, size, "\xABKTX 20\xBB"); }

// The side limit and the memory budget, both before any pixel is allocated; false with `why` set when the
// image is too large to decode.
bool admit(int width, int height, unsigned bytes_per_pixel, int index, InputPolicy& policy, std::string& why) {
  if (width > kMaxImageSide || height > kMaxImageSide) {
    why = fmt::format("{}x{} is larger than the limit of {}x{}", width, height, kMaxImageSide, kMaxImageSide);
    return false;
  }
  policy.ctx.charge(std::uint64_t(width) * std::uint64_t(height), bytes_per_pixel, fmt::format("images[{}]", index));
  return true;
}

// Pixels decoded by libwebp (RGBA8); false with `why` set when the stream is not a decodable WebP.
bool decode_webp(tinygltf::Image* image, int index, const unsigned char* bytes, int size, InputPolicy& policy,
                 std::string& why) {
  int width = 0, height = 0;
  if (WebPGetInfo(bytes, std::size_t(size), &width, &height) == 0) {
    why = "corrupt WebP header";
    return false;
  }
  if (!admit(width, height, 4, index, policy, why)) return false;
  image->image.resize(std::size_t(width) * std::size_t(height) * 4);
  if (WebPDecodeRGBAInto(bytes, std::size_t(size), image->image.data(), image->image.size(), width * 4) == nullptr) {
    image->image.clear();
    why = "corrupt WebP data";
    return false;
  }
  image->width = width;
  image->height = height;
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  return true;
}

bool decode_with_stb(tinygltf::Image* image, int index, const unsigned char* bytes, int size, InputPolicy& policy,
                     std::string& why) {
  StbHeader header;
  if (!read_stb_header(bytes, size, header)) {
    why = is_ktx2(bytes, size) ? "KTX2/Basis Universal (no decoder in this build; add a PNG/JPEG fallback `source`)"
                               : "unknown image format";
    return false;
  }
  if (!admit(header.width, header.height, 4u * (header.wide ? 2u : 1u), index, policy, why)) return false;
  const std::uint64_t cap = stb_decode_cap(header, size);
  StbImage decoded;
  switch (decode_capped(bytes, size, header, cap, decoded)) {
  case StbDecode::over_cap:
    why = fmt::format("corrupt image data: decoding asks for more than {} bytes, more than its {}x{} pixels need", cap,
                      header.width, header.height);
    return false;
  case StbDecode::failed: why = "corrupt image data"; return false;
  case StbDecode::ok: break;
  }
  image->width = decoded.width, image->height = decoded.height;
  image->component = 4;
  image->bits = header.wide ? 16 : 8;
  image->pixel_type = header.wide ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image = std::move(decoded.pixels);
  return true;
}

} // namespace

bool decode_image(tinygltf::Image* image, int index, const unsigned char* bytes, int size, InputPolicy& policy) {
  if (std::binary_search(policy.unused_images.begin(), policy.unused_images.end(), index))
    return true; // no texture refers to it: left empty, never decoded
  std::string why;
  const bool ok = size > 0 && (is_webp(bytes, size) ? decode_webp(image, index, bytes, size, policy, why)
                                                    : decode_with_stb(image, index, bytes, size, policy, why));
  if (!ok) {
    policy.image_problems[index] = why.empty() ? "empty image data" : why;
    image->image.clear();
    image->width = image->height = image->component = 0; // unusable: select_texture_images skips it
  }
  return true; // a texture never fails the load by itself
}

void decode_buffer_view_images(tinygltf::Model& model, InputPolicy& policy) {
  for (std::size_t i = 0; i < model.images.size(); ++i) {
    tinygltf::Image& image = model.images[i];
    if (image.bufferView < 0) continue;
    const int index = int(i);
    // tinygltf has checked that the view and its buffer exist, not that the bytes do.
    const tinygltf::BufferView& view = model.bufferViews[std::size_t(image.bufferView)];
    const std::vector<unsigned char>& data = model.buffers[std::size_t(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset ||
        view.byteLength > std::size_t(std::numeric_limits<int>::max())) {
      policy.image_problems[index] =
          fmt::format("bufferView {} (bytes {}..+{}) lies outside buffer {} ({} bytes)", image.bufferView,
                      view.byteOffset, view.byteLength, view.buffer, data.size());
      continue;
    }
    decode_image(&image, index, data.data() + view.byteOffset, int(view.byteLength), policy);
  }
}

} // namespace probebake::scene::detail
