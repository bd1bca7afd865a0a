#include "streaming/cell_source.h"

#include <utility>

namespace probebake::runtime::detail {
namespace {

formats::ProbeVolume tracing_of(const formats::ProbeVolume& volume) {
  formats::ProbeVolume out;
  out.trace_trees = volume.trace_trees;
  out.trace_nodes = volume.trace_nodes;
  out.trace_faces = volume.trace_faces;
  out.trace_vertices = volume.trace_vertices;
  out.cell_tracing = volume.cell_tracing;
  return out;
}

class MemoryCellSource final : public CellSource {
public:
  explicit MemoryCellSource(const formats::ProbeVolume& volume) : copy_(tracing_of(volume)) {}
  formats::CellTracingData read(std::size_t k) const override { return formats::cell_tracing_data(copy_, k); }
  formats::ProbeVolume tracing() const override { return copy_; }

private:
  formats::ProbeVolume copy_;
};

class FileCellSource final : public CellSource {
public:
  explicit FileCellSource(formats::CellFile file) : file_(std::move(file)) {}
  formats::CellTracingData read(std::size_t k) const override { return file_.read_cell_tracing(k); }
  formats::ProbeVolume tracing() const override { return tracing_of(file_.read_volume()); }

private:
  formats::CellFile file_;
};

} // namespace

std::unique_ptr<CellSource> cell_source_in_memory(const formats::ProbeVolume& volume) {
  return std::make_unique<MemoryCellSource>(volume);
}

std::unique_ptr<CellSource> cell_source_on_disk(formats::CellFile file) {
  return std::make_unique<FileCellSource>(std::move(file));
}

} // namespace probebake::runtime::detail
