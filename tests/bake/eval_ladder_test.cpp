// The reference's direct/indirect split against closed forms, the probe ladder of `probebake eval`
// (--probes), its indirect-error columns, and the reference cache of the version before the split.
#include <algorithm>
#include <cmath>
#include <map>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/eval/eval.h"
#include "probebake/eval/reference.h"
#include "probebake/formats/error.h"
#include "probebake/samples/geometry.h"
#include "probebake/samples/scenes.h"
#include "run_cli.h"

namespace probebake::test {
namespace {

constexpr double kPi = std::numbers::pi;

// A plane alone under a point light: every path that leaves it escapes, so all light is direct.
TEST(IndirectReference, PlaneUnderAPointLightIsAllDirect) {
  const float intensity = 100.0f, height = 1.0f;
  const scene::Scene s = load_generated(
      samples::plane_light({.size = 10.0f, .height = height, .intensity = intensity, .albedo = 0.5f}), "ladder_plane");
  const scene::RayScene rays(s);
  const auto points = bake::surface_sample_points(s, rays, 16, 11);
  ASSERT_EQ(points.size(), 16u);
  const bake::ReferenceResult r = bake::reference_irradiance(s, rays, points, {.paths = 64});
  ASSERT_EQ(r.direct.size(), points.size());
  const auto indirect = bake::indirect_irradiance(r);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 to_light = glm::dvec3(0.0, height, 0.0) - glm::dvec3(points[i].position);
    const double r2 = glm::dot(to_light, to_light);
    const double exact = intensity * (double(height) / std::sqrt(r2)) / r2; // I cos / r^2
    EXPECT_NEAR(r.direct[i].x, exact, 1e-5 * exact) << i;
    EXPECT_EQ(indirect[i], glm::vec3(0.0f)) << i;
    EXPECT_EQ(r.indirect_standard_error[i], glm::vec3(0.0f)) << i;
  }
}

// One bounce, closed form: a point light h above an infinite floor of albedo rho gives the floor radiance
// L(s) = rho / pi * I h / (h^2 + s^2)^1.5 at horizontal distance s; a receiver facing down at height H
// straight above the light receives E = int L(s) H^2 / (H^2 + s^2)^2 2 pi s ds from it. The receiver's
// own plane is black, so nothing bounces twice.
double one_bounce(double intensity, double rho, double h, double height, double radius) {
  const int steps = 200000;
  const double ds = radius / steps;
  double sum = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double s = (k + 0.5) * ds;
    const double floor_radiance = rho / kPi * intensity * h / std::pow(h * h + s * s, 1.5);
    sum += floor_radiance * height * height / std::pow(height * height + s * s, 2.0) * 2.0 * kPi * s * ds;
  }
  return sum;
}

TEST(IndirectReference, BlackCeilingReceivesTheFloorsOneBounce) {
  const float intensity = 100.0f, h = 0.5f, height = 1.0f, size = 100.0f, rho = 0.5f;
  samples::SceneBuilder b = samples::plane_light({.size = size, .height = h, .intensity = intensity, .albedo = rho});
  const samples::MaterialId black = b.add_material({"black", glm::vec3(0.0f), {}});
  // Edges +X then +Z: cross((s,0,0), (0,0,s)) points along -Y, towards the floor.
  const samples::MeshData ceiling =
      samples::quad(glm::vec3(-size / 2, height, -size / 2), glm::vec3(size, 0, 0), glm::vec3(0, 0, size));
  b.add_mesh_node("ceiling", b.add_mesh("ceiling", ceiling, black));
  const scene::Scene s = load_generated(b, "ladder_ceiling");
  const scene::RayScene rays(s);
  const std::vector<bake::SamplePoint> at = {{{0.0f, height, 0.0f}, {0.0f, -1.0f, 0.0f}},
                                             {{0.3f, height, -0.2f}, {0.0f, -1.0f, 0.0f}}};
  const bake::ReferenceResult r = bake::reference_irradiance(s, rays, at, {.paths = 16384, .seed = 4});
  const auto indirect = bake::indirect_irradiance(r);
  const double exact_indirect = one_bounce(intensity, rho, h, height, size / 2); // point 0: above the light
  const double se = r.indirect_standard_error[0].x;
  EXPECT_NEAR(r.direct[0].x, intensity / ((height - h) * (height - h)), 1e-4);
  EXPECT_NEAR(indirect[0].x, exact_indirect, 4.0 * se + 0.005 * exact_indirect);
  EXPECT_LT(se, 0.02 * exact_indirect) << "too noisy to mean anything";
  // Point 1 is off axis: no closed form here, but the split must add up and the indirect part be positive.
  EXPECT_GT(indirect[1].x, 0.0f);
  EXPECT_NEAR(r.direct[1].x + indirect[1].x, r.irradiance[1].x, 1e-6 * r.irradiance[1].x);
  std::printf("[ one bounce ] indirect %.5f +- %.5f, closed form %.5f; direct %.4f (exact %.4f)\n", indirect[0].x, se,
              exact_indirect, r.direct[0].x, intensity / ((height - h) * (height - h)));
}

// Live probes of a placement-only bake, counted here independently of the ladder's own search.
int live_probes(const scene::Scene& scene, bake::BakeSettings s) {
  s.lighting.enabled = false;
  s.runtime_lighting = false;
  try {
    return bake::bake(scene, s).report.probes;
  } catch (const Error&) {
    return 0;
  }
}

// The ladder on the Cornell box: a grid row's resolution gives a count no farther from the rung than the
// resolutions either side of it, within the documented 35% (the worst gap between cubes); the octree and the
// skeleton take the rung as their probe budget and keep at most that many live probes.
TEST(EvalLadder, EveryRowMeetsItsRung) {
  const scene::Scene s = load_generated(samples::cornell(), "ladder_cornell");
  const std::vector<int> ladder = {64, 128};
  const bake::BakeSettings base = bake::quick_bake_settings();
  const auto configs = bake::ladder_sweep(s, ladder, base);
  int grids = 0, budgeted = 0;
  for (const bake::EvalConfig& c : configs) {
    ASSERT_GT(c.asked_probes, 0) << c.label;
    const int asked = c.asked_probes;
    if (c.bake.placement != formats::PlacementKind::grid) {
      EXPECT_EQ(c.budget_by, "probe budget") << c.label;
      EXPECT_EQ(c.bake.probe_budget, asked) << c.label;
      const int n = live_probes(s, c.bake);
      EXPECT_GT(n, asked / 2) << c.label;
      EXPECT_LE(n, asked) << c.label;
      std::printf("[ ladder ] %s: %d live probes for a budget of %d\n", c.label.c_str(), n, asked);
      ++budgeted;
      continue;
    }
    EXPECT_EQ(c.budget_by, "grid resolution") << c.label;
    auto count = [&](int value) {
      bake::BakeSettings b = c.bake;
      b.grid_resolution = value;
      return value < 1 ? 0 : live_probes(s, b);
    };
    const int value = c.bake.grid_resolution, n = count(value), below = count(value - 1), above = count(value + 1);
    EXPECT_LE(std::abs(n - asked), std::abs(below - asked)) << c.label << ": " << n << " vs " << below;
    EXPECT_LE(std::abs(n - asked), std::abs(above - asked)) << c.label << ": " << n << " vs " << above;
    EXPECT_LE(std::abs(n - asked), 0.35 * asked) << c.label << ": " << n;
    ++grids;
    std::printf("[ ladder ] %s: %d probes for %d (either side: %d, %d)\n", c.label.c_str(), n, asked, below, above);
  }
  EXPECT_EQ(grids, 2);    // 64 -> 4^3, 128 -> 5^3
  EXPECT_EQ(budgeted, 4); // octree and skeleton, both rungs
  // Deterministic: the same ladder again gives the same configurations.
  const auto again = bake::ladder_sweep(s, ladder, base);
  ASSERT_EQ(again.size(), configs.size());
  for (std::size_t i = 0; i < configs.size(); ++i) EXPECT_EQ(again[i].label, configs[i].label);
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The reference CSV of the version before the direct part: header and rows cut to their first 10 columns.
void write_without_direct(const std::filesystem::path& path) {
  std::string out;
  for (const std::string& line : lines(read_text(path))) {
    std::size_t cut = 0;
    for (int commas = 0; commas < 10 && cut != std::string::npos; ++commas)
      cut = line.find(',', cut == 0 ? 0 : cut + 1);
    out += line.substr(0, cut) + '\n';
  }
  std::ofstream(path, std::ios::binary) << out;
}

TEST(EvalCache, ACacheWithoutTheDirectPartIsComputedAgainNotMisread) {
  const auto scene = write_generated(samples::cornell(), "ladder_cache");
  bake::EvalSettings settings;
  settings.points = 32;
  settings.paths = 32;
  settings.configs = {bake::quick_sweep().back()};
  std::filesystem::remove(bake::evaluate(scene, settings).cache_file); // start from nothing
  const bake::EvalResult first = bake::evaluate(scene, settings);
  ASSERT_TRUE(first.cache_written);
  ASSERT_FALSE(first.reference_from_cache);
  ASSERT_GT(first.mean_indirect_reference, 0.0);
  write_without_direct(first.cache_file);
  ASSERT_EQ(lines(read_text(first.cache_file)).front(), "x,y,z,nx,ny,nz,r,g,b,stderr");
  std::vector<bake::SamplePoint> points;
  bake::ReferenceResult values;
  EXPECT_FALSE(bake::read_reference_csv(first.cache_file, points, values));

  const bake::EvalResult second = bake::evaluate(scene, settings);
  EXPECT_FALSE(second.reference_from_cache);
  EXPECT_TRUE(second.cache_written);
  const bake::EvalResult third = bake::evaluate(scene, settings); // the rewritten cache reads back
  EXPECT_TRUE(third.reference_from_cache);
  for (const bake::EvalResult* r : {&second, &third}) {
    EXPECT_EQ(r->mean_indirect_reference, first.mean_indirect_reference);
    EXPECT_EQ(r->direct_relative_rmse, first.direct_relative_rmse);
    ASSERT_EQ(r->rows.size(), first.rows.size());
    EXPECT_EQ(r->rows[0].indirect_rmse, first.rows[0].indirect_rmse);
    EXPECT_EQ(r->rows[0].rmse, first.rows[0].rmse);
  }
  std::printf("[ cache ] indirect mean %.4g, direct_irradiance vs traced direct: rel. RMSE %.4f, bias %+.4f\n",
              first.mean_indirect_reference, first.direct_relative_rmse, first.direct_bias);
}

TEST(EvalCli, LadderWritesAskedAndIndirectColumnsAndAProbeCountPlot) {
  const auto scene = write_generated(samples::cornell(), "ladder_cli");
  const auto dir = scene.parent_path();
  const auto csv = dir / "ladder.csv", svg = dir / "ladder.svg";
  const CliResult r =
      run_cli("eval " + quoted(scene) + " --quick --probes 16,64 --csv " + quoted(csv) + " --plot " + quoted(svg));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("| indirect rel. RMSE |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("direct_irradiance against the traced direct part"), std::string::npos) << r.out;
  const auto rows = lines(read_text(csv));
  ASSERT_GE(rows.size(), 4u); // header, at least two rows per method... grid and octree at two rungs, less repeats
  EXPECT_TRUE(rows[0].ends_with(
      ",asked_probes,budget_by,indirect_rmse,indirect_relative_rmse,seam_p99,image_flip_mean,lookup_bytes,"
      "l2_codec_error,l1_codec_error,l2_relative_rmse,l1_relative_rmse,l2_lookup_bytes,l1_lookup_bytes"))
      << rows[0];
  int grid_rows = 0, grid_engine_rows = 0;
  std::map<std::string, double> svo_bytes; // per label: the SVO row's lookup bytes
  for (std::size_t i = 1; i < rows.size(); ++i) {
    std::vector<std::string> cells;
    std::istringstream in(rows[i]);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 38u) << rows[i];
    const int asked = std::stoi(cells[25]);
    const double indirect = std::stod(cells[28]);
    const double seam = std::stod(cells[29]);
    EXPECT_EQ(std::stod(cells[30]), 0.0) << rows[i]; // no camera: no image receivers, no HDR-FLIP
    const double lookup_bytes = std::stod(cells[31]);
    EXPECT_GT(lookup_bytes, 0.0) << rows[i];
    const double l2_error = std::stod(cells[32]), l1_error = std::stod(cells[33]);
    const double l2_bytes = std::stod(cells[36]), l1_bytes = std::stod(cells[37]);
    if (cells[1] == "svo" || cells[1] == "grid") {
      EXPECT_TRUE(asked == 16 || asked == 64) << rows[i];
      EXPECT_TRUE(seam >= 0.0 && seam < 10.0) << rows[i];
      // The l2 code moves the lookup by a fraction of a percent (tests/formats/sh_codec_test.cpp bounds it
      // per probe); l1 drops band 2, a larger but still bounded change.
      EXPECT_TRUE(l2_error > 0.0 && l2_error < 0.01) << rows[i];
      EXPECT_TRUE(l1_error > l2_error && l1_error < 0.2) << rows[i];
      EXPECT_TRUE(lookup_bytes > l2_bytes && l2_bytes > l1_bytes && l1_bytes > 0.0) << rows[i];
    } else {
      EXPECT_EQ(seam, -1.0) << rows[i]; // the all-probe loop is not scored for seams
      EXPECT_EQ(l2_error, -1.0) << rows[i];
      EXPECT_EQ(l2_bytes, 0.0) << rows[i];
    }
    EXPECT_TRUE(std::isfinite(indirect) && indirect > 0.0) << rows[i];
    if (cells[1] == "svo") svo_bytes[cells[0]] = lookup_bytes;
    if (cells[2] == "grid" && cells[1] == "svo") ++grid_rows;
    if (cells[1] == "grid") { // the grid engine's row follows its bake's SVO row, and keeps no SVO
      ++grid_engine_rows;
      EXPECT_LT(lookup_bytes, svo_bytes.at(cells[0])) << rows[i];
    }
  }
  EXPECT_EQ(grid_rows, 2);
  EXPECT_EQ(grid_engine_rows, 2);
  const std::string plot = read_text(svg);
  EXPECT_NE(plot.find("error against probe count"), std::string::npos);
  EXPECT_NE(plot.find("grid indirect"), std::string::npos);
  EXPECT_NE(plot.find("octree total"), std::string::npos);
  EXPECT_EQ(run_cli("eval " + quoted(scene) + " --quick --probes 0").exit_code, 1);
  EXPECT_EQ(run_cli("eval " + quoted(scene) + " --quick --probes 64,32").exit_code, 1);
}

// --svo-depth bakes every configuration's SVO at that depth: the CSV's svo_depth column, and fewer SVO lookup
// bytes than at the default depth for the same configuration. --bytes-plot draws error against those bytes.
TEST(EvalCli, SvoDepthAppliesToEveryBake) {
  const auto scene = write_generated(samples::cornell(), "svo_depth_cli");
  const auto dir = scene.parent_path();
  std::map<std::string, double> bytes[2]; // per (label, sampler): lookup bytes at depth 2, at the default
  for (int run = 0; run < 2; ++run) {
    const auto csv = dir / ("depth" + std::to_string(run) + ".csv");
    const auto plot = dir / "bytes.svg";
    const CliResult r = run_cli("eval " + quoted(scene) + " --quick --csv " + quoted(csv) +
                                (run == 0 ? " --svo-depth 2" : " --bytes-plot " + quoted(plot)));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const auto rows = lines(read_text(csv));
    ASSERT_GE(rows.size(), 3u);
    for (std::size_t i = 1; i < rows.size(); ++i) {
      std::vector<std::string> cells;
      std::istringstream in(rows[i]);
      for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
      if (run == 0) {
        EXPECT_EQ(cells[7], "2") << rows[i];
      }
      bytes[run][cells[0] + "/" + cells[1]] = std::stod(cells[31]);
    }
  }
  const std::string svg = read_text(dir / "bytes.svg");
  EXPECT_NE(svg.find("error against lookup bytes"), std::string::npos);
  EXPECT_NE(svg.find("lookup bytes (log scale)"), std::string::npos);
  for (const char* method : {"octree", "grid", "grid engine"}) // the quick sweep: two octrees and a 4^3 grid
    EXPECT_NE(svg.find(std::string(">") + method + "</text>"), std::string::npos) << method;
  for (const auto& [row, shallow] : bytes[0])
    if (row.ends_with("/svo")) { // the grid engine reads its lattice, the all-probe loop no index
      EXPECT_LT(shallow, bytes[1].at(row)) << row;
    }
  EXPECT_EQ(run_cli("eval " + quoted(scene) + " --quick --svo-depth 9").exit_code, 1);
}

} // namespace
} // namespace probebake::test
