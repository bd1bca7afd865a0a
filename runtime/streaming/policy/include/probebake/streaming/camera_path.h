// A camera path for streaming runs (`probebake stream-plan --path`, issue #15): a CSV file with the header
// `frame,x,y,z` and one row per frame, frames ascending integers, positions finite, world metres.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace probebake::streaming {

struct PathPoint {
  std::int64_t frame = 0;
  glm::vec3 position{0.0f};
};

// Files larger than this or with more rows are refused before they are read whole.
inline constexpr std::uintmax_t kMaxPathFileBytes = 64u << 20;
inline constexpr std::size_t kMaxPathRows = 1u << 20;

// Parses the CSV text (untrusted). Throws Error(input, "<name>:<line>: <reason>").
std::vector<PathPoint> parse_camera_path(std::string_view text, std::string_view name);
// Reads and parses the file; Error(input) naming the file when it cannot be read or is too large.
std::vector<PathPoint> read_camera_path(const std::filesystem::path& path);

} // namespace probebake::streaming
