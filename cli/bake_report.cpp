// The bake's report (bake_report.h).
#include "bake_report.h"

#include <algorithm>
#include <type_traits>

#include <fmt/core.h>

#include "probebake/formats/cells.h"
#include "probebake/formats/volume_sections.h"

namespace probebake::cli {
namespace {

// Probe noise (median, as lighting::LightingReport::noise_median estimates it) above which the lookup shows blotches:
// the window room's grid gave 0.175 at 256 rays (blotches), 0.043 at 4096 (smooth); the Cornell box 0.04 at
// 256 (docs/results/lookup.md, "Convergence"). The estimate takes the rays as independent; the Fibonacci
// lattice's actual error is lower.
constexpr float kVisibleProbeNoise = 0.08f;

// Payload bytes per section of the file, in type order (formats/volume_sections.h).
nlohmann::ordered_json section_bytes(const formats::ProbeVolume& v) {
  nlohmann::ordered_json bytes = nlohmann::ordered_json::object();
  formats::for_each_section(v, [&](formats::SectionType type, const auto& member) {
    using Member = std::decay_t<decltype(member)>;
    std::size_t size = sizeof(Member);
    if constexpr (requires { member.data(); })
      size = member.size() * sizeof(typename Member::value_type);
    else if constexpr (requires { member.has_value(); })
      size = member ? sizeof(typename Member::value_type) : 0;
    if (type == formats::SectionType::leaf_queue_header && v.leaf_entries.empty()) size = 0;
    bytes[formats::section_name(static_cast<std::uint32_t>(type))] = size;
  });
  return bytes;
}

} // namespace

nlohmann::ordered_json bake_report_json(const bake::BakeReport& r, const std::string& output, std::size_t bytes,
                                        const formats::ProbeVolume& v) {
  nlohmann::ordered_json j;
  j["output"] = output;
  j["bytes"] = bytes;
  j["probes"] = r.probes;
  j["placed_probes"] = r.placed_probes;
  j["leaves"] = r.leaves;
  j["depth_histogram"] = r.depth_histogram;
  j["dead_probes"] = r.dead_probes;
  j["moved_probes"] = r.moved_probes;
  j["freed_probes"] = r.freed_probes;
  j["clearance"] = r.clearance;
  j["lighting"] = {{"iterations", r.lighting.iterations},
                   {"extrapolations", r.lighting.extrapolations},
                   {"rejected_extrapolations", r.lighting.rejected_extrapolations},
                   {"converged", r.lighting.converged},
                   {"change", r.lighting.change},
                   {"estimated_error", r.lighting.estimated_error},
                   {"rays", r.lighting.rays},
                   {"noise_median", r.lighting.noise_median},
                   {"noise_p95", r.lighting.noise_p95},
                   {"seconds", r.lighting.seconds}};
  j["svo"] = {{"nodes", r.svo_nodes},
              {"leaves", r.svo_leaves},
              {"solid_voxels", r.svo_solid_voxels},
              {"uncovered_voxels", r.svo_uncovered_voxels},
              {"bytes", v.svo_nodes.size() * 4 + v.svo_leaves.size() * sizeof(gpu::SvoLeaf)}};
  std::uint64_t cell_total = 0, cell_largest = 0;
  for (std::size_t k = 0; k < v.cells.size(); ++k) {
    const std::uint64_t cell = formats::cell_bytes(v, k);
    cell_total += cell, cell_largest = std::max(cell_largest, cell);
  }
  j["cells"] = {{"depth", r.cell_depth}, {"size", r.cell_size},           {"count", v.cells.size()},
                {"bytes", cell_total},   {"largest_bytes", cell_largest}, {"split_tracing", !v.cell_tracing.empty()}};
  j["sections"] = section_bytes(v);
  const bake::RuntimeLightingReport& g = r.runtime_lighting;
  j["runtime_lighting"] = {
      {"written", g.written},
      {"bvh_nodes", g.bvh_nodes},
      {"bvh_depth", g.bvh_depth},
      {"triangles", g.triangles},
      {"left_out_triangles", g.left_out_triangles},
      {"lights", g.lights},
      {"emitter_patches", g.emitter_patches},
      {"dynamic_objects", g.dynamic_objects},
      {"vertices", g.vertices},
      {"materials", g.materials},
      {"bytes", g.bytes},
      {"tracing_bytes", g.tracing_bytes},
      {"tracing_bytes_per_triangle", g.triangles > 0 ? double(g.tracing_bytes) / g.triangles : 0.0},
      {"bvh_seconds", g.bvh_seconds}};
  j["stages"] = nlohmann::ordered_json::object();
  j["stages_cpu"] = nlohmann::ordered_json::object(); // CPU seconds, all threads: comparable on a loaded machine
  double total = 0.0, total_cpu = 0.0;
  for (const auto& s : r.stages) {
    j["stages"][s.stage] = s.seconds;
    j["stages_cpu"][s.stage] = s.cpu_seconds;
    total += s.seconds;
    total_cpu += s.cpu_seconds;
  }
  j["seconds"] = total;
  j["cpu_seconds"] = total_cpu;
  return j;
}

void print_bake_report(const nlohmann::ordered_json& j) {
  fmt::print("wrote        {} ({} bytes)\n", j["output"].get<std::string>(), j["bytes"].get<std::size_t>());
  fmt::print("probes       {} in {} leaves ({} placed, {} freed inside geometry)\n", j["probes"].get<int>(),
             j["leaves"].get<int>(), j["placed_probes"].get<int>(), j["freed_probes"].get<int>());
  std::string histogram;
  const auto depths = j["depth_histogram"].get<std::vector<int>>();
  for (std::size_t d = 0; d < depths.size(); ++d) histogram += fmt::format(" d{}:{}", d, depths[d]);
  fmt::print("depths      {}\n", histogram);
  fmt::print("dead probes  {} ({} moved, {} freed; clearance {:.4g})\n", j["dead_probes"].get<int>(),
             j["moved_probes"].get<int>(), j["freed_probes"].get<int>(), j["clearance"].get<float>());
  const auto& lighting = j["lighting"];
  if (lighting["iterations"].get<int>() > 0)
    fmt::print("lighting     {} iterations ({} extrapolated, {} undone), {}, estimated error {:.2g}\n",
               lighting["iterations"].get<int>(), lighting["extrapolations"].get<int>(),
               lighting["rejected_extrapolations"].get<int>(),
               lighting["converged"].get<bool>() ? "converged" : "NOT converged",
               lighting["estimated_error"].get<float>());
  if (lighting["iterations"].get<int>() > 0) {
    const float noise = lighting["noise_median"].get<float>();
    fmt::print("probe noise  {:.3g} median, {:.3g} 95th percentile (standard error of a probe's mean ray radiance){}\n",
               noise, lighting["noise_p95"].get<float>(),
               noise > kVisibleProbeNoise
                   ? fmt::format("; above {} the lookup shows blotches: 4x --light-rays halves it", kVisibleProbeNoise)
                   : "");
  }
  fmt::print("svo          {} nodes, {} leaves, {} bytes ({} solid and {} uncovered voxels left empty)\n",
             j["svo"]["nodes"].get<int>(), j["svo"]["leaves"].get<int>(), j["svo"]["bytes"].get<std::size_t>(),
             j["svo"]["solid_voxels"].get<int>(), j["svo"]["uncovered_voxels"].get<int>());
  const auto& gpu_scene = j["runtime_lighting"];
  if (gpu_scene["written"].get<bool>())
    fmt::print("gpu scene    {} triangles ({} vertices, {} materials) in {} BVH nodes (depth {}): {:.1f} B per "
               "triangle; {} lights, "
               "{} emitter patches, {} dynamic objects, {} bytes; BVH {:.1f} ms\n",
               gpu_scene["triangles"].get<int>(), gpu_scene["vertices"].get<int>(), gpu_scene["materials"].get<int>(),
               gpu_scene["bvh_nodes"].get<int>(), gpu_scene["bvh_depth"].get<int>(),
               gpu_scene["tracing_bytes_per_triangle"].get<double>(), gpu_scene["lights"].get<int>(),
               gpu_scene["emitter_patches"].get<int>(), gpu_scene["dynamic_objects"].get<int>(),
               gpu_scene["bytes"].get<std::size_t>(), 1e3 * gpu_scene["bvh_seconds"].get<double>());
  const auto& cells = j["cells"];
  fmt::print("cells        {} of {:.4g} m (depth {}), {} bytes in cells, largest {}{}\n",
             cells["count"].get<std::size_t>(), cells["size"].get<float>(), cells["depth"].get<int>(),
             cells["bytes"].get<std::uint64_t>(), cells["largest_bytes"].get<std::uint64_t>(),
             cells["split_tracing"].get<bool>() ? " (tracing split by cell)" : "");
  fmt::print("sections    ");
  for (const auto& [name, bytes] : j["sections"].items())
    if (bytes.get<std::size_t>() > 0) fmt::print(" {}:{}", name, bytes.get<std::size_t>());
  fmt::print("\nstages      ");
  for (const auto& [name, seconds] : j["stages"].items()) fmt::print(" {}:{:.3f}s", name, seconds.get<double>());
  fmt::print("\ntotal        {:.3f} s\n", j["seconds"].get<double>());
}

} // namespace probebake::cli
