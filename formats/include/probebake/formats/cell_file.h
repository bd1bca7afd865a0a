// A .probes file kept open for streaming (issue #15, docs/RUNTIME.md "Streaming cells"). A 1.7 file (with
// cell_global_checksums) is read without its cells: open() reads every byte but the cells' ranges of the trace
// nodes, faces and vertices into zero pages of the file's size, checks the container and every section
// checksum but those three, whose global part (the top level, the dynamic objects' trees) it checks against
// cell_global_checksums; the load validates that (validate_without_cells), and each cell is checked when it
// is read, against its stored checksum and its own invariants (validate_cell_tracing). So the load reads the
// global part only (8.8 of the 64-room world's 65.1 MB; `probebake info` prints it), and memory never holds
// the world. An older file (1.5, 1.6) is mapped and read whole once: its cells' tracing is validated in place
// in the mapping and each cell's checksum computed from the bytes validated (expect()).
//
// Each cell is read again from the same descriptor when it loads, so a file changed or cut short on disk
// since is refused cell by cell and never reaches the GPU. POSIX (open, mmap, pread); reads do not move a
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

#include "probebake/formats/container.h"
#include "probebake/formats/file_mapping.h"
#include "probebake/formats/probe_volume.h"
#include "probebake/formats/validate.h"

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
  // the volume that open() read whole passed validate(); it needs cell_tracing (Error(usage) otherwise).
  void expect(const ProbeVolume& validated, const TracingView& tracing);
  // For a file whose cells open() left unread: keeps each cell's ranges and stored checksum, and `entries`
  // (validate_without_cells' on `volume`), against which each cell read is validated; none: no validation.
  void expect_unread(const ProbeVolume& volume, std::vector<CellEntry> entries);

  // Cell record k's tracing, read again from the file. Throws Error(input, "<path>: cells[k] (cell N):
  // <reason>") when the file is shorter now, the cell's bytes differ from those validated (or from its stored
  // checksum), or they break an invariant of the cell's tracing (expect_unread with entries).
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
  // open() of a 1.7 file: false (nothing changed) for a file without cell_global_checksums.
  bool read_global_part(OpenedCellFile& opened, std::uint64_t size);
  void read_global_ranges(std::span<std::uint8_t> image, std::uint64_t begin, std::uint64_t end,
                          std::vector<std::pair<std::uint64_t, std::uint64_t>> skipped,
                          std::uint64_t& bytes_read) const;
  void keep_ranges(const ProbeVolume& volume);
  void keep_sections(const ContainerView& container);
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
  bool stored_checksums_ = false;    // expect_unread: the file's own cell checksums
  ProbeVolume cell_context_;         // what validate_cell_tracing reads besides the cell (expect_unread)
  std::vector<CellEntry> entries_;
};

// What CellFile::open gives. A file whose tracing is split by cell (cell_tracing) and compact (1.4+) leaves
// the volume's trace nodes, faces and vertices empty: they are read in place, through tracing(), for as long
// as `mapping` lives. Any other file is decoded whole (streaming refuses it later) and unmapped at once.
// A 1.7 file's `mapping` is the zero pages that hold what open() read (`cells_unread`: the cells' ranges of
// the three sections are zeros, never to be read; validate_without_cells and the upload read the rest).
struct OpenedCellFile {
  CellFile file;
  ProbeVolume volume;
  FileMapping mapping;
  std::optional<TracingView> in_mapping;
  bool cells_unread = false;
  std::uint64_t bytes_read = 0; // of the file, by open()
  TracingView tracing() const { return in_mapping ? *in_mapping : tracing_view(volume); }
};

} // namespace probebake::formats
