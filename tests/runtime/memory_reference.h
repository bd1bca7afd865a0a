// The CPU side of the memory update tests (memory_update_test.cpp, dynamic_objects_test.cpp): the baked
// shallow Cornell box, dynamic::TreeUpdate driven by the same frames as the GPU, with a measure that casts
// the volume's own placement lattice through the volume's own triangles (static ones and each dynamic
// object's at its pose) by brute force in the shaders' arithmetic, and a canonical form of a tree to compare.
//
// Comparison is canonical, by node path (octants from the root) and probe position: the GPU pops its free
// lists in an order that depends on its threads (pushes are atomics), so slot indices may differ from the
// CPU's while the tree they describe is the same.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include <glm/mat4x4.hpp>

#include "probebake/dynamic/tree_update.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/probe_volume.h"
#include "probebake/runtime/runtime.h"
#include "runtime_test_util.h"

namespace probebake::test {

// Cornell box at max depth 1 with surfel batches (so the batch pool is exercised) and the lighting sections.
const formats::ProbeVolume& shallow_cornell();

// The nearest hit of a ray through the volume's triangles, dynamic objects at `poses` (world_from_object,
// one per object), every triangle tested.
struct NearestHit {
  float t = 3.4e38f;
  int triangle = -1;
  glm::vec3 normal{0.0f}; // world space
};
NearestHit nearest_hit(const formats::ProbeVolume& v, std::span<const glm::mat4> poses, glm::vec3 origin,
                       glm::vec3 dir);

// The leaf measure (hit and back-face fractions) of a node cube, as octree.glsl computes it.
dynamic::LeafTrace measure(const formats::ProbeVolume& v, const formats::NodeCube& cube,
                           std::span<const glm::mat4> poses = {});

// Octants from the root ("" = root, "37" = child 7 of child 3), or nullopt for a node that is not live.
std::optional<std::string> path_of(const formats::ProbeVolume& v, int node);

struct Canonical {
  std::map<std::string, std::tuple<bool, float, float, float, int>> leaves; // path -> probe?, position, depth
  std::array<std::map<std::string, int>, 3> segments;                       // path -> state, by segment
  int pull_origin = 0;
  int probes = 0, batches = 0, clusters = 0;
};
Canonical canonical(const formats::ProbeVolume& v);
// Names the first difference between two canonical trees, or "" when they are equal.
std::string first_difference(const Canonical& gpu, const Canonical& cpu);

struct Step {
  std::vector<runtime::Box> boxes;
  std::optional<int> max_depth;
};

runtime::Box root_box(const formats::ProbeVolume& v);
// The world box of the object's 8 corners at `pose` (the runtime's rule for the changed boxes).
runtime::Box world_box(const gpu::DynamicObject& object, const glm::mat4& pose);

// dynamic::TreeUpdate on a copy of the volume; dynamic objects start at rest.
struct Cpu {
  formats::ProbeVolume volume;
  formats::Octree tree;
  dynamic::TreeUpdate update;
  std::vector<glm::mat4> poses;

  explicit Cpu(const formats::ProbeVolume& start);
  // One frame: the step's boxes, then for each moved object the union of its old and new world boxes.
  dynamic::TreeFrameStats frame(const Step& step, std::span<const runtime::ObjectPose> moves = {});
};

runtime::UploadOptions dynamic_options();
void expect_same_stats(const runtime::MemoryUpdateStats& gpu, const dynamic::TreeFrameStats& cpu, int frame);
// The live volume obeys every invariant, judged at the deepest max depth of the script (a lowered max
// depth leaves deeper leaves until they merge, which the validator would call too deep).
void expect_valid(formats::ProbeVolume live, int deepest, int frame);

} // namespace probebake::test
