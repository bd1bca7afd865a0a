// `probebake render FILE.probes --scene SCENE -o out.png|.exr`: pictures of a baked volume in its scene,
// shaded with the probes' irradiance from the runtime on its Vulkan device (or the CPU lookup with --cpu),
// and the debug views of probebake/render/render.h. The same camera in `probebake reference --image` gives
// the ground truth and `eval --error-map` the difference.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "camera_options.h"
#include "commands.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "probebake/render/render.h"
#include "probebake/scene/ray_scene.h"
#include "runtime_lookup.h"
#include "scene_input.h"

namespace probebake::cli {
namespace {

struct RenderCommandSettings {
  std::string file;
  std::string scene;
  std::string output;
  std::vector<std::string> views = {"final"};
  int frames = 0;
  float probe_radius = 0.0f;
  bool cpu = false;
  std::string lookup = "blend";
  float exposure = 0.0f;
  int reference_samples = 256;
  int threads = 0;
  bool vk_validation = false;
  std::string device;
  CameraOptions camera;
  SceneInputOptions input;
};

std::vector<render::View> parse_views(const std::vector<std::string>& names) {
  std::vector<render::View> views;
  for (const std::string& name : names) {
    if (name == "all") return {render::kViews.begin(), render::kViews.end()};
    const auto view = render::view_from_name(name);
    if (!view)
      throw Error(ErrorKind::usage,
                  fmt::format("--view: '{}' is not final, indirect, probes, octree, svo, relocation, reference, "
                              "reference-indirect or all",
                              name));
    if (std::find(views.begin(), views.end(), *view) == views.end()) views.push_back(*view);
  }
  return views;
}

// out.png for one view; out_<view>.png for each of several.
std::filesystem::path output_of(const std::filesystem::path& output, render::View view, bool several) {
  if (!several) return output;
  std::filesystem::path path = output;
  path.replace_filename(output.stem().string() + "_" + std::string(render::view_name(view)) +
                        output.extension().string());
  return path;
}

formats::ProbeVolume read_valid_volume(const std::string& path) {
  formats::ProbeVolume volume = formats::read_probes_file(path);
  const formats::ValidationReport report = formats::validate(volume);
  if (!report.valid()) {
    const formats::Violation& v = report.violations.front();
    throw Error(ErrorKind::input, fmt::format("{}: {}: invalid: {} ({} violations; `probebake validate` lists them)",
                                              path, v.section, v.message, report.violations.size()));
  }
  return volume;
}

// The runtime on its device: the file uploaded, `frames` frames of its passes run.
struct DeviceVolume {
  std::optional<runtime::Context> context;
  std::optional<runtime::Volume> volume;
};

DeviceVolume upload(const RenderCommandSettings& s, const formats::ProbeVolume& volume) {
  runtime::ContextOptions options;
  options.validation = s.vk_validation;
  options.device_name_contains = s.device;
  auto context = runtime::Context::create(options);
  if (!context.ok())
    throw Error(ErrorKind::internal, fmt::format("no Vulkan device for the runtime ({}); --cpu renders without one",
                                                 context.status().message));
  DeviceVolume d;
  d.context.emplace(std::move(context).value());
  runtime::UploadOptions upload_options;
  upload_options.light_update = s.frames > 0;
  auto uploaded = runtime::Volume::upload(*d.context, volume, upload_options);
  if (!uploaded.ok()) throw Error(ErrorKind::internal, fmt::format("{}: {}", s.file, uploaded.status().message));
  d.volume.emplace(std::move(uploaded).value());
  for (int f = 0; f < s.frames; ++f)
    if (auto stats = d.volume->run_frame(); !stats.ok())
      throw Error(ErrorKind::internal, fmt::format("{}: frame {}: {}", s.file, f, stats.status().message));
  fmt::print("runtime: {} ({}), {} frame(s) run\n", d.context->device_info().name, d.context->device_info().type,
             s.frames);
  return d;
}

void check_validation(const DeviceVolume& d) {
  if (!d.context || d.context->validation_message_count() == 0) return;
  const std::vector<std::string> messages = d.context->validation_messages();
  throw Error(ErrorKind::internal,
              fmt::format("the Vulkan validation layer reported {} message(s), first: {}",
                          d.context->validation_message_count(), messages.empty() ? "" : messages.front()));
}

int render_command(const RenderCommandSettings& s) {
  const std::vector<render::View> views = parse_views(s.views);
  if (s.frames < 0) throw Error(ErrorKind::usage, "--frames must be >= 0");
  if (s.cpu && (s.frames > 0 || s.vk_validation || !s.device.empty()))
    throw Error(
        ErrorKind::usage,
        "--cpu samples the file's probes without a device: --frames, --vk-validation and --device need the runtime");
  if (s.lookup != "blend" && !(s.lookup == "leaf" && s.cpu))
    throw Error(ErrorKind::usage, "--lookup: 'blend' (the runtime's), or 'leaf' (one SVO leaf's stencil, the lookup "
                                  "before the blend) with --cpu");
  if (!(std::isfinite(s.exposure) && s.exposure >= 0.0f))
    throw Error(ErrorKind::usage, "--exposure must be a finite number >= 0");
  if (s.reference_samples < 2) throw Error(ErrorKind::usage, "--reference-samples must be >= 2");
  const std::filesystem::path output = s.output;
  if (output.extension() != ".png" && output.extension() != ".exr")
    throw Error(ErrorKind::usage, "-o must end in .png or .exr");
  const std::vector<std::filesystem::path> inputs = {s.file, s.scene};
  for (render::View view : views) check_output_path(output_of(output, view, views.size() > 1), inputs);
  (void)s.camera.camera(); // a bad --camera, --look-at, --fov or --size is a usage error before any work

  const formats::ProbeVolume volume = read_valid_volume(s.file);
  // The device first: loading the scene caps the address space (--max-memory), and a GPU driver reserves
  // much of it when it starts.
  DeviceVolume device;
  render::RenderInputs in;
  const bool one_leaf = s.lookup == "leaf";
  if (s.cpu) {
    in.indirect = [&volume, one_leaf](std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) {
      std::vector<glm::vec3> out(positions.size());
      if (!one_leaf) probe_index::sample_irradiance(volume, positions, normals, out);
      for (std::size_t i = 0; one_leaf && i < positions.size(); ++i)
        out[i] =
            probe_index::apply_stencil(volume, probe_index::svo_stencil(volume, positions[i], normals[i]), normals[i]);
      return out;
    };
  } else if (std::any_of(views.begin(), views.end(), render::reads_probes)) {
    device = upload(s, volume);
    in.indirect = runtime_lookup(*device.volume);
  }
  const scene::Scene scene = scene::load_scene(s.scene, load_options(s.input, true));
  const scene::RayScene rays(scene);
  in.scene = &scene, in.rays = &rays, in.volume = &volume;
  in.camera = s.camera.camera_or_default(scene);
  in.emitters_as_lights = !volume.emitter_patches.empty();
  in.probe_radius = s.probe_radius;
  in.reference.paths = s.reference_samples;
  in.reference.threads = s.threads;
  render::Renderer renderer(in);
  float exposure = s.exposure; // one PNG scale for every irradiance view: --exposure, else from the first
  for (render::View view : views) {
    const bake::Image image = renderer.render(view);
    if (render::is_irradiance_view(view) && exposure == 0.0f) {
      exposure = render::exposure_of(image);
      fmt::print("exposure {} (--exposure {} gives another run's images the same scale)\n", exposure, exposure);
    }
    const std::filesystem::path path = output_of(output, view, views.size() > 1);
    render::write_image(path, image, render::is_irradiance_view(view) ? exposure : 1.0f);
    const std::string_view legend = render::view_legend(view);
    fmt::print("wrote {} ({}){}{}\n", path.string(), render::view_name(view), legend.empty() ? "" : ": ", legend);
  }
  check_validation(device);
  return 0;
}

} // namespace

Command add_render_command(CLI::App& root) {
  auto s = std::make_shared<RenderCommandSettings>();
  CLI::App* app = root.add_subcommand(
      "render", "Render a .probes volume in its scene: irradiance from the runtime's probes and debug views");
  app->add_option("file", s->file, "The .probes file")->required();
  app->add_option("--scene", s->scene, "The glTF the file was baked from")->required();
  app->add_option("-o,--output", s->output,
                  "Image file, .png (sRGB, exposed) or .exr (linear); several views add _VIEW to its name")
      ->required();
  app->add_option("--view", s->views, "final, indirect, probes, octree, svo, relocation or all (comma-separated)")
      ->delimiter(',');
  app->add_option("--frames", s->frames,
                  "Frames of the runtime's passes (light update) before rendering (default 0: the file's probes)");
  app->add_option("--probe-radius", s->probe_radius,
                  "Radius of the probe spheres in metres (default: a tenth of each probe's cell)")
      ->check(CLI::NonNegativeNumber);
  app->add_flag("--cpu", s->cpu, "Sample the probes with the CPU lookup instead of the runtime on a Vulkan device");
  app->add_option("--lookup", s->lookup,
                  "blend (default: the runtime's lookup) or, with --cpu, leaf: one SVO leaf's stencil, the lookup "
                  "before the blend");
  app->add_option(
      "--exposure", s->exposure,
      "PNG scale of the irradiance views (default 0: 1 / the 99th percentile of the first one's luminance)");
  app->add_option("--reference-samples", s->reference_samples, "Paths per pixel of the reference views (default 256)");
  app->add_option("--threads", s->threads, "Threads of the reference views' path tracer (0 = all cores)");
  app->add_flag("--vk-validation", s->vk_validation,
                "Run the runtime under VK_LAYER_KHRONOS_validation; any message is an error");
  app->add_option("--device", s->device, "Use the first Vulkan device whose name contains this text");
  add_scene_input_options(app, s->input);
  s->camera.add_to(*app);
  return {app, [s] { return render_command(*s); }};
}

} // namespace probebake::cli
