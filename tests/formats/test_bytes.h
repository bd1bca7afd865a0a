// Byte-level helpers for the container tests: patch header fields and refresh checksums so that a test
// can produce a file that is wrong in exactly one way.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <vector>

#include "probebake/formats/container.h"
#include "probebake/formats/probes_file.h"

namespace probebake::formats::testing {

inline FileHeader header_of(const std::vector<std::uint8_t>& bytes) {
  FileHeader header;
  std::memcpy(&header, bytes.data(), sizeof(header));
  return header;
}

inline void put_header(std::vector<std::uint8_t>& bytes, const FileHeader& header) {
  std::memcpy(bytes.data(), &header, sizeof(header));
}

// Recomputes the header checksum (header bytes except the checksum field, then the section table).
inline void refresh_header_checksum(std::vector<std::uint8_t>& bytes) {
  FileHeader header = header_of(bytes);
  const std::size_t table_end = header.header_size + std::size_t{header.section_count} * header.section_entry_size;
  std::vector<std::uint8_t> covered(bytes.begin(), bytes.begin() + offsetof(FileHeader, header_checksum));
  covered.insert(covered.end(), bytes.begin() + sizeof(FileHeader), bytes.begin() + static_cast<std::ptrdiff_t>(table_end));
  header.header_checksum = checksum64(covered);
  put_header(bytes, header);
}

inline std::filesystem::path golden_path(const char* name) {
  return std::filesystem::path(PROBEBAKE_TEST_DATA) / "golden" / name;
}

} // namespace probebake::formats::testing
