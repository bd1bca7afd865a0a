// `probebake bake SCENE` (also `probebake SCENE`): bake probes and write a .probes file. With --cells, a part
// of a split bake; `probebake merge SCENE PART...` (same options) joins parts into the file the single bake
// writes (bake/bake_parts.h, docs/BAKE_JOBS.md).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <memory>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "bake_report.h"
#include "commands.h"
#include "scene_input.h"
#include "probebake/bake/bake.h"
#include "probebake/bake/bake_parts.h"
#include "probebake/formats/bake_part.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/placement_kind.h"
#include "probebake/formats/probes_file.h"

namespace probebake::cli {
namespace {

// Every method of formats/placement_methods.def, by name.
std::vector<std::string> placement_choices() {
  std::vector<std::string> names;
  for (const formats::PlacementKindInfo& k : formats::placement_kinds()) names.emplace_back(k.name);
  return names;
}

// "Probe placement: octree (--max-depth, --split-range), grid (--grid) or skeleton (--probes)", from the rows.
std::string placement_help() {
  const auto kinds = formats::placement_kinds();
  std::string help = "Probe placement: ";
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    if (i > 0) help += i + 1 == kinds.size() ? " or " : ", ";
    help += std::string(kinds[i].name);
    if (!kinds[i].options.empty()) help += fmt::format(" ({})", kinds[i].options);
  }
  return help;
}

struct BakeCommandSettings {
  std::string scene;
  std::string output;
  std::string placement = "octree";
  std::string lattice = "fibonacci";
  std::string split_rule; // empty: error with --probes, else hit-fraction
  std::vector<float> split_range;
  bool json = false;
  std::string cells;              // --cells LIST: bake a part
  std::vector<std::string> parts; // merge: the parts' files
  bake::BakeSettings bake;
  SceneInputOptions input;
};

std::string default_output(const std::string& scene) {
  std::filesystem::path p(scene);
  return (p.parent_path() / p.stem()).string() + ".probes";
}

// Input errors of the bake (degenerate or out-of-range geometry, no probes) name the scene, like the loader's.
bake::BakeResult bake_scene(const scene::Scene& scene, const BakeCommandSettings& s,
                            const bake::ProgressCallback& progress, const bake::PrecomputedWork* precomputed) {
  try {
    return bake::bake(scene, s.bake, progress, precomputed);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::input) throw;
    throw Error(ErrorKind::input, s.scene + ": " + e.what());
  }
}

// The options' names into the settings; usage errors before any work.
void resolve_settings(BakeCommandSettings& s) {
  s.bake.placement = *formats::parse_placement(s.placement); // the option checks the name
  s.bake.lattice = *parse_lattice(s.lattice);
  const bool budget = s.bake.probe_budget != 0 && s.bake.placement == bake::Placement::octree;
  s.bake.split_rule = s.split_rule == "surface"                                     ? bake::SplitRule::surface
                      : s.split_rule == "error" || (s.split_rule.empty() && budget) ? bake::SplitRule::error
                                                                                    : bake::SplitRule::hit_fraction;
  if (!s.split_range.empty()) {
    s.bake.split_low = s.split_range[0];
    s.bake.split_high = s.split_range[1];
  }
  bake::check_settings(s.bake);
}

struct LoadedScene {
  scene::Scene scene;
  bake::StageTime load_time;
  std::vector<std::filesystem::path> inputs; // every file the command reads: no output may replace one
};

LoadedScene load_bake_scene(const BakeCommandSettings& s) {
  const bake::StageClock load_clock;
  LoadedScene loaded{scene::load_scene(s.scene, load_options(s.input, true)), {}, {}};
  loaded.load_time = load_clock.stop("load");
  loaded.inputs = loaded.scene.input_files;
  loaded.inputs.insert(loaded.inputs.end(), s.parts.begin(), s.parts.end());
  for (const auto& w : loaded.scene.warnings) fmt::print(stderr, "probebake: warning: {}\n", w);
  return loaded;
}

// Bakes (with the parts' work when given) and writes the file and the report.
int bake_and_write(const BakeCommandSettings& s, const LoadedScene& loaded, const bake::PrecomputedWork* precomputed) {
  const std::string output = s.output.empty() ? default_output(s.scene) : s.output;
  check_output_path(output, loaded.inputs); // before the bake, not after it
  const bool tty = isatty(STDERR_FILENO) != 0 && !s.json;
  bake::ProgressCallback progress;
  if (tty)
    progress = [](const std::string& stage, double fraction) {
      fmt::print(stderr, "\r{:<10} {:3.0f}%", stage, 100.0 * fraction);
      std::fflush(stderr);
    };
  bake::BakeResult result = bake_scene(loaded.scene, s, progress, precomputed);
  if (tty) fmt::print(stderr, "\r{:<20}\r", "");
  const bake::StageClock write_clock;
  formats::write_probes_file(output, result.volume);
  result.report.stages.insert(result.report.stages.begin(), loaded.load_time);
  result.report.stages.push_back(write_clock.stop("write"));
  const auto bytes = std::filesystem::file_size(output);
  const nlohmann::ordered_json report = bake_report_json(result.report, output, bytes, result.volume);
  if (s.json)
    std::puts(report.dump(2).c_str());
  else
    print_bake_report(report);
  return 0;
}

// "0-7,9" -> 0..7, 9 (ascending, each once).
std::vector<std::int32_t> parse_cell_list(const std::string& text) {
  std::vector<std::int32_t> cells;
  std::size_t at = 0;
  const auto bad = [&](const std::string& why) {
    throw Error(ErrorKind::usage, fmt::format("--cells {}: {}", text, why));
  };
  const auto number = [&](std::size_t& i) {
    const std::size_t begin = i;
    long long value = 0;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9' && i - begin < 9) value = 10 * value + (text[i++] - '0');
    if (i == begin || (i < text.size() && text[i] >= '0' && text[i] <= '9')) bad("expected cell numbers like 0-7,9");
    return std::int32_t(value);
  };
  while (at < text.size()) {
    const std::int32_t first = number(at);
    std::int32_t last = first;
    if (at < text.size() && text[at] == '-') last = number(++at);
    if (last < first) bad(fmt::format("range {}-{} runs backwards", first, last));
    if (std::int64_t(cells.size()) + (last - first) >= (1 << 24)) bad("too many cells");
    for (std::int32_t c = first; c <= last; ++c) cells.push_back(c);
    if (at < text.size() && (text[at++] != ',' || at == text.size())) bad("expected cell numbers like 0-7,9");
  }
  if (cells.empty()) bad("no cells");
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return cells;
}

int run_bake_part(const BakeCommandSettings& s, const LoadedScene& loaded) {
  if (s.output.empty()) throw Error(ErrorKind::usage, "--cells writes a part of the bake: name it with -o PART");
  check_output_path(s.output, loaded.inputs);
  const bake::StageClock clock;
  const formats::BakePart part = bake::bake_part(loaded.scene, s.bake, parse_cell_list(s.cells));
  const double seconds = clock.stop("part").seconds;
  write_file_atomically(s.output, formats::write_bake_part(part));
  const auto sealed = std::count(part.sealed.begin(), part.sealed.end(), std::uint8_t(1));
  nlohmann::ordered_json j{{"output", s.output},
                           {"bytes", std::filesystem::file_size(s.output)},
                           {"cells", part.cells.size()},
                           {"cell_depth", part.cell_depth},
                           {"triangles", part.sealed.size()},
                           {"sealed_triangles", sealed},
                           {"load_seconds", loaded.load_time.seconds},
                           {"seconds", seconds}};
  if (s.json)
    std::puts(j.dump(2).c_str());
  else
    fmt::print("wrote        {} ({} bytes): {} cells of the {}^3 grid, {} triangles tested ({} sealed) in {:.3f} s\n",
               s.output, j["bytes"].get<std::size_t>(), part.cells.size(), formats::cells_per_axis(part.cell_depth),
               part.sealed.size(), sealed, seconds);
  return 0;
}

int run_bake(BakeCommandSettings& s) {
  resolve_settings(s);
  const LoadedScene loaded = load_bake_scene(s);
  if (!s.cells.empty()) return run_bake_part(s, loaded);
  return bake_and_write(s, loaded, nullptr);
}

int run_merge(BakeCommandSettings& s) {
  resolve_settings(s);
  if (s.output.empty()) throw Error(ErrorKind::usage, "merge: name the merged file with -o FILE");
  const LoadedScene loaded = load_bake_scene(s);
  check_output_path(s.output, loaded.inputs); // before reading the parts, not after the bake
  std::vector<formats::BakePart> parts;
  for (const std::string& path : s.parts) parts.push_back(formats::read_bake_part_file(path));
  const bake::PrecomputedWork work = bake::merge_parts(loaded.scene, s.bake, parts, s.parts);
  return bake_and_write(s, loaded, &work);
}

// The bake's options, which merge takes too (the parts were baked with them).
void add_bake_options(CLI::App* app, BakeCommandSettings& settings) {
  BakeCommandSettings* s = &settings;
  app->add_option("scene", s->scene, "Scene (.gltf or .glb)")->required();
  add_scene_input_options(app, s->input);
  app->add_option("-o,--output", s->output, "Output file (default: the scene's name with .probes, beside it)");
  app->add_option("--placement", s->placement, placement_help())->check(CLI::IsMember(placement_choices()));
  app->add_option("--max-depth", s->bake.max_depth, "Octree: deepest split level (root = 0)");
  app->add_option("--surfels", s->bake.surfels_per_probe, "Surfels (lattice rays) per probe");
  app->add_option("--lattice", s->lattice, "Spherical lattice")
      ->check(CLI::IsMember({"fibonacci", "latlong", "equal-area"}));
  app->add_option("--split-range", s->split_range, "LOW,HIGH hit fractions: free below LOW, split at HIGH")
      ->delimiter(',')
      ->expected(2);
  app->add_option("--split-rule", s->split_rule,
                  "Octree: split by hit fraction, estimated error or visible surface "
                  "(default: error with --probes, else hit-fraction)")
      ->check(CLI::IsMember({"hit-fraction", "error", "surface"}));
  app->add_option("--probes", s->bake.probe_budget,
                  "Probe budget: octree (error/surface rule) or skeleton (0: the fewest that see every surface)");
  app->add_option("--uniform-share", s->bake.uniform_share,
                  "Error/surface rule: share of --probes a uniform start may take");
  app->add_option("--grid", s->bake.grid_resolution, "Grid: N for N^3 probes");
  app->add_option("--svo-depth", s->bake.svo_depth, "Depth of the SVO probe index");
  app->add_option("--clearance", s->bake.clearance, "Minimum probe-to-surface distance (0 = 2% of the scene size)");
  app->add_option("--threads", s->bake.threads, "Worker threads (0 = all cores); output does not depend on it");
  app->add_option("--cell-depth", s->bake.cell_depth, "Streaming cells: (2^N)^3 grid");
  app->add_option("--cell-size", s->bake.cell_size,
                  "Streaming cells at most S metres wide (the shallowest such grid; overrides --cell-depth)");
  app->add_option("--light-rays", s->bake.lighting.rays, "Rays per probe for the bake-time lighting");
  app->add_option("--light-tolerance", s->bake.lighting.tolerance,
                  "Relative error at which the bounce iteration stops");
  app->add_option("--light-max-iterations", s->bake.lighting.max_iterations, "Bounce iterations at most");
  app->add_flag("!--no-lighting", s->bake.lighting.enabled, "Leave probe irradiance at zero (placement only)");
  app->add_flag("!--emitters-in-probes", s->bake.lighting.emissive_as_lights,
                "Let probes carry the light of emissive surfaces seen directly (default: emissive triangles are "
                "area lights added at shading points, like punctual lights)");
  app->add_option("--emitter-samples", s->bake.lighting.emitter_samples,
                  "Sub-triangles per emitter lookup (area lights)");
  app->add_flag("--surfels-out", s->bake.store_surfels, "Also store surfel batches (for dynamic runtime updates)");
  app->add_option(
      "--trace-leaf-cost", s->bake.trace_leaf_cost,
      "Runtime tracing trees: SAH cost of a triangle test (lower: smaller files, slower GPU traces; default 0.35)");
  app->add_flag(
      "!--no-runtime-lighting", s->bake.runtime_lighting,
      "Leave out the runtime lighting sections (tracing trees and faces, lights, emitter patches, ray directions)");
  app->add_flag("--json", s->json, "Print the report as JSON");
}

} // namespace

Command add_bake_command(CLI::App& root) {
  auto s = std::make_shared<BakeCommandSettings>();
  CLI::App* app = root.add_subcommand("bake", "Bake probes for a glTF scene into a .probes file (default command)");
  add_bake_options(app, *s);
  app->add_option(
      "--cells", s->cells,
      "Bake only the per-triangle work of these cells (LIST like 0-7,9) into the part -o PART, for `probebake merge`");
  return {app, [s] { return run_bake(*s); }};
}

Command add_merge_command(CLI::App& root) {
  auto s = std::make_shared<BakeCommandSettings>();
  CLI::App* app = root.add_subcommand(
      "merge", "Join the parts of a split bake (bake --cells) into the .probes file the single bake writes; "
               "give the scene and the options the parts were baked with");
  add_bake_options(app, *s);
  app->add_option("parts", s->parts, "Parts written by `probebake bake SCENE --cells LIST -o PART`")->required();
  return {app, [s] { return run_merge(*s); }};
}

} // namespace probebake::cli
