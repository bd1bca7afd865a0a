// See meshopt_gltf.h. Works on the JSON (nlohmann) and raw buffer bytes, so everything the converter does
// not touch (materials, lights, extras, images' bytes) is carried over exactly.
#include "probebake/samples/meshopt_gltf.h"

#include "gltf_input.h"

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <map>
#include <string>
#include <utility>

namespace probebake::samples {
namespace {

using nlohmann::json;

constexpr const char* kTool = "meshopt";

[[noreturn]] void fail(const std::string& message) { detail::fail(kTool, message); }

using detail::Bytes;
using detail::component_count;
using detail::component_size;

class Writer {
public:
  Writer(detail::GltfInput& in, std::filesystem::path base_dir) : in_(in), base_dir_(std::move(base_dir)) {}

  Bytes run() {
    collect_geometry_accessors();
    json& gltf = in_.gltf;
    json views = json::array();
    remap_old_views(views);
    detail::embed_images(gltf, views, bin_, base_dir_, kTool);
    for (const auto& [accessor, role] : geometry_) compress_accessor(accessor, role, views);
    gltf["bufferViews"] = views;
    json fallback = {{"byteLength", std::max<std::size_t>(fallback_size_, 1)},
                     {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}};
    gltf["buffers"] = json::array({{{"byteLength", bin_.size()}}, fallback});
    add_extension("extensionsUsed", "EXT_meshopt_compression");
    add_extension("extensionsRequired", "EXT_meshopt_compression");
    if (quantized_normals_) add_extension("extensionsUsed", "KHR_mesh_quantization");
    if (quantized_normals_) add_extension("extensionsRequired", "KHR_mesh_quantization");
    return detail::glb_bytes(gltf, bin_);
  }

private:
  enum class Role { attribute, normal, triangles, indices };

  void collect_geometry_accessors() {
    const json& meshes = in_.gltf.contains("meshes") ? in_.gltf["meshes"] : empty_;
    for (const json& mesh : meshes) {
      if (!mesh.contains("primitives")) continue;
      for (const json& primitive : mesh["primitives"]) {
        if (primitive.contains("attributes"))
          for (const auto& [name, accessor] : primitive["attributes"].items())
            add_geometry(accessor.get<int>(), name == "NORMAL" ? Role::normal : Role::attribute);
        if (primitive.contains("indices"))
          add_geometry(primitive["indices"].get<int>(),
                       primitive.value("mode", 4) == 4 ? Role::triangles : Role::indices);
      }
    }
  }
  void add_geometry(int accessor, Role role) {
    const json& a = in_.gltf["accessors"].at(std::size_t(accessor));
    if (!a.contains("bufferView") || a.contains("sparse")) return; // left as it is
    if (role == Role::triangles && a.value("count", 0) % 3 != 0) role = Role::indices;
    geometry_.emplace(accessor, role);
  }

  const Bytes& view_bytes(const json& view, std::size_t& offset) {
    const Bytes& data = in_.buffers.at(view.value("buffer", 0));
    offset = view.value("byteOffset", std::size_t(0));
    if (offset + view.value("byteLength", std::size_t(0)) > data.size()) fail("a bufferView reaches past its buffer");
    return data;
  }

  std::size_t append(const void* data, std::size_t size) { return detail::append_aligned(bin_, data, size); }

  // Views still referenced after geometry is compressed (images, sparse data, other accessors) are copied.
  void remap_old_views(json& views) {
    std::vector<int> remap(in_.gltf.contains("bufferViews") ? in_.gltf["bufferViews"].size() : 0, -1);
    auto keep = [&](json& holder) {
      if (!holder.is_object() || !holder.contains("bufferView")) return;
      const std::size_t old = holder["bufferView"].get<std::size_t>();
      if (remap.at(old) < 0) {
        json view = in_.gltf["bufferViews"][old];
        std::size_t offset = 0;
        const Bytes& data = view_bytes(view, offset);
        view["buffer"] = 0;
        view["byteOffset"] = append(data.data() + offset, view.value("byteLength", std::size_t(0)));
        remap[old] = int(views.size());
        views.push_back(view);
      }
      holder["bufferView"] = remap[old];
    };
    const std::size_t accessors = in_.gltf.contains("accessors") ? in_.gltf["accessors"].size() : 0;
    for (std::size_t i = 0; i < accessors; ++i) {
      json& a = in_.gltf["accessors"][i];
      if (a.contains("sparse")) {
        keep(a["sparse"]["indices"]);
        keep(a["sparse"]["values"]);
      }
      if (!geometry_.count(int(i))) keep(a);
    }
    if (in_.gltf.contains("images"))
      for (json& image : in_.gltf["images"]) keep(image);
  }

  void compress_accessor(int index, Role role, json& views) {
    json& a = in_.gltf["accessors"][std::size_t(index)];
    const json& source_view = in_.gltf["bufferViews"].at(a["bufferView"].get<std::size_t>());
    const std::size_t count = a.value("count", std::size_t(0));
    int type = a.value("componentType", 5126);
    const std::size_t element = component_count(a.value("type", "SCALAR")) * component_size(type);
    std::size_t offset = 0;
    const Bytes& data = view_bytes(source_view, offset);
    const std::size_t src_stride = source_view.value("byteStride", element);
    offset += a.value("byteOffset", std::size_t(0));
    if (count > 0 && offset + (count - 1) * src_stride + element > data.size())
      fail("an accessor reaches past its buffer");
    const bool index_data = role == Role::triangles || role == Role::indices;
    std::size_t stride = index_data ? std::max<std::size_t>(element, 2) : (element + 3) & ~std::size_t{3};
    Bytes packed(count * stride, 0);
    for (std::size_t i = 0; i < count; ++i) {
      if (index_data && element == 1)
        packed[i * 2] = data[offset + i * src_stride]; // uint8 -> uint16
      else
        std::memcpy(&packed[i * stride], &data[offset + i * src_stride], element);
    }
    if (index_data && element == 1) a["componentType"] = type = 5123;
    std::string filter = "NONE";
    if (role == Role::normal && type == 5126 && a.value("type", "") == "VEC3") {
      packed = oct_normals(packed, count);
      stride = 8;
      filter = "OCTAHEDRAL";
      a["componentType"] = 5122;
      a["normalized"] = true;
      a.erase("min");
      a.erase("max");
      quantized_normals_ = true;
    }
    const Bytes encoded = encode(packed, count, stride, role);
    json view = {{"buffer", 1}, {"byteOffset", fallback_size_}, {"byteLength", packed.size()}};
    if (!index_data) view["byteStride"] = stride;
    fallback_size_ = (fallback_size_ + packed.size() + 3) & ~std::size_t{3};
    const char* mode = role == Role::triangles ? "TRIANGLES" : role == Role::indices ? "INDICES" : "ATTRIBUTES";
    json ext = {{"buffer", 0},
                {"byteOffset", append(encoded.data(), encoded.size())},
                {"byteLength", encoded.size()},
                {"byteStride", stride},
                {"count", count},
                {"mode", mode}};
    if (filter != "NONE") ext["filter"] = filter;
    view["extensions"] = {{"EXT_meshopt_compression", ext}};
    a["bufferView"] = views.size();
    a.erase("byteOffset");
    views.push_back(view);
  }

  static Bytes oct_normals(const Bytes& packed, std::size_t count) {
    std::vector<float> xyzw(count * 4, 1.0f);
    for (std::size_t i = 0; i < count; ++i) std::memcpy(&xyzw[i * 4], &packed[i * 12], 12);
    Bytes out(count * 8);
    if (count > 0) meshopt_encodeFilterOct(out.data(), count, 8, 16, xyzw.data());
    return out;
  }

  static Bytes encode(const Bytes& packed, std::size_t count, std::size_t stride, Role role) {
    Bytes out;
    if (role == Role::triangles || role == Role::indices) {
      std::vector<unsigned int> indices(count);
      for (std::size_t i = 0; i < count; ++i) {
        std::uint32_t v = 0;
        std::memcpy(&v, &packed[i * stride], stride);
        indices[i] = v;
      }
      const std::size_t vertices = count == 0 ? 0 : *std::max_element(indices.begin(), indices.end()) + 1;
      if (role == Role::triangles) {
        out.resize(meshopt_encodeIndexBufferBound(count, vertices));
        out.resize(meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), count));
      } else {
        out.resize(meshopt_encodeIndexSequenceBound(count, vertices));
        out.resize(meshopt_encodeIndexSequence(out.data(), out.size(), indices.data(), count));
      }
    } else {
      out.resize(meshopt_encodeVertexBufferBound(count, stride));
      out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), packed.data(), count, stride));
    }
    if (out.empty() && count > 0) fail("the encoder failed");
    return out;
  }

  void add_extension(const char* list, const char* name) {
    json& names = in_.gltf[list];
    if (!names.is_array()) names = json::array();
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }

  detail::GltfInput& in_;
  std::filesystem::path base_dir_;
  std::map<int, Role> geometry_;
  Bytes bin_;
  std::size_t fallback_size_ = 0;
  bool quantized_normals_ = false;
  const json empty_ = json::array();
};

} // namespace

std::vector<std::uint8_t> meshopt_compress_gltf(const std::vector<std::uint8_t>& input,
                                                const std::filesystem::path& base_dir) {
  return detail::rewrite_gltf<Writer>(input, base_dir, kTool);
}

std::vector<std::uint8_t> meshopt_compress_file(const std::filesystem::path& path) {
  return meshopt_compress_gltf(detail::read_file(path, kTool), path.parent_path());
}

} // namespace probebake::samples
