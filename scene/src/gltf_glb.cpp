// The GLB container (glTF 2.0 spec §4.4), read as leniently as the spec allows: bytes past the header's
// declared length (the validator's GLB_EXTRA_DATA) and chunks of unknown type ("client implementations
// must ignore chunks with unknown types") are skipped with one warning each. What tinygltf 2.7 reads is
// then the canonical container: header, JSON chunk and, when the file has one, its first BIN chunk.
// Every length is checked against the bytes present before anything is copied.
#include <cstring>

#include <fmt/core.h>

#include "gltf_internal.h"

namespace probebake::scene::detail {
namespace {

constexpr std::uint32_t kJsonChunk = 0x4E4F534Au; // "JSON"
constexpr std::uint32_t kBinChunk = 0x004E4942u;  // "BIN\0"
constexpr std::size_t kHeaderBytes = 12;
constexpr std::size_t kChunkHeaderBytes = 8;

std::uint32_t read_u32(const unsigned char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v; // glTF is little-endian, as is every platform probebake runs on
}

void append_u32(std::vector<unsigned char>& out, std::uint32_t v) {
  const auto* p = reinterpret_cast<const unsigned char*>(&v);
  out.insert(out.end(), p, p + 4);
}

void append_chunk(std::vector<unsigned char>& out, std::uint32_t type, std::span<const unsigned char> data,
                  unsigned char pad) {
  const std::size_t padded = (data.size() + 3) / 4 * 4;
  append_u32(out, static_cast<std::uint32_t>(padded));
  append_u32(out, type);
  out.insert(out.end(), data.begin(), data.end());
  out.insert(out.end(), padded - data.size(), pad);
}

std::string chunk_type_name(std::uint32_t type) {
  std::string name;
  for (int i = 0; i < 4; ++i) {
    const char c = char((type >> (8 * i)) & 0xFF);
    name += (c >= 0x20 && c < 0x7F) ? c : '?';
  }
  return name;
}

} // namespace

GlbChunks split_glb(std::span<const unsigned char> bytes, const Context& ctx) {
  if (bytes.size() < kHeaderBytes + kChunkHeaderBytes) ctx.fail("glb", "file is shorter than a GLB header");
  GlbChunks out;
  const std::uint32_t declared = read_u32(&bytes[8]);
  if (declared < kHeaderBytes + kChunkHeaderBytes) ctx.fail("glb", "declared length is shorter than a GLB header");
  if (declared > bytes.size())
    ctx.fail("glb", fmt::format("header declares {} bytes but the file has {} (truncated)", declared, bytes.size()));
  if (declared < bytes.size())
    out.warnings.push_back(
        fmt::format("glb: {} bytes after the declared length {} ignored", bytes.size() - declared, declared));
  const std::span<const unsigned char> glb = bytes.first(declared);

  std::size_t offset = kHeaderBytes;
  for (int index = 0; offset < glb.size(); ++index) {
    if (glb.size() - offset < kChunkHeaderBytes) {
      out.warnings.push_back(fmt::format("glb: {} bytes after the last chunk ignored", glb.size() - offset));
      break;
    }
    const std::uint32_t length = read_u32(&glb[offset]);
    const std::uint32_t type = read_u32(&glb[offset + 4]);
    const std::size_t data = offset + kChunkHeaderBytes;
    const std::string place = fmt::format("glb: chunk {}", index);
    if (index == 0 && type != kJsonChunk) ctx.fail("glb", "first chunk is not a JSON chunk");
    if (length > glb.size() - data) ctx.fail(place, fmt::format("{} bytes are longer than the file", length));
    const std::span<const unsigned char> payload = glb.subspan(data, length);
    if (index == 0) {
      out.json = payload;
    } else if (type == kBinChunk && !out.bin) {
      out.bin = payload;
    } else if (type == kBinChunk || type == kJsonChunk) {
      ctx.fail(place, fmt::format("a second {} chunk (a GLB has at most one of each)", chunk_type_name(type)));
    } else {
      out.warnings.push_back(
          fmt::format("{}: unknown type '{}' skipped ({} bytes)", place, chunk_type_name(type), length));
    }
    offset = data + length;
  }
  out.canonical = out.warnings.empty() && declared == bytes.size() && out.json.size() % 4 == 0 &&
                  (!out.bin || (out.bin->size() % 4 == 0 && !out.bin->empty()));
  return out;
}

std::vector<unsigned char> canonical_glb(std::span<const unsigned char> bytes, const GlbChunks& chunks) {
  std::vector<unsigned char> out(bytes.begin(), bytes.begin() + kHeaderBytes);
  append_chunk(out, kJsonChunk, chunks.json, ' ');
  // An empty BIN chunk is left out: tinygltf 2.7 refuses one, and the spec says it SHOULD be omitted.
  if (chunks.bin && !chunks.bin->empty()) append_chunk(out, kBinChunk, *chunks.bin, 0);
  const auto total = static_cast<std::uint32_t>(out.size());
  std::memcpy(&out[8], &total, 4);
  return out;
}

} // namespace probebake::scene::detail
