// Bake benchmark: time per stage, probe counts and bytes for every generated and shared scene, printed
// as a Markdown table (docs/BENCHMARKS.md holds a run). One bake per row; stage times come from the
// bake's own report. Usage: probebake-bench-bake [--shared DIR] [--quick]
#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "probebake/bake/bake.h"
#include "probebake/formats/probes_file.h"
#include "probebake/samples/scenes.h"

namespace {

using namespace probebake;

struct Row {
  std::string scene, settings;
  std::size_t triangles = 0;
  double load_seconds = 0.0;
  bake::BakeReport report;
  std::size_t bytes = 0;
};

Row run(const std::string& name, const std::filesystem::path& path, const std::string& label,
        const bake::BakeSettings& s) {
  Row row;
  row.scene = name;
  row.settings = label;
  const auto t0 = std::chrono::steady_clock::now();
  const scene::Scene scene = scene::load_scene(path, {.require_triangles = true});
  row.load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  row.triangles = scene.triangle_count();
  const bake::BakeResult result = bake::bake(scene, s);
  row.report = result.report;
  row.bytes = formats::write_probes(result.volume).size();
  return row;
}

void print(const std::vector<Row>& rows) {
  const char* stages[] = {"bvh", "place", "sdf", "relocate", "svo", "lighting", "cells"};
  fmt::print("| scene | settings | triangles | probes | dead / moved / freed | file bytes | load s |");
  for (const char* s : stages) fmt::print(" {} s |", s);
  fmt::print(" bake total s |\n|---|---|---:|---:|---|---:|---:|");
  for (std::size_t i = 0; i < std::size(stages); ++i) fmt::print("---:|");
  fmt::print("---:|\n");
  for (const Row& r : rows) {
    std::map<std::string, double> t;
    double total = 0.0;
    for (const auto& st : r.report.stages) {
      t[st.stage] += st.seconds;
      total += st.seconds;
    }
    fmt::print("| {} | {} | {} | {} | {} / {} / {} | {} | {:.3f} |", r.scene, r.settings, r.triangles, r.report.probes,
               r.report.dead_probes, r.report.moved_probes, r.report.freed_probes, r.bytes, r.load_seconds);
    for (const char* s : stages) {
      if (t.count(s) != 0)
        fmt::print(" {:.3f} |", t[s]);
      else
        fmt::print(" – |");
    }
    fmt::print(" {:.3f} |\n", total);
  }
}

} // namespace

int main(int argc, char** argv) {
  std::filesystem::path shared = std::filesystem::path(PROBEBAKE_SOURCE_DIR) / ".." / "shared" / "scenes";
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--shared") == 0 && i + 1 < argc) shared = argv[++i];
    if (std::strcmp(argv[i], "--quick") == 0) quick = true;
  }
  const auto dir = std::filesystem::temp_directory_path() / "probebake-bench";
  std::filesystem::create_directories(dir);
  std::vector<std::pair<std::string, std::filesystem::path>> scenes;
  auto generate = [&](const std::string& name, const samples::SceneBuilder& b) {
    b.write_glb(dir / (name + ".glb"));
    scenes.push_back({name, dir / (name + ".glb")});
  };
  generate("cornell (generated)", samples::cornell());
  generate("leak (generated)", samples::leak());
  if (!quick) generate("rooms 16 (generated)", samples::rooms());
  if (std::filesystem::exists(shared))
    for (const auto& d : std::filesystem::directory_iterator(shared))
      if (d.is_directory())
        for (const auto& f : std::filesystem::directory_iterator(d.path()))
          if (f.path().extension() == ".glb" || f.path().extension() == ".gltf")
            scenes.push_back({d.path().filename().string(), f.path()});
  std::sort(scenes.begin() + 3 - (quick ? 1 : 0), scenes.end());

  std::vector<Row> rows;
  bake::BakeSettings octree; // defaults: max depth 4, 128 surfels, SVO depth 5
  for (const auto& [name, path] : scenes) {
    fmt::print(stderr, "baking {}\n", name);
    rows.push_back(run(name, path, "octree d4", octree));
  }
  bake::BakeSettings grid;
  grid.placement = bake::Placement::grid;
  grid.grid_resolution = 21;
  rows.push_back(run(scenes[0].first, scenes[0].second, "grid 21^3", grid));
  bake::BakeSettings depth3;
  depth3.max_depth = 3;
  rows.push_back(run(scenes[0].first, scenes[0].second, "octree d3", depth3));
  print(rows);
  return 0;
}
