// Making spec-valid files loadable by tinygltf 2.7, which refuses some of what glTF 2.0 allows:
// - a primitive's index accessor must have a bufferView (Draco primitives have none until decoded, and an
//   accessor without bufferView is all zeros by the spec);
// - every buffer of a .gltf (and every buffer but the first of a .glb) must have a uri, yet placeholder
//   buffers (EXT_meshopt_compression fallback) and unused buffers may have none;
// - image data URIs must be PNG/JPEG/BMP/GIF (EXT_texture_webp and KHR_texture_basisu use others).
// The leniency of gltf_lenient.cpp is applied to the same tree. The JSON is rewritten in memory only when
// the preflight or the leniency found something; what is hidden from tinygltf is restored on the parsed model.
#include <algorithm>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "gltf_internal.h"

namespace probebake::scene::detail {
namespace {

bool contains(const std::vector<int>& list, int value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

bool is_object_with_array(const nlohmann::json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_array();
}

void hide_indices(nlohmann::json& gltf, const PreflightFacts& facts, TinygltfRewrite& out) {
  if (!is_object_with_array(gltf, "meshes")) return;
  for (std::size_t m = 0; m < gltf["meshes"].size(); ++m) {
    nlohmann::json& mesh = gltf["meshes"][m];
    if (!is_object_with_array(mesh, "primitives")) continue;
    for (std::size_t p = 0; p < mesh["primitives"].size(); ++p) {
      nlohmann::json& primitive = mesh["primitives"][p];
      if (!primitive.is_object() || !primitive.contains("indices")) continue;
      const auto extensions = primitive.find("extensions");
      const bool draco = extensions != primitive.end() && extensions->is_object() &&
                         extensions->contains("KHR_draco_mesh_compression");
      const nlohmann::json& indices = primitive["indices"];
      const bool viewless = indices.is_number_integer() && contains(facts.accessors_without_view, indices.get<int>());
      if (!draco && !viewless) continue;
      if (viewless && !draco) out.hidden_indices.push_back({int(m), int(p), indices.get<int>()});
      primitive.erase("indices");
    }
  }
}

void fill_placeholders(nlohmann::json& gltf, bool is_glb, const PreflightFacts& facts, TinygltfRewrite& out) {
  if (!is_object_with_array(gltf, "buffers")) return;
  for (int b : facts.buffers_without_uri) {
    if ((is_glb && b == 0) || std::size_t(b) >= gltf["buffers"].size()) continue; // b == 0: the BIN chunk
    nlohmann::json& buffer = gltf["buffers"][std::size_t(b)];
    buffer["uri"] = kPlaceholderUri;
    buffer["byteLength"] = 1;
    out.placeholder_buffers.push_back(b);
  }
}

void generic_image_uris(nlohmann::json& gltf, const PreflightFacts& facts) {
  if (!is_object_with_array(gltf, "images")) return;
  for (int i : facts.images_with_other_media) {
    if (std::size_t(i) >= gltf["images"].size() || !gltf["images"][std::size_t(i)].is_object()) continue;
    // The tree may disagree with the preflight's facts (a repeated "images" key: the SAX pass and the tree
    // keep different ones), so the URI is checked again rather than trusted.
    const auto uri = gltf["images"][std::size_t(i)].find("uri");
    if (uri == gltf["images"][std::size_t(i)].end() || !uri->is_string()) continue;
    const std::string text = uri->get<std::string>();
    const std::size_t comma = text.find(',');
    if (!text.starts_with("data:") || comma == std::string::npos) continue;
    *uri = "data:application/octet-stream;base64" + text.substr(comma);
  }
}

nlohmann::json parse_json(const char* begin, std::size_t size, const Context& ctx) {
  try {
    return nlohmann::json::parse(begin, begin + size);
  } catch (const nlohmann::json::exception& e) {
    ctx.fail("json", e.what());
  }
}

void replace_json(std::vector<unsigned char>& bytes, bool is_glb, const std::string& text, const Context& ctx) {
  if (!is_glb) {
    bytes.assign(text.begin(), text.end());
    return;
  }
  GlbChunks chunks = split_glb(bytes, ctx); // the canonical container: header, JSON, BIN
  chunks.json = {reinterpret_cast<const unsigned char*>(text.data()), text.size()};
  bytes = canonical_glb(bytes, chunks);
}

// Draco is searched in the JSON only, never in a GLB's binary chunk.
bool needs_rewrite(std::string_view json, bool is_glb, const PreflightFacts& facts) {
  static const char kDraco[] = "KHR_draco_mesh_compression";
  const bool placeholders =
      facts.buffers_without_uri.size() > (is_glb && contains(facts.buffers_without_uri, 0) ? 1u : 0u);
  return placeholders || !facts.accessors_without_view.empty() || !facts.images_with_other_media.empty() ||
         facts.integral_floats || json.find(kDraco) != std::string_view::npos;
}

bool hides_anything(const TinygltfRewrite& r) {
  return !r.placeholder_buffers.empty() || !r.hidden_image_uris.empty() || !r.unreadable_accessors.empty() ||
         !r.unknown_cameras.empty();
}

} // namespace

TinygltfRewrite prepare_for_tinygltf(std::vector<unsigned char>& bytes, bool is_glb, const PreflightFacts& facts,
                                     const Context& ctx) {
  TinygltfRewrite out;
  const std::string_view json = gltf_json_text(bytes, is_glb, ctx);
  nlohmann::json gltf = parse_json(json.data(), json.size(), ctx);
  if (!gltf.is_object()) return out; // tinygltf reports it
  apply_leniency(gltf, is_glb, facts, ctx, out);
  if (!needs_rewrite(json, is_glb, facts) && !hides_anything(out)) return out;
  hide_indices(gltf, facts, out);
  fill_placeholders(gltf, is_glb, facts, out);
  generic_image_uris(gltf, facts);
  replace_json(bytes, is_glb, gltf.dump(), ctx);
  return out;
}

void restore_after_tinygltf(tinygltf::Model& model, const TinygltfRewrite& rewrite) {
  for (int i : rewrite.hidden_image_uris)
    if (std::size_t(i) < model.images.size()) model.images[std::size_t(i)].uri.clear();
  for (int a : rewrite.unreadable_accessors)
    if (std::size_t(a) < model.accessors.size()) model.accessors[std::size_t(a)].componentType = -1;
  for (const auto& [c, type] : rewrite.unknown_cameras)
    if (std::size_t(c) < model.cameras.size()) model.cameras[std::size_t(c)].type = type;
  for (int b : rewrite.placeholder_buffers)
    if (std::size_t(b) < model.buffers.size()) model.buffers[std::size_t(b)].data.clear();
  for (const auto& [m, p, accessor] : rewrite.hidden_indices)
    if (std::size_t(m) < model.meshes.size() && std::size_t(p) < model.meshes[std::size_t(m)].primitives.size())
      model.meshes[std::size_t(m)].primitives[std::size_t(p)].indices = accessor;
}

} // namespace probebake::scene::detail
