// Every malformed input gives one line on stderr naming the file and the problem, exit code 2 and no
// crash, both from the library (probebake::Error) and from `probebake info`.
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "mini_gltf.h"
#include "run_cli.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/error.h"

namespace probebake::test {
namespace {

const std::vector<glm::vec3> kTri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

CliResult run_info(const std::filesystem::path& file) { return run_cli("info " + quoted(file)); }

// Writes one malformed case as <test-tmp>/<name>/scene.glb.
std::filesystem::path write_case(const MiniGltf& g, const std::string& name) {
  const auto path = test_dir(name) / "scene.glb";
  g.write_glb(path);
  return path;
}

// The library throws an input error mentioning `reason`; the CLI exits 2 with exactly one stderr line
// that names the file and the reason.
void expect_rejected(const std::filesystem::path& file, const std::string& reason) {
  try {
    scene::load_scene(file, {.require_triangles = true});
    ADD_FAILURE() << file << " was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  const CliResult cli = run_info(file);
  EXPECT_EQ(cli.exit_code, 2) << cli.err;
  EXPECT_EQ(std::count(cli.err.begin(), cli.err.end(), '\n'), 1) << cli.err;
  EXPECT_NE(cli.err.find(file.string()), std::string::npos) << cli.err;
  EXPECT_NE(cli.err.find(reason), std::string::npos) << cli.err;
}

TEST(BadInput, MissingFile) { expect_rejected(test_dir("missing") / "nope.glb", "does not exist"); }

TEST(BadInput, TruncatedGlbAtEveryLength) {
  const auto bytes = MiniGltf::triangles(kTri, {0, 1, 2}).glb();
  const auto dir = test_dir("truncated");
  for (std::size_t n = 1; n < bytes.size(); ++n) {
    const auto path = dir / "t.glb";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(n));
    EXPECT_THROW(scene::load_scene(path, {.require_triangles = true}), Error) << "prefix " << n;
  }
  const auto path = dir / "half.glb";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size() / 2));
  const CliResult cli = run_info(path);
  EXPECT_EQ(cli.exit_code, 2);
  EXPECT_NE(cli.err.find("half.glb"), std::string::npos);
}

TEST(BadInput, GltfPointingAtMissingBin) {
  const auto dir = test_dir("missing_bin");
  MiniGltf::triangles(kTri, {0, 1, 2}).write_gltf(dir / "scene.gltf", "scene.bin");
  std::filesystem::remove(dir / "scene.bin");
  expect_rejected(dir / "scene.gltf", "scene.bin");
}

TEST(BadInput, AccessorPastItsBufferView) {
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["accessors"][0]["count"] = 4; // the view holds three vec3
  const auto path = write_case(g, "accessor");
  expect_rejected(path, "reaches past bufferView");
}

TEST(BadInput, IndexPastVertexCount) {
  const auto path = test_dir("index") / "scene.glb";
  MiniGltf::triangles(kTri, {0, 1, 7}).write_glb(path);
  expect_rejected(path, "index 7 is past the vertex count 3");
}

TEST(BadInput, NanAndInfPositions) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    const auto path = test_dir("nan") / "scene.glb";
    MiniGltf::triangles({{0, 0, 0}, {bad, 0, 0}, {0, 1, 0}}, {0, 1, 2}).write_glb(path);
    expect_rejected(path, "NaN or Inf");
  }
}

TEST(BadInput, CorruptedDracoPayload) {
  MiniGltf g = MiniGltf::triangles(kTri, {});
  const std::array<unsigned char, 24> garbage = {'D', 'R', 'A', 'C', 'O', 2, 2, 1, 0xff, 0xff, 0xff, 0xff};
  const int view = g.add_view(garbage.data(), garbage.size());
  g.json["meshes"][0]["primitives"][0]["extensions"] = {
      {"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", {{"POSITION", 0}}}}}};
  g.json["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  const auto path = write_case(g, "draco");
  expect_rejected(path, "corrupted Draco payload");
}

TEST(BadInput, UnsupportedRequiredExtension) {
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["extensionsUsed"] = {"EXT_made_up"};
  g.json["extensionsRequired"] = {"EXT_made_up"};
  const auto path = write_case(g, "extension");
  expect_rejected(path, "required extension EXT_made_up is not supported");
}

TEST(BadInput, ZeroTrianglesAreDescribedButNotBaked) {
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["nodes"][0].erase("mesh");
  const auto path = write_case(g, "empty");
  EXPECT_EQ(scene::load_scene(path).triangle_count(), 0u); // `info` describes it
  EXPECT_EQ(run_info(path).exit_code, 0);
  try {
    scene::load_scene(path, {.require_triangles = true});
    ADD_FAILURE() << "a scene without triangles was accepted for baking";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("scene has no triangles to bake"), std::string::npos) << e.what();
  }
}

TEST(BadInput, NodeCycle) {
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["nodes"][0]["children"] = {0};
  const auto path = write_case(g, "cycle");
  expect_rejected(path, "reached twice");
}

TEST(BadInput, NotGltfAtAll) {
  const auto path = test_dir("garbage") / "scene.gltf";
  std::ofstream(path) << "this is not json";
  expect_rejected(path, "scene.gltf");
}

} // namespace
} // namespace probebake::test
