// The make-scene executable: exit codes, one-line errors, default output name.
#include "gltf_readback.h"
#include "run_cli.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace pt = probebake::samples::test;

namespace {

using probebake::test::CliResult;

// Runs make-scene with `arguments` (shell syntax) inside `folder`.
CliResult make_scene(const std::filesystem::path& folder, const std::string& arguments) {
  return probebake::test::run_program(MAKE_SCENE_EXE, arguments, folder);
}

bool is_one_error_line(const std::string& text) {
  return text.rfind("make-scene: error: ", 0) == 0 && text.find('\n') == text.size() - 1;
}

} // namespace

TEST(MakeSceneCli, HelpAndVersionSucceed) {
  const auto folder = pt::fresh_folder("cli_help");
  const CliResult help = make_scene(folder, "--help");
  EXPECT_EQ(help.exit_code, 0);
  for (const char* kind : {"cornell", "furnace", "leak", "plane-light", "rooms", "triangle", "empty"}) {
    EXPECT_NE(help.out.find(kind), std::string::npos) << kind;
  }
  const CliResult furnace_help = make_scene(folder, "furnace --help");
  EXPECT_EQ(furnace_help.exit_code, 0);
  EXPECT_NE(furnace_help.out.find("--albedo"), std::string::npos);
  EXPECT_EQ(make_scene(folder, "--version").exit_code, 0);
}

TEST(MakeSceneCli, DefaultOutputIsKindInCurrentFolder) {
  const auto folder = pt::fresh_folder("cli_default");
  const CliResult run = make_scene(folder, "plane-light");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(std::filesystem::exists(folder / "plane-light.glb"));
  EXPECT_NE(run.out.find("2 triangles"), std::string::npos) << run.out;
}

TEST(MakeSceneCli, OptionsAfterTheKindAndPlacement) {
  const auto folder = pt::fresh_folder("cli_options");
  const CliResult run =
      make_scene(folder, "furnace --albedo 0.99 --emission 2 -o box.glb --scale 2 --offset 10 0 0 -q");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.out.empty());
  std::string error;
  const auto model = pt::load_glb(pt::read_file(folder / "box.glb"), error);
  ASSERT_TRUE(error.empty()) << error;
  const pt::WorldBounds b = pt::bounds_of(pt::world_triangles(model));
  EXPECT_FLOAT_EQ(b.min.x, 9.0f);
  EXPECT_FLOAT_EQ(b.max.x, 11.0f);
}

TEST(MakeSceneCli, SameCommandSameBytes) {
  const auto folder = pt::fresh_folder("cli_determinism");
  ASSERT_EQ(make_scene(folder, "cornell -o a.glb").exit_code, 0);
  ASSERT_EQ(make_scene(folder, "cornell -o b.glb").exit_code, 0);
  EXPECT_EQ(pt::read_file(folder / "a.glb"), pt::read_file(folder / "b.glb"));
}

TEST(MakeSceneCli, UsageErrorsExitOne) {
  const auto folder = pt::fresh_folder("cli_usage");
  for (const char* arguments : {"", "bogus", "furnace --albedo abc", "furnace --albedo 2", "furnace --nope",
                                "rooms --count 0", "furnace --scale -1", "furnace --offset 1 2"}) {
    const CliResult run = make_scene(folder, arguments);
    EXPECT_EQ(run.exit_code, 1) << arguments;
    EXPECT_TRUE(is_one_error_line(run.err)) << arguments << ": " << run.err;
  }
  EXPECT_NE(make_scene(folder, "bogus").err.find("unknown kind 'bogus'"), std::string::npos);
}

TEST(MakeSceneCli, UnreadableInputExitsTwo) {
  const auto folder = pt::fresh_folder("cli_input");
  std::ofstream(folder / "junk.glb") << "not a model";
  for (const char* arguments : {"cornell --with missing.glb", "cornell --with junk.glb"}) {
    const CliResult run = make_scene(folder, arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments;
    EXPECT_TRUE(is_one_error_line(run.err)) << run.err;
  }
  EXPECT_FALSE(std::filesystem::exists(folder / "cornell.glb"));
}

TEST(MakeSceneCli, UnwritableOutputExitsThree) {
  const auto folder = pt::fresh_folder("cli_output");
  const CliResult run = make_scene(folder, "triangle -o no/such/folder/t.glb");
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_TRUE(is_one_error_line(run.err)) << run.err;
}

TEST(MakeSceneCli, ConvertFlipWritesTheFlippedScene) {
  const auto folder = pt::fresh_folder("cli_flip");
  ASSERT_EQ(make_scene(folder, "cornell -q -o c.glb").exit_code, 0);
  ASSERT_EQ(make_scene(folder, "convert c.glb --flip -q -o f.glb").exit_code, 0);
  ASSERT_EQ(make_scene(folder, "convert f.glb --flip --meshopt -q -o ff.glb").exit_code, 0);
  std::string error;
  const tinygltf::Model flipped = pt::load_glb(pt::read_file(folder / "f.glb"), error);
  ASSERT_TRUE(error.empty()) << error;
  for (const tinygltf::Material& m : flipped.materials) EXPECT_TRUE(m.doubleSided) << m.name;
  const auto original = pt::world_triangles(pt::load_glb(pt::read_file(folder / "c.glb"), error));
  const auto reversed = pt::world_triangles(flipped);
  ASSERT_EQ(reversed.size(), original.size());
  for (std::size_t i = 0; i < original.size(); ++i) EXPECT_EQ(reversed[i].b, original[i].c) << i;
  // Neither --flip nor --meshopt: usage; a compressed input: input error; the input as output: exit 3.
  const CliResult none = make_scene(folder, "convert c.glb -o n.glb");
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_TRUE(is_one_error_line(none.err)) << none.err;
  const CliResult compressed = make_scene(folder, "convert ff.glb --flip -o n.glb");
  EXPECT_EQ(compressed.exit_code, 2);
  EXPECT_TRUE(is_one_error_line(compressed.err)) << compressed.err;
  EXPECT_EQ(make_scene(folder, "convert c.glb --flip -o c.glb").exit_code, 3);
}
