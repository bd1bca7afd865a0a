// SceneBuilder: validation, the node hierarchy and world-space statistics. Encoding lives in
// gltf_writer.cpp, reading other models in model_import.cpp.
#include "probebake/samples/scene_builder.h"

#include "gltf_writer.h"
#include "model_import.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/vector_relational.hpp>

#include <cmath>
#include <utility>

namespace probebake::samples {
namespace {

[[noreturn]] void invalid(const std::string& message) { throw Error(ErrorKind::usage, message); }

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool in_unit_range(glm::vec3 v) {
  return glm::all(glm::greaterThanEqual(v, glm::vec3(0.0f))) && glm::all(glm::lessThanEqual(v, glm::vec3(1.0f)));
}

void check_material(const Material& m) {
  if (!finite(m.albedo) || !in_unit_range(m.albedo)) invalid("material '" + m.name + "': albedo must be in [0, 1]");
  if (!finite(m.emission) || glm::any(glm::lessThan(m.emission, glm::vec3(0.0f)))) {
    invalid("material '" + m.name + "': emission must be finite and >= 0");
  }
}

void check_light(const Light& l) {
  if (!finite(l.color) || !in_unit_range(l.color)) invalid("light '" + l.name + "': color must be in [0, 1]");
  if (!std::isfinite(l.intensity) || l.intensity < 0.0f)
    invalid("light '" + l.name + "': intensity must be finite and >= 0");
  if (!std::isfinite(l.range) || l.range < 0.0f) invalid("light '" + l.name + "': range must be >= 0");
  const bool cones_ok =
      l.inner_cone_angle >= 0.0f && l.inner_cone_angle < l.outer_cone_angle && l.outer_cone_angle <= 1.5707964f;
  if (l.type == LightType::spot && !cones_ok) invalid("light '" + l.name + "': need 0 <= inner < outer <= pi/2");
}

template <class Id>
void check_id(Id id, std::size_t count, const char* what) {
  if (id.index < 0 || static_cast<std::size_t>(id.index) >= count) invalid(std::string("unknown ") + what + " id");
}

} // namespace

glm::mat4 Transform::matrix() const {
  return glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) * glm::scale(glm::mat4(1.0f), scale);
}

bool Transform::is_identity() const {
  return translation == glm::vec3(0.0f) && rotation == glm::quat(1.0f, 0.0f, 0.0f, 0.0f) && scale == glm::vec3(1.0f);
}

MaterialId SceneBuilder::add_material(const Material& material) {
  check_material(material);
  materials_.push_back(material);
  return MaterialId{static_cast<int>(materials_.size()) - 1};
}

LightId SceneBuilder::add_light(const Light& light) {
  check_light(light);
  lights_.push_back(light);
  return LightId{static_cast<int>(lights_.size()) - 1};
}

MeshId SceneBuilder::add_mesh(std::string name, std::vector<Primitive> primitives) {
  if (primitives.empty()) invalid("mesh '" + name + "' has no primitives");
  for (const Primitive& p : primitives) {
    if (p.geometry.empty()) invalid("mesh '" + name + "' has a primitive without triangles");
    check_id(p.material, materials_.size(), "material");
  }
  meshes_.push_back(MeshEntry{std::move(name), std::move(primitives)});
  return MeshId{static_cast<int>(meshes_.size()) - 1};
}

MeshId SceneBuilder::add_mesh(std::string name, MeshData geometry, MaterialId material) {
  std::vector<Primitive> primitives;
  primitives.push_back(Primitive{std::move(geometry), material});
  return add_mesh(std::move(name), std::move(primitives));
}

MeshId SceneBuilder::add_model(const std::filesystem::path& path, std::string name) {
  ImportedModel model = import_model(path);
  std::vector<Primitive> primitives;
  for (ImportedPart& part : model.parts) {
    primitives.push_back(Primitive{std::move(part.geometry), add_material(part.material)});
  }
  return add_mesh(std::move(name), std::move(primitives));
}

NodeId SceneBuilder::add_node(std::string name, const Transform& transform, std::optional<NodeId> parent) {
  const int index = static_cast<int>(nodes_.size());
  if (parent) {
    check_id(*parent, nodes_.size(), "parent node");
    nodes_[static_cast<std::size_t>(parent->index)].children.push_back(index);
  } else {
    roots_.push_back(index);
  }
  nodes_.push_back(NodeEntry{std::move(name), transform, std::nullopt, std::nullopt, std::nullopt, false, {}});
  return NodeId{index};
}

NodeId SceneBuilder::add_mesh_node(std::string name, MeshId mesh, const Transform& transform,
                                   std::optional<NodeId> parent) {
  check_id(mesh, meshes_.size(), "mesh");
  const NodeId node = add_node(std::move(name), transform, parent);
  nodes_[static_cast<std::size_t>(node.index)].mesh = mesh;
  return node;
}

NodeId SceneBuilder::add_light_node(std::string name, LightId light, glm::vec3 position, glm::vec3 direction,
                                    std::optional<NodeId> parent) {
  check_id(light, lights_.size(), "light");
  if (!finite(position) || !finite(direction) || glm::length(direction) == 0.0f)
    invalid("light node '" + name + "': bad position or direction");
  Transform transform;
  transform.translation = position;
  if (lights_[static_cast<std::size_t>(light.index)].type != LightType::point) {
    transform.rotation =
        glm::quat(glm::vec3(0.0f, 0.0f, -1.0f), glm::normalize(direction)); // glTF lights shine along -Z
  }
  const NodeId node = add_node(std::move(name), transform, parent);
  nodes_[static_cast<std::size_t>(node.index)].light = light;
  return node;
}

NodeId SceneBuilder::add_camera_node(std::string name, glm::vec3 position, glm::vec3 look_at, float yfov) {
  const glm::vec3 forward = look_at - position;
  if (!finite(position) || !finite(look_at) || glm::length(forward) == 0.0f || !(yfov > 0.0f && yfov < 3.14159f))
    invalid("camera node '" + name + "': bad position, target or field of view");
  Transform transform;
  transform.translation = position;
  // glTF cameras look along -Z with +Y up: the inverse of a look-at view matrix.
  transform.rotation = glm::quat_cast(glm::inverse(glm::mat3(glm::lookAt(position, look_at, glm::vec3(0, 1, 0)))));
  const NodeId node = add_node(std::move(name), transform);
  nodes_[static_cast<std::size_t>(node.index)].camera_yfov = yfov;
  return node;
}

void SceneBuilder::set_dynamic(NodeId node, bool dynamic) {
  check_id(node, nodes_.size(), "node");
  nodes_[static_cast<std::size_t>(node.index)].dynamic = dynamic;
}

NodeId SceneBuilder::wrap_roots(std::string name, const Transform& transform) {
  std::vector<int> old_roots = std::exchange(roots_, {});
  const NodeId root = add_node(std::move(name), transform);
  nodes_[static_cast<std::size_t>(root.index)].children = std::move(old_roots);
  return root;
}

template <class Visit>
void SceneBuilder::visit_mesh_instances(Visit&& visit) const {
  // Nodes form a forest (each node has one parent), so a plain depth-first walk terminates.
  std::vector<std::pair<int, glm::mat4>> stack;
  for (auto it = roots_.rbegin(); it != roots_.rend(); ++it) stack.emplace_back(*it, glm::mat4(1.0f));
  while (!stack.empty()) {
    const auto [index, parent_world] = stack.back();
    stack.pop_back();
    const NodeEntry& node = nodes_[static_cast<std::size_t>(index)];
    const glm::mat4 world = parent_world * node.transform.matrix();
    if (node.mesh) visit(meshes_[static_cast<std::size_t>(node.mesh->index)], world);
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.emplace_back(*it, world);
  }
}

std::size_t SceneBuilder::triangle_count() const {
  std::size_t count = 0;
  visit_mesh_instances([&](const MeshEntry& mesh, const glm::mat4&) {
    for (const Primitive& p : mesh.primitives) count += p.geometry.triangle_count();
  });
  return count;
}

Bounds SceneBuilder::bounds() const {
  Bounds bounds;
  visit_mesh_instances([&](const MeshEntry& mesh, const glm::mat4& world) {
    for (const Primitive& p : mesh.primitives) {
      for (const glm::vec3& v : p.geometry.positions) bounds.extend(glm::vec3(world * glm::vec4(v, 1.0f)));
    }
  });
  return bounds;
}

Bounds SceneBuilder::mesh_bounds(MeshId mesh) const {
  check_id(mesh, meshes_.size(), "mesh");
  Bounds bounds;
  for (const Primitive& p : meshes_[static_cast<std::size_t>(mesh.index)].primitives)
    bounds.extend(bounds_of(p.geometry));
  return bounds;
}

std::vector<std::uint8_t> SceneBuilder::to_glb() const { return encode_glb(*this); }

void SceneBuilder::write_glb(const std::filesystem::path& path) const { write_file_atomically(path, to_glb()); }

} // namespace probebake::samples
