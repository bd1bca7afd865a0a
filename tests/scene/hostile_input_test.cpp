// Scenes crafted as a hostile user would (issue #11): external URIs that try to leave the scene's folder in
// every spelling, JSON nested deep enough to overflow a recursive parser, counts that would allocate
// gigabytes from a tiny file, bad data URIs and oversized images. Each is refused with one line naming the
// file, the place and the reason (exit 2), and the bytes outside the folder never reach the output.
#include <unistd.h>

#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "mini_gltf.h"
#include "run_cli.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/error.h"

namespace probebake::test {
namespace {

const std::vector<glm::vec3> kTri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// <dir>/scene/ holds the scene; <dir>/secret.bin sits next to that folder with exactly the bytes the
// scene's buffer needs, so a loader that follows the URI would load it without complaint.
struct Layout {
  std::filesystem::path root, scene_dir, secret;
};

Layout make_layout(const std::string& name) {
  Layout l;
  l.root = test_dir(name);
  l.scene_dir = l.root / "scene";
  std::filesystem::create_directories(l.scene_dir);
  const MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  l.secret = l.root / "secret.bin";
  std::ofstream(l.secret, std::ios::binary)
      .write(reinterpret_cast<const char*>(g.bin.data()), std::streamsize(g.bin.size()));
  return l;
}

// A .gltf whose buffer URI is `uri` (written as is, not re-encoded).
std::filesystem::path scene_with_buffer_uri(const Layout& l, const std::string& uri) {
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["buffers"][0]["uri"] = uri;
  g.json["buffers"][0]["byteLength"] = g.bin.size();
  const auto path = l.scene_dir / "scene.gltf";
  write_text(path, g.json.dump());
  return path;
}

std::string load_error(const std::filesystem::path& path, const scene::LoadOptions& options = {}) {
  try {
    scene::load_scene(path, options);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input) << e.what();
    return e.what();
  }
  return "";
}

void expect_refused(const std::filesystem::path& path, const std::string& place, const std::string& reason) {
  const std::string message = load_error(path);
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find(place), std::string::npos) << message;
  EXPECT_NE(message.find(reason), std::string::npos) << message;
  const CliResult cli = run_cli("info " + quoted(path));
  EXPECT_EQ(cli.exit_code, 2) << cli.err;
  EXPECT_EQ(std::count(cli.err.begin(), cli.err.end(), '\n'), 1) << cli.err;
  EXPECT_NE(cli.err.find(reason), std::string::npos) << cli.err;
}

TEST(Confinement, RelativeEscapesInEverySpellingAreRefused) {
  const Layout l = make_layout("confine-relative");
  for (const char* uri : {"../secret.bin", "..%2Fsecret.bin", "%2E%2E/secret.bin", "%2e%2e%2fsecret.bin",
                          "./../secret.bin", "sub/../../secret.bin", "..//secret.bin"}) {
    SCOPED_TRACE(uri);
    expect_refused(scene_with_buffer_uri(l, uri), "buffers[0].uri", "outside the scene's folder");
  }
}

TEST(Confinement, AbsolutePathsAndSchemesAreRefused) {
  const Layout l = make_layout("confine-absolute");
  const std::vector<std::string> uris = {l.secret.string(), "file://" + l.secret.string(),
                                         "%2F" + l.secret.string().substr(1), "http://example.com/x.bin",
                                         "C:/secret.bin"};
  for (const std::string& uri : uris) {
    SCOPED_TRACE(uri);
    expect_refused(scene_with_buffer_uri(l, uri), "buffers[0].uri", "absolute or has a scheme");
  }
}

TEST(Confinement, SymlinksLeavingTheFolderAreRefused) {
  const Layout l = make_layout("confine-symlink");
  std::filesystem::create_symlink(l.secret, l.scene_dir / "link.bin");
  expect_refused(scene_with_buffer_uri(l, "link.bin"), "buffers[0].uri", "outside the scene's folder");
  std::filesystem::create_directories(l.root / "elsewhere");
  std::filesystem::copy_file(l.secret, l.root / "elsewhere" / "data.bin");
  std::filesystem::create_directory_symlink(l.root / "elsewhere", l.scene_dir / "linked-dir");
  expect_refused(scene_with_buffer_uri(l, "linked-dir/data.bin"), "buffers[0].uri", "outside the scene's folder");
}

TEST(Confinement, TheWorkingDirectoryIsNeverSearched) {
  // tinygltf falls back to "./<uri>"; a file that exists only in the working directory must not be found.
  const Layout l = make_layout("confine-cwd");
  std::filesystem::copy_file(l.secret, l.root / "cwd-only.bin");
  const auto scene = scene_with_buffer_uri(l, "cwd-only.bin");
  const auto previous = std::filesystem::current_path();
  std::filesystem::current_path(l.root);
  const std::string message = load_error(scene);
  const CliResult cli = run_cli("info " + quoted(scene));
  std::filesystem::current_path(previous);
  EXPECT_NE(message.find("File not found : cwd-only.bin"), std::string::npos) << message;
  EXPECT_EQ(cli.exit_code, 2) << cli.out << cli.err;
}

TEST(Confinement, AllowPathAdmitsAFolderAndInsideFilesStillLoad) {
  const Layout l = make_layout("confine-allow");
  const auto scene = scene_with_buffer_uri(l, "../secret.bin");
  const scene::Scene s = scene::load_scene(scene, {.allowed_paths = {l.root}});
  EXPECT_EQ(s.triangle_count(), 1u);
  ASSERT_EQ(s.input_files.size(), 2u); // the scene, then the buffer, resolved
  EXPECT_EQ(s.input_files[1], std::filesystem::canonical(l.secret));
  const CliResult cli = run_cli("info " + quoted(scene) + " --allow-path " + quoted(l.root));
  EXPECT_EQ(cli.exit_code, 0) << cli.err;

  std::filesystem::copy_file(l.secret, l.scene_dir / "inside.bin");
  EXPECT_EQ(scene::load_scene(scene_with_buffer_uri(l, "inside.bin")).triangle_count(), 1u);
  std::filesystem::create_directories(l.scene_dir / "sub");
  EXPECT_EQ(scene::load_scene(scene_with_buffer_uri(l, "sub/../inside.bin")).triangle_count(), 1u);
}

TEST(Confinement, ImageUrisAreConfinedToo) {
  const Layout l = make_layout("confine-image");
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["images"] = nlohmann::json::array({{{"uri", "../secret.png"}}});
  const auto path = l.scene_dir / "scene.glb";
  g.write_glb(path);
  expect_refused(path, "images[0].uri", "outside the scene's folder");
}

TEST(DataUri, InvalidBase64IsNamed) {
  const Layout l = make_layout("data-uri");
  expect_refused(scene_with_buffer_uri(l, "data:application/octet-stream;base64,AAAA$$$$"), "buffers[0].uri",
                 "not valid base64");
  expect_refused(scene_with_buffer_uri(l, "data:application/octet-stream,plain"), "buffers[0].uri", "not base64");
  expect_refused(scene_with_buffer_uri(l, "data:application/octet-stream;base64"), "buffers[0].uri", "no ','");
}

TEST(DataUri, DotAndEmptyUrisAreClearErrors) {
  const Layout l = make_layout("dot-uri");
  const std::string dot = load_error(scene_with_buffer_uri(l, "."));
  EXPECT_NE(dot.find("not found"), std::string::npos) << dot;
  expect_refused(scene_with_buffer_uri(l, ""), "buffers[0].uri", "URI is empty");
}

// A valid .gltf (with its .bin) whose top-level extras hold `depth` nested arrays.
std::filesystem::path nested_scene(const std::filesystem::path& dir, std::size_t depth) {
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["extras"] = "PLACEHOLDER";
  const auto path = dir / ("nested" + std::to_string(depth) + ".gltf");
  g.write_gltf(path, "nested.bin");
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("\"PLACEHOLDER\""), 13, std::string(depth, '[') + std::string(depth, ']'));
  write_text(path, text);
  return path;
}

TEST(Limits, DeepJsonNestingIsRefusedWithoutRecursion) {
  const auto dir = test_dir("deep-json");
  for (const std::size_t depth : {64u, 100000u}) // + the root object: 65 levels and more
    expect_refused(nested_scene(dir, depth), "json", "nesting is deeper than 64 levels");
  EXPECT_EQ(load_error(nested_scene(dir, 63)), ""); // 64 levels with the root object are fine
}

// A key twice in one object: the preflight and the tree could keep different values (the fuzzer found a
// second "images" array whose element had no uri where the first had a data URI: a crash in the rewrite).
TEST(Limits, ARepeatedKeyIsRefused) {
  const auto dir = test_dir("repeated-key");
  const MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  std::string text = g.json.dump();
  const auto top = dir / "top.gltf", nested = dir / "nested.gltf";
  write_text(top, text.substr(0, text.size() - 1) + ",\"images\":[{\"uri\":\"a.png\"}],\"images\":[{}]}");
  expect_refused(top, "json", "key \"images\" appears twice in one object");
  text.insert(text.find("\"asset\":{") + 9, "\"version\":\"1.0\",");
  write_text(nested, text);
  expect_refused(nested, "json", "key \"version\" appears twice in one object");
}

TEST(Limits, DeclaredCountsAreCheckedBeforeAllocation) {
  const auto dir = test_dir("huge-count");
  // POSITION claims 2^31 vertices inside a 36-byte view.
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["accessors"][0]["count"] = 1u << 31;
  g.write_glb(dir / "past-view.glb");
  expect_refused(dir / "past-view.glb", "POSITION", "reaches past bufferView");
  // Without a bufferView an accessor is all zeros (spec): only the memory budget bounds it.
  MiniGltf z = MiniGltf::triangles(kTri, {0, 1, 2});
  z.json["accessors"][0].erase("bufferView");
  z.json["accessors"][0]["count"] = 1u << 30;
  z.write_glb(dir / "zeros.glb");
  const std::string message = load_error(dir / "zeros.glb", {.max_memory = std::uint64_t(1) << 30});
  EXPECT_NE(message.find("memory budget of 1024 MiB"), std::string::npos) << message;
  const CliResult cli = run_cli("info " + quoted(dir / "zeros.glb") + " --max-memory 256M");
  EXPECT_EQ(cli.exit_code, 2) << cli.err;
  EXPECT_NE(cli.err.find("--max-memory"), std::string::npos) << cli.err;
}

TEST(Limits, TheSceneFileItselfCountsAgainstTheBudget) {
  const auto dir = test_dir("budget-file");
  MiniGltf::triangles(kTri, {0, 1, 2}).write_glb(dir / "s.glb");
  EXPECT_NE(load_error(dir / "s.glb", {.max_memory = 64}).find("memory budget"), std::string::npos);
  EXPECT_EQ(load_error(dir / "s.glb", {.max_memory = std::uint64_t(1) << 20}), "");
  const CliResult bad = run_cli("info " + quoted(dir / "s.glb") + " --max-memory lots");
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
}

TEST(Limits, OversizedImagesAreNotDecoded) {
  // A PNG header claiming 17000 x 1000 RGB pixels with no pixel data (stb itself stops at 1 GiB).
  const unsigned char png[] = {0x89, 'P',  'N',  'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R', 0,
                               0,    0x42, 0x68, 0,   0,    0x03, 0xe8, 8,    2, 0, 0, 0,  0,   0,   0,   0};
  const Layout l = make_layout("huge-image");
  std::ofstream(l.scene_dir / "big.png", std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof(png));
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  g.json["images"] = nlohmann::json::array({{{"uri", "big.png"}}});
  g.json["textures"] = {{{"source", 0}}};
  g.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  g.json["meshes"][0]["primitives"][0]["material"] = 0;
  g.write_glb(l.scene_dir / "scene.glb");
  // Never allocated (a 1 MiB budget would refuse 17000 x 1000 x 4 bytes); the texture is one warning...
  const scene::Scene s = scene::load_scene(l.scene_dir / "scene.glb", {.max_memory = 1 << 20});
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("17000x1000 is larger than the limit of 16384x16384"), std::string::npos)
      << s.warnings[0];
  // ... and an error with strict.
  EXPECT_NE(load_error(l.scene_dir / "scene.glb", {.strict = true}).find("larger than the limit"), std::string::npos);
}

TEST(Limits, ImageBufferViewsOutsideTheirBufferAreNeverRead) {
  // tinygltf passes a bufferView image to the decoder without checking the view against its buffer (fuzzing
  // found the read past the end). The PNG header is real, so only the range decides the outcome.
  const unsigned char png[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R', 0,
                               0,    0,   1,   0,   0,    0,    1,    8,    2, 0, 0, 0,  0,   0,   0,   0};
  const auto dir = test_dir("image-view-range");
  MiniGltf g = MiniGltf::triangles(kTri, {0, 1, 2});
  const int view = g.add_view(png, sizeof(png));
  g.json["images"] = nlohmann::json::array({{{"bufferView", view}, {"mimeType", "image/png"}}});
  g.json["textures"] = {{{"source", 0}}};
  g.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  g.json["meshes"][0]["primitives"][0]["material"] = 0;
  const std::size_t buffer_size = g.bin.size();
  g.json["bufferViews"][std::size_t(view)]["byteOffset"] = buffer_size - 8; // the last 8 bytes, then 25 beyond
  g.write_glb(dir / "past-end.glb");
  const scene::Scene s = scene::load_scene(dir / "past-end.glb");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("lies outside buffer 0 (" + std::to_string(buffer_size) + " bytes)"), std::string::npos)
      << s.warnings[0];
  EXPECT_NE(load_error(dir / "past-end.glb", {.strict = true}).find("lies outside buffer"), std::string::npos);
}

} // namespace
} // namespace probebake::test
