// Where the streamed tracing arena reads a cell's tracing when the cell is loaded (issue #15): the file on
// disk for Volume::load, so that host memory holds the global sections and not the world; a copy of the
// tracing sections for Volume::upload of an in-memory volume.
#pragma once

#include <cstddef>
#include <memory>

#include "probebake/formats/cell_file.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::runtime::detail {

class CellSource {
public:
  virtual ~CellSource() = default;
  // Cell record k's tracing, numbered as in the file. Throws probebake::Error(input) naming the cell when it
  // cannot be read or differs from the bytes validated at load.
  virtual formats::CellTracingData read(std::size_t k) const = 0;
  // The whole tracing sections (trees, nodes, faces, vertices): what read_back() reports.
  virtual formats::ProbeVolume tracing() const = 0;
};

// Keeps a copy of the volume's tracing sections.
std::unique_ptr<CellSource> cell_source_in_memory(const formats::ProbeVolume& volume);
// Reads each cell from `file` (CellFile::expect called on the validated volume).
std::unique_ptr<CellSource> cell_source_on_disk(formats::CellFile file);

} // namespace probebake::runtime::detail
