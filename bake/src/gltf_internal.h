// Internals of the glTF loader, shared by its translation units (gltf_*.cpp). Not a public header.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "probebake/formats/error.h"

namespace tinygltf {
class Model;
class TinyGLTF;
class Value;
struct Primitive;
struct Material;
} // namespace tinygltf

namespace probebake::scene {
struct Material;
}

namespace probebake::scene::detail {

// Member `key` of a JSON object value, or a null value when `value` is not an object or lacks the key.
// (tinygltf's Value::Get asserts on non-objects, which hostile files can trigger.)
const tinygltf::Value& member(const tinygltf::Value& value, const char* key);
// Element `i` of a JSON array of numbers as a float, or `fallback`.
float number_at(const tinygltf::Value& array, int i, float fallback);

template <int N>
bool all_finite(const glm::vec<N, float>& v) {
  for (int i = 0; i < N; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

struct Context;

// Bytes the loader may still allocate for file contents and decoded data (LoadOptions::max_memory).
// charge() is called before each large allocation, so a hostile count fails before it is allocated.
class MemoryBudget {
public:
  explicit MemoryBudget(std::uint64_t limit) : limit_(limit) {}
  void charge(std::uint64_t bytes, const Context& ctx, const std::string& place);

private:
  std::uint64_t limit_ = 0; // 0 = no limit
  std::uint64_t used_ = 0;
};

// Where an error happened, for "<file>: <place>: <reason>" messages.
struct Context {
  std::string file;
  std::vector<std::string>* warnings = nullptr; // where non-fatal problems go (Scene::warnings)
  MemoryBudget* budget = nullptr;
  void warn(const std::string& message) const {
    if (warnings != nullptr) warnings->push_back(message);
  }
  [[noreturn]] void fail(const std::string& place, const std::string& reason) const {
    throw Error(ErrorKind::input, file + ": " + place + ": " + reason);
  }
  // Charges `count` elements of `size` bytes, refusing counts whose product overflows.
  void charge(std::uint64_t count, std::uint64_t size, const std::string& place) const {
    if (size != 0 && count > UINT64_MAX / size) fail(place, "element count overflows");
    if (budget != nullptr) budget->charge(count * size, *this, place);
  }
};

// Where external files may come from (the scene's folder and --allow-path folders, resolved), and where
// what was read is recorded. tinygltf's callbacks receive a pointer to it (gltf_files.cpp).
struct InputPolicy {
  InputPolicy(const std::filesystem::path& scene_folder, const std::vector<std::filesystem::path>& allowed,
              MemoryBudget& memory, const Context& context);
  // True when `path`, with symlinks and ".." resolved, lies inside one of the roots.
  bool allows(const std::filesystem::path& path) const;

  std::filesystem::path base_dir;            // the scene's folder, resolved
  std::vector<std::filesystem::path> roots;  // base_dir first
  MemoryBudget* budget;
  const Context& ctx;
  std::vector<std::filesystem::path> files_read; // external files, resolved
};

// Installs the confined file-system callbacks and the size-checking image loader.
void configure_parser(tinygltf::TinyGLTF& parser, InputPolicy& policy);

constexpr std::size_t kMaxJsonDepth = 64; // real glTF needs about 10; extras get the rest

// The JSON text of a .gltf, or the JSON chunk of a .glb (header and chunk sizes checked).
std::string_view gltf_json_text(std::span<const unsigned char> bytes, bool is_glb, const Context& ctx);
// Checks nesting depth, data URIs and external URIs before any tree is built from the JSON.
void preflight_gltf_json(std::string_view json, const InputPolicy& policy, const Context& ctx);
// URI percent-decoding as tinygltf applies it before opening a file.
std::string percent_decode(const std::string& uri);

// Geometry of one triangle primitive in its mesh's local space.
struct PrimitiveGeometry {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> texcoords[2]; // TEXCOORD_0, TEXCOORD_1 (empty when absent)
  std::vector<std::uint32_t> indices;  // three per triangle, already expanded from strips and fans
};

// Reads an accessor as `components` floats per element (normalized integers mapped to [0,1] / [-1,1]),
// sparse substitution applied. Every offset, stride and count is checked against its buffer.
std::vector<float> read_accessor_floats(const tinygltf::Model& model, int accessor, int components,
                                        const Context& ctx, const std::string& place);
// Reads an index accessor (unsigned byte/short/int scalars).
std::vector<std::uint32_t> read_accessor_indices(const tinygltf::Model& model, int accessor, const Context& ctx,
                                                 const std::string& place);

// Decodes a KHR_draco_mesh_compression primitive with Draco.
PrimitiveGeometry decode_draco_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                         const Context& ctx, const std::string& place);

// Removes the index accessors of KHR_draco_mesh_compression primitives from a .gltf/.glb in memory
// (tinygltf refuses them before decoding; the indices come from the Draco bitstream). Returns whether
// anything changed.
bool prepare_draco_for_tinygltf(std::vector<unsigned char>& bytes, bool is_glb, const Context& ctx);

// Reads a plain (uncompressed) primitive.
PrimitiveGeometry read_plain_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                       const Context& ctx, const std::string& place);

// Per-triangle averaged material colours of one primitive (texture lookups at 9 barycentric points).
struct TriangleColors {
  std::vector<glm::vec3> albedo;
  std::vector<glm::vec3> emission;
};
scene::Material convert_material(const tinygltf::Model& model, int material, const Context& ctx);
TriangleColors average_triangle_colors(const tinygltf::Model& model, int material_index,
                                       const scene::Material& material, const PrimitiveGeometry& geometry,
                                       const Context& ctx);

} // namespace probebake::scene::detail
