// Byte-level helpers for the container tests: patch header fields and refresh checksums so that a test
// can produce a file that is wrong in exactly one way.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
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
  covered.insert(covered.end(), bytes.begin() + sizeof(FileHeader),
                 bytes.begin() + static_cast<std::ptrdiff_t>(table_end));
  header.header_checksum = checksum64(covered);
  put_header(bytes, header);
}

// The file's sections, written again by write_container after `edit` changed their list; the header
// fields (cell depth, input hash, minor version) are kept.
inline std::vector<std::uint8_t> rewrite_sections(const std::vector<std::uint8_t>& bytes,
                                                  const std::function<void(std::vector<SectionPayload>&)>& edit) {
  const ContainerView view = parse_container(bytes, "rewrite");
  std::vector<SectionPayload> sections;
  for (std::size_t i = 0; i < view.sections.size(); ++i) {
    const SectionEntry& e = view.sections[i];
    sections.push_back(SectionPayload{e.type, e.flags, e.element_size, e.element_count, view.payloads[i]});
  }
  edit(sections);
  return write_container(
      ContainerHeaderFields{view.header.cell_depth, view.header.input_hash, view.header.version_minor}, sections);
}

// Inserts `count` zero bytes at byte `at` (at or after the header), moves the payloads behind it and
// grows file_size; the caller refreshes the header checksum after any further header change.
inline void insert_zeros(std::vector<std::uint8_t>& bytes, std::size_t at, std::size_t count) {
  FileHeader header = header_of(bytes);
  const std::size_t table = header.header_size;
  bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(at), count, std::uint8_t{0});
  const std::size_t table_now = at <= table ? table + count : table;
  for (std::uint32_t i = 0; i < header.section_count; ++i) {
    SectionEntry entry;
    std::uint8_t* place = bytes.data() + table_now + std::size_t{i} * header.section_entry_size;
    std::memcpy(&entry, place, sizeof(entry));
    if (entry.offset >= at) entry.offset += count;
    std::memcpy(place, &entry, sizeof(entry));
  }
  header.file_size += count;
  put_header(bytes, header);
}

inline std::filesystem::path golden_path(const char* name) {
  return std::filesystem::path(PROBEBAKE_TEST_DATA) / "golden" / name;
}

} // namespace probebake::formats::testing
