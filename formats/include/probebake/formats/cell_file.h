// A .probes file kept open for streaming (issue #15, docs/RUNTIME.md "Streaming cells"). A streaming runtime
// reads and validates the whole file once, keeps only the global sections in host memory, and reads a cell's
// tracing again from the same descriptor each time the cell is loaded: host memory then holds the global
// sections and one cell at a time, not the world (the cells' static tracing is 56.5 of the 64.9 MB of the
// 64-room world; `probebake info` prints what streams).
//
// Every cell read is checked against the checksum of the bytes that were validated (cells.h cell_checksum,
// computed by expect()), so a file changed or cut short on disk since is refused cell by cell and never
// reaches the GPU. POSIX (open, pread); reads do not move a file position, so several threads may read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

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

class CellFile {
public:
  // Opens `path` and reads it whole through the new descriptor into `volume` (read_probes: container and
  // section checks, not validate()). Throws Error(input, "<path>: <reason>").
  static CellFile open(const std::filesystem::path& path, ProbeVolume& volume);

  CellFile(CellFile&&) noexcept = default;
  CellFile& operator=(CellFile&&) noexcept = default;

  // Keeps each cell's ranges and the checksum of its bytes as `validated` holds them. Call once the volume
  // that open() read passed validate(); it needs cell_tracing (Error(usage) otherwise).
  void expect(const ProbeVolume& validated);

  // Cell record k's tracing, read again from the file. Throws Error(input, "<path>: cells[k] (cell N):
  // <reason>") when the file is shorter now or the cell's bytes differ from those validated.
  CellTracingData read_cell_tracing(std::size_t k) const;

  // The whole file again (read_probes): for read-backs that compare the GPU with the file.
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
  std::vector<std::uint8_t> read_bytes(std::uint64_t offset, std::uint64_t size, const std::string& place) const;
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

} // namespace probebake::formats
