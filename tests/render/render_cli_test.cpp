// `probebake render` end to end: every view written on the runtime (lavapipe on CI) under the validation
// layer and on the CPU lookup, the two indirect images equal; refusals with their exit codes and no output.
#include <filesystem>

#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/eval/reference.h"
#include "probebake/formats/probes_file.h"
#include "probebake/samples/scenes.h"
#include "run_cli.h"

namespace probebake::test {
namespace {

namespace fs = std::filesystem;

struct Files {
  fs::path folder, scene, probes;
};

const Files& files() {
  static const Files f = [] {
    Files out;
    out.folder = fs::temp_directory_path() / ("probebake-render-cli-" + std::to_string(::getpid()));
    fs::create_directories(out.folder);
    out.scene = write_generated(samples::cornell(), "render-cli-cornell");
    out.probes = out.folder / "cornell.probes";
    formats::write_probes_file(
        out.probes, bake::bake(load_generated(samples::cornell(), "render-cli-cornell-load"), test_settings()).volume);
    return out;
  }();
  return f;
}

CliResult render(const std::string& arguments) {
  return run_program(PROBEBAKE_CLI,
                     "render " + quoted(files().probes) + " --scene " + quoted(files().scene) + " " + arguments);
}

TEST(RenderCli, WritesEveryViewOnTheRuntimeUnderValidationAndTheCpuAgrees) {
  const fs::path gpu = files().folder / "gpu.exr", cpu = files().folder / "cpu.exr";
  const CliResult r = render("--view all --size 48x36 --vk-validation --frames 2 -o " + quoted(gpu));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* view : {"final", "indirect", "probes", "octree", "svo", "relocation"})
    EXPECT_TRUE(fs::is_regular_file(files().folder / (std::string("gpu_") + view + ".exr"))) << view;
  EXPECT_NE(r.out.find("runtime: "), std::string::npos) << r.out;
  const CliResult c = render("--view indirect --size 48x36 --cpu -o " + quoted(cpu));
  ASSERT_EQ(c.exit_code, 0) << c.err;
  // Two frames of the light update reproduce the bake's probes (docs/results/runtime.md, "The light update
  // against the CPU bake": 1.6e-5 of the brightest DC term on the Cornell octree, asserted < 1e-4), so the
  // runtime's picture is the CPU lookup's.
  const bake::Image a = bake::read_exr(files().folder / "gpu_indirect.exr"), b = bake::read_exr(cpu);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  float brightest = 0.0f, largest_difference = 0.0f;
  for (std::size_t i = 0; i < a.pixels.size(); ++i)
    for (int k = 0; k < 3; ++k)
      brightest = std::max(brightest, b.pixels[i][k]),
      largest_difference = std::max(largest_difference, std::abs(a.pixels[i][k] - b.pixels[i][k]));
  EXPECT_GT(brightest, 0.0f);
  EXPECT_LT(largest_difference, 1e-3f * brightest);
}

TEST(RenderCli, WritesAPng) {
  const fs::path png = files().folder / "view.png";
  const CliResult r = render("--view octree --cpu --size 40x30 -o " + quoted(png));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(fs::file_size(png), 100u);
  EXPECT_NE(r.out.find("leaf borders"), std::string::npos) << "the legend is printed: " << r.out;
}

TEST(RenderCli, RefusalsHaveTheirExitCodesAndWriteNothing) {
  const fs::path out = files().folder / "refused.png";
  EXPECT_EQ(render("--view depth --cpu -o " + quoted(out)).exit_code, 1);
  EXPECT_EQ(render("--cpu -o " + quoted(files().folder / "refused.jpg")).exit_code, 1);
  EXPECT_EQ(render("--cpu --frames 3 -o " + quoted(out)).exit_code, 1);
  fs::create_directories(files().folder / "folder.png");
  EXPECT_EQ(render("--cpu -o " + quoted(files().folder / "folder.png")).exit_code, 3) << "a folder is not replaced";
  EXPECT_EQ(run_program(PROBEBAKE_CLI, "render " + quoted(files().probes) + " --scene " +
                                           quoted(files().folder / "missing.glb") + " --cpu -o " + quoted(out))
                .exit_code,
            2);
  const fs::path broken = files().folder / "broken.probes";
  fs::copy_file(files().probes, broken, fs::copy_options::overwrite_existing);
  fs::resize_file(broken, fs::file_size(broken) / 2);
  const CliResult r = run_program(PROBEBAKE_CLI, "render " + quoted(broken) + " --scene " + quoted(files().scene) +
                                                     " --cpu -o " + quoted(out));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("broken.probes"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

} // namespace
} // namespace probebake::test
