// The .probes container (docs/FORMAT.md): header, section table, aligned payloads, XXH3-64 checksums.
// The parser is the untrusted-input boundary: each field is range-checked before it is used, all size
// arithmetic is done in uint64 with overflow-safe comparisons, and nothing is allocated from a field
// that has not been checked against the actual byte count.
#include "probebake/formats/container.h"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <string>

// Header-only xxhash: the runtime links formats and must run where only libvulkan and libstdc++ exist.
#define XXH_INLINE_ALL
#include <xxhash.h>

#include "byte_io.h"
#include "text.h"
#include "probebake/formats/error.h"
#include "probebake/formats/format_version.h"

namespace probebake::formats {
namespace {

constexpr std::uint64_t kHeaderChecksumOffset = offsetof(FileHeader, header_checksum);

bool is_power_of_two(std::uint32_t value) { return value != 0 && (value & (value - 1)) == 0; }

// Header checksum: header bytes before the checksum field, header bytes after it (fields of later minor
// versions), then the section table.
std::uint64_t header_checksum(std::span<const std::uint8_t> header, std::span<const std::uint8_t> table) {
  std::vector<std::uint8_t> covered(header.begin(), header.begin() + kHeaderChecksumOffset);
  covered.insert(covered.end(), header.begin() + sizeof(FileHeader), header.end());
  covered.insert(covered.end(), table.begin(), table.end());
  return checksum64(covered);
}

class ContainerParser {
public:
  ContainerParser(std::span<const std::uint8_t> bytes, std::string_view name, const ChecksumMismatch& on_mismatch,
                  const ContainerKind& kind, std::span<const SectionType> unread = {})
      : bytes_(bytes), name_(name), on_mismatch_(on_mismatch), kind_(kind), unread_(unread) {}

  ContainerView parse() {
    check_magic_and_header();
    check_table_bounds();
    for (std::uint32_t i = 0; i < view_.header.section_count; ++i) check_entry(i);
    check_padding();
    check_checksums();
    return std::move(view_);
  }

private:
  [[noreturn]] void fail(const std::string& place, const std::string& reason) const {
    throw Error(ErrorKind::input, detail::concat(name_, ": ", place, ": ", reason));
  }

  void check_magic_and_header() {
    if (bytes_.size() < sizeof(kind_.magic) || std::memcmp(bytes_.data(), kind_.magic, sizeof(kind_.magic)) != 0) {
      fail("header", detail::concat("not ", kind_.description, " (bad magic)"));
    }
    if (bytes_.size() < sizeof(FileHeader)) {
      fail("header",
           detail::concat("truncated: ", bytes_.size(), " bytes, the header alone needs ", sizeof(FileHeader)));
    }
    FileHeader& h = view_.header;
    h = detail::value_from<FileHeader>(bytes_);
    if (h.version_major != kFormatVersionMajor) {
      fail("header", detail::concat("unsupported format version ", h.version_major, ".", h.version_minor,
                                    " (this reader reads ", kFormatVersionMajor, ".x)"));
    }
    if (h.header_size < sizeof(FileHeader) || h.header_size % 8 != 0 || h.header_size > bytes_.size()) {
      fail("header", detail::concat("bad header size ", h.header_size));
    }
    if ((h.required_features & ~kKnownRequiredFeatures) != 0) {
      fail("header", "unknown required feature bits 0x" + detail::hex64(h.required_features & ~kKnownRequiredFeatures));
    }
    if (h.file_size != bytes_.size()) {
      fail("header", detail::concat("file size ", bytes_.size(), " but the header says ", h.file_size,
                                    " (truncated or extended)"));
    }
    if (h.reserved != 0) fail("header", "reserved field is not zero");
    if (h.section_entry_size < sizeof(SectionEntry) || h.section_entry_size % 8 != 0 || h.section_entry_size > 1024) {
      fail("header", detail::concat("bad section entry size ", h.section_entry_size));
    }
    if (h.section_count > kMaxSections)
      fail("header", detail::concat(h.section_count, " sections (at most ", kMaxSections, ")"));
  }

  void check_table_bounds() {
    const FileHeader& h = view_.header;
    table_end_ = std::uint64_t{h.header_size} + std::uint64_t{h.section_count} * h.section_entry_size;
    if (table_end_ > bytes_.size()) fail("section_table", "extends past the end of the file");
    previous_end_ = table_end_;
    view_.sections.reserve(h.section_count);
    view_.payloads.reserve(h.section_count);
  }

  void check_entry(std::uint32_t index) {
    const std::uint64_t at = view_.header.header_size + std::uint64_t{index} * view_.header.section_entry_size;
    const SectionEntry entry = detail::value_from<SectionEntry>(bytes_.subspan(at, sizeof(SectionEntry)));
    const std::string place = detail::concat("section_table[", index, "] (", kind_.section_name(entry.type), ")");
    if (!kind_.is_known_section_type(entry.type) && (entry.flags & kSectionRequired) != 0) {
      fail(place, "unknown required section (written by a newer probebake?)");
    }
    if (!is_power_of_two(entry.alignment) || entry.alignment < kSectionAlignment ||
        entry.alignment > kMaxSectionAlignment) {
      fail(place, detail::concat("bad alignment ", entry.alignment));
    }
    if (entry.offset % entry.alignment != 0)
      fail(place, detail::concat("offset ", entry.offset, " not aligned to ", entry.alignment));
    if (entry.offset < previous_end_)
      fail(place, "overlaps the table or the previous section (sections must be in file order)");
    if (entry.offset > bytes_.size() || entry.size > bytes_.size() - entry.offset)
      fail(place, "extends past the end of the file");
    if (entry.element_size == 0 || entry.size % entry.element_size != 0 ||
        entry.size / entry.element_size != entry.element_count) {
      fail(place, detail::concat("size ", entry.size, " is not element size ", entry.element_size, " x count ",
                                 entry.element_count));
    }
    for (const SectionEntry& earlier : view_.sections) {
      if (earlier.type == entry.type) fail(place, "duplicate section type");
    }
    previous_end_ = entry.offset + entry.size;
    view_.sections.push_back(entry);
    view_.payloads.push_back(bytes_.subspan(entry.offset, entry.size));
  }

  // Bytes between the table and the payloads and after the last payload must be zero, so that every
  // byte of a file is covered by a checksum or by a check.
  void check_padding() {
    std::uint64_t cursor = table_end_;
    auto check_zero = [&](std::uint64_t from, std::uint64_t to, const char* where) {
      for (std::uint64_t at = from; at < to; ++at) {
        if (bytes_[at] != 0) fail("padding", detail::concat("byte ", at, " ", where, " is not zero"));
      }
    };
    for (const SectionEntry& entry : view_.sections) {
      check_zero(cursor, entry.offset, "between sections");
      cursor = entry.offset + entry.size;
    }
    // Zero bytes here are read (validate reports them as trailing_bytes); others could hide data.
    check_zero(cursor, bytes_.size(), "after the last payload");
  }

  void check_checksums() {
    const std::uint64_t expected =
        header_checksum(bytes_.first(view_.header.header_size),
                        bytes_.subspan(view_.header.header_size, table_end_ - view_.header.header_size));
    if (expected != view_.header.header_checksum) {
      mismatch("header", -1,
               "header checksum " + detail::hex64(view_.header.header_checksum) + ", computed " +
                   detail::hex64(expected));
    }
    for (std::size_t i = 0; i < view_.sections.size(); ++i) {
      if (std::find(unread_.begin(), unread_.end(), static_cast<SectionType>(view_.sections[i].type)) != unread_.end())
        continue;
      const std::uint64_t computed = checksum64(view_.payloads[i]);
      if (computed != view_.sections[i].checksum) {
        mismatch(kind_.section_name(view_.sections[i].type), static_cast<long long>(i),
                 detail::concat("checksum ", detail::hex64(view_.sections[i].checksum), ", computed ",
                                detail::hex64(computed), " (section table entry ", i, ")"));
      }
    }
  }

  void mismatch(const std::string& section, long long index, const std::string& message) {
    if (!on_mismatch_) fail(section, message);
    on_mismatch_(section, index, message);
  }

  std::span<const std::uint8_t> bytes_;
  std::string_view name_;
  const ChecksumMismatch& on_mismatch_;
  const ContainerKind& kind_;
  std::span<const SectionType> unread_;
  ContainerView view_;
  std::uint64_t table_end_ = 0;
  std::uint64_t previous_end_ = 0;
};

} // namespace

std::string section_name(std::uint32_t type) {
  static constexpr const char* kNames[] = {"volume_info",
                                           "octree",
                                           "probes",
                                           "surfel_batches",
                                           "leaf_queue_header",
                                           "leaf_entries",
                                           "probe_index",
                                           "svo_nodes",
                                           "svo_leaves",
                                           "cells",
                                           "lighting_info",
                                           "ray_directions",
                                           "bvh_nodes",
                                           "trace_triangles",
                                           "punctual_lights",
                                           "emitter_patches",
                                           "dynamic_objects",
                                           "trace_trees",
                                           "trace_nodes",
                                           "trace_faces",
                                           "trace_vertices",
                                           "trace_materials",
                                           "cell_tracing",
                                           "cell_checksums",
                                           "cell_global_checksums",
                                           "grid_lattice",
                                           "sky"};
  static_assert(std::size(kNames) == kSectionTypeCount);
  if (is_known_section_type(type)) return kNames[type - 1];
  return "section_" + std::to_string(type);
}

ContainerView parse_container_without(std::span<const std::uint8_t> bytes, std::string_view name,
                                      std::span<const SectionType> unread) {
  return ContainerParser(bytes, name, {}, kProbesContainer, unread).parse();
}

std::uint64_t checksum64(std::span<const std::uint8_t> bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

bool has_section(const ContainerView& container, SectionType type) {
  return std::any_of(container.sections.begin(), container.sections.end(),
                     [&](const SectionEntry& entry) { return entry.type == static_cast<std::uint32_t>(type); });
}

std::vector<std::uint8_t> write_container(const ContainerHeaderFields& fields, std::span<const SectionPayload> sections,
                                          const ContainerKind& kind) {
  FileHeader header{};
  std::memcpy(header.magic, kind.magic, sizeof(kind.magic));
  header.version_major = kFormatVersionMajor;
  header.version_minor = fields.version_minor;
  header.header_size = sizeof(FileHeader);
  header.section_count = static_cast<std::uint32_t>(sections.size());
  header.section_entry_size = sizeof(SectionEntry);
  header.cell_depth = fields.cell_depth;
  header.input_hash = fields.input_hash;

  std::vector<SectionEntry> table;
  std::uint64_t cursor = sizeof(FileHeader) + sections.size() * sizeof(SectionEntry);
  for (const SectionPayload& section : sections) {
    if (section.element_size == 0 || section.bytes.size() != section.element_size * section.element_count) {
      throw Error(ErrorKind::internal,
                  "write_container: " + kind.section_name(section.type) + ": size disagrees with element count");
    }
    SectionEntry entry{};
    entry.type = section.type;
    entry.flags = section.flags;
    entry.offset = detail::align_up(cursor, kSectionAlignment);
    entry.size = section.bytes.size();
    entry.alignment = kSectionAlignment;
    entry.element_size = section.element_size;
    entry.element_count = section.element_count;
    entry.checksum = checksum64(section.bytes);
    table.push_back(entry);
    cursor = entry.offset + entry.size;
  }
  header.file_size = cursor;

  std::vector<std::uint8_t> bytes(cursor, 0);
  std::memcpy(bytes.data() + sizeof(FileHeader), table.data(), table.size() * sizeof(SectionEntry));
  for (std::size_t i = 0; i < sections.size(); ++i) {
    if (!sections[i].bytes.empty())
      std::memcpy(bytes.data() + table[i].offset, sections[i].bytes.data(), sections[i].bytes.size());
  }
  header.header_checksum = header_checksum(
      detail::as_bytes(header), std::span(bytes).subspan(sizeof(FileHeader), table.size() * sizeof(SectionEntry)));
  std::memcpy(bytes.data(), &header, sizeof(FileHeader));
  return bytes;
}

ContainerView parse_container(std::span<const std::uint8_t> bytes, std::string_view name,
                              const ChecksumMismatch& on_checksum_mismatch, const ContainerKind& kind) {
  return ContainerParser(bytes, name, on_checksum_mismatch, kind).parse();
}

} // namespace probebake::formats
