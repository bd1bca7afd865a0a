#include "probebake/formats/cell_file.h"

#include <cerrno>
#include <cstring>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "probebake/formats/cells.h"
#include "probebake/formats/container.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"

namespace probebake::formats {
namespace {

template <class T>
std::vector<T> slice(const std::vector<T>& section, const CellRange& range) {
  if (std::uint64_t(range.first) + range.count > section.size())
    throw Error(ErrorKind::internal, "cell_tracing_data: a range outside its section");
  return {section.begin() + range.first, section.begin() + range.first + range.count};
}

template <class T>
std::vector<T> elements_of(const std::vector<std::uint8_t>& bytes, std::size_t from, std::uint32_t count) {
  std::vector<T> out(count);
  if (count > 0) std::memcpy(out.data(), bytes.data() + from, std::size_t(count) * sizeof(T));
  return out;
}

std::string errno_text() { return std::strerror(errno); }

} // namespace

CellTracingData cell_tracing_data(const ProbeVolume& volume, std::size_t k) {
  const CellTracing& t = volume.cell_tracing.at(k);
  return {slice(volume.trace_nodes, t.trace_nodes), slice(volume.trace_faces, t.trace_faces),
          slice(volume.trace_vertices, t.trace_vertices)};
}

CellFile CellFile::open(const std::filesystem::path& path, ProbeVolume& volume) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw_input_error(path.string(), "cannot open: " + errno_text());
  CellFile file(fd, path.string()); // closes the descriptor on every throw below
  struct stat info {};
  if (::fstat(fd, &info) != 0) throw_input_error(file.name_, "cannot stat: " + errno_text());
  if (!S_ISREG(info.st_mode)) throw_input_error(file.name_, "not a regular file");
  const std::vector<std::uint8_t> bytes = file.read_bytes(0, std::uint64_t(info.st_size), "file");
  const ContainerView container = parse_container(bytes, file.name_);
  volume = decode_probes(container, file.name_);
  for (const SectionEntry& entry : container.sections) {
    if (!is_known_section_type(entry.type)) continue;
    if (file.sections_.size() <= entry.type) file.sections_.resize(entry.type + 1);
    file.sections_[entry.type] = {entry.offset, entry.size};
  }
  return file;
}

CellFile::CellFile(CellFile&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), name_(std::move(other.name_)), sections_(std::move(other.sections_)),
      cells_(std::move(other.cells_)), tracing_(std::move(other.tracing_)), checksums_(std::move(other.checksums_)) {}

CellFile& CellFile::operator=(CellFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    name_ = std::move(other.name_);
    sections_ = std::move(other.sections_);
    cells_ = std::move(other.cells_);
    tracing_ = std::move(other.tracing_);
    checksums_ = std::move(other.checksums_);
  }
  return *this;
}

CellFile::~CellFile() {
  if (fd_ >= 0) ::close(fd_);
}

void CellFile::expect(const ProbeVolume& validated) {
  if (validated.cell_tracing.empty() || validated.cell_tracing.size() != validated.cells.size())
    throw Error(ErrorKind::usage, name_ + ": reading cells from disk needs the tracing split by cell (format 1.5 cell_tracing)");
  cells_ = validated.cells;
  tracing_ = validated.cell_tracing;
  checksums_.clear();
  for (std::size_t k = 0; k < cells_.size(); ++k) checksums_.push_back(cell_checksum(validated, k));
}

std::vector<std::uint8_t> CellFile::read_bytes(std::uint64_t offset, std::uint64_t size, const std::string& place) const {
  std::vector<std::uint8_t> bytes(size);
  std::uint64_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(fd_, bytes.data() + done, std::size_t(size - done), off_t(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw_input_error(name_, place + ": read error: " + errno_text());
    if (n == 0) throw_input_error(name_, place + ": the file ends at byte " + std::to_string(offset + done) + ", " +
                                             std::to_string(size - done) + " bytes early (changed since it was opened?)");
    done += std::uint64_t(n);
  }
  return bytes;
}

void CellFile::append_range(std::uint32_t type, std::size_t element_size, const CellRange& range, const std::string& place,
                            std::vector<std::uint8_t>& out) const {
  if (range.count == 0) return;
  const std::uint64_t bytes = std::uint64_t(range.count) * element_size;
  const std::uint64_t start = std::uint64_t(range.first) * element_size;
  if (type >= sections_.size() || start + bytes > sections_[type].size) // the ranges were validated against this file
    throw Error(ErrorKind::internal, name_ + ": " + place + ": a range outside its section");
  const std::vector<std::uint8_t> part = read_bytes(sections_[type].offset + start, bytes, place);
  out.insert(out.end(), part.begin(), part.end());
}

CellTracingData CellFile::read_cell_tracing(std::size_t k) const {
  if (k >= cells_.size()) throw Error(ErrorKind::internal, name_ + ": read_cell_tracing before expect(), or a cell out of range");
  const std::string place = "cells[" + std::to_string(k) + "] (cell " + std::to_string(cells_[k].cell_index) + ")";
  const Cell& cell = cells_[k];
  const CellTracing& t = tracing_[k];
  // The six ranges in cell_checksum's order; the tracing ones last, where they are copied out from.
  std::vector<std::uint8_t> bytes;
  const auto type = [](SectionType s) { return static_cast<std::uint32_t>(s); };
  append_range(type(SectionType::probes), sizeof(gpu::Probe), cell.probes, place, bytes);
  append_range(type(SectionType::surfel_batches), sizeof(gpu::SurfelBatch), cell.surfel_batches, place, bytes);
  append_range(type(SectionType::svo_leaves), sizeof(gpu::SvoLeaf), cell.svo_leaves, place, bytes);
  const std::size_t nodes_at = bytes.size();
  append_range(type(SectionType::trace_nodes), sizeof(gpu::TraceNode), t.trace_nodes, place, bytes);
  const std::size_t faces_at = bytes.size();
  append_range(type(SectionType::trace_faces), sizeof(gpu::TraceFace), t.trace_faces, place, bytes);
  const std::size_t vertices_at = bytes.size();
  append_range(type(SectionType::trace_vertices), sizeof(gpu::TraceVertex), t.trace_vertices, place, bytes);
  if (checksum64(bytes) != checksums_[k])
    throw_input_error(name_, place + ": the " + std::to_string(bytes.size()) +
                                 " bytes on disk differ from those validated when the file was opened (changed since?)");
  return {elements_of<gpu::TraceNode>(bytes, nodes_at, t.trace_nodes.count),
          elements_of<gpu::TraceFace>(bytes, faces_at, t.trace_faces.count),
          elements_of<gpu::TraceVertex>(bytes, vertices_at, t.trace_vertices.count)};
}

ProbeVolume CellFile::read_volume() const {
  struct stat info {};
  if (::fstat(fd_, &info) != 0) throw_input_error(name_, "cannot stat: " + errno_text());
  return read_probes(read_bytes(0, std::uint64_t(info.st_size), "file"), name_);
}

} // namespace probebake::formats
