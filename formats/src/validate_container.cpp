// Validator phase for the container (docs/FORMAT.md sections 1-4 and 7): what read_probes accepts,
// because it is harmless to read or needed for forward compatibility, but a file of this format must not
// hold: a minor version below what its sections and flags need, a header or table entries longer than a known
// minor defines, REQUIRED flags that differ from the section type table, slack between payloads, empty
// sections, zero bytes after the last payload, and a leaf queue header without its entries (or back).
// The reader has already checked bounds, order, padding and sizes, so this phase only compares numbers.
#include <algorithm>

#include "probebake/formats/format_version.h"
#include "probebake/formats/probes_file.h"
#include "byte_io.h"
#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

// Sections of the 1.0 model (1-9) are REQUIRED; cells and the 1.1 lighting sections are optional, so that
// a reader without them still reads the file.
std::uint32_t expected_flags(std::uint32_t type) { return is_required_section_type(type) ? kSectionRequired : 0u; }

// Section types (1.1: lighting sections) and flag bits in their elements (1.2: double-sided).
std::uint16_t minor_needed(const ContainerView& container, const ProbeVolume& volume) {
  std::uint16_t minor = 0;
  for (const SectionEntry& entry : container.sections) {
    minor = std::max(minor, minor_version_for_section(entry.type));
  }
  return std::max(minor, minor_version_for_contents(volume));
}

void check_version(const ContainerView& container, const ProbeVolume& volume, Reporter& out) {
  const FileHeader& header = container.header;
  const std::uint16_t needed = minor_needed(container, volume);
  if (header.version_minor < needed) {
    out.add("format_version", "header", -1,
            concat("version ", header.version_major, ".", header.version_minor, " but its sections and flags need ",
                   header.version_major, ".", needed));
  }
  // Later minors may append header fields and grow table entries; the minors known here did neither,
  // so longer ones would hold bytes that no version defines.
  if (header.version_minor <= kFormatVersionMinor &&
      (header.header_size != sizeof(FileHeader) || header.section_entry_size != sizeof(SectionEntry))) {
    out.add("format_version", "header", -1,
            concat("header size ", header.header_size, " and entry size ", header.section_entry_size, " in a ",
                   header.version_major, ".", header.version_minor, " file (", sizeof(FileHeader), " and ",
                   sizeof(SectionEntry), " in this version)"));
  }
}

void check_flags(const ContainerView& container, Reporter& out) {
  for (std::size_t i = 0; i < container.sections.size(); ++i) {
    const SectionEntry& entry = container.sections[i];
    const long long index = static_cast<long long>(i);
    const std::string name = section_name(entry.type);
    if ((entry.flags & ~kKnownSectionFlags) != 0) {
      out.add("section_flags", "section_table", index, concat(name, ": flags ", entry.flags, " set reserved bits"));
    } else if (is_known_section_type(entry.type) && (entry.flags & kSectionRequired) != expected_flags(entry.type)) {
      out.add("section_flags", "section_table", index,
              expected_flags(entry.type) != 0
                  ? concat(name, " is not marked REQUIRED")
                  : concat(name, " is marked REQUIRED (readers without it would refuse the file)"));
    }
  }
}

// Payloads are packed in table order: each at the first multiple of its alignment after the table or the
// previous payload, and the file ends with the last payload. The reader checked that the slack is zero.
void check_layout(const ContainerView& container, Reporter& out) {
  const FileHeader& header = container.header;
  std::uint64_t cursor = header.header_size + std::uint64_t{header.section_count} * header.section_entry_size;
  for (std::size_t i = 0; i < container.sections.size(); ++i) {
    const SectionEntry& entry = container.sections[i];
    const long long index = static_cast<long long>(i);
    if (is_known_section_type(entry.type) && entry.element_count == 0) {
      out.add("section_layout", "section_table", index,
              concat(section_name(entry.type), " has no elements (an empty buffer has no section)"));
    }
    const std::uint64_t packed = align_up(cursor, entry.alignment);
    if (entry.offset != packed) {
      out.add("section_layout", "section_table", index,
              concat(section_name(entry.type), " starts at ", entry.offset, ", not at ", packed,
                     " (the first multiple of its alignment ", entry.alignment, " after the previous payload)"));
    }
    cursor = entry.offset + entry.size;
  }
  if (header.file_size > cursor) {
    out.add("trailing_bytes", "container", -1,
            concat(header.file_size - cursor, " bytes after the last payload (it ends at byte ", cursor,
                   ", the file at ", header.file_size, ")"));
  }
}

// The leaf queue header is a single element, so its absence is not an empty buffer: only the table shows
// it. The other dependencies are between buffers and checked on the volume (check_dependencies).
void check_presence(const ContainerView& container, Reporter& out) {
  const bool header = has_section(container, SectionType::leaf_queue_header);
  const bool entries = has_section(container, SectionType::leaf_entries);
  if (header && !entries)
    out.add("section_dependency", "leaf_queue_header", -1, "a leaf_queue_header section without leaf_entries");
  if (entries && !header)
    out.add("section_dependency", "leaf_entries", -1, "a leaf_entries section without leaf_queue_header");
}

} // namespace

void check_container(const ContainerView& container, const ProbeVolume& volume, Reporter& out) {
  check_version(container, volume, out);
  check_flags(container, out);
  check_layout(container, out);
  check_presence(container, out);
}

} // namespace probebake::formats::detail
