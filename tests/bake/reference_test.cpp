// The path-traced reference against closed forms (white furnace, point light over a black plane),
// its determinism, sample points, and the OpenEXR image it writes.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <numbers>
#include <sstream>

#include <sys/wait.h>

#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bake_test_util.h"
#include "probebake/eval/eval.h"
#include "probebake/eval/reference.h"
#include "probebake/samples/scenes.h"
#include "run_cli.h"

namespace probebake::test {
namespace {

constexpr double kPi = std::numbers::pi;

// Every channel within 3 standard errors of `exact` (plus float rounding); returns the worst |error| / se.
double expect_within_3_se(const bake::ReferenceResult& r, std::size_t i, glm::dvec3 exact, const std::string& what) {
  double worst = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double error = std::abs(double(r.irradiance[i][c]) - exact[c]);
    const double se = r.standard_error[i][c];
    EXPECT_LE(error, 3.0 * se + 1e-5 * std::abs(exact[c])) << what << " point " << i << " channel " << c << ": "
                                                           << r.irradiance[i][c] << " vs " << exact[c] << ", se " << se;
    if (se > 0.0) worst = std::max(worst, error / se);
  }
  return worst;
}

// Furnace: a closed box whose every face emits L with albedo R has irradiance pi L / (1 - R) everywhere.
void check_furnace(float albedo, int points, int paths) {
  const std::string name = "ref_furnace_" + std::to_string(int(albedo * 100));
  const scene::Scene s = load_generated(samples::furnace({.albedo = albedo, .emission = 1.0f}), name);
  const scene::RayScene rays(s);
  const auto p = bake::surface_sample_points(s, rays, points, 7);
  ASSERT_EQ(int(p.size()), points);
  const bake::ReferenceResult r = bake::reference_irradiance(s, rays, p, {.paths = paths, .seed = 3});
  const double exact = kPi / (1.0 - double(albedo));
  double worst = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    worst = std::max(worst, expect_within_3_se(r, i, glm::dvec3(exact), name));
    EXPECT_LT(r.standard_error[i].x, 0.03 * exact) << "too noisy to mean anything";
  }
  std::printf("[ furnace R=%.2f ] exact %.4f, point 0: %.4f +- %.4f; worst |error| / se %.2f\n", albedo, exact,
              r.irradiance[0].x, r.standard_error[0].x, worst);
}

TEST(Reference, FurnaceAlbedo0IsPiL) { check_furnace(0.0f, 4, 256); }
TEST(Reference, FurnaceAlbedoHalf) { check_furnace(0.5f, 4, 4096); }
// Mean path length 100 bounces: Russian roulette must keep the estimate unbiased.
TEST(Reference, FurnaceAlbedo099) { check_furnace(0.99f, 3, 16384); }

TEST(Reference, PointLightOverBlackPlaneIsICosOverR2) {
  const float intensity = 100.0f, height = 1.0f;
  const scene::Scene s = load_generated(samples::plane_light({.size = 10.0f, .height = height, .intensity = intensity}),
                                        "ref_plane_light");
  const scene::RayScene rays(s);
  const auto points = bake::surface_sample_points(s, rays, 16, 11);
  ASSERT_EQ(points.size(), 16u);
  const bake::ReferenceResult r = bake::reference_irradiance(s, rays, points, {.paths = 64});
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(points[i].position.y, 0.0f, 1e-6f);
    const glm::dvec3 to_light = glm::dvec3(0.0, height, 0.0) - glm::dvec3(points[i].position);
    const double r2 = glm::dot(to_light, to_light);
    const double exact = intensity * (double(height) / std::sqrt(r2)) / r2; // I cos / r^2
    expect_within_3_se(r, i, glm::dvec3(exact), "plane");
  }
}

TEST(Reference, SamePointsAndNumbersForAnyThreadCount) {
  const scene::Scene s = load_generated(samples::cornell(), "ref_cornell");
  const scene::RayScene rays(s);
  const auto points = bake::surface_sample_points(s, rays, 24, 5);
  ASSERT_EQ(points.size(), 24u);
  const auto again = bake::surface_sample_points(s, 24, 5);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(points[i].position, again[i].position);
    EXPECT_EQ(points[i].normal, again[i].normal);
  }
  const bake::ReferenceResult one =
      bake::reference_irradiance(s, rays, points, {.paths = 200, .seed = 9, .threads = 1});
  const bake::ReferenceResult two =
      bake::reference_irradiance(s, rays, points, {.paths = 200, .seed = 9, .threads = 2});
  EXPECT_EQ(one.irradiance, two.irradiance);
  EXPECT_EQ(one.standard_error, two.standard_error);
  const bake::ReferenceResult other =
      bake::reference_irradiance(s, rays, points, {.paths = 200, .seed = 10, .threads = 2});
  EXPECT_NE(one.irradiance, other.irradiance);
  double lit = 0.0;
  for (const glm::vec3& e : one.irradiance) lit += e.x + e.y + e.z;
  EXPECT_GT(lit, 0.0);
}

TEST(Reference, SamplePointsAvoidHiddenSurfaces) {
  // The Cornell box's blocks stand on the floor: no point may lie under them (inside geometry).
  const scene::Scene s = load_generated(samples::cornell(), "ref_cornell_points");
  const scene::RayScene rays(s);
  const auto points = bake::surface_sample_points(s, rays, 400, 1);
  ASSERT_EQ(points.size(), 400u);
  for (const bake::SamplePoint& p : points) {
    EXPECT_NEAR(glm::length(p.normal), 1.0f, 1e-5f);
    EXPECT_FALSE(inside_geometry(rays, p.position + 1e-4f * p.normal))
        << p.position.x << " " << p.position.y << " " << p.position.z;
  }
}

TEST(Reference, IrradianceImageIsWrittenAsReadableOpenExr) {
  const scene::Scene s = load_generated(samples::cornell(), "ref_cornell_image");
  const scene::RayScene rays(s);
  const bake::Camera camera{.position = {0.0f, 0.274f, 1.0f},
                            .look_at = {0.0f, 0.274f, 0.0f},
                            .fov_degrees = 40.0f,
                            .width = 24,
                            .height = 16};
  const bake::Image image = bake::render_irradiance_image(s, rays, camera, {.paths = 16});
  const auto path = write_generated(samples::empty(), "ref_image_dir").parent_path() / "ref_cornell.exr";
  std::filesystem::remove(path);
  bake::write_exr(path, image);
  ASSERT_TRUE(std::filesystem::exists(path));

  Imf::RgbaInputFile file(path.c_str()); // read back through OpenEXR's RGBA interface (half floats)
  const Imath::Box2i window = file.dataWindow();
  ASSERT_EQ(window.max.x - window.min.x + 1, 24);
  ASSERT_EQ(window.max.y - window.min.y + 1, 16);
  Imf::Array2D<Imf::Rgba> pixels(16, 24);
  file.setFrameBuffer(&pixels[0][0], 1, 24);
  file.readPixels(window.min.y, window.max.y);
  int lit = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) {
      const glm::vec3 e = image.pixels[std::size_t(y * 24 + x)];
      EXPECT_NEAR(float(pixels[y][x].r), e.x, 2e-3f * e.x + 1e-4f);
      EXPECT_NEAR(float(pixels[y][x].b), e.z, 2e-3f * e.z + 1e-4f);
      lit += e.x > 0.0f ? 1 : 0;
    }
  EXPECT_GT(lit, 24 * 16 / 2);                          // the camera looks into the box
  EXPECT_EQ(bake::read_exr(path).pixels, image.pixels); // float channels round-trip exactly
}

TEST(Reference, BadSettingsAreUsageErrors) {
  const scene::Scene s = load_generated(samples::triangle(), "ref_triangle");
  const scene::RayScene rays(s);
  const std::vector<bake::SamplePoint> points(1);
  EXPECT_THROW(bake::reference_irradiance(s, rays, points, {.paths = 1}), Error);
  EXPECT_THROW(bake::surface_sample_points(s, rays, 0, 1), Error);
  EXPECT_THROW(bake::camera_surface_points(rays, {.position = {0, 0, 0}, .look_at = {0, 0, 0}}), Error);
}

// ---- CLI: probebake reference / eval ----------------------------------------------------------------------

// The CLI's exit code, stdout and stderr (run_cli.h).
CliResult run(const std::string& args) { return run_cli(args); }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(ReferenceCli, WritesCsvAndImage) {
  const auto scene = write_generated(samples::cornell(), "ref_cli_cornell");
  const auto dir = scene.parent_path();
  const CliResult r =
      run("reference " + quoted(scene) + " --points 16 --samples 16 --csv " + quoted(dir / "ref_cli.csv") +
          " --image " + quoted(dir / "ref_cli.exr") + " --camera 0,0.27,1 --look-at 0,0.27,0 --size 8x6 --json");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(nlohmann::json::parse(r.out)["points"]["count"].get<int>(), 16);
  const auto csv = lines_of(read_text(dir / "ref_cli.csv"));
  ASSERT_EQ(csv.size(), 17u);
  EXPECT_EQ(csv[0], "x,y,z,nx,ny,nz,r,g,b,stderr,direct_r,direct_g,direct_b,indirect_stderr");
  EXPECT_EQ(bake::read_exr(dir / "ref_cli.exr").pixels.size(), 48u);
  EXPECT_EQ(run("reference " + quoted(scene) + " --image x.exr").exit_code, 1); // no camera
  EXPECT_EQ(run("reference " + quoted(scene) + " --samples 1").exit_code, 1);
  EXPECT_EQ(run("reference missing.glb").exit_code, 2);
}

void write_text(const std::filesystem::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// `--animate NAME --frame F` traces the scene with its dynamic objects where `probebake run --animate` has
// them: the rest pose before the motion (the same bytes as without --animate), the turned blocks after it.
TEST(ReferenceCli, AnimateTracesTheScenesPoseAtAFrame) {
  samples::CornellOptions options;
  options.dynamic = true;
  const auto scene = write_generated(samples::cornell(options), "ref_animate_cornell");
  const auto dir = scene.parent_path();
  const auto reference = [&](const std::string& extra, const char* csv) {
    const CliResult r =
        run("reference " + quoted(scene) + " --points 32 --samples 16 --csv " + quoted(dir / csv) + extra);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    return read_text(dir / csv);
  };
  const std::string rest = reference("", "ref_rest.csv");
  EXPECT_EQ(reference(" --animate thesis --frame 150", "ref_150.csv"), rest);
  EXPECT_NE(reference(" --animate thesis --frame 350", "ref_350.csv"), rest);
  EXPECT_EQ(run("reference " + quoted(scene) + " --animate spin").exit_code, 1);
}

TEST(ReferenceCli, AtReadsReceiversAndItsOwnCsvBack) {
  const auto scene =
      write_generated(samples::plane_light({.size = 4.0f, .height = 1.0f, .intensity = 10.0f}), "ref_at_plane");
  const auto dir = scene.parent_path();
  // Header, blank line, CRLF and spaces are accepted; the normal is normalised.
  write_text(dir / "at.csv", "x,y,z,nx,ny,nz\n0,0,0,0,2,0\r\n\n 0.5 , 0 , 0 , 0 , 1 , 0\n");
  const CliResult r = run("reference " + quoted(scene) + " --at " + quoted(dir / "at.csv") + " --samples 16 --csv " +
                          quoted(dir / "at_out.csv") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["points"]["count"].get<int>(), 2);
  const auto points = bake::read_receivers_csv(dir / "at_out.csv"); // the --csv output reads back as --at
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].normal, glm::vec3(0.0f, 1.0f, 0.0f));
  EXPECT_EQ(points[1].position, glm::vec3(0.5f, 0.0f, 0.0f));
  std::vector<bake::SamplePoint> p;
  bake::ReferenceResult values;
  ASSERT_TRUE(bake::read_reference_csv(dir / "at_out.csv", p, values));
  // E = I h / r^3 under a 10 cd light 1 m up (the plane is black): 10 and 10 / 1.25^1.5.
  EXPECT_NEAR(values.irradiance[0].x, 10.0f, 1e-3f);
  EXPECT_NEAR(values.irradiance[1].x, 10.0f / std::pow(1.25f, 1.5f), 1e-3f);
}

TEST(ReferenceCli, AtRefusesMalformedRowsNamingFileAndLine) {
  const auto scene = write_generated(samples::triangle(), "ref_at_bad");
  const auto dir = scene.parent_path();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0,0,0,0,1,0\n0,0,abc,0,1,0\n", "line 2: column 3: 'abc' is not a number"},
      {"0,0,0,0,1\n", "line 1: 5 columns"},
      {"x,y,z,nx,ny,nz\n0,0,0,0,0,0\n", "line 2: the normal nx,ny,nz has no direction"},
      {"0,0,nan,0,1,0\n", "line 1: column 3: nan is not finite"},
      {"0,0,1e39,0,1,0\n", "line 1: column 3: '1e39' is not a number"},
      {"0,0,0,0,1,0,\n", "line 1: column 7: '' is not a number"},
      {"\n\n", "no receivers"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto file = dir / ("bad" + std::to_string(i) + ".csv");
    write_text(file, cases[i].first);
    const CliResult r = run("reference " + quoted(scene) + " --at " + quoted(file) + " --samples 4");
    EXPECT_EQ(r.exit_code, 2) << cases[i].first;
    EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(file.string() + ": " + cases[i].second), std::string::npos) << r.err;
  }
  EXPECT_EQ(run("reference " + quoted(scene) + " --at " + quoted(dir / "missing.csv")).exit_code, 2);
  EXPECT_EQ(run("reference " + quoted(scene) + " --at " + quoted(dir / "bad0.csv") + " --points 4").exit_code, 1);
  // The output may not replace the receivers it reads.
  write_text(dir / "good.csv", "0.2,0,-0.2,0,1,0\n");
  EXPECT_EQ(
      run("reference " + quoted(scene) + " --at " + quoted(dir / "good.csv") + " --csv " + quoted(dir / "good.csv"))
          .exit_code,
      3);
}

// The limits of read_receivers_csv: kMaxReceivers rows are read, one more is refused naming its line, and a
// file over kMaxReceiverFileBytes is refused by its size before any byte is read (a sparse file: no disk).
TEST(ReferenceCsv, ReceiverLimitsAreExact) {
  const auto dir = std::filesystem::path(PROBEBAKE_BINARY_DIR) / "test-tmp" / "bake" / "receiver-limits";
  std::filesystem::create_directories(dir);
  std::string rows;
  rows.reserve(12 * (bake::kMaxReceivers + 1));
  for (std::size_t i = 0; i < bake::kMaxReceivers; ++i) rows += "0,0,0,0,1,0\n";
  write_text(dir / "max.csv", rows);
  EXPECT_EQ(bake::read_receivers_csv(dir / "max.csv").size(), bake::kMaxReceivers);
  write_text(dir / "over.csv", rows + "0,0,0,0,1,0\n");
  expect_refusal([&] { bake::read_receivers_csv(dir / "over.csv"); }, "line 1000001: more than 1000000 receivers",
                 "one receiver over the limit was read");
  std::filesystem::remove(dir / "max.csv");
  std::filesystem::remove(dir / "over.csv");
  { std::ofstream(dir / "huge.csv") << "0,0,0,0,1,0\n"; }
  std::filesystem::resize_file(dir / "huge.csv", bake::kMaxReceiverFileBytes + 1);
  expect_refusal([&] { bake::read_receivers_csv(dir / "huge.csv"); }, "receiver files are limited to 268435456",
                 "a file over the size limit was read");
  std::filesystem::remove(dir / "huge.csv");
}

// Markdown rows after the header separator.
std::vector<std::string> table_rows(const std::string& out) {
  std::vector<std::string> rows;
  bool body = false;
  for (const std::string& line : lines_of(out)) {
    if (line.starts_with("|---"))
      body = true;
    else if (body && line.starts_with("| "))
      rows.push_back(line);
  }
  return rows;
}

TEST(EvalCli, QuickSweepOnCornellWritesTableCsvSvgAndCachesTheReference) {
  const auto scene = write_generated(samples::cornell(), "ref_eval_cornell");
  const auto dir = scene.parent_path();
  for (const auto& entry : std::filesystem::directory_iterator(dir)) // start without a cached reference
    if (entry.path().filename().string().starts_with("ref_eval_cornell.glb.reference."))
      std::filesystem::remove(entry.path());
  const auto csv = dir / "ref_eval.csv", svg = dir / "ref_eval.svg";
  const CliResult first = run("eval " + quoted(scene) + " --quick --csv " + quoted(csv) + " --plot " + quoted(svg));
  ASSERT_EQ(first.exit_code, 0) << first.out;
  // One row per configuration, one more per grid (its grid engine's lookup), plus the all-probes baseline.
  const std::vector<bake::EvalConfig> sweep = bake::quick_sweep();
  const std::size_t grids = std::size_t(std::count_if(
      sweep.begin(), sweep.end(), [](const bake::EvalConfig& c) { return c.bake.placement == bake::Placement::grid; }));
  ASSERT_GE(grids, 1u);
  const std::size_t configs = sweep.size() + grids;
  const auto rows = table_rows(first.out);
  ASSERT_EQ(rows.size(), configs + 1) << first.out;
  for (const auto& c : sweep) {
    const auto count = [&](const char* sampler) {
      return std::count_if(rows.begin(), rows.end(), [&](const std::string& r) {
        return r.starts_with("| " + c.label + " | " + sampler + " |");
      });
    };
    EXPECT_EQ(count("svo"), 1) << c.label;
    EXPECT_EQ(count("grid"), c.bake.placement == bake::Placement::grid ? 1 : 0) << c.label;
  }
  EXPECT_EQ(lines_of(read_text(csv)).size(), configs + 2); // header + rows
  const std::string plot = read_text(svg);
  EXPECT_TRUE(plot.starts_with("<svg")) << plot.substr(0, 80);
  EXPECT_NE(plot.find("Pareto front"), std::string::npos);
  EXPECT_NE(plot.find("</svg>"), std::string::npos);

  const CliResult second = run("eval " + quoted(scene) + " --quick --json --light-rays 24");
  ASSERT_EQ(second.exit_code, 0) << second.out;
  const auto j = nlohmann::json::parse(second.out);
  EXPECT_TRUE(j["reference_cached"].get<bool>());
  EXPECT_TRUE(std::filesystem::exists(j["cache_file"].get<std::string>()));
  ASSERT_EQ(j["rows"].size(), configs + 1);
  EXPECT_EQ(j["receivers"].get<std::string>(), "visible");
  for (const auto& row : j["rows"]) {
    EXPECT_GT(row["coverage"].get<double>(), 0.0);
    EXPECT_GT(row["probes"].get<int>(), 0);
    EXPECT_GT(row["file_bytes"].get<long>(), 0);
    EXPECT_GT(row["lookup_bytes"].get<long>(), 0);
    EXPECT_TRUE(std::isfinite(row["relative_rmse"].get<double>()));
    EXPECT_EQ(row["light_rays"].get<int>(), 24); // --light-rays reaches every bake of the sweep
  }
}

TEST(EvalCli, BadOptionsAreUsageErrors) {
  const auto scene = write_generated(samples::cornell(), "ref_eval_bad");
  EXPECT_EQ(run("eval " + quoted(scene) + " --quick --points 0").exit_code, 1);
  EXPECT_EQ(run("eval " + quoted(scene) + " --quick --error-map maps").exit_code, 1); // needs a camera
  EXPECT_EQ(run("eval " + quoted(scene) + " --quick --camera 0,0,1").exit_code, 1);   // needs --look-at
  EXPECT_EQ(run("eval " + quoted(scene) + " --quick --receivers surfaces").exit_code, 1);
  EXPECT_EQ(run("eval " + quoted(scene) + " --quick --light-rays -1").exit_code, 1);
}

} // namespace
} // namespace probebake::test
