// `probebake SCENE` end to end: default output name, report JSON, validate, byte-identical rebakes,
// usage errors.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bake_test_util.h"
#include "run_cli.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

using CliRun = CliResult;

CliRun run(const std::string& args) { return run_cli(args); }

// One command-line word: text as is, a path in single quotes.
struct Arg {
  Arg(const char* word) : text(word) {}
  Arg(const std::filesystem::path& path) {
    text += '\'';
    text += path.string();
    text += '\'';
  }
  std::string text;
};

// Joined with +=: GCC 12 at -O3 warns falsely (-Wrestrict) on "'" + std::string&&.
CliRun run(std::initializer_list<Arg> args) {
  std::string line;
  for (const Arg& arg : args) {
    if (!line.empty()) line += ' ';
    line += arg.text;
  }
  return run_cli(line);
}

std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(BakeCli, CornellAtDepth3WritesAValidFileWithFewProbesAndRebakesIdentically) {
  const auto scene = write_generated(samples::cornell(), "cli_cornell");
  const auto probes = scene.parent_path() / "cli_cornell.probes";
  std::filesystem::remove(probes);
  CliRun bake = run({scene, "--max-depth 3 --svo-depth 4 --json"});
  ASSERT_EQ(bake.exit_code, 0) << bake.out;
  ASSERT_TRUE(std::filesystem::exists(probes)); // default output: beside the scene
  const auto report = nlohmann::json::parse(bake.out);
  EXPECT_LT(report["probes"].get<int>(), 512);
  EXPECT_EQ(report["output"].get<std::string>(), probes.string());

  const CliRun validate = run({"validate", probes});
  EXPECT_EQ(validate.exit_code, 0) << validate.out;
  const CliRun info = run({"info --json", probes});
  ASSERT_EQ(info.exit_code, 0) << info.out;
  const auto info_json = nlohmann::json::parse(info.out);
  EXPECT_EQ(info_json["probes"].get<int>(), report["probes"].get<int>());
  EXPECT_GT(info_json["lookup_bytes"]["svo"].get<long>(), 0);
  EXPECT_TRUE(info_json["lookup_bytes"]["grid_lattice"].is_null()); // an octree bake has no lattice

  const auto again = scene.parent_path() / "again.probes";
  ASSERT_EQ(run({"bake", scene, "--max-depth 3 --svo-depth 4 --threads 1 -o", again}).exit_code, 0);
  EXPECT_EQ(read_bytes(probes), read_bytes(again));
}

// A grid bake writes its lattice (format 1.8); info counts what each lookup keeps on the GPU: volume_info and
// the probes, plus the SVO or the lattice (8 header words and 2 per point).
TEST(BakeCli, AGridBakeWritesItsLatticeAndInfoCountsItsLookupBytes) {
  const auto scene = write_generated(samples::cornell(), "cli_grid_lattice");
  const auto probes = scene.parent_path() / "grid4.probes";
  ASSERT_EQ(run({scene, "--placement grid --grid 4 --svo-depth 4 -o", probes}).exit_code, 0);
  EXPECT_EQ(run({"validate", probes}).exit_code, 0);
  const auto info = nlohmann::json::parse(run({"info --json", probes}).out);
  EXPECT_EQ(info["format_version"].get<std::string>(), "1.10"); // a lattice (1.8), the light's material (1.10)
  std::size_t probe_bytes = 0, svo_bytes = 0;
  for (const auto& section : info["sections"]) {
    const std::string name = section["name"].get<std::string>();
    if (name == "probes") probe_bytes = section["bytes"].get<std::size_t>();
    if (name == "svo_nodes" || name == "svo_leaves") svo_bytes += section["bytes"].get<std::size_t>();
  }
  EXPECT_EQ(info["lookup_bytes"]["grid_lattice"].get<std::size_t>(), 80 + probe_bytes + 4 * (8 + 2 * 64));
  EXPECT_EQ(info["lookup_bytes"]["svo"].get<std::size_t>(), 80 + probe_bytes + svo_bytes);
  // Compact probes: a 16-byte point and a 32-byte (l2) or 16-byte (l1) code per probe slot.
  const std::size_t slots = probe_bytes / 144;
  EXPECT_EQ(info["lookup_bytes"]["grid_lattice_l2"].get<std::size_t>(), 80 + slots * 48 + 4 * (8 + 2 * 64));
  EXPECT_EQ(info["lookup_bytes"]["svo_l1"].get<std::size_t>(), 80 + slots * 32 + svo_bytes);
  EXPECT_NE(run({"info", probes}).out.find("B through the grid lattice"), std::string::npos);
}

// The runtime lighting sections are written by default and reported; --no-runtime-lighting leaves them out.
TEST(BakeCli, RuntimeLightingSectionsAndTheirSwitch) {
  const auto scene = write_generated(samples::triangle(), "cli_runtime_lighting");
  const auto with = scene.parent_path() / "with.probes", without = scene.parent_path() / "without.probes";
  const CliRun bake = run({scene, "--placement grid --grid 3 --json -o", with});
  ASSERT_EQ(bake.exit_code, 0) << bake.err;
  const auto report = nlohmann::json::parse(bake.out);
  EXPECT_TRUE(report["runtime_lighting"]["written"].get<bool>());
  EXPECT_EQ(report["runtime_lighting"]["bvh_nodes"].get<int>(), 0); // one triangle: the root is a leaf
  EXPECT_EQ(report["runtime_lighting"]["triangles"].get<int>(), 1);
  EXPECT_EQ(report["runtime_lighting"]["lights"].get<int>(), 1);
  EXPECT_EQ(report["sections"]["trace_faces"].get<int>(), 16);
  EXPECT_EQ(report["sections"]["trace_vertices"].get<int>(), 36);
  EXPECT_EQ(report["runtime_lighting"]["tracing_bytes"].get<int>(),
            32 + 16 + 36 + 32); // tree, face, vertices, material
  EXPECT_EQ(report["sections"]["punctual_lights"].get<int>(), 64);
  EXPECT_TRUE(report["stages"].contains("gpu_scene"));
  const auto info = nlohmann::json::parse(run({"info --json", with}).out);
  EXPECT_EQ(info["format_version"].get<std::string>(), "1.7");
  EXPECT_EQ(run({"validate", with}).exit_code, 0);

  const CliRun off = run({scene, "--placement grid --grid 3 --no-runtime-lighting --json -o", without});
  ASSERT_EQ(off.exit_code, 0) << off.err;
  EXPECT_FALSE(nlohmann::json::parse(off.out)["runtime_lighting"]["written"].get<bool>());
  const auto plain = nlohmann::json::parse(run({"info --json", without}).out);
  EXPECT_EQ(plain["format_version"].get<std::string>(), "1.0");
  for (const auto& section : plain["sections"]) EXPECT_LE(section["type"].get<int>(), 10) << section["name"];
}

// --json times every stage, in pipeline order, in wall and CPU seconds that add up to the totals. The
// Cornell box has dead probes, so the sdf and relocate stages run.
TEST(BakeCli, JsonReportTimesEveryStage) {
  const auto scene = write_generated(samples::cornell(), "cli_stages");
  const CliRun bake = run({scene, "--max-depth 3 --light-rays 64 --json -o", scene.parent_path() / "stages.probes"});
  ASSERT_EQ(bake.exit_code, 0) << bake.err;
  const auto report = nlohmann::ordered_json::parse(bake.out);
  ASSERT_GT(report["moved_probes"].get<int>(), 0);
  const std::vector<std::string> expected = {"load", "bvh",      "sealed",    "place", "sdf",  "relocate",
                                             "svo",  "lighting", "gpu_scene", "cells", "write"};
  for (const char* key : {"stages", "stages_cpu"}) {
    std::vector<std::string> names;
    double sum = 0.0;
    for (const auto& [name, seconds] : report[key].items()) {
      names.push_back(name);
      EXPECT_TRUE(std::isfinite(seconds.get<double>()) && seconds.get<double>() >= 0.0) << key << " " << name;
      sum += seconds.get<double>();
    }
    EXPECT_EQ(names, expected) << key;
    EXPECT_NEAR(sum, report[key == std::string("stages") ? "seconds" : "cpu_seconds"].get<double>(), 1e-9) << key;
  }
}

// The split bake as jobs run it: two parts with --cells, then merge, give the single bake's bytes; what a
// part or a merge is missing is a usage error (exit 1) and a damaged part an input error (exit 2).
TEST(BakeCli, PartsBakedWithCellsMergeIntoTheSingleBakesBytes) {
  const auto scene = write_generated(samples::rooms({.count = 2, .detail = 3, .seed = 3}), "cli_split");
  const auto dir = scene.parent_path();
  const std::string options = "--max-depth 3 --light-rays 32 --cell-depth 1";
  ASSERT_EQ(run({scene, options.c_str(), "-o", dir / "single.probes"}).exit_code, 0);
  const CliRun a = run({"bake", scene, options.c_str(), "--cells 0-3 --threads 1 --json -o", dir / "a.part"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto report = nlohmann::json::parse(a.out);
  EXPECT_EQ(report["cells"].get<int>(), 4);
  EXPECT_EQ(report["cell_depth"].get<int>(), 1);
  ASSERT_EQ(run({"bake", scene, options.c_str(), "--cells 4,5-7 -o", dir / "b.part"}).exit_code, 0);
  const CliRun info = run({"info --json", dir / "a.part"});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto part = nlohmann::json::parse(info.out);
  EXPECT_EQ(part["kind"].get<std::string>(), "bake part");
  EXPECT_EQ(part["cells"].get<std::vector<int>>(), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(part["tested_triangles"].get<int>(), report["triangles"].get<int>());
  EXPECT_EQ(part["sealed_triangles"].get<int>(), report["sealed_triangles"].get<int>());
  const CliRun merge =
      run({"merge", scene, dir / "b.part", dir / "a.part", options.c_str(), "-o", dir / "merged.probes"});
  ASSERT_EQ(merge.exit_code, 0) << merge.err;
  EXPECT_EQ(read_bytes(dir / "merged.probes"), read_bytes(dir / "single.probes"));

  EXPECT_EQ(run({"bake", scene, options.c_str(), "--cells 0-3"}).exit_code, 1);                    // no -o
  EXPECT_EQ(run({"bake", scene, options.c_str(), "--cells 3-1 -o", dir / "c.part"}).exit_code, 1); // backwards
  EXPECT_EQ(run({"bake", scene, options.c_str(), "--cells 8 -o", dir / "c.part"}).exit_code, 1);   // outside 2^3
  EXPECT_EQ(run({"merge", scene, dir / "a.part", options.c_str()}).exit_code, 1);                  // no -o
  const CliRun missing = run({"merge", scene, dir / "a.part", options.c_str(), "-o", dir / "m.probes"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("no part bakes cell"), std::string::npos) << missing.err;
  const CliRun other = run({"merge", scene, dir / "a.part", dir / "b.part", "--max-depth 2 -o", dir / "m.probes"});
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("baked from another scene or with other settings"), std::string::npos) << other.err;
  const CliRun not_part =
      run({"merge", scene, dir / "a.part", dir / "single.probes", options.c_str(), "-o", dir / "m.probes"});
  EXPECT_EQ(not_part.exit_code, 2);
  EXPECT_NE(not_part.err.find("single.probes: header: not a probebake bake part (bad magic)"), std::string::npos)
      << not_part.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "m.probes"));
  const std::string part_bytes = read_bytes(dir / "a.part");
  EXPECT_EQ(run({"merge", scene, dir / "a.part", dir / "b.part", options.c_str(), "-o", dir / "a.part"}).exit_code,
            3); // an input
  EXPECT_EQ(read_bytes(dir / "a.part"), part_bytes);
  EXPECT_EQ(run({"bake", scene, options.c_str(), "--cells 0-3, -o", dir / "c.part"}).exit_code, 1); // a trailing comma
}

TEST(BakeCli, GridOf21CubedPlaces9261Probes) {
  const auto scene = write_generated(samples::cornell(), "cli_grid");
  const CliRun bake = run({scene, "--placement grid --grid 21 --svo-depth 3 --json"});
  ASSERT_EQ(bake.exit_code, 0) << bake.out;
  const auto report = nlohmann::json::parse(bake.out);
  EXPECT_EQ(report["placed_probes"].get<int>(), 9261);
  EXPECT_EQ(report["probes"].get<int>() + report["freed_probes"].get<int>(), 9261);
}

TEST(BakeCli, BadSettingsAreUsageErrorsAndWriteNothing) {
  const auto scene = write_generated(samples::cornell(), "cli_bad");
  const auto out = scene.parent_path() / "bad.probes";
  std::filesystem::remove(out);
  EXPECT_EQ(run({scene, "--max-depth 40 -o", out}).exit_code, 1);
  EXPECT_EQ(run({scene, "--split-range 0.9,0.1 -o", out}).exit_code, 1);
  EXPECT_EQ(run({scene, "--lattice cubic -o", out}).exit_code, 1);
  const CliRun clearance = run({scene, "--clearance 1e30 -o", out}); // used to hang building the SDF
  EXPECT_EQ(clearance.exit_code, 1);
  EXPECT_NE(clearance.err.find("more than half the scene's size"), std::string::npos) << clearance.err;
  EXPECT_EQ(run({scene, "--max-memory lots -o", out}).exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(out));
  // More threads than cores are clamped (TBB crashed asked for 100000) and change nothing.
  const auto a = scene.parent_path() / "threads-a.probes", b = scene.parent_path() / "threads-b.probes";
  ASSERT_EQ(run({scene, "--max-depth 2 --light-rays 32 --threads 100000 -o", a}).exit_code, 0);
  ASSERT_EQ(run({scene, "--max-depth 2 --light-rays 32 --threads 1 -o", b}).exit_code, 0);
  EXPECT_EQ(read_bytes(a), read_bytes(b));
  EXPECT_EQ(run("missing.glb").exit_code, 2);
}

TEST(BakeCli, EmptySceneIsAClearRefusal) {
  const auto scene = write_generated(samples::empty(), "cli_empty");
  const CliRun bake = run({"bake", scene});
  EXPECT_EQ(bake.exit_code, 2);
  EXPECT_NE(bake.err.find("scene has no triangles"), std::string::npos) << bake.err;
  EXPECT_FALSE(std::filesystem::exists(scene.parent_path() / "cli_empty.probes"));
}

// `probebake run --day-cycle --reference`: the reference of a frame is lit by that frame's sky and sun (10:00 in
// frame 1 of a 0.1 s day), which error.csv records.
TEST(BakeCli, RunScoresADayCycleAgainstTheReferenceOfItsHour) {
  const auto scene = write_generated(samples::plane_light(), "cli_day");
  const auto probes = scene.parent_path() / "cli_day.probes", folder = scene.parent_path() / "cli_day_error";
  ASSERT_EQ(run({scene, "--sky physical --sun 30,90 --placement grid --grid 3 --light-rays 16 -o", probes}).exit_code,
            0);
  const CliRun r = run({"run", probes, "--frames 2 --day-cycle 0.1 --scene", scene,
                        "--sky physical --sun 30,90 --at-frames 1 --receivers 16 --paths 16 --reference", folder});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("frame 1 at 10:00: indirect relative RMSE"), std::string::npos) << r.out;
  std::ifstream csv(folder / "error.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_EQ(header.substr(header.rfind(',') + 1), "hour");
  EXPECT_EQ(row.substr(row.rfind(',') + 1), "10.0000") << row;
}

} // namespace
} // namespace probebake::test
