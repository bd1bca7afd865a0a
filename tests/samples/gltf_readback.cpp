#include "gltf_readback.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <unistd.h>

#include <array>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <tuple>

namespace probebake::samples::test {
namespace {

const unsigned char* element(const tinygltf::Model& model, int accessor_index, std::size_t i, std::size_t size) {
  const tinygltf::Accessor& accessor = model.accessors.at(static_cast<std::size_t>(accessor_index));
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<std::size_t>(accessor.bufferView));
  const std::vector<unsigned char>& data = model.buffers.at(static_cast<std::size_t>(view.buffer)).data;
  const std::size_t stride = view.byteStride ? view.byteStride : size;
  const std::size_t offset = view.byteOffset + accessor.byteOffset + i * stride;
  if (offset + size > data.size()) throw std::runtime_error("accessor out of range");
  return data.data() + offset;
}

glm::vec3 read_vec3(const tinygltf::Model& model, int accessor, std::size_t i) {
  glm::vec3 v;
  std::memcpy(&v, element(model, accessor, i, sizeof v), sizeof v);
  return v;
}

std::uint32_t read_index(const tinygltf::Model& model, int accessor, std::size_t i) {
  const int type = model.accessors.at(static_cast<std::size_t>(accessor)).componentType;
  if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
    std::uint16_t v;
    std::memcpy(&v, element(model, accessor, i, 2), 2);
    return v;
  }
  if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) throw std::runtime_error("unexpected index type");
  std::uint32_t v;
  std::memcpy(&v, element(model, accessor, i, 4), 4);
  return v;
}

glm::mat4 local_matrix(const tinygltf::Node& node) {
  glm::mat4 m(1.0f);
  if (node.translation.size() == 3)
    m = glm::translate(m, glm::vec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4) {
    m *= glm::mat4_cast(glm::quat(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                                  static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2])));
  }
  if (node.scale.size() == 3) m = glm::scale(m, glm::vec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

void add_mesh(const tinygltf::Model& model, const tinygltf::Node& node, const glm::mat4& world,
              std::vector<WorldTriangle>& out) {
  for (const tinygltf::Primitive& primitive : model.meshes.at(static_cast<std::size_t>(node.mesh)).primitives) {
    const int positions = primitive.attributes.at("POSITION");
    const std::size_t count = model.accessors.at(static_cast<std::size_t>(primitive.indices)).count;
    for (std::size_t t = 0; t + 2 < count; t += 3) {
      std::array<glm::vec3, 3> p;
      for (std::size_t k = 0; k < 3; ++k) {
        p[k] = glm::vec3(world *
                         glm::vec4(read_vec3(model, positions, read_index(model, primitive.indices, t + k)), 1.0f));
      }
      out.push_back(WorldTriangle{p[0], p[1], p[2], primitive.material, node.name});
    }
  }
}

void walk(const tinygltf::Model& model, int index, const glm::mat4& parent, std::vector<WorldTriangle>& out) {
  const tinygltf::Node& node = model.nodes.at(static_cast<std::size_t>(index));
  const glm::mat4 world = parent * local_matrix(node);
  if (node.mesh >= 0) add_mesh(model, node, world, out);
  for (int child : node.children) walk(model, child, world, out);
}

} // namespace

tinygltf::Model load_glb(const std::vector<std::uint8_t>& bytes, std::string& error) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string warning;
  if (!loader.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(), static_cast<unsigned int>(bytes.size()))) {
    if (error.empty()) error = "tinygltf refused the file";
    return tinygltf::Model{};
  }
  return model;
}

std::vector<std::uint8_t> read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

glm::vec3 WorldTriangle::normal() const { return glm::normalize(glm::cross(b - a, c - a)); }

std::vector<WorldTriangle> world_triangles(const tinygltf::Model& model) {
  std::vector<WorldTriangle> out;
  if (model.scenes.empty()) return out;
  const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  for (int root : model.scenes.at(static_cast<std::size_t>(scene)).nodes) walk(model, root, glm::mat4(1.0f), out);
  return out;
}

WorldBounds bounds_of(const std::vector<WorldTriangle>& triangles) {
  WorldBounds b{glm::vec3(1e30f), glm::vec3(-1e30f)};
  for (const WorldTriangle& t : triangles) {
    for (const glm::vec3& p : {t.a, t.b, t.c}) {
      b.min = glm::min(b.min, p);
      b.max = glm::max(b.max, p);
    }
  }
  return b;
}

bool is_closed_and_oriented(const std::vector<WorldTriangle>& triangles) {
  using Point = std::tuple<float, float, float>;
  std::map<std::pair<Point, Point>, int> directed;
  auto key = [](glm::vec3 p) { return Point{p.x, p.y, p.z}; };
  for (const WorldTriangle& t : triangles) {
    const std::array<Point, 3> v{key(t.a), key(t.b), key(t.c)};
    for (std::size_t k = 0; k < 3; ++k) ++directed[{v[k], v[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) return false;
  }
  return !triangles.empty();
}

std::vector<std::string> dynamic_node_names(const tinygltf::Model& model) {
  std::vector<std::string> names;
  for (const tinygltf::Node& node : model.nodes) {
    if (!node.extras.Has("probebake")) continue;
    const tinygltf::Value& probebake = node.extras.Get("probebake");
    if (probebake.Has("dynamic") && probebake.Get("dynamic").IsBool() && probebake.Get("dynamic").Get<bool>()) {
      names.push_back(node.name);
    }
  }
  return names;
}

std::filesystem::path fresh_folder(const std::string& name) {
  // One root per test process, removed when the process ends.
  struct RemovedAtExit {
    std::filesystem::path root;
    ~RemovedAtExit() {
      std::error_code ignored;
      std::filesystem::remove_all(root, ignored);
    }
  };
  static const RemovedAtExit process_root{std::filesystem::temp_directory_path() /
                                          ("probebake_samples_" + std::to_string(::getpid()))};
  const std::filesystem::path folder = process_root.root / name;
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

} // namespace probebake::samples::test
