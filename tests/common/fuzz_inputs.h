// Replays files through a fuzz entry function in a GoogleTest: every regular file of the given folders
// (missing folders are skipped), each reported with its path when anything escapes the entry function.
#pragma once

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include <gtest/gtest.h>

namespace probebake::fuzz {

inline std::vector<std::filesystem::path> files_in(const std::vector<std::filesystem::path>& folders) {
  std::vector<std::filesystem::path> files;
  for (const auto& folder : folders) {
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Runs `entry` on each file; returns how many ran.
template <class Entry>
std::size_t replay(const std::vector<std::filesystem::path>& files, Entry entry) {
  for (const auto& path : files) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    try {
      entry(bytes.data(), bytes.size());
    } catch (const std::exception& error) {
      ADD_FAILURE() << path.string() << ": " << error.what();
    } catch (...) {
      ADD_FAILURE() << path.string() << ": a non-standard exception";
    }
  }
  return files.size();
}

} // namespace probebake::fuzz
