// Internals of the glTF loader, shared by its translation units (gltf_*.cpp). Not a public header.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json_fwd.hpp>

#include "probebake/formats/error.h"
#include "probebake/sky/sky.h"

namespace tinygltf {
class Model;
class TinyGLTF;
class Value;
struct Primitive;
struct Image;
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
  bool strict = false; // LoadOptions::strict: degraded content (textures) is an error
  void warn(const std::string& message) const {
    if (warnings != nullptr) warnings->push_back(message);
  }
  // Content the bake replaces by an approximation (an undecodable texture): a warning, or an error when strict.
  void degrade(const std::string& place, const std::string& reason) const {
    if (strict) fail(place, reason + " (--strict)");
    warn(place + ": " + reason);
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

  std::filesystem::path base_dir;           // the scene's folder, resolved
  std::vector<std::filesystem::path> roots; // base_dir first
  MemoryBudget* budget;
  const Context& ctx;
  std::vector<std::filesystem::path> files_read; // external files, resolved
  std::map<int, std::string> image_problems;     // images[i] that could not be decoded, and why
  std::vector<int> unused_images;                // images[i] no texture refers to, ascending: never decoded
};

// Installs the confined file-system callbacks and the size-checking image loader.
void configure_parser(tinygltf::TinyGLTF& parser, InputPolicy& policy);

constexpr std::size_t kMaxJsonDepth = 64; // real glTF needs about 10; extras get the rest

// The chunks of a GLB (header and chunk lengths checked), with one warning per thing skipped: bytes past the
// declared length or after the last chunk, chunks of unknown type. `canonical`: nothing was skipped and every
// chunk is padded as tinygltf 2.7 requires, so the bytes can be parsed as they are.
struct GlbChunks {
  std::span<const unsigned char> json;
  std::optional<std::span<const unsigned char>> bin;
  std::vector<std::string> warnings;
  bool canonical = false;
};
GlbChunks split_glb(std::span<const unsigned char> bytes, const Context& ctx);
// The header (length corrected), the JSON chunk and the BIN chunk when it has bytes, each padded to 4 bytes.
std::vector<unsigned char> canonical_glb(std::span<const unsigned char> bytes, const GlbChunks& chunks);

// The JSON text of a .gltf, or the JSON chunk of a .glb (header and chunk sizes checked).
std::string_view gltf_json_text(std::span<const unsigned char> bytes, bool is_glb, const Context& ctx);
// What the preflight saw that tinygltf 2.7 would refuse although the glTF spec allows it.
// One value of an array element that the preflight noted: `array`[`index`].`key` and what is wrong or unknown.
struct ElementFact {
  std::string array;
  int index = 0;
  std::string key;
  std::string text;
};
struct PreflightFacts {
  std::vector<int> buffers_without_uri;     // GLB BIN, placeholder/fallback buffers, unused buffers
  std::vector<int> accessors_without_view;  // all zeros (plus sparse values)
  std::vector<int> images_with_other_media; // data URIs of media types tinygltf does not know (image/webp, image/ktx2)
  std::vector<ElementFact> bad_data_uris;   // buffers/images whose data URI cannot be decoded; text: why
  std::vector<ElementFact> unknown_enums;   // accessors type/componentType, cameras type outside glTF 2.0
  bool integral_floats = false;             // a float with an integer value outside `extras` (1.0 for 1)
};

// What anything that may be read refers to (gltf_usage.cpp), one flag per element of each array.
struct UsedObjects {
  std::vector<bool> buffers, views, accessors, images;
};
UsedObjects find_used_objects(const nlohmann::json& gltf);
// Checks nesting depth, data URIs and external URIs before any tree is built from the JSON.
PreflightFacts preflight_gltf_json(std::string_view json, const InputPolicy& policy, const Context& ctx);

// Rewrites the JSON (in memory) so that tinygltf 2.7 accepts what the spec allows: Draco primitives lose
// their index accessor (the bitstream has the indices), index accessors without bufferView are hidden from
// tinygltf's check, uri-less buffers other than the GLB BIN become one-byte placeholders, and image data
// URIs of other media types become application/octet-stream (the image decoder sniffs the bytes).
struct TinygltfRewrite {
  std::vector<int> placeholder_buffers;                     // emptied after parsing
  std::vector<std::array<int, 3>> hidden_indices;           // {mesh, primitive, accessor}, restored after parsing
  std::vector<int> unused_images;                           // never decoded (InputPolicy::unused_images)
  std::vector<int> hidden_image_uris;                       // unused images whose URI became a placeholder
  std::vector<int> unreadable_accessors;                    // unused, of an unknown type: no reader accepts them
  std::vector<std::pair<int, std::string>> unknown_cameras; // {camera, its type}, restored after parsing
};
// A one-byte buffer: tinygltf 2.7 refuses a zero-length one. Stands in for what is never read.
inline constexpr const char* kPlaceholderUri = "data:application/octet-stream;base64,AA==";
// Integral floats to integers, unused buffers and images hidden, unknown enum values accepted or refused
// (gltf_lenient.cpp). Faults in objects that may be read are refused here with their place and reason.
void apply_leniency(nlohmann::json& gltf, bool is_glb, const PreflightFacts& facts, const Context& ctx,
                    TinygltfRewrite& out);
TinygltfRewrite prepare_for_tinygltf(std::vector<unsigned char>& bytes, bool is_glb, const PreflightFacts& facts,
                                     const Context& ctx);
// Undoes what prepare_for_tinygltf hid from tinygltf.
void restore_after_tinygltf(tinygltf::Model& model, const TinygltfRewrite& rewrite);

// EXT_meshopt_compression: decodes every compressed bufferView (bounds and sizes checked first, memory
// charged) into a new buffer of its own and points the bufferView at it, so accessors read it as usual.
void decode_meshopt_buffer_views(tinygltf::Model& model, const Context& ctx);
// One compressed stream: `count` elements of `stride` bytes (mode/filter as in the extension's JSON).
std::vector<unsigned char> decode_meshopt_stream(std::span<const unsigned char> source, std::size_t count,
                                                 std::size_t stride, const std::string& mode, const std::string& filter,
                                                 const Context& ctx, const std::string& place);

// Image decoding for tinygltf's callback: WebP through libwebp, PNG/JPEG/... through stb, sizes checked and
// charged before pixels are allocated. An image that cannot be decoded is recorded in
// policy.image_problems and left empty: a texture never fails the load by itself.
bool decode_image(tinygltf::Image* image, int index, const unsigned char* bytes, int size, InputPolicy& policy);
// Images stored in a bufferView, decoded after parsing (and after EXT_meshopt_compression is decoded): a view
// whose range does not lie inside its buffer is recorded as an image problem, never read.
void decode_buffer_view_images(tinygltf::Model& model, InputPolicy& policy);

// Geometry of one triangle primitive in its mesh's local space.
struct PrimitiveGeometry {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec2> texcoords[2]; // TEXCOORD_0, TEXCOORD_1 (empty when absent)
  std::vector<std::uint32_t> indices;  // three per triangle, already expanded from strips and fans
};

// Reads an accessor as `components` floats per element (normalized integers mapped to [0,1] / [-1,1]),
// sparse substitution applied. Every offset, stride and count is checked against its buffer.
std::vector<float> read_accessor_floats(const tinygltf::Model& model, int accessor, int components, const Context& ctx,
                                        const std::string& place);
// Reads an index accessor (unsigned byte/short/int scalars).
std::vector<std::uint32_t> read_accessor_indices(const tinygltf::Model& model, int accessor, const Context& ctx,
                                                 const std::string& place);

// Decodes a KHR_draco_mesh_compression primitive with Draco.
PrimitiveGeometry decode_draco_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                         const Context& ctx, const std::string& place);

// Reads a plain (uncompressed) primitive.
PrimitiveGeometry read_plain_primitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                       const Context& ctx, const std::string& place);

// Per-triangle averaged material colours of one primitive (texture lookups at 9 barycentric points).
struct TriangleColors {
  std::vector<glm::vec3> albedo;
  std::vector<glm::vec3> emission;
};
scene::Material convert_material(const tinygltf::Model& model, int material, const Context& ctx);

// EXT_lights_image_based (gltf_image_light.cpp): the loaded scene's image-based light as a sky (its irradiance
// coefficients as radiance), or nothing when the scene names none; Error(input) naming the place when malformed.
std::optional<sky::Sky> image_based_sky(const tinygltf::Model& model, const Context& ctx);
// For each texture, the image the bake samples (EXT_texture_webp source, else the texture's own source,
// which is KHR_texture_basisu's fallback), or -1. A texture that a material uses and that has no decodable
// image gets one warning naming it (an error under ctx.strict); its materials use their factors.
std::vector<int> select_texture_images(const tinygltf::Model& model, const std::map<int, std::string>& problems,
                                       const Context& ctx);
TriangleColors average_triangle_colors(const tinygltf::Model& model, const std::vector<int>& texture_images,
                                       int material_index, const scene::Material& material,
                                       const PrimitiveGeometry& geometry);

} // namespace probebake::scene::detail
