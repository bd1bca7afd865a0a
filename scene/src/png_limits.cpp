#include "png_limits.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>

#include <fmt/core.h>
#include <zlib.h>

namespace probebake::scene::detail {
namespace {

std::uint32_t big_endian32(const unsigned char* p) {
  return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | std::uint32_t(p[3]);
}

struct Header {
  std::uint32_t width = 0, height = 0;
  unsigned bit_depth = 0, channels = 0;
  bool interlaced = false;
};

// The bytes the pixel data inflates to: per row a filter byte and the row's bits, per Adam7 pass when
// interlaced (PNG specification, 8.2). 0 for a header stb refuses anyway.
std::uint64_t raw_bytes(const Header& h) {
  if (h.channels == 0 || h.bit_depth == 0) return 0;
  const auto pass_bytes = [&](std::uint64_t w, std::uint64_t rows) {
    return w == 0 || rows == 0 ? 0 : rows * (1 + (w * h.channels * h.bit_depth + 7) / 8);
  };
  if (!h.interlaced) return pass_bytes(h.width, h.height);
  constexpr int x0[7] = {0, 4, 0, 2, 0, 1, 0}, dx[7] = {8, 8, 4, 4, 2, 2, 1};
  constexpr int y0[7] = {0, 0, 4, 0, 2, 0, 1}, dy[7] = {8, 8, 8, 4, 4, 2, 2};
  std::uint64_t total = 0;
  for (int p = 0; p < 7; ++p)
    total += pass_bytes((h.width + dx[p] - 1 - x0[p]) / dx[p], (h.height + dy[p] - 1 - y0[p]) / dy[p]);
  return total;
}

Header read_header(const unsigned char* ihdr) {
  Header h;
  h.width = big_endian32(ihdr), h.height = big_endian32(ihdr + 4);
  h.bit_depth = ihdr[8];
  constexpr unsigned kChannels[7] = {1, 0, 3, 1, 2, 0, 4}; // by colour type: grey, -, RGB, palette, grey+alpha, -, RGBA
  h.channels = ihdr[9] < 7 ? kChannels[ihdr[9]] : 0;
  h.interlaced = ihdr[12] == 1;
  return h;
}

// Counts what a zlib stream (raw deflate for Apple's CgBI PNGs) inflates to, fed chunk by chunk, stopping
// as soon as it passes `limit`.
class InflateCounter {
public:
  InflateCounter(bool raw, std::uint64_t limit) : limit_(limit) { ok_ = inflateInit2(&stream_, raw ? -MAX_WBITS : MAX_WBITS) == Z_OK; }
  ~InflateCounter() {
    if (ok_) inflateEnd(&stream_);
  }
  InflateCounter(const InflateCounter&) = delete;
  InflateCounter& operator=(const InflateCounter&) = delete;

  // False once the output passes the limit. A stream zlib cannot read is left to stb.
  bool feed(const unsigned char* data, std::uint32_t size) {
    if (!ok_ || ended_) return true;
    stream_.next_in = const_cast<Bytef*>(data); // zlib's API is not const; it does not write the input
    stream_.avail_in = size;
    while (stream_.avail_in > 0) {
      stream_.next_out = window_.data();
      stream_.avail_out = uInt(window_.size());
      const int status = inflate(&stream_, Z_NO_FLUSH);
      if (stream_.total_out > limit_) return false;
      if (status == Z_STREAM_END) return ended_ = true;
      if (status != Z_OK) return ended_ = true; // corrupt: stb reports it
    }
    return true;
  }
  std::uint64_t total() const { return stream_.total_out; }

private:
  z_stream stream_{};
  std::array<Bytef, 1 << 16> window_{};
  std::uint64_t limit_;
  bool ok_ = false, ended_ = false;
};

} // namespace

bool png_within_limits(const unsigned char* bytes, std::size_t size, std::string& why) {
  if (size < 8 || std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) != 0) return true;
  Header header;
  std::uint64_t limit = 0;
  std::unique_ptr<InflateCounter> counter;
  bool cgbi = false;
  std::size_t at = 8;
  for (int chunk = 0; at + 12 <= size; ++chunk) {
    const std::uint32_t length = big_endian32(bytes + at);
    if (length > size - at - 12) {
      why = fmt::format("corrupt PNG: chunk {} at byte {} declares {} bytes, {} are left", chunk, at, length, size - at - 12);
      return false;
    }
    const unsigned char* type = bytes + at + 4;
    const unsigned char* data = bytes + at + 8;
    if (std::memcmp(type, "IEND", 4) == 0) break;
    if (std::memcmp(type, "CgBI", 4) == 0) cgbi = true;
    if (std::memcmp(type, "IHDR", 4) == 0 && length == 13 && !counter) {
      header = read_header(data);
      limit = raw_bytes(header);
    }
    if (std::memcmp(type, "IDAT", 4) == 0 && limit > 0) {
      if (!counter) counter = std::make_unique<InflateCounter>(cgbi, limit);
      if (!counter->feed(data, length)) {
        why = fmt::format("corrupt PNG: its pixel data inflates past the {} bytes its {}x{} header needs (chunk {} at byte {})",
                          limit, header.width, header.height, chunk, at);
        return false;
      }
    }
    at += 12 + std::size_t(length);
  }
  return true; // a file cut short after a whole chunk: stb reports it
}

} // namespace probebake::scene::detail
