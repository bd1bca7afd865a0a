// Which buffers, bufferViews, accessors and images a glTF file references, so that unused ones are never
// decoded and their faults are warnings at most, as the Khronos validator treats them (UNUSED_OBJECT is
// information). An object counts as used when anything that may be read refers to it: any mesh primitive
// (attributes, indices, morph targets, Draco), skin, animation sampler, texture or image. The tree's depth
// was bounded by the preflight.
#include <nlohmann/json.hpp>

#include "gltf_internal.h"

namespace probebake::scene::detail {
namespace {

using nlohmann::json;

const json& array_at(const json& gltf, const char* key) {
  static const json kEmpty = json::array();
  const auto it = gltf.find(key);
  return it != gltf.end() && it->is_array() ? *it : kEmpty;
}

// Marks `object[key]` when it is a valid index; out-of-range references are left for the readers to refuse.
void mark(const json& object, const char* key, std::vector<bool>& used) {
  if (!object.is_object()) return;
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return;
  const double index = it->get<double>();
  if (index >= 0 && index < double(used.size()) && index == double(std::size_t(index))) used[std::size_t(index)] = true;
}

void mark_values(const json& object, std::vector<bool>& used) {
  if (!object.is_object()) return;
  for (const auto& [name, value] : object.items()) mark(object, name.c_str(), used);
}

void mark_primitive(const json& primitive, UsedObjects& used) {
  if (!primitive.is_object()) return;
  mark_values(primitive.value("attributes", json::object()), used.accessors);
  mark(primitive, "indices", used.accessors);
  for (const json& target : primitive.value("targets", json::array())) mark_values(target, used.accessors);
  const json& extensions = primitive.value("extensions", json::object());
  if (extensions.is_object())
    mark(extensions.value("KHR_draco_mesh_compression", json::object()), "bufferView", used.views);
}

void mark_accessor_views(const json& accessor, UsedObjects& used) {
  mark(accessor, "bufferView", used.views);
  if (!accessor.is_object() || !accessor.contains("sparse") || !accessor["sparse"].is_object()) return;
  const json& sparse = accessor["sparse"];
  mark(sparse.value("indices", json::object()), "bufferView", used.views);
  mark(sparse.value("values", json::object()), "bufferView", used.views);
}

void mark_view_buffers(const json& view, UsedObjects& used) {
  mark(view, "buffer", used.buffers);
  if (!view.is_object() || !view.contains("extensions") || !view["extensions"].is_object()) return;
  mark(view["extensions"].value("EXT_meshopt_compression", json::object()), "buffer", used.buffers);
}

// A texture's image: its `source`, or the `source` of any extension (EXT_texture_webp, KHR_texture_basisu, ...).
void mark_texture_images(const json& texture, UsedObjects& used) {
  mark(texture, "source", used.images);
  if (!texture.is_object() || !texture.contains("extensions") || !texture["extensions"].is_object()) return;
  for (const auto& [name, extension] : texture["extensions"].items()) mark(extension, "source", used.images);
}

} // namespace

UsedObjects find_used_objects(const json& gltf) {
  UsedObjects used;
  used.buffers.assign(array_at(gltf, "buffers").size(), false);
  used.views.assign(array_at(gltf, "bufferViews").size(), false);
  used.accessors.assign(array_at(gltf, "accessors").size(), false);
  used.images.assign(array_at(gltf, "images").size(), false);

  for (const json& mesh : array_at(gltf, "meshes"))
    if (mesh.is_object())
      for (const json& primitive : mesh.value("primitives", json::array())) mark_primitive(primitive, used);
  for (const json& skin : array_at(gltf, "skins")) mark(skin, "inverseBindMatrices", used.accessors);
  for (const json& animation : array_at(gltf, "animations"))
    if (animation.is_object())
      for (const json& sampler : animation.value("samplers", json::array())) {
        mark(sampler, "input", used.accessors);
        mark(sampler, "output", used.accessors);
      }
  for (const json& texture : array_at(gltf, "textures")) mark_texture_images(texture, used);

  const json& accessors = array_at(gltf, "accessors");
  for (std::size_t a = 0; a < accessors.size(); ++a)
    if (used.accessors[a]) mark_accessor_views(accessors[a], used);
  const json& images = array_at(gltf, "images");
  for (std::size_t i = 0; i < images.size(); ++i)
    if (used.images[i]) mark(images[i], "bufferView", used.views);
  const json& views = array_at(gltf, "bufferViews");
  for (std::size_t v = 0; v < views.size(); ++v)
    if (used.views[v]) mark_view_buffers(views[v], used);
  return used;
}

} // namespace probebake::scene::detail
