// `probebake info FILE`: what a glTF scene (or a .probes file, or a part of a split bake) contains.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "scene_input.h"
#include "info_probes.h"
#include "probebake/formats/bake_part.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/container.h"
#include "probebake/scene/scene.h"

namespace probebake::cli {
namespace {

struct InfoSettings {
  std::string path;
  bool json = false;
  SceneInputOptions input;
};

const char* light_type_name(scene::LightType type) {
  switch (type) {
  case scene::LightType::point: return "point";
  case scene::LightType::spot: return "spot";
  default: return "directional";
  }
}

nlohmann::json vec_json(const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json scene_info_json(const scene::Scene& s) {
  const scene::SceneSummary summary = scene::summarize(s);
  nlohmann::json j;
  j["triangles"] = s.triangle_count();
  j["vertices"] = s.positions.size();
  j["meshes"] = s.mesh_count;
  j["instances"] = s.instances.size();
  j["bounds"] = s.bounds.empty() ? nlohmann::json(nullptr)
                                 : nlohmann::json{{"min", vec_json(s.bounds.min)}, {"max", vec_json(s.bounds.max)}};
  j["materials"] = nlohmann::json::array();
  for (const auto& m : s.materials)
    j["materials"].push_back({{"name", m.name},
                              {"base_color", vec_json(m.base_color)},
                              {"emission", vec_json(m.emission)},
                              {"textured", m.base_color_texture >= 0}});
  j["lights"] = nlohmann::json::array();
  for (const auto& l : s.lights)
    j["lights"].push_back({{"name", l.name},
                           {"type", light_type_name(l.type)},
                           {"intensity", l.intensity},
                           {"color", vec_json(l.color)},
                           {"position", vec_json(l.position)},
                           {"direction", vec_json(l.direction)}});
  j["emissive_triangles"] = summary.emissive_triangles;
  j["emissive_area"] = summary.emissive_area;
  j["degenerate_triangles"] = summary.degenerate_triangles;
  j["dynamic_nodes"] = nlohmann::json::array();
  for (const auto& i : s.instances)
    if (i.dynamic)
      j["dynamic_nodes"].push_back({{"node", i.node}, {"name", i.node_name}, {"triangles", i.triangle_count}});
  j["extensions_used"] = s.extensions_used;
  j["extensions_required"] = s.extensions_required;
  j["warnings"] = s.warnings;
  return j;
}

void print_scene_info(const std::string& path, const scene::Scene& s) {
  const scene::SceneSummary summary = scene::summarize(s);
  fmt::print("scene        {}\n", path);
  fmt::print("triangles    {} ({} degenerate)\n", s.triangle_count(), summary.degenerate_triangles);
  fmt::print("meshes       {} in {} instances ({} dynamic)\n", s.mesh_count, s.instances.size(),
             summary.dynamic_instances);
  if (s.bounds.empty())
    fmt::print("bounds       (empty: no triangles, nothing to bake)\n");
  else
    fmt::print("bounds       ({:.4g}, {:.4g}, {:.4g}) .. ({:.4g}, {:.4g}, {:.4g})\n", s.bounds.min.x, s.bounds.min.y,
               s.bounds.min.z, s.bounds.max.x, s.bounds.max.y, s.bounds.max.z);
  fmt::print("materials    {}\n", s.materials.size() - 1); // the glTF default material is not counted
  fmt::print("emissive     {} triangles, {:.4g} m^2\n", summary.emissive_triangles, summary.emissive_area);
  fmt::print("lights       {}\n", s.lights.size());
  for (const auto& l : s.lights)
    fmt::print("  {:<11} {:<16} intensity {:.4g}\n", light_type_name(l.type), l.name.empty() ? "(unnamed)" : l.name,
               l.intensity);
  std::string extensions;
  for (const auto& e : s.extensions_used) extensions += (extensions.empty() ? "" : ", ") + e;
  fmt::print("extensions   {}\n", extensions.empty() ? "(none)" : extensions);
  for (const auto& w : s.warnings) fmt::print(stderr, "probebake: warning: {}\n", w);
}

// A .probes file or a bake part is recognised by its magic, whatever its name.
bool has_magic(const std::string& path, const formats::ContainerKind& kind) {
  std::ifstream in(path, std::ios::binary);
  char magic[sizeof(kind.magic)] = {};
  in.read(magic, sizeof(magic));
  return in.gcount() == std::streamsize(sizeof(magic)) && std::memcmp(magic, kind.magic, sizeof(magic)) == 0;
}

// A part of a split bake (docs/BAKE_JOBS.md): its cells and triangles, for the jobs' logs.
int run_info_part(const std::string& path, bool json) {
  const formats::BakePart part = formats::read_bake_part_file(path);
  const auto sealed = std::count(part.sealed.begin(), part.sealed.end(), std::uint8_t(1));
  const int n = formats::cells_per_axis(part.cell_depth);
  if (json) {
    const nlohmann::json j{{"file", path},
                           {"kind", "bake part"},
                           {"input_hash", fmt::format("{:016x}", part.input_hash)},
                           {"cell_depth", part.cell_depth},
                           {"cells", part.cells},
                           {"scene_triangles", part.scene_triangles},
                           {"tested_triangles", part.sealed.size()},
                           {"sealed_triangles", sealed}};
    std::puts(j.dump(2).c_str());
    return 0;
  }
  fmt::print("file         {} (bake part, input hash {:016x})\n", path, part.input_hash);
  fmt::print("cells        {} of the {}^3 grid, {} to {}\n", part.cells.size(), n,
             part.cells.empty() ? 0 : part.cells.front(), part.cells.empty() ? 0 : part.cells.back());
  fmt::print("triangles    {} of the scene's {} tested, {} sealed\n", part.sealed.size(), part.scene_triangles, sealed);
  return 0;
}

int run_info(const InfoSettings& settings) {
  if (has_magic(settings.path, formats::kProbesContainer)) return run_info_probes(settings.path, settings.json);
  if (has_magic(settings.path, formats::kPartContainer)) return run_info_part(settings.path, settings.json);
  const scene::Scene s = scene::load_scene(settings.path, load_options(settings.input, false)); // any readable scene
  if (settings.json) {
    std::puts(scene_info_json(s).dump(2).c_str());
  } else {
    print_scene_info(settings.path, s);
  }
  return 0;
}

} // namespace

Command add_info_command(CLI::App& root) {
  auto settings = std::make_shared<InfoSettings>();
  CLI::App* app =
      root.add_subcommand("info", "Describe a glTF scene (.gltf/.glb), a baked .probes file or a bake part");
  app->add_option("file", settings->path, "Scene, .probes file or bake part")->required();
  app->add_flag("--json", settings->json, "Print one JSON object instead of text");
  add_scene_input_options(app, settings->input);
  return {app, [settings] { return run_info(*settings); }};
}

} // namespace probebake::cli
