// Another glTF model as builder primitives, read through probebake's own scene loader (bake/scene.h):
// one loader for the bake and for `make-scene cornell --with`, so both accept and refuse the same files
// (Draco, malformed input, unsupported required extensions).
#include "model_import.h"

#include "probebake/scene/scene.h"

#include <glm/geometric.hpp>

#include <map>

namespace probebake::samples {
namespace {

struct MaterialTotals {
  MeshData geometry;
  glm::dvec3 albedo_sum{0.0};
  glm::dvec3 emission_sum{0.0};
};

void add_triangle(const scene::Scene& model, std::size_t t, MaterialTotals& totals) {
  const glm::uvec3 corners = model.triangles[t];
  const glm::vec3 normal = scene::triangle_normal(model, t);
  const auto base = static_cast<std::uint32_t>(totals.geometry.positions.size());
  for (int k = 0; k < 3; ++k) {
    totals.geometry.positions.push_back(model.positions[corners[k]]);
    totals.geometry.normals.push_back(normal); // flat: the bake uses geometric normals
  }
  totals.geometry.indices.insert(totals.geometry.indices.end(), {base, base + 1, base + 2});
  totals.albedo_sum += glm::dvec3(model.triangle_albedo[t]);
  totals.emission_sum += glm::dvec3(model.triangle_emission[t]);
}

Material averaged_material(const scene::Material& source, const MaterialTotals& totals) {
  const double count = static_cast<double>(totals.geometry.triangle_count());
  Material material;
  material.name = source.name.empty() ? "model_material" : source.name;
  material.albedo = glm::clamp(glm::vec3(totals.albedo_sum / count), 0.0f, 1.0f);
  material.emission = glm::max(glm::vec3(totals.emission_sum / count), 0.0f);
  material.double_sided = source.double_sided;
  return material;
}

} // namespace

ImportedModel import_model(const std::filesystem::path& path) {
  scene::LoadOptions options;
  options.require_triangles = true;
  const scene::Scene model = scene::load_scene(path, options); // throws Error(input)
  std::map<std::uint32_t, MaterialTotals> by_material;         // ordered: deterministic output
  for (std::size_t t = 0; t < model.triangle_count(); ++t)
    add_triangle(model, t, by_material[model.triangle_material[t]]);
  ImportedModel result;
  for (const auto& [index, totals] : by_material) {
    result.parts.push_back(ImportedPart{averaged_material(model.materials.at(index), totals), totals.geometry});
  }
  if (result.parts.empty()) throw Error(ErrorKind::input, path.string() + ": it has no triangles");
  return result;
}

} // namespace probebake::samples
