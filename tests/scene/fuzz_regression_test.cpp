// Every crash, timeout or out-of-memory input the loader fuzzer found (tests/data/fuzz-regressions/
// scene_loader), its seeds (tests/data/fuzz/scene_loader) and, when present, ../shared/scenes, through the
// same entry function as the libFuzzer target, so that a fixed bug stays fixed in the ordinary gcc build.
#include "fuzz_inputs.h"
#include "fuzz_scene_loader_entry.h"

namespace probebake::fuzz {
namespace {

const std::filesystem::path kData = PROBEBAKE_TEST_DATA;

TEST(FuzzRegression, SceneLoader) {
  std::vector<std::filesystem::path> folders = {kData / "fuzz" / "scene_loader",
                                                kData / "fuzz-regressions" / "scene_loader"};
  std::error_code ec;
  if (std::filesystem::is_directory(PROBEBAKE_SHARED_SCENES, ec))
    for (const auto& entry : std::filesystem::directory_iterator(PROBEBAKE_SHARED_SCENES))
      if (entry.is_directory()) folders.push_back(entry.path());
  std::vector<std::filesystem::path> scenes;
  for (const auto& file : files_in(folders))
    if (file.extension() != ".md" && file.extension() != ".png" && file.extension() != ".jpg" &&
        file.filename().string().rfind("LICENSE", 0) != 0)
      scenes.push_back(file);
  EXPECT_GE(replay(scenes, fuzz_one_scene_loader), 1u);
}

// The scratch folder's canary stays unread however a scene names it.
TEST(FuzzRegression, ScratchFolderConfinesExternalUris) {
  for (const std::string uri :
       {"../outside.bin", "buffer.bin/../../outside.bin", "/etc/passwd", "file:///etc/passwd"}) {
    const std::string gltf = R"({"asset":{"version":"2.0"},"buffers":[{"uri":")" + uri + R"(","byteLength":36}]})";
    EXPECT_NO_THROW(fuzz_one_scene_loader(reinterpret_cast<const std::uint8_t*>(gltf.data()), gltf.size())) << uri;
  }
}

} // namespace
} // namespace probebake::fuzz
