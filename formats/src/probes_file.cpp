// ProbeVolume <-> .probes bytes (docs/FORMAT.md): one section per non-empty buffer, and atomic file
// writing (temporary file in the target directory, fsync, rename).
#include "probebake/formats/probes_file.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "byte_io.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/format_version.h"
#include "probebake/formats/volume_sections.h"
#include "text.h"

namespace probebake::formats {
namespace {

template <typename T>
void add_section(std::vector<SectionPayload>& sections, SectionType type, std::uint32_t flags,
                 const std::vector<T>& elements) {
  if (elements.empty()) return; // only sections with data are written
  sections.push_back(
      SectionPayload{static_cast<std::uint32_t>(type), flags, sizeof(T), elements.size(), detail::as_bytes(elements)});
}

template <typename T>
void add_single(std::vector<SectionPayload>& sections, SectionType type, const T& value,
                std::uint32_t flags = kSectionRequired) {
  sections.push_back(SectionPayload{static_cast<std::uint32_t>(type), flags, sizeof(T), 1, detail::as_bytes(value)});
}

template <class T>
struct is_vector : std::false_type {};
template <class T>
struct is_vector<std::vector<T>> : std::true_type {};
template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};

std::uint32_t section_flags(SectionType type) {
  return is_required_section_type(static_cast<std::uint32_t>(type)) ? kSectionRequired : 0u;
}

// Every section of the volume with data, in type order (volume_sections.h); the leaf header only with
// leaf entries (docs/FORMAT.md); `cell_checksums` and `global_checksums` in place of the volume's: like the section checksums
// they are taken from the bytes written (a volume edited in memory keeps those it was read with).
std::vector<SectionPayload> sections_of(const ProbeVolume& volume, const std::vector<std::uint64_t>& cell_checksums,
                                        const std::vector<std::uint64_t>& global_checksums) {
  std::vector<SectionPayload> sections;
  for_each_section(volume, [&](SectionType type, const auto& member) {
    using Member = std::decay_t<decltype(member)>;
    if (type == SectionType::cell_checksums)
      add_section(sections, type, section_flags(type), cell_checksums);
    else if (type == SectionType::cell_global_checksums)
      add_section(sections, type, section_flags(type), global_checksums);
    else if constexpr (is_vector<Member>::value)
      add_section(sections, type, section_flags(type), member);
    else if constexpr (is_optional<Member>::value) {
      if (member) add_single(sections, type, *member, section_flags(type));
    } else if (type != SectionType::leaf_queue_header || !volume.leaf_entries.empty()) {
      add_single(sections, type, member, section_flags(type));
    }
  });
  return sections;
}

// The lowest minor version whose section types and flags the file uses: 1.0 files stay byte-identical
// to 1.0, 1.1 files to 1.1.
std::uint16_t minor_version_for(const std::vector<SectionPayload>& sections, const ProbeVolume& volume) {
  std::uint16_t minor = 0;
  for (const SectionPayload& section : sections) {
    minor = std::max(minor, minor_version_for_section(section.type));
  }
  return std::max(minor, minor_version_for_contents(volume));
}

// Decodes one known section into `out`; element size and (for singletons) count are checked here.
class SectionDecoder {
public:
  SectionDecoder(std::string_view name, const SectionEntry& entry, std::span<const std::uint8_t> payload)
      : name_(name), entry_(entry), payload_(payload) {}

  template <typename T>
  std::vector<T> elements() const {
    check_elements<T>();
    return detail::elements_from<T>(payload_);
  }

  // The elements where they lie in the payload (at a multiple of 16 bytes from the start of the bytes:
  // parse_container checks each section's alignment).
  template <typename T>
  std::span<const T> in_place() const {
    check_elements<T>();
    static_assert(std::is_trivially_copyable_v<T> && alignof(T) <= kSectionAlignment);
    if (reinterpret_cast<std::uintptr_t>(payload_.data()) % alignof(T) != 0)
      fail("the bytes are not aligned for reading in place");
    return {reinterpret_cast<const T*>(payload_.data()), payload_.size() / sizeof(T)};
  }

  template <typename T>
  T single() const {
    check_element_size(sizeof(T));
    if (entry_.element_count != 1) fail(detail::concat(entry_.element_count, " elements, expected 1"));
    return detail::value_from<T>(payload_);
  }

private:
  template <typename T>
  void check_elements() const {
    check_element_size(sizeof(T));
    if (entry_.element_count > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max())) {
      fail(detail::concat(entry_.element_count, " elements (indices are int32)"));
    }
  }
  void check_element_size(std::size_t expected) const {
    if (entry_.element_size != expected)
      fail(detail::concat("element size ", entry_.element_size, ", expected ", expected));
  }
  [[noreturn]] void fail(const std::string& reason) const {
    throw Error(ErrorKind::input, detail::concat(name_, ": section '", section_name(entry_.type), "': ", reason));
  }

  std::string_view name_;
  const SectionEntry& entry_;
  std::span<const std::uint8_t> payload_;
};

// An unknown optional section is skipped (parse_container refused unknown required ones).
void decode_section(ProbeVolume& volume, const SectionDecoder& section, std::uint32_t type) {
  for_each_section(volume, [&](SectionType member_type, auto& member) {
    if (static_cast<std::uint32_t>(member_type) != type) return;
    using Member = std::decay_t<decltype(member)>;
    if constexpr (is_vector<Member>::value)
      member = section.elements<typename Member::value_type>();
    else if constexpr (is_optional<Member>::value)
      member = section.single<typename Member::value_type>();
    else
      member = section.single<Member>();
  });
}

std::string errno_text() { return std::strerror(errno); }

} // namespace

std::uint16_t minor_version_for_contents(const ProbeVolume& volume) {
  const auto flagged = [](const auto& element) { return element.flags != 0u; };
  const bool flags = std::any_of(volume.trace_triangles.begin(), volume.trace_triangles.end(), flagged) ||
                     std::any_of(volume.emitter_patches.begin(), volume.emitter_patches.end(), flagged);
  const auto grouped = [](const gpu::EmitterPatch& p) { return p.emitter != 0u || p.material != 0; };
  if (std::any_of(volume.emitter_patches.begin(), volume.emitter_patches.end(), grouped)) return kEmitterGroupsMinor;
  return flags ? kDoubleSidedFlagsMinor : std::uint16_t{0};
}

std::vector<std::uint8_t> write_probes(const ProbeVolume& volume) {
  const std::vector<std::uint64_t> cell_checksums = cell_checksums_of(volume);
  const bool read_as_1_6 = !volume.cell_checksums.empty() && volume.cell_global_checksums.empty();
  const std::vector<std::uint64_t> global_checksums =
      read_as_1_6 ? std::vector<std::uint64_t>{} : cell_global_checksums_of(volume, tracing_view(volume));
  const std::vector<SectionPayload> sections = sections_of(volume, cell_checksums, global_checksums);
  const ContainerHeaderFields fields{static_cast<std::uint32_t>(volume.cell_depth), volume.input_hash,
                                     minor_version_for(sections, volume)};
  return write_container(fields, sections);
}

void write_probes_file(const std::filesystem::path& path, const ProbeVolume& volume) {
  write_file_atomically(path, write_probes(volume));
}

ProbeVolume decode_probes(const ContainerView& container, std::string_view name, TraceSections trace_sections) {
  ProbeVolume volume;
  bool has_info = false;
  for (std::size_t i = 0; i < container.sections.size(); ++i) {
    const SectionEntry& entry = container.sections[i];
    if (trace_sections == TraceSections::leave_in_bytes && is_in_place_trace_section(entry.type)) continue;
    decode_section(volume, SectionDecoder(name, entry, container.payloads[i]), entry.type);
    has_info = has_info || entry.type == static_cast<std::uint32_t>(SectionType::volume_info);
  }
  if (!has_info) throw Error(ErrorKind::input, detail::concat(name, ": section_table: no volume_info section"));
  volume.cell_depth = static_cast<std::int32_t>(std::min<std::uint32_t>(container.header.cell_depth, 1u << 30));
  volume.input_hash = container.header.input_hash;
  return volume;
}

TracingView tracing_in(const ContainerView& container, std::string_view name) {
  TracingView view;
  for (std::size_t i = 0; i < container.sections.size(); ++i) {
    const SectionEntry& entry = container.sections[i];
    const SectionDecoder section(name, entry, container.payloads[i]);
    if (entry.type == static_cast<std::uint32_t>(SectionType::trace_nodes))
      view.nodes = section.in_place<gpu::TraceNode>();
    if (entry.type == static_cast<std::uint32_t>(SectionType::trace_faces))
      view.faces = section.in_place<gpu::TraceFace>();
    if (entry.type == static_cast<std::uint32_t>(SectionType::trace_vertices))
      view.vertices = section.in_place<gpu::TraceVertex>();
  }
  return view;
}

ProbeVolume read_probes(std::span<const std::uint8_t> bytes, std::string_view name_for_errors) {
  return decode_probes(parse_container(bytes, name_for_errors), name_for_errors);
}

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) throw Error(ErrorKind::input, path.string() + ": cannot open: " + errno_text());
  std::vector<std::uint8_t> bytes;
  // A regular file's size up front: one allocation, where growing by doubling held up to three times the file.
  struct stat info {};
  const bool known = ::fstat(::fileno(file), &info) == 0;
  if (known && S_ISDIR(info.st_mode)) {
    std::fclose(file);
    throw Error(ErrorKind::input, path.string() + ": is a directory");
  }
  if (known && S_ISREG(info.st_mode) && info.st_size > 0) bytes.reserve(std::size_t(info.st_size));
  std::uint8_t buffer[1 << 16];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof(buffer), file)) > 0) bytes.insert(bytes.end(), buffer, buffer + n);
  const bool failed = std::ferror(file) != 0;
  std::fclose(file);
  if (failed) throw Error(ErrorKind::input, path.string() + ": read error");
  return bytes;
}

ProbeVolume read_probes_file(const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = read_file_bytes(path);
  return read_probes(bytes, path.string());
}

} // namespace probebake::formats
