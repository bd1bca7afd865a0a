#include "probebake/formats/cell_file.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "probebake/formats/cells.h"
#include "probebake/formats/container.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"

// Header-only, as in container.cpp: the runtime links formats.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace probebake::formats {
namespace {

template <class T>
std::vector<T> slice(const std::vector<T>& section, const CellRange& range) {
  if (std::uint64_t(range.first) + range.count > section.size())
    throw Error(ErrorKind::internal, "cell_tracing_data: a range outside its section");
  return {section.begin() + range.first, section.begin() + range.first + range.count};
}

std::string errno_text() { return std::strerror(errno); }

using ByteRanges = std::vector<std::pair<std::uint64_t, std::uint64_t>>; // [begin, end)

// The payload ranges of the three trace sections as the raw table gives them (unchecked, clamped to the
// file), and whether it lists cell_global_checksums. The table lies inside `table_bytes`.
std::pair<ByteRanges, bool> trace_payloads(std::span<const std::uint8_t> table_bytes, const FileHeader& header,
                                           std::uint64_t size) {
  ByteRanges ranges;
  bool global = false;
  for (std::uint32_t i = 0; i < header.section_count; ++i) {
    SectionEntry entry;
    std::memcpy(&entry, table_bytes.data() + header.header_size + std::uint64_t(i) * header.section_entry_size,
                sizeof(entry));
    global = global || entry.type == static_cast<std::uint32_t>(SectionType::cell_global_checksums);
    if (!is_in_place_trace_section(entry.type)) continue;
    const std::uint64_t begin = std::min(entry.offset, size);
    ranges.emplace_back(begin, begin + std::min(entry.size, size - begin));
  }
  return std::pair{ranges, global};
}

// The file bytes of every cell's range of the trace section `entry` (clamped to the section).
ByteRanges cell_byte_ranges(const SectionEntry& entry, const std::vector<CellTracing>& cells) {
  ByteRanges ranges;
  for (const CellTracing& t : cells) {
    const CellRange& r = entry.type == static_cast<std::uint32_t>(SectionType::trace_nodes)   ? t.trace_nodes
                         : entry.type == static_cast<std::uint32_t>(SectionType::trace_faces) ? t.trace_faces
                                                                                              : t.trace_vertices;
    const std::uint64_t from = std::uint64_t(r.first) * entry.element_size,
                        bytes = std::uint64_t(r.count) * entry.element_size;
    ranges.emplace_back(entry.offset + std::min(from, entry.size), entry.offset + std::min(from + bytes, entry.size));
  }
  return ranges;
}

// The global part against the file's cell_global_checksums. Throws Error(input, "<name>: ...").
void check_global_checksums(const std::string& name, const ProbeVolume& volume, const TracingView& tracing) {
  std::vector<std::uint64_t> computed;
  try {
    computed = cell_global_checksums_of(volume, tracing);
  } catch (const Error&) {
    throw_input_error(name, "cells: the cells' ranges do not ascend inside their sections");
  }
  if (volume.cell_global_checksums.size() != computed.size())
    throw_input_error(name, "cell_global_checksums: " + std::to_string(volume.cell_global_checksums.size()) +
                                " checksums, expected " + std::to_string(computed.size()));
  for (std::size_t s = 0; s < computed.size(); ++s)
    if (computed[s] != volume.cell_global_checksums[s])
      throw_input_error(name, "cell_global_checksums[" + std::to_string(s) + "]: the bytes of " +
                                  section_name(static_cast<std::uint32_t>(kCellSplitSections[s])) +
                                  " outside the cells differ from their checksum");
}

} // namespace

CellTracingData cell_tracing_data(const ProbeVolume& volume, std::size_t k) {
  const CellTracing& t = volume.cell_tracing.at(k);
  return {slice(volume.trace_nodes, t.trace_nodes), slice(volume.trace_faces, t.trace_faces),
          slice(volume.trace_vertices, t.trace_vertices)};
}

OpenedCellFile CellFile::open(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw_input_error(path.string(), "cannot open: " + errno_text());
  OpenedCellFile opened{CellFile(fd, path.string()), {}, {}, {}}; // closes the descriptor on every throw below
  CellFile& file = opened.file;
  struct stat info {};
  if (::fstat(fd, &info) != 0) throw_input_error(file.name_, "cannot stat: " + errno_text());
  if (!S_ISREG(info.st_mode)) throw_input_error(file.name_, "not a regular file");
  if (file.read_global_part(opened, std::uint64_t(info.st_size))) return opened;
  opened.mapping = FileMapping(fd, std::uint64_t(info.st_size), file.name_);
  opened.bytes_read = std::uint64_t(info.st_size);
  const ContainerView container = parse_container(opened.mapping.bytes(), file.name_);
  // Only files that can stream keep their tracing in the mapping; a 1.1-1.3 file is upgraded in memory.
  const bool in_place = has_section(container, SectionType::cell_tracing) &&
                        !has_section(container, SectionType::bvh_nodes) &&
                        !has_section(container, SectionType::trace_triangles);
  opened.volume =
      decode_probes(container, file.name_, in_place ? TraceSections::leave_in_bytes : TraceSections::decode);
  if (in_place)
    opened.in_mapping = tracing_in(container, file.name_);
  else
    opened.mapping.reset();
  file.keep_sections(container);
  return opened;
}

void CellFile::keep_sections(const ContainerView& container) {
  for (const SectionEntry& entry : container.sections) {
    if (!is_known_section_type(entry.type)) continue;
    if (sections_.size() <= entry.type) sections_.resize(entry.type + 1);
    sections_[entry.type] = {entry.offset, entry.size};
  }
}

// [begin, end) of the file into the image, but the `skipped` ranges.
void CellFile::read_global_ranges(std::span<std::uint8_t> image, std::uint64_t begin, std::uint64_t end,
                                  ByteRanges skipped, std::uint64_t& bytes_read) const {
  std::sort(skipped.begin(), skipped.end());
  std::uint64_t cursor = begin;
  const auto read_to = [&](std::uint64_t to) {
    if (to > cursor) read_into(image.data() + cursor, cursor, to - cursor, "global part"), bytes_read += to - cursor;
  };
  for (const auto& [from, to] : skipped) {
    read_to(std::min(from, end));
    cursor = std::max(cursor, std::min(to, end));
  }
  read_to(end);
}

bool CellFile::read_global_part(OpenedCellFile& opened, std::uint64_t size) {
  FileHeader header{};
  if (size < sizeof(header)) return false;
  read_into(&header, 0, sizeof(header), "header");
  const std::uint64_t table_end =
      std::uint64_t(header.header_size) + std::uint64_t(header.section_count) * header.section_entry_size;
  if (header.header_size < sizeof(FileHeader) || header.section_entry_size < sizeof(SectionEntry) ||
      header.section_entry_size > 1024 || header.section_count > kMaxSections || table_end > size)
    return false; // the whole read's parse_container says what is wrong
  std::vector<std::uint8_t> table(table_end);
  read_into(table.data(), 0, table_end, "section_table");
  const auto [payloads, has_global_checksums] = trace_payloads(table, header, size);
  if (!has_global_checksums) return false;
  // Everything but the trace sections' payloads (header, table, padding, other sections), checked; then the
  // global part of those three, which the cells' ranges (now checked) leave.
  FileMapping image = FileMapping::anonymous(size, name_);
  std::uint64_t bytes_read = 0;
  read_global_ranges(image.writable(), 0, size, payloads, bytes_read);
  const ContainerView container = parse_container_without(image.bytes(), name_, kInPlaceTraceSections);
  ProbeVolume volume = decode_probes(container, name_, TraceSections::leave_in_bytes);
  if (volume.cell_tracing.empty()) throw_input_error(name_, "cell_global_checksums: the file has no cell_tracing");
  for (const SectionEntry& entry : container.sections)
    if (is_in_place_trace_section(entry.type))
      read_global_ranges(image.writable(), entry.offset, entry.offset + entry.size,
                         cell_byte_ranges(entry, volume.cell_tracing), bytes_read);
  const TracingView view = tracing_in(container, name_);
  check_global_checksums(name_, volume, view);
  keep_sections(container);
  opened.volume = std::move(volume);
  opened.mapping = std::move(image);
  opened.in_mapping = view;
  opened.cells_unread = true;
  opened.bytes_read = bytes_read;
  return true;
}

CellFile::Descriptor::~Descriptor() {
  if (fd_ >= 0) ::close(fd_);
}

void CellFile::keep_ranges(const ProbeVolume& volume) {
  if (volume.cell_tracing.empty() || volume.cell_tracing.size() != volume.cells.size())
    throw Error(ErrorKind::usage,
                name_ + ": reading cells from disk needs the tracing split by cell (format 1.5 cell_tracing)");
  cells_ = volume.cells;
  tracing_ = volume.cell_tracing;
  bytes_.clear();
  for (std::size_t k = 0; k < cells_.size(); ++k) bytes_.push_back(cell_bytes(volume, k));
}

void CellFile::expect(const ProbeVolume& validated, const TracingView& tracing) {
  keep_ranges(validated);
  checksums_.clear(), stored_checksums_ = false, entries_.clear();
  for (std::size_t k = 0; k < cells_.size(); ++k) checksums_.push_back(cell_checksum(validated, tracing, k));
}

void CellFile::expect_unread(const ProbeVolume& volume, std::vector<CellEntry> entries) {
  keep_ranges(volume);
  if (volume.cell_checksums.size() != cells_.size()) throw_input_error(name_, "cell_checksums: not one per cell");
  checksums_ = volume.cell_checksums;
  stored_checksums_ = true;
  entries_ = std::move(entries);
  cell_context_ = {};
  cell_context_.info = volume.info;
  cell_context_.cell_depth = volume.cell_depth;
  cell_context_.cells = volume.cells;
  cell_context_.cell_tracing = volume.cell_tracing;
  cell_context_.trace_trees = volume.trace_trees;
  cell_context_.trace_materials = volume.trace_materials;
}

void CellFile::read_into(void* out, std::uint64_t offset, std::uint64_t size, const std::string& place) const {
  auto* bytes = static_cast<std::uint8_t*>(out);
  std::uint64_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(fd_.get(), bytes + done, std::size_t(size - done), off_t(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw_input_error(name_, place + ": read error: " + errno_text());
    if (n == 0)
      throw_input_error(name_, place + ": the file ends at byte " + std::to_string(offset + done) + ", " +
                                   std::to_string(size - done) + " bytes early (changed since it was opened?)");
    done += std::uint64_t(n);
  }
}

template <class T, class Hash>
std::vector<T> CellFile::read_range(std::uint32_t type, const CellRange& range, const std::string& place,
                                    Hash& hash) const {
  std::vector<T> out(range.count);
  if (range.count == 0) return out;
  const std::uint64_t bytes = std::uint64_t(range.count) * sizeof(T), start = std::uint64_t(range.first) * sizeof(T);
  if (type >= sections_.size() || start + bytes > sections_[type].size) // the ranges were validated against this file
    throw Error(ErrorKind::internal, name_ + ": " + place + ": a range outside its section");
  read_into(out.data(), sections_[type].offset + start, bytes, place);
  XXH3_64bits_update(&hash, out.data(), std::size_t(bytes));
  return out;
}

CellTracingData CellFile::read_cell_tracing(std::size_t k) const {
  if (k >= cells_.size())
    throw Error(ErrorKind::internal, name_ + ": read_cell_tracing before expect(), or a cell out of range");
  const std::string place = "cells[" + std::to_string(k) + "] (cell " + std::to_string(cells_[k].cell_index) + ")";
  const Cell& cell = cells_[k];
  const CellTracing& t = tracing_[k];
  const auto type = [](SectionType section) { return static_cast<std::uint32_t>(section); };
  // Straight into the vectors returned, hashed as read, in cell_checksum's order.
  XXH3_state_t hash;
  XXH3_64bits_reset(&hash);
  read_range<gpu::Probe>(type(SectionType::probes), cell.probes, place, hash);
  read_range<gpu::SurfelBatch>(type(SectionType::surfel_batches), cell.surfel_batches, place, hash);
  read_range<gpu::SvoLeaf>(type(SectionType::svo_leaves), cell.svo_leaves, place, hash);
  CellTracingData data;
  data.nodes = read_range<gpu::TraceNode>(type(SectionType::trace_nodes), t.trace_nodes, place, hash);
  data.faces = read_range<gpu::TraceFace>(type(SectionType::trace_faces), t.trace_faces, place, hash);
  data.vertices = read_range<gpu::TraceVertex>(type(SectionType::trace_vertices), t.trace_vertices, place, hash);
  if (XXH3_64bits_digest(&hash) != checksums_[k])
    throw_input_error(
        name_, place + ": its " + std::to_string(bytes_[k]) +
                   (stored_checksums_
                        ? " bytes on disk differ from their checksum"
                        : " bytes on disk differ from those validated when the file was opened (changed since?)"));
  if (!entries_.empty()) {
    const ValidationReport report =
        validate_cell_tracing(cell_context_, entries_, k, {data.nodes, data.faces, data.vertices});
    if (!report.valid()) throw_input_error(name_, place + ": " + format_violation(report.violations.front()));
  }
  return data;
}

ProbeVolume CellFile::read_volume() const {
  struct stat info {};
  if (::fstat(fd_.get(), &info) != 0) throw_input_error(name_, "cannot stat: " + errno_text());
  const FileMapping mapping(fd_.get(), std::uint64_t(info.st_size), name_);
  return read_probes(mapping.bytes(), name_);
}

} // namespace probebake::formats
