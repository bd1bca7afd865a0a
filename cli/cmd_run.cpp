// probebake run FILE.probes ...: the runtime's run driver (runtime/tools/run_driver.h). Its options are
// parsed by the driver's own parser (run_options.cpp, the one definition shared with the runtime-only
// probebake-run); this command adds what needs the scene and the path tracer (run_pictures.h): images and
// error against the reference at chosen frames of an animated run.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "camera_options.h"
#include "commands.h"
#include "probebake/formats/error.h"
#include "run_driver.h"
#include "run_pictures.h"
#include "scene_input.h"

namespace probebake::cli {
namespace {

struct RunCommandSettings {
  std::string scene;
  std::string images, reference;
  std::vector<int> at_frames = {0, 199, 230, 275, 350, 400, 599};
  int receivers = 256;
  int paths = 256;
  CameraOptions camera;
  SceneInputOptions input;
};

constexpr const char* kCliOptions =
    "probebake run adds, with --scene SCENE (the glTF the file was baked from; its --dynamic nodes as at the bake):\n"
    "  --images DIR      at --at-frames, irradiance images of the runtime's probes in the current pose:\n"
    "                    frame_NNNN_final (direct + indirect) and frame_NNNN_indirect, .exr (linear) and .png\n"
    "  --reference DIR   at --at-frames, the indirect irradiance's error against a path-traced reference of\n"
    "                    the current pose (--receivers N visible receivers, --paths N): DIR/error.csv, error.svg\n"
    "  --at-frames LIST  0-based frames, comma-separated (default 0,199,230,275,350,400,599)\n"
    "  --camera x,y,z --look-at x,y,z --fov DEG --size WxH   the images' camera (default: the scene's first)\n";

int run_command(CLI::App* app, RunCommandSettings& s) {
  std::vector<std::string> args = app->remaining();
  std::vector<char*> argv{const_cast<char*>("probebake run")};
  for (std::string& a : args) argv.push_back(a.data());
  std::string message;
  int exit_code = 0;
  std::optional<run::RunOptions> options = run::parse_run_options(int(argv.size()), argv.data(), message, exit_code);
  if (!options) {
    std::fputs(message.c_str(), exit_code == 0 ? stdout : stderr);
    if (exit_code == 0) std::fputs(kCliOptions, stdout);
    return exit_code;
  }
  options->program = "probebake run";
  std::unique_ptr<RunPictures> pictures;
  if (!s.images.empty() || !s.reference.empty()) {
    if (s.scene.empty())
      throw probebake::Error(probebake::ErrorKind::usage, "--images and --reference need --scene SCENE");
    if (!s.images.empty() && !s.reference.empty() && s.images != s.reference)
      throw probebake::Error(probebake::ErrorKind::usage,
                             "--images and --reference write into one folder: give them the same DIR");
    RunPictureOptions picture_options;
    picture_options.scene = s.scene;
    picture_options.folder = s.images.empty() ? s.reference : s.images;
    picture_options.at_frames = s.at_frames;
    picture_options.images = !s.images.empty();
    picture_options.reference = !s.reference.empty();
    picture_options.receivers = s.receivers;
    picture_options.paths = s.paths;
    picture_options.day_cycle = options->day_cycle;
    scene::Scene scene = scene::load_scene(s.scene, load_options(s.input, true));
    picture_options.camera = s.camera.camera_or_default(scene);
    pictures = std::make_unique<RunPictures>(picture_options, std::move(scene));
    options->after_frame = [&pictures](int frame, runtime::Volume& volume) {
      return pictures->after_frame(frame, volume);
    };
  }
  const int code = run::run_volume(*options);
  if (code == 0 && pictures)
    for (const std::string& file : pictures->finish()) fmt::print("wrote {}\n", file);
  return code;
}

} // namespace

Command add_run_command(CLI::App& root) {
  auto s = std::make_shared<RunCommandSettings>();
  CLI::App* app =
      root.add_subcommand("run", "Run a .probes volume in the Vulkan runtime (headless): per-pass GPU timings and "
                                 "statistics; `probebake run --help` lists the options");
  // Everything but the options below goes to the run driver's parser (also probebake-run's).
  app->allow_extras();
  app->set_help_flag();
  app->add_option("--scene", s->scene, "The glTF the file was baked from (for --images and --reference)");
  app->add_option("--images", s->images, "Folder for irradiance images at --at-frames");
  app->add_option("--reference", s->reference, "Folder for the error against the path-traced pose at --at-frames");
  app->add_option("--at-frames", s->at_frames, "Frames (0-based) of the images and the reference")->delimiter(',');
  app->add_option("--receivers", s->receivers, "Visible receivers of the reference")->check(CLI::PositiveNumber);
  app->add_option("--paths", s->paths, "Paths per receiver of the reference")->check(CLI::Range(2, 1 << 20));
  add_scene_input_options(app, s->input);
  s->camera.add_to(*app);
  return {app, [app, s] { return run_command(app, *s); }};
}

} // namespace probebake::cli
