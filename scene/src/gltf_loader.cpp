// glTF 2.0 scene loading: parse with tinygltf, check what tinygltf leaves unchecked, and flatten the node
// hierarchy into world-space triangles (glTF 2.0 spec §3.5 nodes, §3.7 meshes; KHR_lights_punctual).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>

#include <fmt/core.h>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <tiny_gltf.h>

#include "gltf_internal.h"
#include "probebake/scene/scene.h"

namespace probebake::scene {
namespace {

using detail::Context;

// tinygltf keeps the JSON tree and its own copy of every value: a generous bound on its bytes per
// character of JSON text, charged before parsing.
constexpr std::uint64_t kJsonTreeBytesPerChar = 16;
// Scene arrays per triangle: indices, material, albedo, emission.
constexpr std::uint64_t kSceneBytesPerTriangle = sizeof(glm::uvec3) + sizeof(std::uint32_t) + 2 * sizeof(glm::vec3);

// The file must fit the budget before it is read; load_scene_from_memory then charges it to the load's budget.
std::vector<unsigned char> read_file_bytes(const std::filesystem::path& path, std::uint64_t max_memory,
                                           const Context& ctx) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) ctx.fail("open", "file does not exist");
  if (!std::filesystem::is_regular_file(path, ec)) ctx.fail("open", "is not a regular file");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) ctx.fail("open", "cannot read the file size");
  detail::MemoryBudget(max_memory).charge(size, ctx, "open");
  std::ifstream in(path, std::ios::binary);
  if (!in) ctx.fail("open", "cannot open for reading");
  std::vector<unsigned char> bytes(size);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)) || in.gcount() != std::streamsize(size))
    ctx.fail("open", "cannot read the whole file (did it change while reading?)");
  return bytes;
}

std::string first_line(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line.empty() ? "unknown parse error" : line;
}

// A GLB with skipped content (detail::split_glb) is parsed as the canonical container of its JSON and BIN.
std::vector<unsigned char> canonical_container(std::vector<unsigned char> bytes, const Context& ctx) {
  const detail::GlbChunks chunks = detail::split_glb(bytes, ctx);
  for (const std::string& warning : chunks.warnings) ctx.warn(warning);
  if (chunks.canonical) return bytes;
  ctx.charge(bytes.size() + 32, 1, "glb"); // the copy: at most the file and three chunk paddings
  return detail::canonical_glb(bytes, chunks);
}

tinygltf::Model parse_gltf(std::vector<unsigned char> bytes, detail::InputPolicy& policy, const Context& ctx) {
  if (bytes.empty()) ctx.fail("parse", "file is empty");
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) ctx.fail("parse", "file is larger than 4 GiB");
  const bool is_glb = bytes.size() >= 4 && bytes[0] == 'g' && bytes[1] == 'l' && bytes[2] == 'T' && bytes[3] == 'F';
  if (is_glb) bytes = canonical_container(std::move(bytes), ctx);
  const std::string_view json = detail::gltf_json_text(bytes, is_glb, ctx);
  const detail::PreflightFacts facts = detail::preflight_gltf_json(json, policy, ctx);
  ctx.charge(json.size(), kJsonTreeBytesPerChar, "json");
  const detail::TinygltfRewrite rewrite = detail::prepare_for_tinygltf(bytes, is_glb, facts, ctx);
  policy.unused_images = rewrite.unused_images;
  tinygltf::TinyGLTF parser;
  detail::configure_parser(parser, policy);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base_dir = policy.base_dir.string();
  const bool ok = is_glb ? parser.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                                       static_cast<unsigned int>(bytes.size()), base_dir)
                         : parser.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                                      static_cast<unsigned int>(bytes.size()), base_dir);
  if (!ok) ctx.fail(is_glb ? "glb" : "gltf", first_line(err));
  if (!warn.empty()) ctx.warn(first_line(warn));
  detail::restore_after_tinygltf(model, rewrite);
  return model;
}

void check_required_extensions(const tinygltf::Model& model, const Context& ctx) {
  const auto& supported = supported_extensions();
  for (const std::string& name : model.extensionsRequired)
    if (std::find(supported.begin(), supported.end(), name) == supported.end())
      ctx.fail("extensionsRequired", fmt::format("required extension {} is not supported", name));
}

glm::mat4 local_transform(const tinygltf::Node& node, const Context& ctx, const std::string& place) {
  if (node.matrix.size() == 16) {
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = float(node.matrix[std::size_t(i)]); // column-major
    return m;
  }
  if (!node.matrix.empty()) ctx.fail(place, "matrix must have 16 elements");
  glm::mat4 m(1.0f);
  if (node.translation.size() == 3)
    m = glm::translate(m,
                       glm::vec3(float(node.translation[0]), float(node.translation[1]), float(node.translation[2])));
  if (node.rotation.size() == 4) {
    const glm::quat q(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]),
                      float(node.rotation[2]));
    m = m * glm::mat4_cast(glm::normalize(q));
  }
  if (node.scale.size() == 3)
    m = glm::scale(m, glm::vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2])));
  return m;
}

bool is_dynamic(const tinygltf::Node& node) {
  const tinygltf::Value& flag = detail::member(detail::member(node.extras, "probebake"), "dynamic");
  return flag.IsBool() && flag.Get<bool>();
}

Light convert_light(const tinygltf::Light& in, const glm::mat4& world, const Context& ctx, const std::string& place) {
  Light light;
  light.name = in.name;
  if (in.type == "point")
    light.type = LightType::point;
  else if (in.type == "spot")
    light.type = LightType::spot;
  else if (in.type == "directional")
    light.type = LightType::directional;
  else
    ctx.fail(place, fmt::format("unknown light type '{}'", in.type));
  if (in.color.size() == 3) light.color = {float(in.color[0]), float(in.color[1]), float(in.color[2])};
  light.intensity = float(in.intensity);
  light.range = light.type == LightType::directional ? 0.0f : float(in.range); // range is ignored for sun lights
  light.inner_cone_angle = float(in.spot.innerConeAngle);
  light.outer_cone_angle = float(in.spot.outerConeAngle);
  light.position = glm::vec3(world * glm::vec4(0, 0, 0, 1));
  const glm::vec3 dir = glm::mat3(world) * glm::vec3(0, 0, -1);
  light.direction = glm::length(dir) > 0.0f ? glm::normalize(dir) : glm::vec3(0, 0, -1);
  const bool finite = std::isfinite(light.intensity) && std::isfinite(light.range) && detail::all_finite(light.color) &&
                      detail::all_finite(light.position);
  if (!finite || light.intensity < 0.0f || glm::any(glm::lessThan(light.color, glm::vec3(0.0f))))
    ctx.fail(place, "light colour, intensity and position must be finite and non-negative");
  return light;
}

class SceneBuilder {
  static constexpr int kMaxNodeDepth = 4096; // keeps hostile node chains from exhausting the stack

public:
  SceneBuilder(const tinygltf::Model& model, const std::vector<int>& texture_images, Scene& scene, const Context& ctx)
      : model_(model), texture_images_(texture_images), scene_(scene), ctx_(ctx) {}

  // `parent_object`: the dynamic object of the nearest dynamic ancestor, or -1.
  void add_node(int index, const glm::mat4& parent, int parent_object, int depth) {
    const std::string place = fmt::format("nodes[{}]", index);
    if (index < 0 || std::size_t(index) >= model_.nodes.size()) ctx_.fail(place, "node does not exist");
    if (depth > kMaxNodeDepth) ctx_.fail(place, "node hierarchy is deeper than 4096 levels");
    if (!visited_.insert(index).second) ctx_.fail(place, "node is reached twice (cycle or shared child)");
    const tinygltf::Node& node = model_.nodes[std::size_t(index)];
    const glm::mat4 world = parent * local_transform(node, ctx_, place);
    if (!detail::all_finite(world[0]) || !detail::all_finite(world[1]) || !detail::all_finite(world[2]) ||
        !detail::all_finite(world[3]))
      ctx_.fail(place, "transform is not finite");
    int object = parent_object;
    if (object < 0 && (is_dynamic(node) || named_dynamic(node.name))) {
      object = int(scene_.dynamic_objects.size());
      scene_.dynamic_objects.push_back({index, node.name, world});
    }
    if (node.mesh >= 0) add_mesh_instance(node, index, world, object, place);
    auto light = node.extensions.find("KHR_lights_punctual");
    if (light != node.extensions.end() && detail::member(light->second, "light").IsInt()) {
      const int li = detail::member(light->second, "light").Get<int>();
      if (li < 0 || std::size_t(li) >= model_.lights.size())
        ctx_.fail(place, fmt::format("light {} does not exist", li));
      const tinygltf::Light& punctual = model_.lights[std::size_t(li)];
      if (punctual.type == "point" || punctual.type == "spot" || punctual.type == "directional")
        scene_.lights.push_back(convert_light(punctual, world, ctx_, place));
      else // a later version's light type: the validator warns, and so does the loader
        ctx_.warn(fmt::format("{}: light {} of unknown type '{}' skipped", place, li, punctual.type));
    }
    if (node.camera >= 0) add_camera(node, world, place);
    for (int child : node.children) add_node(child, world, object, depth + 1);
  }

  // Nodes named dynamic by the caller (LoadOptions::dynamic_nodes); each name must name a node.
  void set_dynamic_names(const std::vector<std::string>& names) {
    for (const std::string& name : names) {
      const bool found = std::any_of(model_.nodes.begin(), model_.nodes.end(),
                                     [&](const tinygltf::Node& n) { return n.name == name; });
      if (!found) ctx_.fail("nodes", fmt::format("no node is named '{}' (--dynamic)", name));
      dynamic_names_.insert(name);
    }
  }

private:
  void add_camera(const tinygltf::Node& node, const glm::mat4& world, const std::string& place) {
    if (std::size_t(node.camera) >= model_.cameras.size())
      ctx_.fail(place, fmt::format("camera {} does not exist", node.camera));
    const tinygltf::Camera& camera = model_.cameras[std::size_t(node.camera)];
    if (camera.type == "orthographic") {
      ctx_.warn(fmt::format("{}: {} camera not used (eval takes perspective cameras)", place, camera.type));
      return;
    }
    if (camera.type != "perspective") return; // an unknown type, warned of when the file was parsed
    const glm::vec3 forward = glm::mat3(world) * glm::vec3(0, 0, -1);
    const float yfov = float(camera.perspective.yfov);
    if (!(glm::length(forward) > 0.0f) || !(yfov > 0.0f && yfov < 3.14159f))
      ctx_.fail(place, "camera has no direction or a field of view outside (0, pi)");
    scene_.cameras.push_back({node.name, glm::vec3(world * glm::vec4(0, 0, 0, 1)), glm::normalize(forward), yfov});
  }

  bool named_dynamic(const std::string& name) const { return !name.empty() && dynamic_names_.count(name) != 0; }

  void add_mesh_instance(const tinygltf::Node& node, int index, const glm::mat4& world, int object,
                         const std::string& place) {
    if (std::size_t(node.mesh) >= model_.meshes.size())
      ctx_.fail(place, fmt::format("mesh {} does not exist", node.mesh));
    Instance instance;
    instance.node_name = node.name;
    instance.node = index;
    instance.mesh = node.mesh;
    instance.dynamic = object >= 0;
    instance.dynamic_object = object;
    instance.world_from_local = world;
    instance.first_triangle = static_cast<std::uint32_t>(scene_.triangles.size());
    const tinygltf::Mesh& mesh = model_.meshes[std::size_t(node.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
      add_primitive(mesh.primitives[p], world, fmt::format("meshes[{}].primitives[{}]", node.mesh, p), instance);
    instance.triangle_count = static_cast<std::uint32_t>(scene_.triangles.size()) - instance.first_triangle;
    scene_.instances.push_back(instance);
  }

  void add_primitive(const tinygltf::Primitive& primitive, const glm::mat4& world, const std::string& place,
                     Instance& instance) {
    static const char* kModeNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    if (primitive.mode >= 0 && primitive.mode <= 3) {
      ctx_.warn(fmt::format("{}: mode {} skipped (only triangles are baked)", place, kModeNames[primitive.mode]));
      return;
    }
    if (primitive.mode > 6) { // a later version's mode: the validator warns, and so does the loader
      ctx_.warn(fmt::format("{}: unknown mode {} skipped (only triangles are baked)", place, primitive.mode));
      return;
    }
    const bool draco = primitive.extensions.count("KHR_draco_mesh_compression") != 0;
    detail::PrimitiveGeometry g = draco ? detail::decode_draco_primitive(model_, primitive, ctx_, place)
                                        : detail::read_plain_primitive(model_, primitive, ctx_, place);
    if (primitive.mode == TINYGLTF_MODE_TRIANGLE_STRIP || primitive.mode == TINYGLTF_MODE_TRIANGLE_FAN)
      ctx_.charge(g.indices.size(), 3 * sizeof(std::uint32_t), place);
    expand_strips_and_fans(g, primitive.mode);
    ctx_.charge(g.positions.size(), sizeof(glm::vec3), place);
    ctx_.charge(g.indices.size() / 3, kSceneBytesPerTriangle, place);
    for (std::uint32_t i : g.indices)
      if (i >= g.positions.size())
        ctx_.fail(place, fmt::format("index {} is past the vertex count {}", i, g.positions.size()));
    const int material = primitive.material;
    if (material >= 0 && std::size_t(material) >= model_.materials.size())
      ctx_.fail(place, fmt::format("material {} does not exist", material));
    const std::size_t material_slot = material >= 0 ? std::size_t(material) : scene_.materials.size() - 1;
    const detail::TriangleColors colors =
        detail::average_triangle_colors(model_, texture_images_, material, scene_.materials[material_slot], g);

    const bool flip = glm::determinant(glm::mat3(world)) < 0.0f; // mirrored instances reverse the winding
    const auto base = static_cast<std::uint32_t>(scene_.positions.size());
    for (const glm::vec3& p : g.positions) {
      if (!detail::all_finite(p)) ctx_.fail(place, "POSITION holds NaN or Inf");
      const glm::vec3 w = glm::vec3(world * glm::vec4(p, 1.0f));
      if (!detail::all_finite(w)) ctx_.fail(place, "transformed position is not finite");
      scene_.positions.push_back(w);
      instance.bounds.extend(w);
    }
    for (std::size_t t = 0; t < g.indices.size() / 3; ++t) {
      glm::uvec3 tri(g.indices[3 * t], g.indices[3 * t + 1], g.indices[3 * t + 2]);
      if (flip) std::swap(tri.y, tri.z);
      scene_.triangles.push_back(tri + base);
      scene_.triangle_material.push_back(static_cast<std::uint32_t>(material_slot));
      scene_.triangle_albedo.push_back(colors.albedo[t]);
      scene_.triangle_emission.push_back(colors.emission[t]);
    }
  }

  void expand_strips_and_fans(detail::PrimitiveGeometry& g, int mode) const {
    if (mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      g.indices.resize(g.indices.size() / 3 * 3); // a trailing partial triangle is dropped
      return;
    }
    std::vector<std::uint32_t> v = std::move(g.indices);
    g.indices.clear();
    for (std::size_t i = 0; i + 2 < v.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
        g.indices.insert(g.indices.end(), {v[i + 1], v[i + 2], v[0]});
      else if (i % 2 == 0)
        g.indices.insert(g.indices.end(), {v[i], v[i + 1], v[i + 2]});
      else
        g.indices.insert(g.indices.end(), {v[i + 1], v[i], v[i + 2]});
    }
  }

  const tinygltf::Model& model_;
  const std::vector<int>& texture_images_;
  Scene& scene_;
  const Context& ctx_;
  std::set<int> visited_;
  std::set<std::string> dynamic_names_;
};

std::vector<int> root_nodes(const tinygltf::Model& model, const Context& ctx) {
  if (!model.scenes.empty()) {
    const int s = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (std::size_t(s) >= model.scenes.size()) ctx.fail("scene", fmt::format("default scene {} does not exist", s));
    return model.scenes[std::size_t(s)].nodes;
  }
  std::vector<bool> is_child(model.nodes.size(), false); // no scenes: every node without a parent is a root
  for (const auto& node : model.nodes)
    for (int c : node.children)
      if (c >= 0 && std::size_t(c) < model.nodes.size()) is_child[std::size_t(c)] = true;
  std::vector<int> roots;
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (!is_child[i]) roots.push_back(int(i));
  return roots;
}

} // namespace

Scene load_scene(const std::filesystem::path& path, const LoadOptions& options) {
  const Context ctx{path.string()};
  Scene scene = load_scene_from_memory(read_file_bytes(path, options.max_memory, ctx), path.string(),
                                       path.parent_path(), options);
  std::error_code ec;
  scene.input_files.insert(scene.input_files.begin(), std::filesystem::weakly_canonical(path, ec));
  return scene;
}

Scene load_scene_from_memory(std::vector<unsigned char> bytes, const std::string& name,
                             const std::filesystem::path& base_dir, const LoadOptions& options) {
  Scene scene;
  detail::MemoryBudget budget(options.max_memory);
  const Context ctx{name, &scene.warnings, &budget, options.strict};
  ctx.charge(bytes.size(), 1, "open");
  detail::InputPolicy policy(base_dir, options.allowed_paths, budget, ctx);
  tinygltf::Model parsed = parse_gltf(std::move(bytes), policy, ctx);
  check_required_extensions(parsed, ctx);
  detail::decode_meshopt_buffer_views(parsed, ctx);
  detail::decode_buffer_view_images(parsed, policy);
  const tinygltf::Model& model = parsed;
  scene.input_files = std::move(policy.files_read);
  scene.extensions_used = model.extensionsUsed;
  scene.extensions_required = model.extensionsRequired;
  scene.mesh_count = int(model.meshes.size());
  for (std::size_t m = 0; m < model.materials.size(); ++m)
    scene.materials.push_back(detail::convert_material(model, int(m), ctx));
  scene.materials.push_back(detail::convert_material(model, -1, ctx)); // glTF default material
  const std::vector<int> texture_images = detail::select_texture_images(model, policy.image_problems, ctx);

  SceneBuilder builder(model, texture_images, scene, ctx);
  builder.set_dynamic_names(options.dynamic_nodes);
  for (int root : root_nodes(model, ctx)) builder.add_node(root, glm::mat4(1.0f), -1, 0);
  for (const glm::vec3& p : scene.positions) scene.bounds.extend(p);
  if (options.require_triangles && scene.triangles.empty())
    ctx.fail("meshes",
             fmt::format("scene has no triangles to bake ({} meshes, {} lights; `probebake info` describes it)",
                         scene.mesh_count, scene.lights.size()));
  // The caller's sky wins over the scene's EXT_lights_image_based.
  if (options.sky) {
    set_sky(scene, *options.sky);
  } else if (std::optional<sky::Sky> image_based = detail::image_based_sky(model, ctx)) {
    set_sky(scene, std::move(*image_based));
  }
  return scene;
}

} // namespace probebake::scene
