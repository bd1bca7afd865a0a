// Internals of make-scene's glTF rewriters (convert --meshopt, convert --flip): a glTF's JSON and buffer
// bytes, read without tinygltf so that everything a rewriter does not touch is carried over exactly.
// Not a public header.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace probebake::samples::detail {

using Bytes = std::vector<std::uint8_t>;

struct GltfInput {
  nlohmann::json gltf;
  std::vector<Bytes> buffers; // one per glTF buffer: the GLB BIN chunk, a data URI or an external file
};

// Errors are Error(input) "<tool>: <reason>".
[[noreturn]] void fail(const std::string& tool, const std::string& message);
Bytes read_file(const std::filesystem::path& path, const std::string& tool);

// A .glb or .gltf (external files resolved against `base_dir`). Refuses inputs that already use Draco or
// meshopt compression (the rewriters read geometry bytes directly).
GltfInput parse_gltf_input(const Bytes& bytes, const std::filesystem::path& base_dir, const std::string& tool);

// A rewriter's whole run: `Rewriter(parsed input, base_dir).run()`, JSON that does not have the shape glTF
// gives it an input error of `tool`.
template <typename Rewriter>
Bytes rewrite_gltf(const Bytes& input, const std::filesystem::path& base_dir, const std::string& tool) {
  try {
    GltfInput parsed = parse_gltf_input(input, base_dir, tool);
    return Rewriter(parsed, base_dir).run();
  } catch (const nlohmann::json::exception& e) {
    fail(tool, std::string("malformed glTF JSON: ") + e.what());
  }
}

std::size_t component_size(int type);
std::size_t component_count(const std::string& type);

// Appends `size` bytes at the next multiple of 4 and returns where they start.
std::size_t append_aligned(Bytes& bin, const void* data, std::size_t size);

// Every image with a uri (external file or data URI) becomes a bufferView of buffer 0 appended to `views`
// and `bin`, with its mimeType.
void embed_images(nlohmann::json& gltf, nlohmann::json& views, Bytes& bin, const std::filesystem::path& base_dir,
                  const std::string& tool);

// A GLB of `gltf` with `bin` as its BIN chunk (buffer 0).
Bytes glb_bytes(const nlohmann::json& gltf, Bytes bin);

} // namespace probebake::samples::detail
