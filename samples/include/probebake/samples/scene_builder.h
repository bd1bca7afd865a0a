// SceneBuilder: assembles a glTF 2.0 scene (meshes, diffuse/emissive materials, KHR_lights_punctual
// lights, a node hierarchy) and writes it as a binary .glb with one embedded buffer.
//
// Units and conventions: metres, Y up, counter-clockwise front faces (glTF). Light intensities use
// KHR_lights_punctual units: candela for point and spot lights, lux for directional lights. Emission is
// radiance in the same radiometric scale (the bake treats candela as W/sr and emission as W/(m^2 sr)).
// The output bytes depend only on what was added, in the order it was added (no timestamps, no paths).
// A builder is a plain value: not thread-safe, copyable.
//
// Dynamic nodes carry `"extras": {"probebake": {"dynamic": true}}` (see samples/README.md).
// Errors: probebake::Error (formats/error.h) with ErrorKind::usage for invalid arguments, ::input for an
// unreadable model, ::output for an unwritable file.
#pragma once

#include "probebake/formats/error.h"
#include "probebake/samples/geometry.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace probebake::samples {

struct Material {
  std::string name;
  glm::vec3 albedo{0.8f};    // baseColorFactor.rgb (alpha 1): the diffuse albedo, each in [0, 1]
  glm::vec3 emission{0.0f};  // emitted radiance, >= 0; written as emissiveFactor, with
                             // KHR_materials_emissive_strength when a component exceeds 1
  bool double_sided = false; // glTF doubleSided: both sides reflect and emit
};

enum class LightType { point, spot, directional };

struct Light {
  std::string name;
  LightType type = LightType::point;
  glm::vec3 color{1.0f};         // linear RGB, each in [0, 1]
  float intensity = 1.0f;        // candela (point, spot) or lux (directional), >= 0
  float range = 0.0f;            // metres; 0 = infinite
  float inner_cone_angle = 0.0f; // spot only, radians, 0 <= inner < outer <= pi/2
  float outer_cone_angle = 0.7853982f;
};

// A node's local transform: translation * rotation * scale.
struct Transform {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f}; // (w, x, y, z)
  glm::vec3 scale{1.0f};

  glm::mat4 matrix() const;
  bool is_identity() const;
};

// Indices into the builder's lists; only valid for the builder that returned them.
struct MaterialId {
  int index = -1;
};
struct MeshId {
  int index = -1;
};
struct LightId {
  int index = -1;
};
struct NodeId {
  int index = -1;
};

// One glTF primitive: triangles with one material.
struct Primitive {
  MeshData geometry;
  MaterialId material;
};

class SceneBuilder {
public:
  struct MeshEntry {
    std::string name;
    std::vector<Primitive> primitives;
  };
  struct NodeEntry {
    std::string name;
    Transform transform;
    std::optional<MeshId> mesh;
    std::optional<LightId> light;
    std::optional<float> camera_yfov; // a perspective camera (radians) looking along the node's -Z
    bool dynamic = false;
    std::vector<int> children;
  };

  explicit SceneBuilder(std::string scene_name = "scene") : scene_name_(std::move(scene_name)) {}

  MaterialId add_material(const Material& material);
  LightId add_light(const Light& light);
  // Throws Error(usage) if there are no primitives or one has no triangles.
  MeshId add_mesh(std::string name, std::vector<Primitive> primitives);
  MeshId add_mesh(std::string name, MeshData geometry, MaterialId material);
  // Copies the triangles of another glTF file (.glb or .gltf, Draco allowed; read by probebake's scene
  // loader) into one mesh, in the model's own space with its node transforms applied; one primitive per
  // material, whose albedo and emission are the loader's per-triangle values (textures averaged) averaged
  // over the material's triangles. Its lights are not copied. Throws Error(input) on a bad or
  // triangle-less file.
  MeshId add_model(const std::filesystem::path& path, std::string name);

  // A node; without parent it is a root of the scene.
  NodeId add_node(std::string name, const Transform& transform = {}, std::optional<NodeId> parent = {});
  NodeId add_mesh_node(std::string name, MeshId mesh, const Transform& transform = {},
                       std::optional<NodeId> parent = {});
  // A light node at `position`; spot and directional lights shine along `direction` (glTF's -Z axis).
  NodeId add_light_node(std::string name, LightId light, glm::vec3 position, glm::vec3 direction = {0.0f, -1.0f, 0.0f},
                        std::optional<NodeId> parent = {});
  // A perspective camera node at `position` looking at `look_at` (+Y up), vertical field of view in radians.
  NodeId add_camera_node(std::string name, glm::vec3 position, glm::vec3 look_at, float yfov);
  // Marks a node as moving at run time (the extras key above).
  void set_dynamic(NodeId node, bool dynamic = true);
  // Puts every current root under one new root with this transform (e.g. to scale or move the scene).
  NodeId wrap_roots(std::string name, const Transform& transform);

  // World-space statistics: a mesh counts once per node that uses it.
  std::size_t triangle_count() const;
  Bounds bounds() const;
  Bounds mesh_bounds(MeshId mesh) const;

  // The scene as .glb bytes (deterministic).
  std::vector<std::uint8_t> to_glb() const;
  // Writes to_glb() to `path` atomically (a temporary file in the same folder, then a rename).
  // Throws Error(output).
  void write_glb(const std::filesystem::path& path) const;

  const std::string& scene_name() const { return scene_name_; }
  const std::vector<Material>& materials() const { return materials_; }
  const std::vector<Light>& lights() const { return lights_; }
  const std::vector<MeshEntry>& meshes() const { return meshes_; }
  const std::vector<NodeEntry>& nodes() const { return nodes_; }
  const std::vector<int>& roots() const { return roots_; }

private:
  template <class Visit>
  void visit_mesh_instances(Visit&& visit) const;

  std::string scene_name_;
  std::vector<Material> materials_;
  std::vector<Light> lights_;
  std::vector<MeshEntry> meshes_;
  std::vector<NodeEntry> nodes_;
  std::vector<int> roots_;
};

// Writes bytes to `path` atomically (temporary file + rename). Throws Error(output).
void write_file_atomically(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes);

} // namespace probebake::samples
