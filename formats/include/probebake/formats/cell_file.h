// A .probes file kept open for streaming (issue #15, docs/RUNTIME.md "Streaming cells"). The load maps the
// file, checks its container (every checksum) and decodes every section but the three that hold the cells'
// tracing (trace nodes, faces and vertices), which the validator and the upload read in place through the
// mapping; the mapping is dropped once the volume is uploaded. Host memory then holds the global sections
// (8.8 of the 64-room world's 65.1 MB; `probebake info` prints what streams) and one cell at a time, never the
// world: the mapping's pages are the file's own, which the kernel reads in and drops as it needs.
//
// Each cell is read again from the same descriptor when it loads, and checked against the checksum of the
// bytes that were validated (cells.h cell_checksum, computed by expect()), so a file changed or cut short on
// disk since is refused cell by cell and never reaches the GPU. POSIX (open, mmap, pread); reads do not move a
// file position, so several threads may read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "probebake/formats/file_mapping.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::formats {

// One cell's part of the static tracing tree (a CellTracing record's three ranges), numbered as in the
// whole file: node children and leaves by file index, face vertices by file index.
struct CellTracingData {
  std::vector<gpu::TraceNode> nodes;
  std::vector<gpu::TraceFace> faces;
  std::vector<gpu::TraceVertex> vertices;
};

// Cell record k's tracing, copied out of a volume that holds the whole file.
CellTracingData cell_tracing_data(const ProbeVolume& volume, std::size_t k);

struct OpenedCellFile;

class CellFile {
public:
  // Opens and maps `path` and decodes it (read_probes' container and section checks, not validate()); see
  // OpenedCellFile. Throws Error(input, "<path>: <reason>").
  static OpenedCellFile open(const std::filesystem::path& path);

  CellFile(CellFile&&) noexcept = default;
  CellFile& operator=(CellFile&&) noexcept = default;

  // Keeps each cell's ranges and the checksum of its bytes as `validated` and `tracing` hold them. Call once
  // the volume that open() read passed validate(); it needs cell_tracing (Error(usage) otherwise).
  void expect(const ProbeVolume& validated, const TracingView& tracing);

  // Cell record k's tracing, read again from the file. Throws Error(input, "<path>: cells[k] (cell N):
  // <reason>") when the file is shorter now or the cell's bytes differ from those validated.
  CellTracingData read_cell_tracing(std::size_t k) const;

  // The whole file again (read_probes through a new mapping): for read-backs that compare the GPU with the file.
  ProbeVolume read_volume() const;

private:
  struct Section {
    std::uint64_t offset = 0, size = 0;
  };
  // The open file: closed on destruction, moved as a value that leaves -1 behind.
  class Descriptor {
  public:
    explicit Descriptor(int fd) : fd_(fd) {}
    Descriptor(Descriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
    Descriptor& operator=(Descriptor&& other) noexcept {
      std::swap(fd_, other.fd_);
      return *this;
    }
    ~Descriptor();
    int get() const { return fd_; }

  private:
    int fd_ = -1;
  };
  CellFile(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  void read_into(void* out, std::uint64_t offset, std::uint64_t size, const std::string& place) const;
  // The elements of `range` of the section of `type`, added to `hash` (an XXH3_state_t).
  template <class T, class Hash>
  std::vector<T> read_range(std::uint32_t type, const CellRange& range, const std::string& place, Hash& hash) const;

  Descriptor fd_;
  std::string name_;
  std::vector<Section> sections_; // by SectionType value, empty when the file has none
  std::vector<Cell> cells_;
  std::vector<CellTracing> tracing_;
  std::vector<std::uint64_t> checksums_;
  std::vector<std::uint64_t> bytes_; // cells.h cell_bytes of each cell, for the message of a refusal
};

// What CellFile::open gives. A file whose tracing is split by cell (cell_tracing) and compact (1.4+) leaves
// the volume's trace nodes, faces and vertices empty: they are read in place, through tracing(), for as long
// as `mapping` lives. Any other file is decoded whole (streaming refuses it later) and unmapped at once.
struct OpenedCellFile {
  CellFile file;
  ProbeVolume volume;
  FileMapping mapping;
  std::optional<TracingView> in_mapping;
  TracingView tracing() const { return in_mapping ? *in_mapping : tracing_view(volume); }
};

} // namespace probebake::formats
