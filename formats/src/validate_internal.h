// Shared pieces of the validator phases (validate_*.cpp): the violation sink and the facts the octree
// phase establishes for the later ones.
#pragma once

#include <string>
#include <vector>

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
  const ValidateOptions& options() const { return options_; }

private:
  ValidationReport& report_;
  const ValidateOptions& options_;
};

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
void check_cells(const ProbeVolume& volume, const OctreeFacts& octree, Reporter& out);
// Runtime lighting sections (validate_lighting.cpp): their floats, called by check_finite; then the
// sections, values and BVH, run last.
void check_lighting_finite(const ProbeVolume& volume, Reporter& out);
void check_lighting(const ProbeVolume& volume, Reporter& out);

} // namespace probebake::formats::detail
