// See gltf_input.h.
#include "gltf_input.h"

#include "probebake/scene/scene.h"
#include "probebake/formats/error.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>

namespace probebake::samples::detail {
namespace {

using nlohmann::json;

std::uint32_t read_u32(const Bytes& b, std::size_t at) {
  std::uint32_t v = 0;
  if (at + 4 <= b.size()) std::memcpy(&v, &b[at], 4);
  return v;
}

} // namespace

void fail(const std::string& tool, const std::string& message) { throw Error(ErrorKind::input, tool + ": " + message); }

Bytes read_file(const std::filesystem::path& path, const std::string& tool) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(tool, "cannot read " + path.string());
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

GltfInput parse_gltf_input(const Bytes& bytes, const std::filesystem::path& base_dir, const std::string& tool) {
  GltfInput in;
  Bytes bin;
  const bool glb = bytes.size() >= 20 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  std::size_t json_length = glb ? read_u32(bytes, 12) : bytes.size();
  const std::size_t json_start = glb ? 20 : 0;
  if (json_start + json_length > bytes.size()) fail(tool, "truncated GLB");
  if (glb && json_start + json_length + 8 <= bytes.size()) {
    const std::size_t bin_start = json_start + json_length + 8;
    const std::size_t bin_length =
        std::min<std::size_t>(read_u32(bytes, json_start + json_length), bytes.size() - bin_start);
    bin.assign(bytes.begin() + std::ptrdiff_t(bin_start), bytes.begin() + std::ptrdiff_t(bin_start + bin_length));
  }
  in.gltf =
      json::parse(bytes.begin() + std::ptrdiff_t(json_start), bytes.begin() + std::ptrdiff_t(json_start + json_length));
  const std::vector<std::string> used = in.gltf.value("extensionsUsed", std::vector<std::string>{});
  for (const std::string& name : used)
    if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression")
      fail(tool, "the input already uses " + name + "; give the uncompressed original");
  const json buffers = in.gltf.contains("buffers") ? in.gltf["buffers"] : json::array();
  for (const json& buffer : buffers) {
    const std::string uri = buffer.value("uri", "");
    Bytes data;
    if (uri.empty())
      data = in.buffers.empty() ? bin : Bytes();
    else if (tinygltf::IsDataURI(uri)) {
      std::string mime;
      if (!tinygltf::DecodeDataURI(&data, mime, uri, 0, false)) fail(tool, "bad data URI in a buffer");
    } else
      data = read_file(base_dir / scene::percent_decode(uri), tool);
    in.buffers.push_back(std::move(data));
  }
  return in;
}

std::size_t component_size(int type) { return type == 5120 || type == 5121 ? 1 : type == 5122 || type == 5123 ? 2 : 4; }

std::size_t component_count(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4" || type == "MAT2") return 4;
  return type == "MAT3" ? 9 : 16;
}

std::size_t append_aligned(Bytes& bin, const void* data, std::size_t size) {
  bin.resize((bin.size() + 3) & ~std::size_t{3}, 0);
  const std::size_t at = bin.size();
  bin.insert(bin.end(), static_cast<const std::uint8_t*>(data), static_cast<const std::uint8_t*>(data) + size);
  return at;
}

void embed_images(json& gltf, json& views, Bytes& bin, const std::filesystem::path& base_dir, const std::string& tool) {
  if (!gltf.contains("images")) return;
  for (json& image : gltf["images"]) {
    if (!image.contains("uri")) continue;
    const std::string uri = image["uri"].get<std::string>();
    Bytes data;
    std::string mime;
    if (uri.rfind("data:", 0) == 0) {
      mime = uri.substr(5, uri.find(';') - 5);
      std::string ignored;
      if (!tinygltf::DecodeDataURI(&data, ignored,
                                   "data:application/octet-stream;base64," + uri.substr(uri.find(',') + 1), 0, false))
        fail(tool, "bad image data URI");
    } else {
      data = read_file(base_dir / scene::percent_decode(uri), tool);
      const std::string ext = std::filesystem::path(uri).extension().string();
      mime = ext == ".png" ? "image/png" : ext == ".webp" ? "image/webp" : ext == ".ktx2" ? "image/ktx2" : "image/jpeg";
    }
    image.erase("uri");
    image["mimeType"] = mime;
    image["bufferView"] = views.size();
    views.push_back(
        {{"buffer", 0}, {"byteOffset", append_aligned(bin, data.data(), data.size())}, {"byteLength", data.size()}});
  }
}

Bytes glb_bytes(const json& gltf, Bytes bin) {
  std::string text = gltf.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  bin.resize((bin.size() + 3) & ~std::size_t{3}, 0);
  Bytes out;
  auto u32 = [&out](std::size_t v) {
    const auto x = static_cast<std::uint32_t>(v);
    out.insert(out.end(), reinterpret_cast<const std::uint8_t*>(&x), reinterpret_cast<const std::uint8_t*>(&x) + 4);
  };
  out.insert(out.end(), {'g', 'l', 'T', 'F'});
  u32(2);
  u32(12 + 8 + text.size() + 8 + bin.size());
  u32(text.size());
  u32(0x4E4F534Au);
  out.insert(out.end(), text.begin(), text.end());
  u32(bin.size());
  u32(0x004E4942u);
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

} // namespace probebake::samples::detail
