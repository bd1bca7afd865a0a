// Flattens a glTF model: walks its default scene, applies node transforms, reads triangle primitives
// (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN) and groups them by material, with flat normals (the bake
// uses geometric normals; NORMAL attributes are not read). Every accessor read is bounds checked, so a
// malformed file gives an error instead of a crash.
#include "model_import.h"

#include <tiny_gltf.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>

namespace probebake::samples {
namespace {

[[noreturn]] void unreadable(const std::filesystem::path& path, const std::string& why) {
  throw SceneError(ErrorKind::unreadable_input, "cannot read model '" + path.string() + "': " + why);
}

// Textures are not used (only material factors are), so images are not decoded.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

bool has_glb_magic(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 4> magic{};
  return in.read(magic.data(), 4) && std::memcmp(magic.data(), "glTF", 4) == 0;
}

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

tinygltf::Model load(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) unreadable(path, "no such file (or not a regular file)");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  const bool ok = has_glb_magic(path) ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                      : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  if (!ok) unreadable(path, err.empty() ? "not a glTF file" : first_line(err));
  return model;
}

// A bounds-checked view of one accessor's elements.
struct ElementView {
  const unsigned char* first = nullptr;
  std::size_t count = 0;
  std::size_t stride = 0;
};

ElementView element_view(const std::filesystem::path& path, const tinygltf::Model& model, int index,
                         std::size_t element_size) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) unreadable(path, "bad accessor index");
  const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
  if (accessor.sparse.isSparse) unreadable(path, "sparse accessors are not supported");
  if (accessor.bufferView < 0 || static_cast<std::size_t>(accessor.bufferView) >= model.bufferViews.size()) {
    unreadable(path, "accessor without a valid bufferView");
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) unreadable(path, "bad buffer index");
  const std::vector<unsigned char>& buffer = model.buffers[static_cast<std::size_t>(view.buffer)].data;
  const std::size_t stride = view.byteStride != 0 ? view.byteStride : element_size;
  // Written so that no sum or product can overflow, whatever the file claims.
  const bool view_fits = view.byteOffset <= buffer.size() && view.byteLength <= buffer.size() - view.byteOffset;
  if (!view_fits || accessor.byteOffset > view.byteLength || stride < element_size) unreadable(path, "bad bufferView");
  const std::size_t available = view.byteLength - accessor.byteOffset;  // from the first element to the view's end
  const bool fits = accessor.count == 0 ||
                    (available >= element_size && accessor.count - 1 <= (available - element_size) / stride);
  if (!fits) unreadable(path, "accessor runs past its buffer");
  return ElementView{buffer.data() + view.byteOffset + accessor.byteOffset, accessor.count, stride};
}

std::vector<glm::vec3> read_positions(const std::filesystem::path& path, const tinygltf::Model& model, int index) {
  const tinygltf::Accessor& accessor = model.accessors.at(static_cast<std::size_t>(index));
  if (accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || accessor.type != TINYGLTF_TYPE_VEC3) {
    unreadable(path, "only float VEC3 positions are supported");
  }
  const ElementView view = element_view(path, model, index, sizeof(glm::vec3));
  std::vector<glm::vec3> values(view.count);
  for (std::size_t i = 0; i < view.count; ++i) std::memcpy(&values[i], view.first + i * view.stride, sizeof(glm::vec3));
  return values;
}

std::vector<std::uint32_t> read_indices(const std::filesystem::path& path, const tinygltf::Model& model, int index) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) unreadable(path, "bad index accessor");
  const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(accessor.componentType));
  const bool integer = accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                       accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                       accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  if (!integer || accessor.type != TINYGLTF_TYPE_SCALAR) unreadable(path, "indices must be unsigned integer scalars");
  const ElementView view = element_view(path, model, index, static_cast<std::size_t>(size));
  std::vector<std::uint32_t> values(view.count);
  for (std::size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.first + i * view.stride;
    if (size == 1) values[i] = *p;
    if (size == 2) { std::uint16_t v; std::memcpy(&v, p, 2); values[i] = v; }
    if (size == 4) std::memcpy(&values[i], p, 4);
  }
  return values;
}

// Triangle corner indices (into the vertex list) for a primitive's mode; empty for points and lines.
std::vector<std::uint32_t> triangle_corners(int mode, const std::vector<std::uint32_t>& order) {
  std::vector<std::uint32_t> corners;
  const std::size_t n = order.size();
  if (mode == TINYGLTF_MODE_TRIANGLES || mode == -1) {
    corners.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n - n % 3));
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 0; i + 2 < n; ++i) {  // keeps every triangle counter-clockwise
      const std::size_t odd = i % 2;
      corners.insert(corners.end(), {order[i], order[i + 1 + odd], order[i + 2 - odd]});
    }
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (std::size_t i = 0; i + 2 < n; ++i) corners.insert(corners.end(), {order[i + 1], order[i + 2], order[0]});
  }
  return corners;
}

glm::vec3 unit_or_up(glm::vec3 v) {
  const float length = glm::length(v);
  return (std::isfinite(length) && length > 0.0f) ? v / length : glm::vec3(0.0f, 1.0f, 0.0f);
}

// Appends a primitive's triangles, transformed to scene space, to `mesh`.
void append_primitive(const std::filesystem::path& path, const tinygltf::Model& model,
                      const tinygltf::Primitive& primitive, const glm::mat4& world, MeshData& mesh) {
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) return;
  std::vector<glm::vec3> positions = read_positions(path, model, position->second);
  std::vector<std::uint32_t> order(positions.size());
  if (primitive.indices >= 0) {
    order = read_indices(path, model, primitive.indices);
  } else {
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
  }
  const std::vector<std::uint32_t> corners = triangle_corners(primitive.mode, order);
  const bool mirrored = glm::determinant(glm::mat3(world)) < 0.0f;
  for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
    std::array<glm::vec3, 3> p;
    for (std::size_t k = 0; k < 3; ++k) {
      if (corners[t + k] >= positions.size()) unreadable(path, "index out of range");
      p[k] = glm::vec3(world * glm::vec4(positions[corners[t + k]], 1.0f));
      if (!std::isfinite(p[k].x) || !std::isfinite(p[k].y) || !std::isfinite(p[k].z)) unreadable(path, "non-finite position");
    }
    if (mirrored) std::swap(p[1], p[2]);
    // Flat normals: the bake uses geometric normals, and this keeps files without NORMAL simple.
    const glm::vec3 normal = unit_or_up(glm::cross(p[1] - p[0], p[2] - p[0]));
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), p.begin(), p.end());
    mesh.normals.insert(mesh.normals.end(), 3, normal);
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
  }
}

glm::mat4 local_matrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    std::array<float, 16> m{};
    std::transform(node.matrix.begin(), node.matrix.end(), m.begin(), [](double v) { return static_cast<float>(v); });
    return glm::make_mat4(m.data());  // glTF matrices are column-major, like glm
  }
  glm::mat4 result(1.0f);
  if (node.translation.size() == 3) {
    result = glm::translate(result, glm::vec3(glm::dvec3(node.translation[0], node.translation[1], node.translation[2])));
  }
  if (node.rotation.size() == 4) {
    const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF: x, y, z, w
    result *= glm::mat4_cast(glm::quat(glm::normalize(q)));
  }
  if (node.scale.size() == 3) result = glm::scale(result, glm::vec3(glm::dvec3(node.scale[0], node.scale[1], node.scale[2])));
  return result;
}

std::vector<int> root_nodes(const tinygltf::Model& model) {
  if (!model.scenes.empty()) {
    const int scene = model.defaultScene >= 0 && static_cast<std::size_t>(model.defaultScene) < model.scenes.size()
                          ? model.defaultScene : 0;
    return model.scenes[static_cast<std::size_t>(scene)].nodes;
  }
  std::vector<bool> is_child(model.nodes.size(), false);  // no scene: every node that is nobody's child
  for (const tinygltf::Node& node : model.nodes) {
    for (int child : node.children) {
      if (child >= 0 && static_cast<std::size_t>(child) < is_child.size()) is_child[static_cast<std::size_t>(child)] = true;
    }
  }
  std::vector<int> roots;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) if (!is_child[i]) roots.push_back(static_cast<int>(i));
  return roots;
}

Material convert_material(const tinygltf::Model& model, int index) {
  Material material;
  material.albedo = glm::vec3(1.0f);  // glTF's default base colour
  material.name = "default";
  if (index < 0 || static_cast<std::size_t>(index) >= model.materials.size()) return material;
  const tinygltf::Material& source = model.materials[static_cast<std::size_t>(index)];
  material.name = source.name.empty() ? "material_" + std::to_string(index) : source.name;
  const auto& base = source.pbrMetallicRoughness.baseColorFactor;
  for (std::size_t c = 0; c < 3 && c < base.size(); ++c) {
    material.albedo[static_cast<int>(c)] = std::isfinite(base[c]) ? std::clamp(static_cast<float>(base[c]), 0.0f, 1.0f) : 1.0f;
  }
  double strength = 1.0;
  const auto extension = source.extensions.find("KHR_materials_emissive_strength");
  if (extension != source.extensions.end() && extension->second.Has("emissiveStrength")) {
    strength = extension->second.Get("emissiveStrength").GetNumberAsDouble();
  }
  for (std::size_t c = 0; c < 3 && c < source.emissiveFactor.size(); ++c) {
    const double e = source.emissiveFactor[c] * strength;
    material.emission[static_cast<int>(c)] = std::isfinite(e) && e > 0.0 ? static_cast<float>(e) : 0.0f;
  }
  return material;
}

}  // namespace

ImportedModel import_model(const std::filesystem::path& path) {
  const tinygltf::Model model = load(path);
  std::map<int, MeshData> by_material;
  std::vector<bool> visited(model.nodes.size(), false);
  std::vector<std::pair<int, glm::mat4>> stack;
  for (int root : root_nodes(model)) stack.emplace_back(root, glm::mat4(1.0f));
  while (!stack.empty()) {
    const auto [index, parent_world] = stack.back();
    stack.pop_back();
    if (index < 0 || static_cast<std::size_t>(index) >= model.nodes.size()) unreadable(path, "bad node index");
    if (visited[static_cast<std::size_t>(index)]) unreadable(path, "the node hierarchy is not a tree");
    visited[static_cast<std::size_t>(index)] = true;
    const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(index)];
    const glm::mat4 world = parent_world * local_matrix(node);
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= model.meshes.size()) unreadable(path, "bad mesh index");
      for (const tinygltf::Primitive& primitive : model.meshes[static_cast<std::size_t>(node.mesh)].primitives) {
        append_primitive(path, model, primitive, world, by_material[primitive.material]);
      }
    }
    for (int child : node.children) stack.emplace_back(child, world);
  }
  ImportedModel result;
  for (auto& [material, geometry] : by_material) {
    if (!geometry.empty()) result.parts.push_back(ImportedPart{convert_material(model, material), std::move(geometry)});
  }
  if (result.parts.empty()) unreadable(path, "it has no triangles");
  return result;
}

}  // namespace probebake::samples
