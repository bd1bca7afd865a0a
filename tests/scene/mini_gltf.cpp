#include "mini_gltf.h"

#include "gltf_input.h" // samples/src: make-scene's GLB container and aligned appends

#include <fstream>

#include <glm/common.hpp>

namespace probebake::test {

int MiniGltf::add_view(const void* data, std::size_t size) {
  const std::size_t offset = samples::detail::append_aligned(bin, data, size);
  json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}});
  json["buffers"][0]["byteLength"] = bin.size();
  return int(json["bufferViews"].size()) - 1;
}

int MiniGltf::add_accessor(int view, int component_type, std::size_t count, const std::string& type, bool normalized) {
  nlohmann::json a = {{"componentType", component_type}, {"count", count}, {"type", type}};
  if (view >= 0) a["bufferView"] = view;
  if (normalized) a["normalized"] = true;
  json["accessors"].push_back(a);
  return int(json["accessors"].size()) - 1;
}

MiniGltf MiniGltf::one_mesh_node() {
  MiniGltf g;
  g.json = {{"asset", {{"version", "2.0"}}},
            {"buffers", {{{"byteLength", 0}}}},
            {"bufferViews", nlohmann::json::array()},
            {"accessors", nlohmann::json::array()},
            {"scene", 0},
            {"scenes", {{{"nodes", {0}}}}},
            {"nodes", {{{"mesh", 0}}}}};
  return g;
}

MiniGltf MiniGltf::triangles(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                             int index_component_type) {
  MiniGltf g = one_mesh_node();
  g.json["nodes"][0]["name"] = "root";
  const int pv = g.add_view(positions.data(), positions.size() * sizeof(glm::vec3));
  const int pa = g.add_accessor(pv, 5126, positions.size(), "VEC3");
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (auto p : positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  g.json["accessors"][pa]["min"] = {lo.x, lo.y, lo.z};
  g.json["accessors"][pa]["max"] = {hi.x, hi.y, hi.z};
  nlohmann::json primitive = {{"attributes", {{"POSITION", pa}}}};
  if (!indices.empty()) {
    int iv;
    if (index_component_type == 5123) {
      std::vector<std::uint16_t> small(indices.begin(), indices.end());
      iv = g.add_view(small.data(), small.size() * 2);
    } else if (index_component_type == 5121) {
      std::vector<std::uint8_t> tiny(indices.begin(), indices.end());
      iv = g.add_view(tiny.data(), tiny.size());
    } else {
      iv = g.add_view(indices.data(), indices.size() * 4);
    }
    primitive["indices"] = g.add_accessor(iv, index_component_type, indices.size(), "SCALAR");
  }
  g.json["meshes"] = {{{"primitives", {primitive}}}};
  return g;
}

// The GLB container is make-scene's (the same framing its convert writes): JSON padded with spaces, BIN with zeros.
std::vector<unsigned char> MiniGltf::glb() const {
  nlohmann::json j = json;
  j["buffers"][0].erase("uri");
  return samples::detail::glb_bytes(j, bin);
}

namespace {
void write_bytes(const std::filesystem::path& path, const void* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
}

std::string base64(const std::vector<unsigned char>& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    std::uint32_t v = std::uint32_t(in[i]) << 16;
    if (i + 1 < in.size()) v |= std::uint32_t(in[i + 1]) << 8;
    if (i + 2 < in.size()) v |= in[i + 2];
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < in.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? table[v & 63] : '=';
  }
  return out;
}
} // namespace

std::vector<unsigned char> MiniGltf::gltf_text() const {
  nlohmann::json j = json;
  j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
  const std::string text = j.dump(1);
  return {text.begin(), text.end()};
}

void MiniGltf::write_gltf(const std::filesystem::path& path, const std::string& bin_name) const {
  if (bin_name.empty()) {
    const auto text = gltf_text();
    return write_bytes(path, text.data(), text.size());
  }
  nlohmann::json j = json;
  j["buffers"][0]["uri"] = bin_name;
  write_bytes(path.parent_path() / bin_name, bin.data(), bin.size());
  const std::string text = j.dump(1);
  write_bytes(path, text.data(), text.size());
}

void MiniGltf::write_glb(const std::filesystem::path& path) const {
  const auto bytes = glb();
  write_bytes(path, bytes.data(), bytes.size());
}

std::filesystem::path test_dir(const std::string& name) {
  const auto dir = std::filesystem::path(PROBEBAKE_BINARY_DIR) / "test-tmp" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

} // namespace probebake::test
