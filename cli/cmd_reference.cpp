// `probebake reference SCENE`: path-traced reference irradiance at seeded surface points or at given
// receivers (--at FILE.csv; --csv writes the values) and/or an irradiance image from a pinhole camera
// (--image, OpenEXR).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "camera_options.h"
#include "commands.h"
#include "scene_input.h"
#include "probebake/bake/gpu_scene.h"
#include "probebake/dynamic/animation.h"
#include "probebake/eval/reference.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"

namespace probebake::cli {
namespace {

struct ReferenceCommandSettings {
  std::string scene;
  int points = 1000;
  std::string at; // receivers x,y,z,nx,ny,nz instead of seeded points
  int image_samples = 64;
  std::string csv;
  std::string image;
  bool json = false;
  bake::ReferenceSettings reference;
  CameraOptions camera;
  SceneInputOptions input;
  std::string animate; // pose the dynamic objects as `probebake run --animate` does at `frame`
  int frame = 0;
};

// The scene with its dynamic objects where `probebake run --animate NAME` has them after frame `frame`:
// the poses come from the bake's own object records (gpu_scene), so both see the same pivot.
scene::Scene animated_scene(const scene::Scene& scene, const std::string& name, int frame) {
  const std::optional<dynamic::Animation> animation = dynamic::parse_animation(name);
  if (!animation) throw Error(ErrorKind::usage, "--animate: '" + name + "' is not thesis, revolution or soak");
  if (frame < 0) throw Error(ErrorKind::usage, "--frame must be >= 0");
  formats::ProbeVolume records = formats::make_empty_volume(gpu::VolumeInfo{});
  bake::add_runtime_lighting(scene, bake::BakeSettings{}, records);
  std::vector<glm::mat4> poses;
  for (const scene::DynamicObject& object : scene.dynamic_objects) {
    glm::mat4 pose = object.world_from_object;
    for (const gpu::DynamicObject& record : records.dynamic_objects)
      if (record.gltf_node == object.node) pose = dynamic::animated_pose(*animation, frame, record);
    poses.push_back(pose);
  }
  return scene::posed(scene, poses);
}

nlohmann::json points_json(const bake::ReferenceResult& r) {
  glm::dvec3 mean(0.0);
  double relative_se = 0.0;
  for (std::size_t i = 0; i < r.irradiance.size(); ++i) {
    mean += glm::dvec3(r.irradiance[i]);
    const double e = (r.irradiance[i].x + r.irradiance[i].y + r.irradiance[i].z) / 3.0;
    const double se = (r.standard_error[i].x + r.standard_error[i].y + r.standard_error[i].z) / 3.0;
    relative_se += e > 0.0 ? se / e : 0.0;
  }
  const double n = std::max<double>(1.0, double(r.irradiance.size()));
  return {{"count", r.irradiance.size()},
          {"mean_irradiance", {mean.x / n, mean.y / n, mean.z / n}},
          {"mean_relative_standard_error", relative_se / n},
          {"seconds", r.seconds}};
}

void print_report(const nlohmann::json& j) {
  if (j.contains("points")) {
    const auto& p = j["points"];
    const auto m = p["mean_irradiance"].get<std::vector<double>>();
    fmt::print("points       {} x {} paths in {:.2f} s\n", p["count"].get<std::size_t>(), j["paths"].get<int>(),
               p["seconds"].get<double>());
    fmt::print("irradiance   mean {:.4g} {:.4g} {:.4g} W/m^2, standard error {:.2f}% of the value on average\n", m[0],
               m[1], m[2], 100.0 * p["mean_relative_standard_error"].get<double>());
  }
  if (j.contains("csv")) fmt::print("wrote        {}\n", j["csv"].get<std::string>());
  if (j.contains("image"))
    fmt::print("wrote        {} ({:.2f} s)\n", j["image"].get<std::string>(), j["image_seconds"].get<double>());
}

int run_reference(ReferenceCommandSettings& s) {
  bake::check_reference_settings(s.reference);
  if (s.points < 0) throw Error(ErrorKind::usage, "--points must be >= 0");
  const std::optional<bake::Camera> camera = s.camera.camera();
  if (!s.image.empty() && !camera) throw Error(ErrorKind::usage, "--image needs --camera and --look-at");
  const bool want_points = s.points > 0 || !s.at.empty();
  if (!want_points && s.image.empty()) throw Error(ErrorKind::usage, "nothing to do: --points 0 and no --image");
  // Given receivers are read (and refused when malformed) before the scene is loaded.
  const std::vector<bake::SamplePoint> given =
      s.at.empty() ? std::vector<bake::SamplePoint>{} : bake::read_receivers_csv(s.at);
  const scene::Scene loaded = scene::load_scene(s.scene, load_options(s.input, true));
  const scene::Scene scene = s.animate.empty() ? loaded : animated_scene(loaded, s.animate, s.frame);
  for (const auto& w : scene.warnings) fmt::print(stderr, "probebake: warning: {}\n", w);
  // Before the path tracing: the scene, every buffer and image it read, and the receivers file.
  std::vector<std::filesystem::path> inputs = scene.input_files;
  if (!s.at.empty()) inputs.emplace_back(s.at);
  if (want_points && !s.csv.empty()) check_output_path(s.csv, inputs);
  if (!s.image.empty()) check_output_path(s.image, inputs);
  const scene::RayScene rays(scene);
  nlohmann::json j = {{"scene", s.scene}, {"paths", s.reference.paths}, {"seed", s.reference.seed}};
  if (want_points) {
    const auto points = s.at.empty() ? bake::surface_sample_points(scene, rays, s.points, s.reference.seed) : given;
    const bake::ReferenceResult r = bake::reference_irradiance(scene, rays, points, s.reference);
    j["points"] = points_json(r);
    if (!s.csv.empty()) {
      bake::write_reference_csv(s.csv, points, r);
      j["csv"] = s.csv;
    }
  }
  if (!s.image.empty()) {
    bake::ReferenceSettings image_settings = s.reference;
    image_settings.paths = s.image_samples;
    const auto start = std::chrono::steady_clock::now();
    const bake::Image image = bake::render_irradiance_image(scene, rays, *camera, image_settings);
    bake::write_exr(s.image, image);
    j["image"] = s.image;
    j["image_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (s.json)
    std::puts(j.dump(2).c_str());
  else
    print_report(j);
  return 0;
}

} // namespace

Command add_reference_command(CLI::App& root) {
  auto s = std::make_shared<ReferenceCommandSettings>();
  CLI::App* app = add_scene_subcommand(
      root, "reference", "Path-traced reference irradiance at surface points and/or as an image", s->scene, s->input);
  CLI::Option* points = app->add_option("--points", s->points, "Seeded surface points, stratified by area (0 = none)");
  app->add_option("--at", s->at,
                  "Receivers from a CSV file instead of seeded points: rows x,y,z,nx,ny,nz (header line optional; "
                  "the normal picks the side of a double-sided surface)")
      ->excludes(points);
  app->add_option("--samples", s->reference.paths, "Paths per point");
  app->add_option("--seed", s->reference.seed, "Seed of the points and paths");
  app->add_option("--threads", s->reference.threads, "Worker threads (0 = all cores); results do not depend on it");
  app->add_option("--csv", s->csv, "Write x,y,z,nx,ny,nz,r,g,b,stderr per point");
  app->add_option("--image", s->image, "Write an irradiance image (OpenEXR, float RGB) seen from --camera");
  app->add_option("--image-samples", s->image_samples, "Paths per pixel of --image");
  s->camera.add_to(*app);
  app->add_option("--animate", s->animate,
                  "Pose the dynamic objects as `probebake run --animate NAME` (thesis, revolution, soak) ...");
  app->add_option("--frame", s->frame, "... after this frame (0-based)");
  app->add_flag("--json", s->json, "Print the report as JSON");
  return {app, [s] { return run_reference(*s); }};
}

} // namespace probebake::cli
