// Issue #18 end to end: make-scene --meshopt (meshoptimizer's own encoder) bakes byte-identically to the
// plain scene; a broken texture bakes with one warning and fails with --strict; `info` describes a scene
// without triangles while the bake refuses it; a meshopt copy of each shared scene bakes and validates.
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "mini_gltf.h"
#include "run_cli.h"

namespace probebake::test {
namespace {

const std::filesystem::path kScenes = PROBEBAKE_SHARED_SCENES;
const std::string kFastBake = " --max-depth 3 --surfels 64 --light-rays 64 --threads 2";

CliResult make_scene(const std::string& arguments) { return run_program(PROBEBAKE_MAKE_SCENE, arguments); }

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::size_t lines_with(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(OptimisedCli, MeshoptCornellBakesByteIdenticallyToPlain) {
  const auto dir = test_dir("cli-meshopt-cornell");
  ASSERT_EQ(make_scene("cornell -q -o " + quoted(dir / "plain.glb")).exit_code, 0);
  ASSERT_EQ(make_scene("cornell -q --meshopt -o " + quoted(dir / "meshopt.glb")).exit_code, 0);
  EXPECT_NE(slurp(dir / "meshopt.glb").find("\"EXT_meshopt_compression\""), std::string::npos);
  for (const char* name : {"plain", "meshopt"}) {
    const CliResult bake = run_cli("bake " + quoted(dir / (std::string(name) + ".glb")) + kFastBake + " -o " +
                                   quoted(dir / (std::string(name) + ".probes")));
    ASSERT_EQ(bake.exit_code, 0) << bake.err;
    EXPECT_EQ(bake.err.find("warning"), std::string::npos) << bake.err;
  }
  const std::string plain = slurp(dir / "plain.probes"), meshopt = slurp(dir / "meshopt.probes");
  ASSERT_FALSE(plain.empty());
  EXPECT_TRUE(plain == meshopt) << "the meshopt scene baked differently";
  const CliResult validate = run_cli("validate " + quoted(dir / "meshopt.probes"));
  EXPECT_EQ(validate.exit_code, 0) << validate.out << validate.err;
}

TEST(OptimisedCli, BrokenTextureBakesWithOneWarningAndFailsWithStrict) {
  const auto dir = test_dir("cli-broken-texture");
  ASSERT_EQ(make_scene("cornell -q -o " + quoted(dir / "cornell.glb")).exit_code, 0);
  // Give every material the same texture whose image is not an image; UVs are absent, which is fine.
  std::string glb = slurp(dir / "cornell.glb");
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, &glb[12], 4);
  nlohmann::json j = nlohmann::json::parse(glb.substr(20, json_length));
  for (auto& m : j["materials"]) m["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  j["textures"] = {{{"source", 0}}};
  j["images"] = {{{"uri", "broken.png"}}};
  std::ofstream(dir / "broken.png") << "not a png";
  MiniGltf g;
  g.json = j;
  g.bin.assign(glb.begin() + 20 + json_length + 8, glb.end());
  g.write_glb(dir / "scene.glb");

  const CliResult bake = run_cli("bake " + quoted(dir / "scene.glb") + kFastBake + " -o " + quoted(dir / "a.probes"));
  EXPECT_EQ(bake.exit_code, 0) << bake.err;
  EXPECT_EQ(lines_with(bake.err, "warning"), 1u) << bake.err;
  EXPECT_NE(bake.err.find("textures[0]: image 0 'broken.png': unknown image format"), std::string::npos) << bake.err;
  EXPECT_EQ(run_cli("validate " + quoted(dir / "a.probes")).exit_code, 0);
  const CliResult strict =
      run_cli("bake " + quoted(dir / "scene.glb") + kFastBake + " --strict -o " + quoted(dir / "b.probes"));
  EXPECT_EQ(strict.exit_code, 2) << strict.err;
  EXPECT_NE(strict.err.find("(--strict)"), std::string::npos) << strict.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "b.probes"));
  EXPECT_EQ(run_cli("info --strict " + quoted(dir / "scene.glb")).exit_code, 2);
}

TEST(OptimisedCli, InfoDescribesAnEmptySceneWhichTheBakeRefuses) {
  const auto dir = test_dir("cli-empty");
  ASSERT_EQ(make_scene("empty -q -o " + quoted(dir / "empty.glb")).exit_code, 0);
  const CliResult info = run_cli("info " + quoted(dir / "empty.glb"));
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("triangles    0"), std::string::npos) << info.out;
  const CliResult json = run_cli("info --json " + quoted(dir / "empty.glb"));
  EXPECT_EQ(nlohmann::json::parse(json.out)["triangles"], 0);
  const CliResult bake = run_cli("bake " + quoted(dir / "empty.glb") + " -o " + quoted(dir / "e.probes"));
  EXPECT_EQ(bake.exit_code, 2);
  EXPECT_NE(bake.err.find("no triangles to bake"), std::string::npos) << bake.err;
}

// Every shared scene that is not already compressed, through `make-scene convert --meshopt`: the copy
// bakes to a file that validates, with the same triangles. (Not byte-identical: the TRIANGLES codec may
// rotate a triangle's corners, which reorders floating-point sums in the bake.)
TEST(OptimisedCli, MeshoptCopiesOfTheSharedScenesBakeAndValidate) {
  if (!std::filesystem::exists(kScenes / "README.md")) GTEST_SKIP() << "no ../shared/scenes here";
  const auto dir = test_dir("cli-shared-meshopt");
  int converted = 0;
  for (const auto& folder : std::filesystem::directory_iterator(kScenes)) {
    if (!folder.is_directory() || folder.path().filename().string().find("draco") != std::string::npos) continue;
    for (const auto& file : std::filesystem::directory_iterator(folder.path())) {
      const auto ext = file.path().extension();
      if (ext != ".gltf" && ext != ".glb") continue;
      const std::string name = folder.path().filename().string();
      const auto copy = dir / (name + "-meshopt.glb");
      ASSERT_EQ(make_scene("convert --meshopt -q " + quoted(file.path()) + " -o " + quoted(copy)).exit_code, 0) << name;
      for (const auto& [scene, out] :
           {std::pair{file.path(), dir / (name + ".probes")}, std::pair{copy, dir / (name + "-meshopt.probes")}}) {
        const CliResult bake = run_cli("bake " + quoted(scene) + kFastBake + " -o " + quoted(out));
        ASSERT_EQ(bake.exit_code, 0) << name << ": " << bake.err;
      }
      EXPECT_EQ(run_cli("validate " + quoted(dir / (name + "-meshopt.probes"))).exit_code, 0) << name;
      const CliResult a = run_cli("info --json " + quoted(file.path())), b = run_cli("info --json " + quoted(copy));
      EXPECT_EQ(nlohmann::json::parse(a.out)["triangles"], nlohmann::json::parse(b.out)["triangles"]) << name;
      EXPECT_EQ(nlohmann::json::parse(a.out)["bounds"], nlohmann::json::parse(b.out)["bounds"]) << name;
      ++converted;
    }
  }
  EXPECT_GE(converted, 4);
}

} // namespace
} // namespace probebake::test
