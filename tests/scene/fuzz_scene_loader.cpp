// libFuzzer target for the glTF loader; the checks are in fuzz_scene_loader_entry.cpp. Seeds:
// tests/data/fuzz/scene_loader, generated scenes and ../shared/scenes (scripts/fuzz.sh assembles the corpus).
//   fuzz_scene_loader -dict=tests/scene/fuzz_scene_loader.dict -rss_limit_mb=2048 CORPUS tests/data/fuzz/scene_loader
#include "fuzz_scene_loader_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  probebake::fuzz::fuzz_one_scene_loader(data, size);
  return 0;
}
