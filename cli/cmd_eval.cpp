// `probebake eval SCENE`: error against bake time over a sweep of bake settings, scored against the
// path-traced reference (cached beside the scene). Markdown table on stdout; --csv, --json, --plot (SVG),
// --error-map DIR (per-configuration error images from --camera).
#include <unistd.h>

#include <cstdio>
#include <map>
#include <memory>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "camera_options.h"
#include "commands.h"
#include "scene_input.h"
#include "probebake/eval/eval.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"
#include "probebake/formats/placement_kind.h"

namespace probebake::cli {
namespace {

struct EvalCommandSettings {
  std::string scene;
  bool quick = false;
  int light_rays = 0; // 0: each configuration's own
  int svo_depth = -1; // -1: each configuration's own
  bool no_cache = false;
  std::string csv;
  std::string plot;
  std::string bytes_plot;
  std::string error_map;
  bool json = false;
  bake::EvalSettings eval;
  CameraOptions camera;
  CLI::Option* points_option = nullptr;
  CLI::Option* samples_option = nullptr;
  SceneInputOptions input;
};

nlohmann::json row_json(const bake::EvalRow& r) {
  return {{"label", r.label},
          {"sampler", r.sampler},
          {"placement", std::string(formats::placement_name(r.bake.placement))},
          {"max_depth", r.bake.max_depth},
          {"grid", r.bake.grid_resolution},
          {"surfels", r.bake.surfels_per_probe},
          {"lattice", std::string(lattice_name(r.bake.lattice))},
          {"svo_depth", r.bake.svo_depth},
          {"light_rays", r.bake.lighting.rays},
          {"probes", r.probes},
          {"file_bytes", r.file_bytes},
          {"lookup_bytes", r.lookup_bytes},
          {"bake_seconds", r.bake_seconds},
          {"sample_ns", r.sample_ns},
          {"rmse", r.rmse},
          {"relative_rmse", r.relative_rmse},
          {"bias", r.bias},
          {"p95", r.p95},
          {"max_error", r.max_error},
          {"leak_rmse", r.leak_rmse},
          {"leak_points", r.leak_points},
          {"misses", r.misses},
          {"coverage", r.coverage},
          {"relative_median", r.relative_median},
          {"relative_p95", r.relative_p95},
          {"image_relative_rmse", r.image_relative_rmse},
          {"image_mean_error", r.image_mean_error},
          {"image_flip_mean", r.image_flip_mean},
          {"asked_probes", r.asked_probes},
          {"budget_by", r.budget_by},
          {"indirect_rmse", r.indirect_rmse},
          {"indirect_relative_rmse", r.indirect_relative_rmse},
          {"seam_p99", r.seam_p99},
          {"l2_codec_error", r.l2_codec_error},
          {"l1_codec_error", r.l1_codec_error},
          {"l2_relative_rmse", r.l2_relative_rmse},
          {"l1_relative_rmse", r.l1_relative_rmse},
          {"l2_lookup_bytes", r.l2_lookup_bytes},
          {"l1_lookup_bytes", r.l1_lookup_bytes}};
}

nlohmann::json result_json(const bake::EvalResult& r) {
  nlohmann::json j = {{"scene", r.scene.string()},
                      {"receivers", r.receivers},
                      {"viewpoints", r.viewpoints},
                      {"points", r.points},
                      {"image_pixels", r.image_pixels},
                      {"image_mean_reference", r.image_mean_reference},
                      {"image_flip_exposures",
                       {{"start", r.image_flip_exposures.start},
                        {"stop", r.image_flip_exposures.stop},
                        {"count", r.image_flip_exposures.count}}},
                      {"paths", r.paths},
                      {"seed", r.seed},
                      {"mean_reference", r.mean_reference},
                      {"reference_noise", r.reference_noise},
                      {"mean_indirect_reference", r.mean_indirect_reference},
                      {"indirect_noise", r.indirect_noise},
                      {"direct_relative_rmse", r.direct_relative_rmse},
                      {"direct_bias", r.direct_bias},
                      {"reference_seconds", r.reference_seconds},
                      {"reference_cached", r.reference_from_cache},
                      {"cache_file", r.cache_file.string()},
                      {"cache_written", r.cache_written}};
  j["rows"] = nlohmann::json::array();
  for (const bake::EvalRow& row : r.rows) j["rows"].push_back(row_json(row));
  j["error_maps"] = nlohmann::json::array();
  for (const auto& p : r.error_maps) j["error_maps"].push_back(p.string());
  return j;
}

int run_eval(EvalCommandSettings& s) {
  if (s.quick) { // with --probes: the ladder with quick bakes
    if (s.eval.probe_ladder.empty()) s.eval.configs = bake::quick_sweep();
    s.eval.ladder_base = bake::quick_bake_settings();
    if (s.points_option->count() == 0) s.eval.points = 64;
    if (s.samples_option->count() == 0) s.eval.paths = 64;
  }
  if (s.light_rays != 0) { // every bake of the sweep or ladder with this many lighting rays per probe
    if (s.light_rays < 1) throw Error(ErrorKind::usage, "--light-rays must be >= 1");
    if (s.eval.configs.empty() && s.eval.probe_ladder.empty()) s.eval.configs = bake::default_sweep();
    for (bake::EvalConfig& c : s.eval.configs) c.bake.lighting.rays = s.light_rays;
    s.eval.ladder_base.lighting.rays = s.light_rays;
  }
  if (s.svo_depth != -1) { // every bake's SVO at this depth: index bytes against lookup error
    if (s.eval.configs.empty() && s.eval.probe_ladder.empty()) s.eval.configs = bake::default_sweep();
    for (bake::EvalConfig& c : s.eval.configs) c.bake.svo_depth = s.svo_depth;
    s.eval.ladder_base.svo_depth = s.svo_depth;
  }
  s.eval.use_cache = !s.no_cache;
  s.eval.camera = s.camera.camera();
  s.eval.error_map_dir = s.error_map;
  bake::check_eval_settings(s.eval); // usage errors before any work
  // Outputs before the sweep: against the scene file here, against its buffers and images in evaluate().
  const std::vector<std::filesystem::path> inputs = {s.scene};
  for (const std::string* output : {&s.csv, &s.plot, &s.bytes_plot})
    if (!output->empty()) {
      check_output_path(*output, inputs);
      s.eval.outputs.emplace_back(*output);
    }
  std::error_code ec;
  if (!s.error_map.empty() && std::filesystem::exists(s.error_map, ec) &&
      !std::filesystem::is_directory(s.error_map, ec))
    throw Error(ErrorKind::output, s.error_map + ": is not a folder (--error-map names a folder)");
  bake::EvalProgress progress;
  if (isatty(STDERR_FILENO) != 0)
    progress = [](const std::string& message) {
      fmt::print(stderr, "\r{:<40}", message);
      std::fflush(stderr);
    };
  s.eval.scene_input = load_options(s.input, true);
  const bake::EvalResult result = bake::evaluate(s.scene, s.eval, progress);
  if (progress) fmt::print(stderr, "\r{:<40}\r", "");
  if (!s.csv.empty()) bake::write_eval_csv(s.csv, result);
  if (!s.plot.empty()) bake::write_text_file(s.plot, bake::eval_svg_plot(result));
  if (!s.bytes_plot.empty()) bake::write_text_file(s.bytes_plot, bake::eval_bytes_svg_plot(result));
  if (s.json) {
    std::puts(result_json(result).dump(2).c_str());
  } else {
    fmt::print("{}", bake::eval_markdown_table(result));
    for (const auto& p : result.error_maps) fmt::print("wrote {}\n", p.string());
  }
  return 0;
}

} // namespace

Command add_eval_command(CLI::App& root) {
  auto s = std::make_shared<EvalCommandSettings>();
  CLI::App* app = add_scene_subcommand(
      root, "eval", "Error against bake time over a sweep of settings, vs. the path-traced reference", s->scene,
      s->input);
  s->points_option = app->add_option("--points", s->eval.points, "Seeded receivers (default 1000, --quick 64)");
  s->samples_option =
      app->add_option("--samples", s->eval.paths, "Reference paths per point (default 4096, --quick 64)");
  app->add_option("--receivers", s->eval.receivers,
                  "visible: surfaces seen from open space (default); volume: open-space points, random normals; "
                  "area: every front face by area")
      ->transform(
          CLI::CheckedTransformer(std::map<std::string, bake::ReceiverMode>{{"visible", bake::ReceiverMode::visible},
                                                                            {"volume", bake::ReceiverMode::volume},
                                                                            {"area", bake::ReceiverMode::area}}));
  app->add_option("--seed", s->eval.seed, "Seed of the points and the reference");
  app->add_option("--threads", s->eval.threads, "Worker threads for bakes and the reference (0 = all cores)");
  app->add_flag("--quick", s->quick, "A tiny sweep (3 configurations) for tests; with --probes, small bakes");
  app->add_option("--light-rays", s->light_rays, "Lighting rays per probe of every bake (default: the bake's, 256)");
  app->add_option("--svo-depth", s->svo_depth, "SVO probe index depth of every bake, 0..8 (default: the bake's, 5)")
      ->check(CLI::Range(0, 8));
  app->add_option("--probes", s->eval.probe_ladder,
                  "Probe ladder N1,N2,...: every placement method that meets a probe budget, baked to about each "
                  "count (instead of the sweep)")
      ->delimiter(',');
  app->add_option("--baseline", s->eval.baseline, "Configuration also sampled with all probes (default octree-d4)");
  app->add_flag("--no-cache", s->no_cache, "Neither read nor write the reference cache beside the scene");
  app->add_option("--csv", s->csv, "Write the table as CSV");
  app->add_option("--plot", s->plot, "Write relative RMSE against bake time as SVG, Pareto front marked");
  app->add_option("--bytes-plot", s->bytes_plot,
                  "Write relative RMSE against lookup bytes (l2 probes) as SVG, each method's Pareto front marked");
  app->add_option("--error-map", s->error_map, "Write per-configuration error images (OpenEXR) from --camera to DIR");
  app->add_option("--image-samples", s->eval.image_paths, "Reference paths per pixel of the error maps");
  s->camera.add_to(*app);
  app->add_flag("--json", s->json, "Print the result as JSON");
  return {app, [s] { return run_eval(*s); }};
}

} // namespace probebake::cli
