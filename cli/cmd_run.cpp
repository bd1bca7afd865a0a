// probebake run FILE.probes --frames N [--csv OUT]: the runtime's run driver (runtime/tools/run_driver.h)
// behind CLI11 parsing; the same driver is the runtime-only program probebake-run.
#include <memory>

#include "commands.h"
#include "run_driver.h"

namespace probebake::cli {

Command add_run_command(CLI::App& root) {
  auto options = std::make_shared<run::RunOptions>();
  options->program = "probebake run";
  CLI::App* app = root.add_subcommand("run", "Run a .probes volume in the Vulkan runtime (headless) and print per-pass "
                                             "GPU timings and statistics");
  app->add_option("file", options->input, ".probes file")->required();
  app->add_option("--frames", options->frames, "Frames to run: probe index build, then the light update")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app->add_option("--csv", options->csv, "Write one row per frame and pass (frame,pass,gpu_ms,cpu_ms,...)");
  app->add_flag("--validate", options->validate, "Validate the live GPU state after every frame");
  app->add_flag("--vk-validation", options->vulkan_validation,
                "Enable the Khronos validation layer (synchronization validation on); exit 4 on any message");
  app->add_option("--device", options->device, "Use the first Vulkan device whose name contains this");
  app->add_option("--samples", options->samples, "After the frames, time N irradiance lookups at random points")
      ->check(CLI::NonNegativeNumber);
  app->add_flag("--compare-all-probes", options->compare_all_probes,
                "With --samples: also time the thesis's all-probe loop (3.2.4) on the same points");
  app->add_option("--hysteresis", options->hysteresis, "Weight of the old irradiance per frame, [0, 1)")
      ->check(CLI::Range(0.0f, 0.999999f))->capture_default_str();
  app->add_flag("--no-light-update{false}", options->light_update, "Keep the baked irradiance (no light passes)");
  return {app, [options] { return run::run_volume(*options); }};
}

} // namespace probebake::cli
