// Shared pieces of the validator phases (validate_*.cpp): the violation sink and the facts the octree
// phase establishes for the later ones.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "probebake/formats/container.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/validate.h"

namespace probebake::formats::detail {

// Thrown by Reporter::add past max_errors; caught by the validate() driver only.
struct StopValidation {};

class Reporter {
public:
  Reporter(ValidationReport& report, const ValidateOptions& options) : report_(report), options_(options) {}

  // Stops at the first violation past max_errors, so `truncated` means that something was left out.
  void add(const std::string& invariant, const std::string& section, long long index, const std::string& message) {
    if (options_.max_errors != 0 && report_.violations.size() >= options_.max_errors) {
      report_.truncated = true;
      throw StopValidation{};
    }
    report_.violations.push_back(Violation{invariant, section, index, message});
  }
  std::size_t count() const { return report_.violations.size(); }
  void cells_checked(std::size_t cells) { report_.cells_checked = cells; }
  const ValidateOptions& options() const { return options_; }

private:
  ValidationReport& report_;
  const ValidateOptions& options_;
};

// Float checks shared by the phases. NaN fails every comparison, so negative() and unit() say nothing
// about it: non_finite (check_finite) reports it once.
inline bool all_finite(std::initializer_list<float> values) {
  for (float value : values) {
    if (!std::isfinite(value)) return false;
  }
  return true;
}

inline bool finite3(const glm::vec3& v) { return all_finite({v.x, v.y, v.z}); }

// Padding must be +0.0 bit for bit (the writer zero-initialises every struct).
inline bool zero_bits(std::initializer_list<float> values) {
  for (float value : values) {
    if (std::bit_cast<std::uint32_t>(value) != 0u) return false;
  }
  return true;
}

inline constexpr float kUnitTolerance = 1e-4f; // |length - 1| of directions and normals
inline bool unit(const glm::vec3& v) { return std::abs(glm::length(v) - 1.0f) <= kUnitTolerance; }
inline bool negative(const glm::vec3& v) { return v.x < 0.0f || v.y < 0.0f || v.z < 0.0f; }

// Every float of a surfel, padding included (non_finite in check_finite; surfel_values skips such surfels).
inline bool surfel_finite(const gpu::Surfel& s) {
  return finite3(s.position) && finite3(s.normal) && finite3(s.albedo) && finite3(s.radiance) &&
         all_finite({s.distance, s.pad0, s.pad1});
}

// What the octree phase learned: the cube of every node reachable from the root (node == -1 when the
// node is not reachable) and whether the octree was free of violations.
struct OctreeFacts {
  std::vector<NodeCube> cubes;
  bool clean = true;
  bool reachable(int node) const {
    return node >= 0 && static_cast<std::size_t>(node) < cubes.size() && cubes[node].node == node;
  }
};

// File level (validate_container.cpp), run by validate_file() before the model phases: what the reader
// accepts but the format does not allow (version, flags, gaps, trailing bytes, section presence).
// `volume` is the decoded container (its element flags decide the minor version too).
void check_container(const ContainerView& container, const ProbeVolume& volume, Reporter& out);

// Phases, in the order validate() runs them (cheap and structural first).
void check_volume_info(const ProbeVolume& volume, Reporter& out);
void check_counts(const ProbeVolume& volume, Reporter& out);
void check_dependencies(const ProbeVolume& volume, Reporter& out);
void check_finite(const ProbeVolume& volume, Reporter& out);
OctreeFacts check_octree(const ProbeVolume& volume, Reporter& out);
void check_probes(const ProbeVolume& volume, const OctreeFacts& octree, Reporter& out);
void check_surfel_batches(const ProbeVolume& volume, Reporter& out);
void check_probe_index(const ProbeVolume& volume, Reporter& out);
void check_leaf_queue(const ProbeVolume& volume, const OctreeFacts& octree, Reporter& out);
void check_svo(const ProbeVolume& volume, Reporter& out);
void check_grid_lattice(const ProbeVolume& volume, Reporter& out);
void check_sky(const ProbeVolume& volume, Reporter& out);
// The elements of the three trace sections that a check reads: element i of each span is the file's element
// base + i. A volume is one window at 0; a cell read alone (validate_cell_tracing) the window of its ranges.
struct TracingWindow {
  TracingView view;
  std::uint64_t node_base = 0, face_base = 0, vertex_base = 0;
  bool has_node(std::uint64_t n) const { return n >= node_base && n - node_base < view.nodes.size(); }
  bool has_face(std::uint64_t f) const { return f >= face_base && f - face_base < view.faces.size(); }
  bool has_vertex(std::uint64_t k) const { return k >= vertex_base && k - vertex_base < view.vertices.size(); }
  const gpu::TraceNode& node(std::uint64_t n) const { return view.nodes[n - node_base]; }
  const gpu::TraceFace& face(std::uint64_t f) const { return view.faces[f - face_base]; }
  const gpu::TraceVertex& vertex(std::uint64_t k) const { return view.vertices[k - vertex_base]; }
};

// validate_without_cells' run: the cells' ranges of the trace sections are never read, and the walk of the
// static tree records in `entries` where it enters each cell. Null in validate()'s run.
struct DeferredCells {
  std::vector<CellEntry>& entries;
};

void check_cells(const ProbeVolume& volume, const TracingView& tracing, const OctreeFacts& octree,
                 const DeferredCells* deferred, Reporter& out);
// Cell record k read alone: its tracing refers only to itself and its faces' centroids lie in it (cell_tracing).
void check_cell_self_contained(const ProbeVolume& volume, std::size_t k, const TracingWindow& cell, Reporter& out);
// Files only (validate_file): a volume edited in memory keeps the checksums it was read with.
void check_cell_checksums(const ProbeVolume& volume, const TracingView& tracing, Reporter& out);
void check_cell_global_checksums(const ProbeVolume& volume, const TracingView& tracing, Reporter& out);
// Runtime lighting sections (validate_lighting.cpp): their floats, called by check_finite; then the
// sections, values and BVH, run last.
void check_lighting_finite(const ProbeVolume& volume, Reporter& out);
void check_lighting(const ProbeVolume& volume, const TracingView& tracing, const DeferredCells* deferred,
                    Reporter& out);
void check_dynamic_objects(const ProbeVolume& volume, const TracingView& tracing,
                           Reporter& out); // format 1.3 (validate_dynamic.cpp)
// Format 1.4 (validate_tracing.cpp): the compact tracing sections, and the dynamic objects' ranges in them.
bool uses_compact_tracing(const ProbeVolume& volume, const TracingView& tracing);
void check_trace_mesh(const ProbeVolume& volume, const TracingView& tracing, const DeferredCells* deferred,
                      Reporter& out);
// Cell record k read alone: its vertices and faces' values, and its subtree from `entry` (trace_tree).
void check_cell_trace_mesh(const ProbeVolume& volume, const CellEntry& entry, std::size_t k, const TracingWindow& cell,
                           Reporter& out);

} // namespace probebake::formats::detail
