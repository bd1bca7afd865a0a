// Hand-built glTF files for loader tests: every byte is under the test's control, so each malformed
// input can be produced exactly (the sample generator writes only valid files).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace probebake::test {

struct MiniGltf {
  nlohmann::json json;
  std::vector<unsigned char> bin;

  // The skeleton every hand-built file starts from: one empty buffer, no views or accessors yet, and scene 0
  // of one node that uses mesh 0 (which the caller adds).
  static MiniGltf one_mesh_node();
  // One mesh of one triangle primitive (float positions, uint32 or uint16 indices) and a node using it.
  static MiniGltf triangles(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                            int index_component_type = 5125);
  // Appends bytes to the binary buffer (4-byte aligned) and returns a new bufferView index.
  int add_view(const void* data, std::size_t size);
  int add_accessor(int view, int component_type, std::size_t count, const std::string& type, bool normalized = false);

  std::vector<unsigned char> glb() const;
  // The .gltf text with the buffer as a data URI.
  std::vector<unsigned char> gltf_text() const;
  // .gltf + external .bin (or the buffer as a data URI when `bin_name` is empty).
  void write_gltf(const std::filesystem::path& path, const std::string& bin_name) const;
  void write_glb(const std::filesystem::path& path) const;
};

// A fresh empty directory under the test binary's temp dir.
std::filesystem::path test_dir(const std::string& name);

} // namespace probebake::test
