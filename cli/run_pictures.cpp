#include "run_pictures.h"

#include "camera_options.h"
#include "runtime_lookup.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/core.h>

#include "probebake/eval/pose_error.h"
#include "probebake/formats/error.h"
#include "probebake/render/render.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/sky/sky.h"
#include "run_lighting_changes.h"
#include "camera_options.h"
#include "runtime_lookup.h"

namespace probebake::cli {
namespace {

std::string svg_number(double v) { return fmt::format("{:.6g}", v); }

} // namespace

RunPictures::RunPictures(RunPictureOptions options, scene::Scene scene)
    : options_(std::move(options)), scene_(std::move(scene)) {
  if (!options_.camera) options_.camera = default_camera(scene_);
  std::error_code ec;
  std::filesystem::create_directories(options_.folder, ec);
  if (ec) throw Error(ErrorKind::output, fmt::format("{}: cannot create folder: {}", options_.folder, ec.message()));
}

// The runtime's objects carry the glTF node they came from; the scene's objects too. With a day cycle (hour >= 0),
// that hour's sky and sun.
scene::Scene RunPictures::posed_scene(const runtime::Volume& volume, float hour) const {
  std::vector<glm::mat4> poses;
  for (const scene::DynamicObject& object : scene_.dynamic_objects) {
    glm::mat4 pose = object.world_from_object;
    const std::span<const gpu::DynamicObject> objects = volume.dynamic_objects();
    for (std::size_t o = 0; o < objects.size(); ++o)
      if (objects[o].gltf_node == object.node) pose = volume.object_pose(int(o));
    poses.push_back(pose);
  }
  scene::Scene posed = scene::posed(scene_, poses);
  if (hour >= 0.0f && scene_.sky.physical)
    scene::set_sky(posed, sky::physical_sky(run::day_sky(hour, scene_.sky.physical->turbidity)));
  return posed;
}

runtime::Status RunPictures::after_frame(int frame, runtime::Volume& volume) {
  if (std::find(options_.at_frames.begin(), options_.at_frames.end(), frame) == options_.at_frames.end()) return {};
  try {
    const float hour = options_.day_cycle ? run::day_hour(*options_.day_cycle, frame) : -1.0f;
    const scene::Scene posed = posed_scene(volume, hour);
    if (options_.images) write_images(frame, posed, volume);
    if (options_.reference) {
      errors_.push_back(measure(frame, hour, posed, volume));
      const ErrorRow& e = errors_.back();
      const std::string at =
          e.hour >= 0.0f ? fmt::format(" at {:02d}:{:02d}", int(e.hour), int(std::fmod(e.hour, 1.0f) * 60.0f)) : "";
      fmt::print("frame {}{}: indirect relative RMSE {:.4f} (median {:.4f}, reference noise {:.4f}) against {} paths "
                 "at {} receivers, {:.1f} s\n",
                 frame, at, e.relative_rmse, e.relative_median, e.reference_noise, options_.paths, options_.receivers,
                 e.seconds);
    }
  } catch (const Error& e) {
    return {e.kind() == ErrorKind::output ? runtime::StatusCode::invalid_argument : runtime::StatusCode::internal,
            e.what()};
  }
  return {};
}

void RunPictures::write_images(int frame, const scene::Scene& posed, runtime::Volume& volume) {
  const scene::RayScene rays(posed);
  render::RenderInputs inputs;
  inputs.scene = &posed, inputs.rays = &rays, inputs.camera = *options_.camera;
  inputs.emitters_as_lights = volume.buffers().emitter_patches.buffer != VK_NULL_HANDLE;
  inputs.indirect = runtime_lookup(volume);
  render::Renderer renderer(inputs);
  const bake::Image final_image = renderer.render(render::View::final),
                    indirect_image = renderer.render(render::View::indirect);
  if (exposure_ == 0.0f) exposure_ = render::exposure_of(final_image);
  const std::filesystem::path base = std::filesystem::path(options_.folder) / fmt::format("frame_{:04d}", frame);
  for (const auto& [image, name] : {std::pair{&final_image, "final"}, std::pair{&indirect_image, "indirect"}}) {
    render::write_image(base.string() + "_" + name + ".exr", *image);
    render::write_image(base.string() + "_" + name + ".png", *image, exposure_);
  }
  fmt::print("frame {}: wrote {}_final.(exr|png) and {}_indirect.(exr|png)\n", frame, base.string(), base.string());
}

RunPictures::ErrorRow RunPictures::measure(int frame, float hour, const scene::Scene& posed,
                                           runtime::Volume& volume) const {
  bake::PoseReferenceSettings settings;
  settings.receivers.count = options_.receivers;
  settings.reference.paths = options_.paths;
  const bake::PoseReference reference = bake::pose_reference(posed, settings);
  std::vector<glm::vec3> positions, normals;
  for (const bake::SamplePoint& p : reference.points) positions.push_back(p.position), normals.push_back(p.normal);
  auto runtime_values = volume.sample_irradiance(positions, normals);
  if (!runtime_values.ok()) throw Error(ErrorKind::internal, runtime_values.status().message);
  const bake::PoseError error = bake::pose_error(reference, runtime_values.value());
  ErrorRow row{frame,
               hour,
               error.relative_rmse,
               error.relative_median,
               error.reference_noise,
               reference.mean_indirect,
               0.0,
               reference.seconds};
  for (const glm::vec3& v : runtime_values.value())
    row.mean_runtime += double(v.x + v.y + v.z) / (3.0 * double(runtime_values.value().size()));
  return row;
}

std::vector<std::string> RunPictures::finish() const {
  if (!options_.reference || errors_.empty()) return {};
  const std::filesystem::path csv_path = std::filesystem::path(options_.folder) / "error.csv";
  std::ofstream csv(csv_path);
  csv << "frame,relative_rmse,relative_median,reference_noise,mean_reference,mean_runtime,reference_seconds,hour\n";
  for (const ErrorRow& e : errors_)
    csv << e.frame << ',' << e.relative_rmse << ',' << e.relative_median << ',' << e.reference_noise << ','
        << e.mean_reference << ',' << e.mean_runtime << ',' << e.seconds << ','
        << (e.hour >= 0.0f ? fmt::format("{:.4f}", e.hour) : std::string()) << '\n';
  if (!csv.flush()) throw Error(ErrorKind::output, csv_path.string() + ": cannot be written");
  // Error against frame: the runtime's lag behind the motion shows as the error after the motion ends.
  constexpr double kW = 760, kH = 400, kL = 70, kR = 20, kT = 40, kB = 50;
  double x_max = 1, y_max = 0;
  for (const ErrorRow& e : errors_) x_max = std::max(x_max, double(e.frame)), y_max = std::max(y_max, e.relative_rmse);
  y_max = y_max > 0 ? y_max * 1.15 : 1.0;
  const auto x = [&](double f) { return kL + (kW - kL - kR) * f / x_max; };
  const auto y = [&](double v) { return kH - kB - (kH - kB - kT) * v / y_max; };
  std::string svg =
      fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif'>\n"
                  "<rect width='100%' height='100%' fill='white'/>\n<rect x='{}' y='{}' width='{}' height='{}' "
                  "fill='none' stroke='#444'/>\n"
                  "<text x='{}' y='24' font-size='14' text-anchor='middle'>indirect irradiance: relative RMSE against "
                  "the path-traced pose</text>\n"
                  "<text x='{}' y='{}' font-size='13' text-anchor='middle'>frame</text>\n",
                  kW, kH, kL, kT, kW - kL - kR, kH - kB - kT, kW / 2, kW / 2, kH - 12);
  std::string line, noise;
  for (const ErrorRow& e : errors_) {
    line += svg_number(x(e.frame)) + "," + svg_number(y(e.relative_rmse)) + " ";
    noise += svg_number(x(e.frame)) + "," + svg_number(y(e.reference_noise)) + " ";
    svg += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='3' fill='#1f77b4'/><text x='{:.1f}' y='{}' font-size='10' "
                       "text-anchor='middle'>{}</text>\n",
                       x(e.frame), y(e.relative_rmse), x(e.frame), kH - kB + 14, e.frame);
  }
  for (int k = 0; k <= 4; ++k)
    svg += fmt::format("<text x='{}' y='{:.1f}' font-size='11' text-anchor='end'>{:.3g}</text>\n", kL - 6,
                       y(y_max * k / 4) + 4, y_max * k / 4);
  svg += "<polyline fill='none' stroke='#1f77b4' points='" + line +
         "'/>\n<polyline fill='none' stroke='#999' stroke-dasharray='4 3' points='" + noise + "'/>\n" +
         fmt::format("<text x='{}' y='{}' font-size='12' fill='#999'>reference noise</text>\n</svg>\n", kW - kR - 110,
                     kT + 16);
  const std::filesystem::path svg_path = std::filesystem::path(options_.folder) / "error.svg";
  std::ofstream out(svg_path);
  if (!(out << svg) || !out.flush()) throw Error(ErrorKind::output, svg_path.string() + ": cannot be written");
  return {csv_path.string(), svg_path.string()};
}

} // namespace probebake::cli
