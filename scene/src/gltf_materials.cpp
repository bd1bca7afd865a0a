// glTF materials to diffuse albedo and emission (pbrMetallicRoughness base colour, emissive factor and
// texture, KHR_materials_emissive_strength, KHR_texture_transform). Textures are averaged per triangle at
// the centroids of its 9 sub-triangles (3x subdivision): equal-area, deterministic, cheap.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <tiny_gltf.h>

#include "gltf_internal.h"
#include "probebake/scene/scene.h"

namespace probebake::scene::detail {
namespace {

constexpr int kSubdivision = 3; // 9 samples per triangle

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

glm::vec3 factor3(const std::vector<double>& v, glm::vec3 fallback) {
  if (v.size() < 3) return fallback;
  return {float(v[0]), float(v[1]), float(v[2])};
}

// A texture reference resolved to an image, its wrap modes and the UV transform.
struct TextureLookup {
  const tinygltf::Image* image = nullptr;
  int wrap_s = TINYGLTF_TEXTURE_WRAP_REPEAT;
  int wrap_t = TINYGLTF_TEXTURE_WRAP_REPEAT;
  int texcoord = 0;
  glm::vec2 offset{0.0f}, scale{1.0f};
  float rotation = 0.0f;

  glm::vec2 transform(glm::vec2 uv) const {
    const float c = std::cos(rotation), s = std::sin(rotation);
    const glm::vec2 scaled = uv * scale;
    return {c * scaled.x + s * scaled.y + offset.x, -s * scaled.x + c * scaled.y + offset.y};
  }
};

float wrap_coordinate(float x, int mode) {
  if (std::isnan(x)) return 0.0f; // a NaN texture coordinate (the int conversions below would be undefined)
  if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return std::clamp(x, 0.0f, 1.0f);
  if (!(std::fabs(x) < 16777216.0f)) return 0.0f; // infinite, or >= 2^24 where every float is an even integer
  const float f = x - std::floor(x);
  if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT && int(std::floor(x)) % 2 != 0) return 1.0f - f;
  return f;
}

// Nearest texel, RGB in [0,1] before colour-space decoding. Missing channels read as 1 (grey -> rgb copy).
glm::vec3 fetch_texel(const tinygltf::Image& image, glm::vec2 uv, int wrap_s, int wrap_t) {
  const float u = wrap_coordinate(uv.x, wrap_s), v = wrap_coordinate(uv.y, wrap_t);
  const int x = std::min(int(u * float(image.width)), image.width - 1);
  const int y = std::min(int(v * float(image.height)), image.height - 1);
  const std::size_t bytes = image.bits == 16 ? 2 : 1;
  const std::size_t base =
      (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * std::size_t(image.component) * bytes;
  auto channel = [&](int c) {
    const std::size_t at = base + std::size_t(c) * bytes;
    if (bytes == 2) return float(image.image[at] | (image.image[at + 1] << 8)) / 65535.0f;
    return float(image.image[at]) / 255.0f;
  };
  if (image.component < 3) return glm::vec3(channel(0));
  return {channel(0), channel(1), channel(2)};
}

bool image_is_usable(const tinygltf::Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.component <= 0 || image.component > 4) return false;
  if (image.bits != 8 && image.bits != 16) return false;
  const std::size_t need =
      std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.component) * std::size_t(image.bits / 8);
  return image.image.size() >= need;
}

// The image of `texture` that the bake samples: EXT_texture_webp's source when it decodes, else the
// texture's own source (the fallback of EXT_texture_webp and KHR_texture_basisu), else -1.
int usable_image(const tinygltf::Model& model, const tinygltf::Texture& texture, std::string& why,
                 const std::map<int, std::string>& problems) {
  std::vector<int> candidates;
  for (const char* extension : {"EXT_texture_webp", "KHR_texture_basisu"}) {
    auto ext = texture.extensions.find(extension);
    if (ext != texture.extensions.end() && member(ext->second, "source").IsInt())
      candidates.push_back(member(ext->second, "source").Get<int>());
  }
  if (texture.source >= 0) candidates.push_back(texture.source);
  why = "has no image";
  for (int source : candidates) {
    if (source < 0 || std::size_t(source) >= model.images.size()) {
      why = fmt::format("image {} does not exist", source);
      continue;
    }
    const tinygltf::Image& image = model.images[std::size_t(source)];
    if (image_is_usable(image)) return source;
    auto problem = problems.find(source);
    const std::string name = !image.name.empty() ? image.name : image.uri.starts_with("data:") ? "" : image.uri;
    why = fmt::format("image {}{}: {}", source, name.empty() ? "" : " '" + name + "'",
                      problem != problems.end() ? problem->second : "no image data (file missing or unreadable)");
  }
  return -1;
}

TextureLookup resolve_texture(const tinygltf::Model& model, const std::vector<int>& texture_images,
                              const tinygltf::TextureInfo& info) {
  TextureLookup lookup;
  if (info.index < 0 || std::size_t(info.index) >= texture_images.size() || texture_images[std::size_t(info.index)] < 0)
    return lookup;
  const tinygltf::Texture& texture = model.textures[std::size_t(info.index)];
  const tinygltf::Image& image = model.images[std::size_t(texture_images[std::size_t(info.index)])];
  lookup.image = &image;
  lookup.texcoord = info.texCoord;
  if (texture.sampler >= 0 && std::size_t(texture.sampler) < model.samplers.size()) {
    lookup.wrap_s = model.samplers[std::size_t(texture.sampler)].wrapS;
    lookup.wrap_t = model.samplers[std::size_t(texture.sampler)].wrapT;
  }
  auto ext = info.extensions.find("KHR_texture_transform");
  if (ext != info.extensions.end()) {
    const tinygltf::Value& t = ext->second;
    const tinygltf::Value& offset = member(t, "offset");
    const tinygltf::Value& scale = member(t, "scale");
    lookup.offset = {number_at(offset, 0, 0.0f), number_at(offset, 1, 0.0f)};
    lookup.scale = {number_at(scale, 0, 1.0f), number_at(scale, 1, 1.0f)};
    if (member(t, "rotation").IsNumber()) lookup.rotation = float(member(t, "rotation").GetNumberAsDouble());
    if (member(t, "texCoord").IsInt()) lookup.texcoord = member(t, "texCoord").Get<int>();
  }
  return lookup;
}

// Barycentric (b1, b2) of the centroids of the kSubdivision^2 equal sub-triangles.
const std::array<glm::vec2, kSubdivision * kSubdivision>& sample_points() {
  static const auto points = [] {
    std::array<glm::vec2, kSubdivision * kSubdivision> p{};
    std::size_t k = 0;
    const float n = float(kSubdivision);
    for (int i = 0; i < kSubdivision; ++i)
      for (int j = 0; i + j < kSubdivision; ++j) {
        p[k++] = {(float(i) + 1.0f / 3.0f) / n, (float(j) + 1.0f / 3.0f) / n};
        if (i + j < kSubdivision - 1) p[k++] = {(float(i) + 2.0f / 3.0f) / n, (float(j) + 2.0f / 3.0f) / n};
      }
    return p;
  }();
  return points;
}

// Average linear colour of `lookup` over triangle t, or 1 when the texture or its UVs are absent.
glm::vec3 average_texture(const TextureLookup& lookup, const PrimitiveGeometry& g, std::size_t t) {
  if (lookup.image == nullptr || lookup.texcoord < 0 || lookup.texcoord > 1) return glm::vec3(1.0f);
  const auto& uv = g.texcoords[lookup.texcoord];
  if (uv.size() != g.positions.size()) return glm::vec3(1.0f);
  const glm::vec2 a = uv[g.indices[3 * t]], b = uv[g.indices[3 * t + 1]], c = uv[g.indices[3 * t + 2]];
  glm::vec3 sum(0.0f);
  for (const glm::vec2& w : sample_points()) {
    const glm::vec2 p = lookup.transform(a * (1.0f - w.x - w.y) + b * w.x + c * w.y);
    const glm::vec3 texel = fetch_texel(*lookup.image, p, lookup.wrap_s, lookup.wrap_t);
    sum += glm::vec3(srgb_to_linear(texel.r), srgb_to_linear(texel.g), srgb_to_linear(texel.b));
  }
  return sum / float(sample_points().size());
}

} // namespace

scene::Material convert_material(const tinygltf::Model& model, int index, const Context& ctx) {
  scene::Material out;
  if (index < 0) {
    out.name = "(default)";
    return out;
  }
  const std::string place = fmt::format("materials[{}]", index);
  const tinygltf::Material& m = model.materials[std::size_t(index)];
  out.name = m.name;
  out.double_sided = m.doubleSided;
  out.base_color = factor3(m.pbrMetallicRoughness.baseColorFactor, glm::vec3(1.0f));
  float strength = 1.0f;
  auto ext = m.extensions.find("KHR_materials_emissive_strength");
  if (ext != m.extensions.end() && member(ext->second, "emissiveStrength").IsNumber())
    strength = float(member(ext->second, "emissiveStrength").GetNumberAsDouble());
  out.emission = factor3(m.emissiveFactor, glm::vec3(0.0f)) * strength;
  out.base_color_texture = m.pbrMetallicRoughness.baseColorTexture.index;
  out.emissive_texture = m.emissiveTexture.index;
  const auto finite_nonnegative = [](glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0 && v.y >= 0 && v.z >= 0;
  };
  if (!finite_nonnegative(out.base_color) || !finite_nonnegative(out.emission))
    ctx.fail(place, "baseColorFactor and emission must be finite and non-negative");
  if (glm::any(glm::greaterThan(out.base_color, glm::vec3(1.0f)))) {
    ctx.warn(place + ": baseColorFactor above 1 clamped (albedo must conserve energy)");
    out.base_color = glm::min(out.base_color, glm::vec3(1.0f));
  }
  return out;
}

std::vector<int> select_texture_images(const tinygltf::Model& model, const std::map<int, std::string>& problems,
                                       const Context& ctx) {
  std::vector<int> images(model.textures.size(), -1);
  std::vector<bool> used(model.textures.size(), false);
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    const tinygltf::Material& material = model.materials[m];
    for (const auto* info : {&material.pbrMetallicRoughness.baseColorTexture, &material.emissiveTexture}) {
      if (info->index < 0) continue;
      if (std::size_t(info->index) >= model.textures.size())
        ctx.fail(fmt::format("materials[{}]", m), fmt::format("references missing texture {}", info->index));
      used[std::size_t(info->index)] = true;
    }
  }
  for (std::size_t t = 0; t < model.textures.size(); ++t) {
    if (!used[t]) continue; // not sampled by the bake (normal maps, ...): never a reason to warn
    std::string why;
    images[t] = usable_image(model, model.textures[t], why, problems);
    if (images[t] < 0) ctx.degrade(fmt::format("textures[{}]", t), why + "; its materials use their factors instead");
  }
  return images;
}

TriangleColors average_triangle_colors(const tinygltf::Model& model, const std::vector<int>& texture_images, int index,
                                       const scene::Material& material, const PrimitiveGeometry& geometry) {
  const std::size_t triangles = geometry.indices.size() / 3;
  TextureLookup base, emissive;
  if (index >= 0) {
    const tinygltf::Material& m = model.materials[std::size_t(index)];
    base = resolve_texture(model, texture_images, m.pbrMetallicRoughness.baseColorTexture);
    emissive = resolve_texture(model, texture_images, m.emissiveTexture);
  }
  TriangleColors colors;
  colors.albedo.assign(triangles, material.base_color);
  colors.emission.assign(triangles, material.emission);
  for (std::size_t t = 0; t < triangles; ++t) {
    if (base.image != nullptr)
      colors.albedo[t] = glm::min(material.base_color * average_texture(base, geometry, t), glm::vec3(1.0f));
    if (emissive.image != nullptr) colors.emission[t] = material.emission * average_texture(emissive, geometry, t);
  }
  return colors;
}

} // namespace probebake::scene::detail
