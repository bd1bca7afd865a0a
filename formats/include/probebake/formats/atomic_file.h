// Atomic file output for every file probebake writes: the bytes go to a temporary file in the target's
// folder, are flushed to disk (fsync), and the temporary file is renamed over the target, so a reader
// never sees a half-written file. On failure the temporary file is removed and Error(output) thrown with
// "<path>: cannot write: <reason>".
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

namespace probebake {

void write_file_atomically(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

} // namespace probebake
