// The glTF loader on untrusted bytes: any bytes either load into a scene whose every position is finite,
// every index and per-triangle array in range, and every file read inside the base directory, or give
// probebake::Error. External URIs resolve against a scratch folder of this process (never the source tree or
// the working directory), with a memory budget so that the fuzzer's RSS limit only catches what the
// budget misses.
#include "fuzz_scene_loader_entry.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "fuzz_check.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/error.h"

namespace probebake::fuzz {
namespace {

constexpr std::uint64_t kMemoryBudget = std::uint64_t(512) << 20; // well under libFuzzer's -rss_limit_mb=2048

void write_file(const std::filesystem::path& path, const std::vector<float>& values) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
  check(bool(out), "cannot write " + path.string());
}

std::filesystem::path make_scratch() {
  std::filesystem::path root;
  if (const char* given = std::getenv("PROBEBAKE_FUZZ_SCRATCH"); given != nullptr && *given != '\0') {
    root = given;
  } else {
    root = std::filesystem::temp_directory_path() / ("probebake-fuzz-" + std::to_string(::getpid()));
    // Never destroyed: static destructors run before this handler. (libFuzzer ends with _Exit, so its
    // runs leave the folder: scripts/fuzz.sh gives them one in the build folder.)
    static const auto* to_remove = new std::filesystem::path(root);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(*to_remove, ec);
    });
  }
  std::filesystem::create_directories(root / "scene");
  // A triangle (positions, then uint32 indices 0 1 2 as bit patterns) that "buffer.bin" URIs may use.
  write_file(root / "scene" / "buffer.bin", {0, 0, 0, 1, 0, 0, 0, 0, -1});
  write_file(root / "outside.bin", {0, 0, 0, 1, 0, 0, 0, 0, -1}); // "../outside.bin" must stay unread
  return std::filesystem::canonical(root / "scene");
}

bool inside(const std::filesystem::path& path, const std::filesystem::path& folder) {
  const std::filesystem::path p = std::filesystem::weakly_canonical(path);
  auto [folder_end, unused] = std::mismatch(folder.begin(), folder.end(), p.begin(), p.end());
  return folder_end == folder.end();
}

void check_scene(const scene::Scene& s, const std::filesystem::path& base) {
  const std::size_t n = s.positions.size();
  for (const auto& t : s.triangles) check(t.x < n && t.y < n && t.z < n, "triangle index out of range");
  for (const auto& p : s.positions)
    check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), "non-finite position");
  check(s.triangle_albedo.size() == s.triangles.size() && s.triangle_emission.size() == s.triangles.size() &&
            s.triangle_material.size() == s.triangles.size(),
        "per-triangle arrays match the triangle count");
  for (std::uint32_t m : s.triangle_material) check(m < s.materials.size(), "triangle material out of range");
  for (const auto& file : s.input_files) check(inside(file, base), "read outside the scene's folder: " + file.string());
}

} // namespace

const std::filesystem::path& fuzz_scratch_folder() {
  static const std::filesystem::path base = make_scratch();
  return base;
}

void fuzz_one_scene_loader(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& base = fuzz_scratch_folder();
  try {
    const scene::Scene s = scene::load_scene_from_memory(std::vector<unsigned char>(data, data + size), "fuzz", base,
                                                         scene::LoadOptions{.max_memory = kMemoryBudget});
    check_scene(s, base);
  } catch (const Error&) {
  }
}

} // namespace probebake::fuzz
