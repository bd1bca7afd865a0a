// Shared by atomic_file_test.cpp and atomic_write_helper.cpp: the bytes the helper writes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace probebake::test {

inline std::vector<std::uint8_t> helper_bytes(std::size_t size, unsigned seed) {
  std::vector<std::uint8_t> bytes(size);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = static_cast<std::uint8_t>(i * 131u + seed * 7u + (i >> 12));
  return bytes;
}

} // namespace probebake::test
