// Spec-valid glTF that other readers refuse loads, with one warning where the Khronos validator warns and
// none where it only informs; the faults that would be read stay refused with their place and reason
// (issue #40). The files are tests/data/gltf-lenient, written by make-gltf-cases.
#include <fstream>
#include <iterator>
#include <set>

#include <gtest/gtest.h>

#include "lenient_cases.h"
#include "mini_gltf.h"
#include "run_cli.h"
#include "probebake/scene/scene.h"

namespace probebake::test {
namespace {

const std::filesystem::path kCases = std::filesystem::path(PROBEBAKE_TEST_DATA) / "gltf-lenient";

std::vector<unsigned char> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    out.push_back(text.substr(start, end - start));
  return out;
}

void expect_warnings(const std::string& err, const LenientCase& c, const std::string& command) {
  const std::vector<std::string> said = lines(err);
  ASSERT_EQ(said.size(), c.warnings.size()) << command << ":\n" << err;
  for (std::size_t i = 0; i < said.size(); ++i) {
    EXPECT_TRUE(said[i].starts_with("probebake: warning: ")) << said[i];
    EXPECT_NE(said[i].find(c.warnings[i]), std::string::npos) << said[i];
  }
}

TEST(LenientCases, TheCommittedFilesAreTheGeneratorsOutput) {
  const std::vector<LenientCase> cases = lenient_cases();
  std::set<std::string> expected = {"README.md"};
  for (const LenientCase& c : cases) {
    expected.insert(c.file);
    EXPECT_EQ(read_bytes(kCases / c.file), c.bytes) << c.file << ": run make-gltf-cases tests/data/gltf-lenient";
  }
  const std::string readme = lenient_cases_readme(cases);
  EXPECT_EQ(read_bytes(kCases / "README.md"), std::vector<unsigned char>(readme.begin(), readme.end()));
  std::set<std::string> present;
  for (const auto& entry : std::filesystem::directory_iterator(kCases))
    present.insert(entry.path().filename().string());
  EXPECT_EQ(present, expected);
}

TEST(LenientCases, EachFileHasItsOutcome) {
  for (const LenientCase& c : lenient_cases()) {
    SCOPED_TRACE(c.file);
    const auto dir = test_dir("lenient-" + c.file);
    const auto scene = dir / c.file, probes = dir / "out.probes";
    std::filesystem::copy_file(kCases / c.file, scene);
    const CliResult info = run_cli("info " + quoted(scene));
    const CliResult bake = run_cli("bake " + quoted(scene) + " --max-depth 2 -o " + quoted(probes));
    if (c.outcome == LenientOutcome::refused) {
      for (const CliResult* r : {&info, &bake}) {
        EXPECT_EQ(r->exit_code, 2) << r->err;
        EXPECT_EQ(lines(r->err).size(), 1u) << r->err;
        EXPECT_NE(r->err.find(scene.string() + ": "), std::string::npos) << r->err;
        EXPECT_NE(r->err.find(c.error), std::string::npos) << r->err;
      }
      EXPECT_FALSE(std::filesystem::exists(probes));
      continue;
    }
    ASSERT_EQ(info.exit_code, 0) << info.err;
    expect_warnings(info.err, c, "info");
    EXPECT_NE(info.out.find("12 (0 degenerate)"), std::string::npos) << info.out;
    ASSERT_EQ(bake.exit_code, 0) << bake.err;
    expect_warnings(bake.err, c, "bake");
    const CliResult valid = run_cli("validate " + quoted(probes));
    EXPECT_EQ(valid.exit_code, 0) << valid.out << valid.err;
  }
}

void expect_same_scene(const scene::Scene& a, const scene::Scene& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.triangle_albedo, b.triangle_albedo);
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (std::size_t i = 0; i < a.lights.size(); ++i) {
    EXPECT_EQ(a.lights[i].position, b.lights[i].position);
    EXPECT_EQ(a.lights[i].intensity, b.lights[i].intensity);
  }
}

// Each accepted file is the room every case starts from, plus what the case adds: the loaded scenes agree.
TEST(LenientCases, AcceptedFilesLoadAsTheRoomTheyHold) {
  const scene::Scene plain = scene::load_scene(kCases / "integral_floats.gltf");
  EXPECT_EQ(plain.triangles.size(), 12u);
  EXPECT_EQ(plain.lights.size(), 1u);
  EXPECT_TRUE(plain.warnings.empty());
  for (const LenientCase& c : lenient_cases()) {
    if (c.outcome == LenientOutcome::refused) continue;
    SCOPED_TRACE(c.file);
    const scene::Scene loaded = scene::load_scene(kCases / c.file);
    expect_same_scene(loaded, plain);
    EXPECT_EQ(loaded.warnings.size(), c.warnings.size());
  }
}

// An unused image is never decoded, so a valid but oversized one costs nothing either.
TEST(LenientCases, UnusedImagesAreNotDecoded) {
  MiniGltf g = MiniGltf::triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  const auto dir = test_dir("lenient-unused-image");
  g.json["images"] = {{{"uri", "missing.png"}}};
  g.write_gltf(dir / "scene.gltf", "scene.bin");
  const scene::Scene loaded = scene::load_scene(dir / "scene.gltf");
  EXPECT_TRUE(loaded.warnings.empty()) << loaded.warnings.front();
  EXPECT_EQ(loaded.triangles.size(), 1u);
}

} // namespace
} // namespace probebake::test
