#include "probebake/formats/cell_file.h"

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
  opened.mapping = FileMapping(fd, std::uint64_t(info.st_size), file.name_);
  const ContainerView container = parse_container(opened.mapping.bytes(), file.name_);
  // Only files that can stream keep their tracing in the mapping; a 1.1-1.3 file is upgraded in memory.
  const bool in_place = has_section(container, SectionType::cell_tracing) && !has_section(container, SectionType::bvh_nodes) &&
                        !has_section(container, SectionType::trace_triangles);
  opened.volume = decode_probes(container, file.name_, in_place ? TraceSections::leave_in_bytes : TraceSections::decode);
  if (in_place) opened.in_mapping = tracing_in(container, file.name_);
  else opened.mapping.reset();
  for (const SectionEntry& entry : container.sections) {
    if (!is_known_section_type(entry.type)) continue;
    if (file.sections_.size() <= entry.type) file.sections_.resize(entry.type + 1);
    file.sections_[entry.type] = {entry.offset, entry.size};
  }
  return opened;
}

CellFile::Descriptor::~Descriptor() {
  if (fd_ >= 0) ::close(fd_);
}

void CellFile::expect(const ProbeVolume& validated, const TracingView& tracing) {
  if (validated.cell_tracing.empty() || validated.cell_tracing.size() != validated.cells.size())
    throw Error(ErrorKind::usage, name_ + ": reading cells from disk needs the tracing split by cell (format 1.5 cell_tracing)");
  cells_ = validated.cells;
  tracing_ = validated.cell_tracing;
  checksums_.clear(), bytes_.clear();
  for (std::size_t k = 0; k < cells_.size(); ++k) {
    checksums_.push_back(cell_checksum(validated, tracing, k));
    bytes_.push_back(cell_bytes(validated, k));
  }
}

void CellFile::read_into(void* out, std::uint64_t offset, std::uint64_t size, const std::string& place) const {
  auto* bytes = static_cast<std::uint8_t*>(out);
  std::uint64_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(fd_.get(), bytes + done, std::size_t(size - done), off_t(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw_input_error(name_, place + ": read error: " + errno_text());
    if (n == 0) throw_input_error(name_, place + ": the file ends at byte " + std::to_string(offset + done) + ", " +
                                             std::to_string(size - done) + " bytes early (changed since it was opened?)");
    done += std::uint64_t(n);
  }
}

template <class T, class Hash>
std::vector<T> CellFile::read_range(std::uint32_t type, const CellRange& range, const std::string& place, Hash& hash) const {
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
  if (k >= cells_.size()) throw Error(ErrorKind::internal, name_ + ": read_cell_tracing before expect(), or a cell out of range");
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
    throw_input_error(name_, place + ": its " + std::to_string(bytes_[k]) +
                                 " bytes on disk differ from those validated when the file was opened (changed since?)");
  return data;
}

ProbeVolume CellFile::read_volume() const {
  struct stat info {};
  if (::fstat(fd_.get(), &info) != 0) throw_input_error(name_, "cannot stat: " + errno_text());
  const FileMapping mapping(fd_.get(), std::uint64_t(info.st_size), name_);
  return read_probes(mapping.bytes(), name_);
}

} // namespace probebake::formats
