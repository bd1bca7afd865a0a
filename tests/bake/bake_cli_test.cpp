// `probebake SCENE` end to end: default output name, report JSON, validate, byte-identical rebakes,
// usage errors.
#include <cstdlib>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bake_test_util.h"
#include "run_cli.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

using CliRun = CliResult;

CliRun run(const std::string& args) { return run_cli(args); }

std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(BakeCli, CornellAtDepth3WritesAValidFileWithFewProbesAndRebakesIdentically) {
  const auto scene = write_generated(samples::cornell(), "cli_cornell");
  const auto probes = scene.parent_path() / "cli_cornell.probes";
  std::filesystem::remove(probes);
  CliRun bake = run("'" + scene.string() + "' --max-depth 3 --svo-depth 4 --json");
  ASSERT_EQ(bake.exit_code, 0) << bake.out;
  ASSERT_TRUE(std::filesystem::exists(probes)); // default output: beside the scene
  const auto report = nlohmann::json::parse(bake.out);
  EXPECT_LT(report["probes"].get<int>(), 512);
  EXPECT_EQ(report["output"].get<std::string>(), probes.string());

  const CliRun validate = run("validate '" + probes.string() + "'");
  EXPECT_EQ(validate.exit_code, 0) << validate.out;
  const CliRun info = run("info --json '" + probes.string() + "'");
  ASSERT_EQ(info.exit_code, 0) << info.out;
  EXPECT_EQ(nlohmann::json::parse(info.out)["probes"].get<int>(), report["probes"].get<int>());

  const auto again = scene.parent_path() / "again.probes";
  ASSERT_EQ(run("bake '" + scene.string() + "' --max-depth 3 --svo-depth 4 --threads 1 -o '" + again.string() + "'").exit_code, 0);
  EXPECT_EQ(read_bytes(probes), read_bytes(again));
}

TEST(BakeCli, GridOf21CubedPlaces9261Probes) {
  const auto scene = write_generated(samples::cornell(), "cli_grid");
  const CliRun bake = run("'" + scene.string() + "' --placement grid --grid 21 --svo-depth 3 --json");
  ASSERT_EQ(bake.exit_code, 0) << bake.out;
  const auto report = nlohmann::json::parse(bake.out);
  EXPECT_EQ(report["placed_probes"].get<int>(), 9261);
  EXPECT_EQ(report["probes"].get<int>() + report["freed_probes"].get<int>(), 9261);
}

TEST(BakeCli, BadSettingsAreUsageErrorsAndWriteNothing) {
  const auto scene = write_generated(samples::cornell(), "cli_bad");
  const auto out = scene.parent_path() / "bad.probes";
  std::filesystem::remove(out);
  EXPECT_EQ(run("'" + scene.string() + "' --max-depth 40 -o '" + out.string() + "'").exit_code, 1);
  EXPECT_EQ(run("'" + scene.string() + "' --split-range 0.9,0.1 -o '" + out.string() + "'").exit_code, 1);
  EXPECT_EQ(run("'" + scene.string() + "' --lattice cubic -o '" + out.string() + "'").exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(run("missing.glb").exit_code, 2);
}

TEST(BakeCli, EmptySceneIsAClearRefusal) {
  const auto scene = write_generated(samples::empty(), "cli_empty");
  const CliRun bake = run("'" + scene.string() + "'");
  EXPECT_EQ(bake.exit_code, 2);
  EXPECT_NE(bake.err.find("scene has no triangles"), std::string::npos) << bake.err;
  EXPECT_FALSE(std::filesystem::exists(scene.parent_path() / "cli_empty.probes"));
}

} // namespace
} // namespace probebake::test
