// See flip_gltf.h. Works on the JSON and raw buffer bytes (gltf_input.h): every buffer is copied into one
// BIN chunk, and the flipped index and normal data are appended to it as new accessors, so accessors the
// flip does not touch keep their exact bytes.
#include "probebake/samples/flip_gltf.h"

#include "gltf_input.h"
#include "probebake/formats/error.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <string>
#include <utility>

namespace probebake::samples {
namespace {

using detail::Bytes;
using nlohmann::json;

constexpr const char* kTool = "flip";
constexpr int kTriangles = 4, kStrip = 5, kFan = 6;
constexpr int kUnsignedInt = 5125, kFloat = 5126;

[[noreturn]] void fail(const std::string& message) { detail::fail(kTool, message); }

class Flipper {
public:
  Flipper(detail::GltfInput& in, std::filesystem::path base_dir) : in_(in), base_dir_(std::move(base_dir)) {}

  Bytes run() {
    json& gltf = in_.gltf;
    merge_buffers();
    json views = gltf.contains("bufferViews") ? gltf["bufferViews"] : json::array();
    detail::embed_images(gltf, views, bin_, base_dir_, kTool);
    gltf["bufferViews"] = views;
    if (gltf.contains("meshes"))
      for (json& mesh : gltf["meshes"])
        if (mesh.contains("primitives"))
          for (json& primitive : mesh["primitives"]) flip_primitive(primitive);
    if (gltf.contains("materials"))
      for (json& material : gltf["materials"]) material["doubleSided"] = true;
    if (views_.empty() && gltf["bufferViews"].empty()) gltf.erase("bufferViews");
    for (json& v : views_) gltf["bufferViews"].push_back(std::move(v));
    gltf["buffers"] = json::array({{{"byteLength", bin_.size()}}});
    if (bin_.empty()) gltf.erase("buffers");
    return detail::glb_bytes(gltf, bin_);
  }

private:
  // Every buffer into the BIN chunk (16-byte aligned starts keep every view's alignment); views follow.
  void merge_buffers() {
    std::vector<std::size_t> base;
    for (const Bytes& b : in_.buffers) {
      bin_.resize((bin_.size() + 15) & ~std::size_t{15}, 0);
      base.push_back(bin_.size());
      bin_.insert(bin_.end(), b.begin(), b.end());
    }
    if (!in_.gltf.contains("bufferViews")) return;
    for (json& view : in_.gltf["bufferViews"]) {
      const std::size_t buffer = view.value("buffer", std::size_t(0));
      if (buffer >= base.size()) fail("a bufferView names a missing buffer");
      const std::size_t offset = view.value("byteOffset", std::size_t(0));
      if (offset + view.value("byteLength", std::size_t(0)) > in_.buffers[buffer].size())
        fail("a bufferView reaches past its buffer");
      view["buffer"] = 0;
      view["byteOffset"] = base[buffer] + offset;
    }
  }

  const json& accessor(int index) const {
    const json& accessors = in_.gltf.at("accessors");
    if (index < 0 || std::size_t(index) >= accessors.size()) fail("a primitive names a missing accessor");
    return accessors[std::size_t(index)];
  }

  // The elements of an accessor as doubles, component by component (normalized integers scaled as the
  // spec says); an accessor without bufferView is zeros.
  std::vector<double> read_accessor(int index) const {
    const json& a = accessor(index);
    if (a.contains("sparse")) fail("accessor " + std::to_string(index) + " is sparse; not supported");
    const std::size_t count = a.value("count", std::size_t(0));
    const std::size_t components = detail::component_count(a.value("type", "SCALAR"));
    const int type = a.value("componentType", kFloat);
    const std::size_t size = detail::component_size(type);
    if (count > bin_.size() + 1) fail("accessor " + std::to_string(index) + " has more elements than the file bytes");
    std::vector<double> out(count * components, 0.0);
    if (!a.contains("bufferView")) return out;
    const json& view = in_.gltf["bufferViews"].at(a["bufferView"].get<std::size_t>());
    const std::size_t stride = view.value("byteStride", components * size);
    const std::size_t start = view.value("byteOffset", std::size_t(0)) + a.value("byteOffset", std::size_t(0));
    if (count > 0 && start + (count - 1) * stride + components * size > bin_.size())
      fail("accessor " + std::to_string(index) + " reaches past its buffer");
    const bool normalized = a.value("normalized", false);
    for (std::size_t i = 0; i < count; ++i)
      for (std::size_t c = 0; c < components; ++c)
        out[i * components + c] = component(&bin_[start + i * stride + c * size], type, normalized);
    return out;
  }

  static double component(const std::uint8_t* p, int type, bool normalized) {
    auto read = [p](auto v) {
      std::memcpy(&v, p, sizeof v);
      return v;
    };
    switch (type) {
    case 5120: return normalized ? std::max(read(std::int8_t()) / 127.0, -1.0) : read(std::int8_t());
    case 5121: return normalized ? read(std::uint8_t()) / 255.0 : read(std::uint8_t());
    case 5122: return normalized ? std::max(read(std::int16_t()) / 32767.0, -1.0) : read(std::int16_t());
    case 5123: return normalized ? read(std::uint16_t()) / 65535.0 : read(std::uint16_t());
    case kUnsignedInt: return read(std::uint32_t());
    default: return read(float());
    }
  }

  // A new accessor over data appended to the BIN chunk.
  int add_accessor(const void* data, std::size_t bytes, std::size_t count, int component_type, const char* type,
                   bool vertex_data) {
    json view = {{"buffer", 0}, {"byteOffset", detail::append_aligned(bin_, data, bytes)}, {"byteLength", bytes}};
    view["target"] = vertex_data ? 34962 : 34963;
    const std::size_t view_index = in_.gltf["bufferViews"].size() + views_.size();
    views_.push_back(view);
    json& accessors = in_.gltf["accessors"];
    accessors.push_back(
        {{"bufferView", view_index}, {"componentType", component_type}, {"count", count}, {"type", type}});
    return int(accessors.size()) - 1;
  }

  // The primitive's triangles as a list, each with its winding reversed.
  std::vector<std::uint32_t> reversed_triangles(const json& primitive, int mode) const {
    std::vector<std::uint32_t> vertices;
    if (primitive.contains("indices")) {
      for (const double v : read_accessor(primitive["indices"].get<int>())) vertices.push_back(std::uint32_t(v));
    } else {
      if (!primitive.contains("attributes") || !primitive["attributes"].contains("POSITION"))
        fail("a primitive has neither indices nor POSITION");
      const std::size_t count = accessor(primitive["attributes"]["POSITION"].get<int>()).value("count", std::size_t(0));
      if (count > std::size_t(UINT32_MAX)) fail("a primitive has too many vertices");
      vertices.resize(count);
      for (std::size_t i = 0; i < count; ++i) vertices[i] = std::uint32_t(i);
    }
    std::vector<std::uint32_t> out;
    auto add = [&out](std::uint32_t a, std::uint32_t b, std::uint32_t c) { out.insert(out.end(), {a, c, b}); };
    const std::size_t n = vertices.size();
    if (mode == kTriangles)
      for (std::size_t i = 0; i + 2 < n; i += 3) add(vertices[i], vertices[i + 1], vertices[i + 2]);
    else if (mode == kStrip) // glTF: triangle i is {v_i, v_(i+1+i%2), v_(i+2-i%2)}
      for (std::size_t i = 0; i + 2 < n; ++i) add(vertices[i], vertices[i + 1 + i % 2], vertices[i + 2 - i % 2]);
    else // fan: triangle i is {v_(i+1), v_(i+2), v_0}
      for (std::size_t i = 0; i + 2 < n; ++i) add(vertices[i + 1], vertices[i + 2], vertices[0]);
    return out;
  }

  int flipped_indices(const json& primitive, int mode) {
    const std::pair<int, int> key{primitive.contains("indices") ? primitive["indices"].get<int>()
                                                                : -1 - primitive["attributes"].value("POSITION", 0),
                                  mode};
    if (const auto it = indices_.find(key); it != indices_.end()) return it->second;
    const std::vector<std::uint32_t> triangles = reversed_triangles(primitive, mode);
    return indices_[key] =
               add_accessor(triangles.data(), triangles.size() * 4, triangles.size(), kUnsignedInt, "SCALAR", false);
  }

  int negated_normals(int index) {
    if (const auto it = normals_.find(index); it != normals_.end()) return it->second;
    const json& a = accessor(index);
    if (a.value("type", "") != "VEC3") fail("accessor " + std::to_string(index) + ": NORMAL is not VEC3");
    std::vector<double> values = read_accessor(index);
    std::vector<float> negated(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) negated[i] = float(-values[i]);
    return normals_[index] = add_accessor(negated.data(), negated.size() * 4, negated.size() / 3, kFloat, "VEC3", true);
  }

  void flip_primitive(json& primitive) {
    const int mode = primitive.value("mode", kTriangles);
    if (mode != kTriangles && mode != kStrip && mode != kFan) return; // points and lines have no sides
    primitive["indices"] = flipped_indices(primitive, mode);
    primitive["mode"] = kTriangles;
    if (primitive.contains("attributes") && primitive["attributes"].contains("NORMAL"))
      primitive["attributes"]["NORMAL"] = negated_normals(primitive["attributes"]["NORMAL"].get<int>());
    if (primitive.contains("targets"))
      for (json& target : primitive["targets"])
        if (target.contains("NORMAL")) target["NORMAL"] = negated_normals(target["NORMAL"].get<int>());
    if (!primitive.contains("material")) primitive["material"] = default_material();
  }

  // The glTF default material (white, metallic 1, roughness 1), double-sided.
  int default_material() {
    if (default_material_ < 0) {
      json& materials = in_.gltf["materials"];
      materials.push_back({{"name", "default (flipped)"}, {"doubleSided", true}});
      default_material_ = int(materials.size()) - 1;
    }
    return default_material_;
  }

  detail::GltfInput& in_;
  std::filesystem::path base_dir_;
  Bytes bin_;
  json views_ = json::array();                 // bufferViews of the new accessors
  std::map<std::pair<int, int>, int> indices_; // (indices accessor or -1 - POSITION, mode) -> flipped
  std::map<int, int> normals_;                 // NORMAL accessor -> negated
  int default_material_ = -1;
};

} // namespace

std::vector<std::uint8_t> flip_sides_gltf(const std::vector<std::uint8_t>& input,
                                          const std::filesystem::path& base_dir) {
  return detail::rewrite_gltf<Flipper>(input, base_dir, kTool);
}

std::vector<std::uint8_t> flip_sides_file(const std::filesystem::path& path) {
  return flip_sides_gltf(detail::read_file(path, kTool), path.parent_path());
}

} // namespace probebake::samples
