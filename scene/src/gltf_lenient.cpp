// Leniency where the glTF spec and the Khronos validator are lenient (docs/GLTF.md, "Accepted with a
// warning"), applied to the JSON tree before tinygltf 2.7 parses it:
// - integral floats become integers (JSON does not tell 1.0 from 1; tinygltf takes only integers);
// - unused buffers and images are never read or decoded, so a fault of theirs (a data URI that is not base64)
//   is not the scene's; the same fault in an object that may be read is refused with its reason;
// - an unknown enum value (a later version's accessor type, a camera type) is a warning in an unused object,
//   and refused only where its data would be read.
#include <cmath>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "gltf_internal.h"

namespace probebake::scene::detail {
namespace {

using nlohmann::json;

constexpr double kLargestExactInteger = 9007199254740992.0; // 2^53

// Depth is bounded by the preflight (kMaxJsonDepth), so this recursion is too.
void integers_from_integral_floats(json& value) {
  if (value.is_number_float()) {
    const double v = value.get<double>();
    if (std::abs(v) <= kLargestExactInteger && v == std::floor(v)) {
      if (v < 0)
        value = std::int64_t(v);
      else
        value = std::uint64_t(v);
    }
    return;
  }
  if (value.is_array())
    for (json& element : value) integers_from_integral_floats(element);
  if (value.is_object())
    for (auto& [key, element] : value.items())
      if (key != "extras") integers_from_integral_floats(element); // extras are the author's, kept as written
}

json* element(json& gltf, const std::string& array, int index) {
  const auto it = gltf.find(array);
  if (it == gltf.end() || !it->is_array() || index < 0 || std::size_t(index) >= it->size()) return nullptr;
  json& e = (*it)[std::size_t(index)];
  return e.is_object() ? &e : nullptr;
}

bool is_used(const UsedObjects& used, const std::string& array, int index) {
  const std::vector<bool>* flags = array == "buffers"     ? &used.buffers
                                   : array == "images"    ? &used.images
                                   : array == "accessors" ? &used.accessors
                                                          : nullptr;
  return flags != nullptr && index >= 0 && std::size_t(index) < flags->size() && (*flags)[std::size_t(index)];
}

std::string place_of(const ElementFact& fact) { return fmt::format("{}[{}].{}", fact.array, fact.index, fact.key); }

// Unused buffers (other than a GLB's BIN chunk) become placeholders and unused images lose their URI, so
// neither is read, decoded or charged; a URI fault in a used one is refused.
void hide_unused_data(json& gltf, bool is_glb, const UsedObjects& used, const PreflightFacts& facts, const Context& ctx,
                      TinygltfRewrite& out) {
  for (const ElementFact& fact : facts.bad_data_uris)
    if (is_used(used, fact.array, fact.index)) ctx.fail(place_of(fact), fact.text);
  for (std::size_t b = 0; b < used.buffers.size(); ++b) {
    json* buffer = element(gltf, "buffers", int(b));
    if (used.buffers[b] || buffer == nullptr || !buffer->contains("uri")) continue;
    if (is_glb && b == 0) continue;
    (*buffer)["uri"] = kPlaceholderUri;
    (*buffer)["byteLength"] = 1;
    out.placeholder_buffers.push_back(int(b));
  }
  for (std::size_t i = 0; i < used.images.size(); ++i) {
    if (used.images[i]) continue;
    out.unused_images.push_back(int(i));
    json* image = element(gltf, "images", int(i));
    if (image == nullptr || !image->contains("uri")) continue;
    (*image)["uri"] = kPlaceholderUri;
    out.hidden_image_uris.push_back(int(i));
  }
}

void accept_unknown_enums(json& gltf, const UsedObjects& used, const PreflightFacts& facts, const Context& ctx,
                          TinygltfRewrite& out) {
  for (const ElementFact& fact : facts.unknown_enums) {
    json* object = element(gltf, fact.array, fact.index);
    if (object == nullptr) continue;
    if (fact.array == "cameras") {
      // Only perspective cameras are used (eval viewpoints); tinygltf needs a known type to parse the rest.
      ctx.warn(fmt::format("{}: unknown value '{}', camera not used", place_of(fact), fact.text));
      *object = {{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"zfar", 1}, {"znear", 0}}}};
      out.unknown_cameras.push_back({fact.index, fact.text});
      continue;
    }
    if (is_used(used, fact.array, fact.index))
      ctx.fail(place_of(fact), fmt::format("'{}' is not a glTF 2.0 accessor {}", fact.text, fact.key));
    ctx.warn(fmt::format("{}: unknown value '{}' in an unused accessor, ignored", place_of(fact), fact.text));
    (*object)["type"] = "SCALAR";
    (*object)["componentType"] = 5126;
    out.unreadable_accessors.push_back(fact.index);
  }
}

} // namespace

void apply_leniency(json& gltf, bool is_glb, const PreflightFacts& facts, const Context& ctx, TinygltfRewrite& out) {
  if (facts.integral_floats) integers_from_integral_floats(gltf);
  const UsedObjects used = find_used_objects(gltf);
  hide_unused_data(gltf, is_glb, used, facts, ctx, out);
  accept_unknown_enums(gltf, used, facts, ctx, out);
}

} // namespace probebake::scene::detail
