// Scene input: a glTF 2.0 file flattened into world-space triangles with per-triangle diffuse albedo and
// emission, punctual lights and the instances they came from.
//
// Units are glTF's: metres, Y up; light intensities in candela (point, spot) and lux (directional),
// treated as radiometric values (W/sr, W/m^2) by the light transport. Front faces are counter-clockwise
// in world space (instances with a negative-determinant transform have their winding flipped).
// Textures are averaged per triangle (sampled at a fixed set of barycentric points) rather than sampled
// at hit points: diffuse probes integrate over far larger areas than a texel, and a per-triangle colour
// is what a GPU tracer without texture access can read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "probebake/sky/sky.h"

namespace probebake::scene {

struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  float largest_extent() const; // 0 when empty
  void extend(const glm::vec3& p);
  void extend(const Bounds& b);
};

enum class LightType { point, spot, directional };

struct Light {
  std::string name;
  LightType type = LightType::point;
  glm::vec3 color{1.0f};                 // linear RGB
  float intensity = 1.0f;                // candela (point, spot) or lux (directional)
  glm::vec3 position{0.0f};              // world space (point, spot)
  glm::vec3 direction{0, 0, -1};         // world-space unit direction the light travels (spot, directional)
  float range = 0.0f;                    // 0 = infinite
  float inner_cone_angle = 0.0f;         // radians (spot)
  float outer_cone_angle = 0.785398163f; // radians (spot), glTF default pi/4
};

// A glTF perspective camera placed by its node (eval's viewpoints and image receivers).
struct SceneCamera {
  std::string name;
  glm::vec3 position{0.0f};
  glm::vec3 forward{0, 0, -1}; // unit, world space (the node's -Z)
  float yfov = 0.8f;           // vertical field of view, radians
};

struct Material {
  std::string name;
  glm::vec3 base_color{1.0f};  // baseColorFactor (linear RGB, alpha ignored)
  glm::vec3 emission{0.0f};    // emissiveFactor * KHR_materials_emissive_strength
  int base_color_texture = -1; // glTF texture index, -1 = none
  int emissive_texture = -1;
  bool double_sided = false;
};

// One node that references a mesh. Its triangles are [first_triangle, first_triangle + triangle_count).
struct Instance {
  std::string node_name;
  int node = -1;
  int mesh = -1;
  std::uint32_t first_triangle = 0;
  std::uint32_t triangle_count = 0;
  bool dynamic = false;    // node (or an ancestor) is dynamic (extras {"probebake": {"dynamic": true}} or by name)
  int dynamic_object = -1; // index into Scene::dynamic_objects when dynamic
  glm::mat4 world_from_local{1.0f};
  Bounds bounds;
};

// A node that moves at run time with everything below it (the outermost dynamic node of its subtree): its
// triangles are one object for the runtime, in this node's frame at rest (docs/FORMAT.md "Dynamic objects").
struct DynamicObject {
  int node = -1;
  std::string name;
  glm::mat4 world_from_object{1.0f}; // the node's world transform at rest, as loaded
};

struct Scene {
  std::vector<glm::vec3> positions;             // world space
  std::vector<glm::uvec3> triangles;            // indices into positions, CCW front faces
  std::vector<std::uint32_t> triangle_material; // index into materials
  std::vector<glm::vec3> triangle_albedo;       // diffuse albedo, texture averaged over the triangle
  std::vector<glm::vec3> triangle_emission;     // emitted radiance, texture averaged
  std::vector<Material> materials;              // always at least one (the glTF default material last)
  std::vector<Light> lights;
  sky::Sky sky;                     // what rays that leave the scene see (set_sky); black unless a command sets one
  int sun_light = -1;               // the physical sky's sun in `lights` (set_sky), else -1
  std::vector<SceneCamera> cameras; // perspective cameras, scene order (orthographic ones skipped)
  std::vector<Instance> instances;
  std::vector<DynamicObject> dynamic_objects; // in the order the node walk meets them
  std::vector<std::string> extensions_used;
  std::vector<std::string> extensions_required;
  std::vector<std::string> warnings; // things skipped, e.g. non-triangle primitives
  int mesh_count = 0;
  Bounds bounds;                                  // of all triangles
  std::vector<std::filesystem::path> input_files; // every file read: the scene, then its buffers and images (resolved)

  std::size_t triangle_count() const { return triangles.size(); }
};

struct LoadOptions {
  // Refuse scenes without triangles (the bake needs geometry; `info` accepts them).
  bool require_triangles = false;
  // External buffers and images resolve only inside the scene's folder (symlinks and ".." resolved) and
  // these folders; never through the working directory. Absolute URIs and URI schemes are refused.
  std::vector<std::filesystem::path> allowed_paths = {};
  // Bytes the loader may allocate for file contents and decoded geometry and images; 0 = no limit.
  std::uint64_t max_memory = 0;
  // A texture that cannot be decoded (unknown format, KTX2 without fallback, missing file, corrupt data) is
  // an error instead of a warning (its materials would otherwise use their factors alone).
  bool strict = false;
  // Nodes that move at run time besides those whose extras say so (`--dynamic NAME`): every node with one
  // of these names; a name no node has is an error.
  std::vector<std::string> dynamic_nodes = {};
  // The sky (glTF has no ratified one): set with set_sky after the scene's own lights, so a physical sky's sun
  // comes last. Unset: black.
  std::optional<sky::Sky> sky = {};
};

// The scene's sky. A physical sky brings its sun: a directional light named "probebake sun" (colour and
// intensity sky::sun_irradiance, travelling away from the sun direction) appended to `lights` (a sun of an
// earlier set_sky is replaced), its index in sun_light.
void set_sky(Scene& scene, sky::Sky sky);

// Loads .gltf (external files or data URIs) or .glb. Throws probebake::Error (ErrorKind::input) with a
// one-line "<file>: <place>: <reason>" message on any malformed, truncated, unsupported or unsafe input
// (README "Security": confinement, JSON depth, sizes checked before allocation).
Scene load_scene(const std::filesystem::path& path, const LoadOptions& options = {});
// The same from bytes in memory; `name` is used in messages, external URIs resolve against `base_dir`.
Scene load_scene_from_memory(std::vector<unsigned char> bytes, const std::string& name,
                             const std::filesystem::path& base_dir, const LoadOptions& options = {});

struct SceneSummary {
  std::size_t emissive_triangles = 0;
  double emissive_area = 0.0; // m^2
  std::size_t dynamic_instances = 0;
  std::size_t degenerate_triangles = 0; // zero area
};
SceneSummary summarize(const Scene& scene);

double triangle_area(const Scene& scene, std::size_t triangle);
glm::vec3 triangle_normal(const Scene& scene, std::size_t triangle); // unit geometric normal (CCW)
// glTF doubleSided of the triangle's material: both sides reflect and emit (the back with the normal
// reversed) and neither side is the inside of a solid.
bool is_double_sided(const Scene& scene, std::size_t triangle);

// The surfaces that receive light, for sampling by area (the reference's receivers, the skeleton's surface
// samples): the front of every triangle of positive area and the back of a double-sided one, in triangle
// order, with the inclusive prefix sums of their areas.
struct ReceivingSide {
  std::uint32_t triangle = 0;
  bool back = false;
};
struct ReceivingSides {
  std::vector<ReceivingSide> sides;
  std::vector<double> cumulative_area; // m^2, per side
  double total_area = 0.0;
};
ReceivingSides receiving_sides(const Scene& scene);

// The scene with each dynamic object moved from its rest pose to world_from_object[o] (one per
// Scene::dynamic_objects entry): its triangles' vertices are transformed, everything else is kept. What the
// path-traced reference and the CPU tests trace for a pose of the runtime's objects.
Scene posed(const Scene& scene, std::span<const glm::mat4> world_from_object);

// Distance by which ray origins are lifted off their surface: relative to the scene's size and to the
// magnitude of its coordinates (float spacing grows with them).
float ray_epsilon(const Scene& scene);

// A glTF URI percent-decoded as tinygltf decodes it before opening the file ('+' as a space), so that the
// path checked is the path opened.
std::string percent_decode(const std::string& uri);

// The glTF extensions the loader understands (others in extensionsRequired are refused).
const std::vector<std::string>& supported_extensions();

} // namespace probebake::scene
