// Validator phase for the runtime lighting sections (format 1.1, docs/FORMAT.md): which sections are
// present and their counts (lighting_sections), the values the shaders rely on (lighting_values), the
// flag bits of triangles and emitter patches (lighting_flags, 1.2), and the
// BVH that the GPU traverses without bounds checks of its own (bvh_tree). Finiteness is checked with the
// other floats by check_finite (non_finite), so NaN values are not reported twice here.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

constexpr float kBoxTolerance = 1e-5f;   // box containment, relative to the largest root box coordinate
constexpr float kMaxSpotScale = 1000.0f; // 1 / 0.001, the floor of the spot cone's smooth band

bool is_zero(const glm::vec3& v) { return zero_bits({v.x, v.y, v.z}); }

bool triangle_finite(const gpu::TraceTriangle& t) {
  return finite3(t.v0) && finite3(t.edge1) && finite3(t.edge2) && finite3(t.normal) && finite3(t.albedo) &&
         finite3(t.emission) && all_finite({t.pad1, t.pad2, t.pad3, t.pad4});
}

bool light_finite(const gpu::PunctualLight& l) {
  return finite3(l.position) && finite3(l.direction) && finite3(l.intensity) &&
         all_finite({l.range, l.cos_outer, l.spot_scale, l.pad0, l.pad1, l.pad2});
}

bool patch_finite(const gpu::EmitterPatch& p) {
  return finite3(p.a) && finite3(p.b) && finite3(p.c) && finite3(p.normal) && finite3(p.radiance) &&
         all_finite({p.pad3, p.pad4});
}

template <typename T, typename Finite>
void report_non_finite(const std::vector<T>& elements, const char* section, Finite finite, Reporter& out) {
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (!finite(elements[i])) out.add("non_finite", section, static_cast<long long>(i), "a float is NaN or infinite");
  }
}

// ---- lighting_sections ----------------------------------------------------------------------------------

void check_count(Reporter& out, const char* section, long long expected, std::size_t actual, const char* what) {
  if (static_cast<long long>(actual) != expected) {
    out.add("lighting_sections", section, -1,
            concat(what, " is ", expected, " but the section has ", actual, " elements"));
  }
}

void check_no_lighting_data(const ProbeVolume& v, const TracingView& tracing, Reporter& out) {
  const std::pair<const char*, bool> sections[] = {
      {"ray_directions", v.ray_directions.empty()},   {"bvh_nodes", v.bvh_nodes.empty()},
      {"trace_triangles", v.trace_triangles.empty()}, {"punctual_lights", v.punctual_lights.empty()},
      {"emitter_patches", v.emitter_patches.empty()}, {"trace_trees", !uses_compact_tracing(v, tracing)}};
  for (const auto& [section, empty] : sections) {
    if (!empty) out.add("lighting_sections", section, -1, "lighting data without a lighting_info section");
  }
}

void check_lighting_sections(const ProbeVolume& v, const TracingView& tracing, Reporter& out) {
  if (!v.lighting) return check_no_lighting_data(v, tracing, out);
  const gpu::LightingInfo& info = *v.lighting;
  const bool compact = uses_compact_tracing(v, tracing); // format 1.4
  check_count(out, compact ? "trace_nodes" : "bvh_nodes", info.bvh_nodes,
              compact ? tracing.nodes.size() : v.bvh_nodes.size(), "bvh_nodes");
  check_count(out, compact ? "trace_faces" : "trace_triangles", info.triangles,
              compact ? tracing.faces.size() : v.trace_triangles.size(), "triangles");
  check_count(out, "punctual_lights", info.lights, v.punctual_lights.size(), "lights");
  check_count(out, "emitter_patches", info.emitter_patches, v.emitter_patches.size(), "emitter_patches");
  check_count(out, "ray_directions", static_cast<long long>(info.rays) + info.placement_rays, v.ray_directions.size(),
              "rays + placement_rays");
  if (info.rays < 1) out.add("lighting_sections", "lighting_info", 0, concat("rays ", info.rays, " < 1"));
  if (info.placement_rays != v.info.surfels_per_probe) {
    out.add("lighting_sections", "lighting_info", 0,
            concat("placement_rays ", info.placement_rays, " != surfels_per_probe ", v.info.surfels_per_probe));
  }
  if (info.emissive_as_lights == 0 && !v.emitter_patches.empty()) {
    out.add("lighting_sections", "emitter_patches", -1, "emitter patches although emissive_as_lights is 0");
  }
}

// ---- lighting_values ------------------------------------------------------------------------------------

void check_info_values(const gpu::LightingInfo& info, Reporter& out) {
  auto bad = [&](const std::string& message) { out.add("lighting_values", "lighting_info", 0, message); };
  if (std::isfinite(info.shadow_offset) && !(info.shadow_offset > 0.0f))
    bad(concat("shadow_offset ", info.shadow_offset, " is not positive"));
  if (info.emissive_as_lights != 0 && info.emissive_as_lights != 1)
    bad(concat("emissive_as_lights ", info.emissive_as_lights, " not 0 or 1"));
  if (negative(info.sky_radiance)) bad("sky_radiance is negative");
  if (info.dynamic_objects < 0) bad("dynamic_objects is negative");
}

void check_directions(const std::vector<glm::vec4>& directions, Reporter& out) {
  for (std::size_t i = 0; i < directions.size(); ++i) {
    const glm::vec4& d = directions[i];
    if (!all_finite({d.x, d.y, d.z, d.w})) continue;
    if (!unit(glm::vec3(d)) || !zero_bits({d.w})) {
      out.add("lighting_values", "ray_directions", static_cast<long long>(i), "not a unit direction with w = 0");
    }
  }
}

// The normal must be the unit normal of edge1 x edge2 (the counter-clockwise front face): the runtime
// decides front and back faces with it.
std::string triangle_problem(const gpu::TraceTriangle& t) {
  if (t.source < 0) return concat("source ", t.source, " is negative");
  const glm::vec3 cross = glm::cross(t.edge1, t.edge2);
  const float length = glm::length(cross);
  if (!(length > 0.0f)) return "zero area (such triangles are left out)";
  if (!unit(t.normal) || glm::length(t.normal - cross / length) > kUnitTolerance)
    return "normal is not the unit normal of edge1 x edge2";
  if (negative(t.albedo) || negative(t.emission)) return "negative albedo or emission";
  if (!zero_bits({t.pad1, t.pad2, t.pad3, t.pad4})) return "padding is not zero";
  return "";
}

// Fields a light type does not use are zero (point: direction and cone; directional: position, range
// and cone), so every light has one byte representation.
std::string light_problem(const gpu::PunctualLight& l) {
  if (l.type != gpu::LIGHT_POINT && l.type != gpu::LIGHT_SPOT && l.type != gpu::LIGHT_DIRECTIONAL)
    return concat("unknown type ", l.type);
  if (negative(l.intensity)) return "negative intensity";
  if (l.range < 0.0f) return concat("range ", l.range, " is negative");
  if (!zero_bits({l.pad0, l.pad1, l.pad2})) return "padding is not zero";
  const bool spot = l.type == gpu::LIGHT_SPOT;
  if (l.type != gpu::LIGHT_POINT && !unit(l.direction)) return "direction is not a unit vector";
  if (l.type == gpu::LIGHT_POINT && !is_zero(l.direction)) return "a point light's direction is not zero";
  if (l.type == gpu::LIGHT_DIRECTIONAL && !(is_zero(l.position) && zero_bits({l.range}))) {
    return "a directional light's position and range are not zero";
  }
  if (!spot)
    return zero_bits({l.cos_outer, l.spot_scale}) ? "" : "cone fields of a light that is not a spot are not zero";
  if (!(l.cos_outer >= -1.0f && l.cos_outer <= 1.0f)) return concat("cos_outer ", l.cos_outer, " outside [-1, 1]");
  if (!(l.spot_scale > 0.0f && l.spot_scale <= kMaxSpotScale))
    return concat("spot_scale ", l.spot_scale, " outside (0, 1000]");
  return "";
}

std::string patch_problem(const gpu::EmitterPatch& p) {
  if (!unit(p.normal)) return "normal is not a unit vector";
  if (negative(p.radiance)) return "negative radiance";
  if (!zero_bits({p.pad3, p.pad4})) return "padding is not zero";
  return "";
}

// Format 1.10: the emitters are numbered by their first patch (0, 1, 2, ... in patch order), and every patch of an
// emitter names its material, a glTF material index (the runtime scales an emitter by it).
void check_emitter_groups(const std::vector<gpu::EmitterPatch>& patches, Reporter& out) {
  std::vector<std::int32_t> materials; // by emitter
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const gpu::EmitterPatch& p = patches[i];
    const auto bad = [&](const std::string& message) {
      out.add("lighting_values", "emitter_patches", static_cast<long long>(i), message);
    };
    if (p.material < 0) {
      bad(concat("material ", p.material, " is negative"));
    } else if (p.emitter > materials.size()) {
      bad(concat("emitter ", p.emitter, " skips numbers: the patches before name ", materials.size(), " emitters"));
    } else if (p.emitter == materials.size()) {
      materials.push_back(p.material);
    } else if (materials[p.emitter] != p.material) {
      bad(concat("emitter ", p.emitter, " has material ", p.material, ", its first patch ", materials[p.emitter]));
    }
  }
}

// ---- lighting_flags -------------------------------------------------------------------------------------

// Bit 0 (double-sided) is the only flag of 1.2; a later bit would change what the shaders do, so a file
// that sets one is refused rather than traced as if the bit were not there.
template <typename T>
void check_flag_bits(const std::vector<T>& elements, const char* section, std::uint32_t known, Reporter& out) {
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const std::uint32_t unknown = elements[i].flags & ~known;
    if (unknown != 0)
      out.add("lighting_flags", section, static_cast<long long>(i),
              concat("flags ", elements[i].flags, " set unknown bits (bit 0, double-sided, is the only one)"));
  }
}

void check_lighting_flags(const ProbeVolume& v, Reporter& out) {
  check_flag_bits(v.trace_triangles, "trace_triangles", gpu::TRIANGLE_DOUBLE_SIDED, out);
  check_flag_bits(v.emitter_patches, "emitter_patches", gpu::EMITTER_DOUBLE_SIDED, out);
}

template <typename T, typename Finite, typename Problem>
void report_problems(const std::vector<T>& elements, const char* section, Finite finite, Problem problem,
                     Reporter& out) {
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (!finite(elements[i])) continue;
    const std::string message = problem(elements[i]);
    if (!message.empty()) out.add("lighting_values", section, static_cast<long long>(i), message);
  }
}

void check_lighting_values(const ProbeVolume& v, Reporter& out) {
  if (v.lighting) check_info_values(*v.lighting, out);
  check_directions(v.ray_directions, out);
  report_problems(v.trace_triangles, "trace_triangles", triangle_finite, triangle_problem, out);
  report_problems(v.punctual_lights, "punctual_lights", light_finite, light_problem, out);
  report_problems(v.emitter_patches, "emitter_patches", patch_finite, patch_problem, out);
  check_emitter_groups(v.emitter_patches, out);
}

// ---- bvh_tree -----------------------------------------------------------------------------------------

// Checks one node at a time from the root down: structure, depth, boxes, leaf ranges. Every node must be
// reached exactly once and every triangle must lie in exactly one leaf.
class BvhChecker {
public:
  BvhChecker(const ProbeVolume& v, Reporter& out)
      : nodes_(v.bvh_nodes),
        triangles_(v.trace_triangles),
        out_(out),
        reached_(nodes_.size(), 0),
        covered_(triangles_.size(), 0) {
    // Format 1.3: the static tree at 0 (unless the first object's nodes start there), then each object's.
    if (v.dynamic_objects.empty() || v.dynamic_objects[0].bvh_root > 0) roots_.push_back(0);
    for (const gpu::DynamicObject& o : v.dynamic_objects)
      if (o.bvh_root >= 0 && std::size_t(o.bvh_root) < nodes_.size()) roots_.push_back(std::size_t(o.bvh_root));
  }

  void run() {
    if (nodes_.empty()) {
      if (!triangles_.empty()) out_.add("bvh_tree", "trace_triangles", -1, "triangles but no BVH nodes");
      return;
    }
    for (const std::size_t root : roots_) {
      if (reached_[root] != 0) {
        bad("bvh_nodes", root, "a root reached from another tree");
        continue;
      }
      tolerance_ = box_tolerance(nodes_[root]);
      reached_[root] = 1;
      std::vector<std::pair<std::size_t, int>> stack{{root, 0}}; // node, depth
      while (!stack.empty()) {
        const auto [index, depth] = stack.back();
        stack.pop_back();
        visit(index, depth, stack);
      }
    }
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (reached_[i] == 0) bad("bvh_nodes", i, "not reachable from the root");
    }
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      if (covered_[t] == 0) bad("trace_triangles", t, "in no leaf");
    }
  }

private:
  std::vector<std::size_t> roots_;

  static float box_tolerance(const gpu::BvhNode& root) {
    const glm::vec3 magnitude = glm::max(glm::abs(root.lower), glm::abs(root.upper));
    return kBoxTolerance * std::max({magnitude.x, magnitude.y, magnitude.z});
  }

  void bad(const char* section, std::size_t index, const std::string& message) {
    out_.add("bvh_tree", section, static_cast<long long>(index), message);
  }

  bool contains(const gpu::BvhNode& box, const glm::vec3& p) const {
    return glm::all(glm::greaterThanEqual(p, box.lower - tolerance_)) &&
           glm::all(glm::lessThanEqual(p, box.upper + tolerance_));
  }

  void visit(std::size_t index, int depth, std::vector<std::pair<std::size_t, int>>& stack) {
    const gpu::BvhNode& node = nodes_[index];
    if (depth == gpu::BVH_MAX_DEPTH) bad("bvh_nodes", index, concat("depth ", depth, " reaches BVH_MAX_DEPTH"));
    if (finite3(node.lower) && finite3(node.upper) && !glm::all(glm::lessThanEqual(node.lower, node.upper))) {
      bad("bvh_nodes", index, "lower corner above the upper corner");
    }
    if (node.count == 0) return visit_inner(index, node, depth, stack);
    if (node.count < 0 || node.count > gpu::BVH_MAX_LEAF_TRIANGLES)
      return bad("bvh_nodes", index, concat("leaf count ", node.count, " outside [1, 4]"));
    visit_leaf(index, node);
  }

  void visit_inner(std::size_t index, const gpu::BvhNode& node, int depth,
                   std::vector<std::pair<std::size_t, int>>& stack) {
    const long long first = node.first;
    if (first <= static_cast<long long>(index) || first + 1 >= static_cast<long long>(nodes_.size())) {
      return bad("bvh_nodes", index,
                 concat("children ", first, ", ", first + 1, " not after the node and inside the buffer"));
    }
    for (std::size_t child = static_cast<std::size_t>(first); child <= static_cast<std::size_t>(first) + 1; ++child) {
      if (reached_[child]++ != 0) {
        bad("bvh_nodes", child, concat("reached twice (again from node ", index, ")"));
        continue;
      }
      if (!contains(node, nodes_[child].lower) || !contains(node, nodes_[child].upper)) {
        bad("bvh_nodes", child, concat("box not inside its parent's (node ", index, ")"));
      }
      stack.emplace_back(child, depth + 1);
    }
  }

  void visit_leaf(std::size_t index, const gpu::BvhNode& node) {
    const long long first = node.first;
    if (first < 0 || first + node.count > static_cast<long long>(triangles_.size())) {
      return bad("bvh_nodes", index,
                 concat("triangles [", first, ", ", first + node.count, ") outside trace_triangles"));
    }
    for (std::size_t t = static_cast<std::size_t>(first); t < static_cast<std::size_t>(first + node.count); ++t) {
      if (covered_[t]++ != 0) bad("trace_triangles", t, concat("in two leaves (again in node ", index, ")"));
      const gpu::TraceTriangle& tri = triangles_[t];
      if (!contains(node, tri.v0) || !contains(node, tri.v0 + tri.edge1) || !contains(node, tri.v0 + tri.edge2)) {
        bad("bvh_nodes", index, concat("box does not contain triangle ", t));
      }
    }
  }

  const std::vector<gpu::BvhNode>& nodes_;
  const std::vector<gpu::TraceTriangle>& triangles_;
  Reporter& out_;
  std::vector<std::uint8_t> reached_;
  std::vector<std::uint8_t> covered_;
  float tolerance_ = 0.0f;
};

} // namespace

void check_lighting_finite(const ProbeVolume& v, Reporter& out) {
  if (v.lighting && !(finite3(v.lighting->sky_radiance) && std::isfinite(v.lighting->shadow_offset))) {
    out.add("non_finite", "lighting_info", 0, "a float is NaN or infinite");
  }
  report_non_finite(
      v.ray_directions, "ray_directions",
      [](const glm::vec4& d) {
        return all_finite({d.x, d.y, d.z, d.w});
      },
      out);
  report_non_finite(
      v.bvh_nodes, "bvh_nodes", [](const gpu::BvhNode& n) { return finite3(n.lower) && finite3(n.upper); }, out);
  report_non_finite(v.trace_triangles, "trace_triangles", triangle_finite, out);
  report_non_finite(v.punctual_lights, "punctual_lights", light_finite, out);
  report_non_finite(v.emitter_patches, "emitter_patches", patch_finite, out);
}

void check_lighting(const ProbeVolume& volume, const TracingView& tracing, const DeferredCells* deferred,
                    Reporter& out) {
  check_lighting_sections(volume, tracing, out);
  check_lighting_values(volume, out);
  check_lighting_flags(volume, out);
  check_dynamic_objects(volume, tracing, out); // first: the BVH walk starts at the objects' roots
  if (uses_compact_tracing(volume, tracing)) return check_trace_mesh(volume, tracing, deferred, out);
  BvhChecker(volume, out).run();
}

} // namespace probebake::formats::detail
