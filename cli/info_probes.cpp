// `probebake info FILE.probes`: what a baked file holds (sections and bytes, counts, depth histogram,
// cells, bake settings), as text or JSON.
#include "info_probes.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "probebake/common/lattice.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/container.h"
#include "probebake/formats/placement_kind.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/file_mapping.h"
#include "probebake/formats/trace_mesh.h"
#include "probebake/formats/volume_stats.h"

namespace probebake::cli {
namespace {

struct ProbesInfo {
  std::string path;
  std::size_t file_size = 0;
  formats::ContainerView container;
  formats::ProbeVolume volume;  // without its trace nodes, faces and vertices: those stay in the mapping
  formats::TracingView tracing; // the three, in the mapping
  formats::VolumeStats stats;
};

std::string placement_name(int code) {
  const formats::PlacementKindInfo* kind = formats::placement_kind_for_code(code);
  return kind != nullptr ? std::string(kind->name) : fmt::format("unknown ({})", code);
}

// The file stores the bake's Lattice value (VolumeInfo.lattice); a code outside it reads as the default.
static_assert(int(Lattice::fibonacci) == gpu::LATTICE_FIBONACCI && int(Lattice::latlong) == gpu::LATTICE_LATLONG &&
              int(Lattice::equal_area) == gpu::LATTICE_EQUAL_AREA);
std::string lattice_name(int code) {
  const bool known = code >= gpu::LATTICE_FIBONACCI && code <= gpu::LATTICE_EQUAL_AREA;
  return std::string(probebake::lattice_name(known ? Lattice(code) : Lattice::fibonacci));
}

nlohmann::json vec_json(const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json range_json(const formats::CellRange& r) {
  return {{"first", r.first}, {"count", r.count}, {"byte_offset", r.byte_offset}, {"bytes", r.byte_size}};
}

nlohmann::json settings_json(const gpu::VolumeInfo& info) {
  return {{"placement", placement_name(info.placement)},
          {"root_min", vec_json(info.root_min)},
          {"root_size", info.root_size},
          {"max_depth", info.max_depth},
          {"svo_depth", info.svo_depth},
          {"lattice", lattice_name(info.lattice)},
          {"surfels_per_probe", info.surfels_per_probe},
          {"split_low", info.split_low},
          {"split_high", info.split_high},
          {"grid_resolution", info.grid_resolution}};
}

// What a game keeps on the GPU to answer lookups (formats::lookup_bytes): through the SVO, and through a grid
// bake's lattice (null without one); with float probes, and with the compact l2 and l1 codes.
nlohmann::json lookup_bytes_json(const formats::ProbeVolume& v) {
  nlohmann::json out;
  for (formats::ShCodec codec : formats::kShCodecs) {
    const std::string suffix =
        codec == formats::ShCodec::float32 ? "" : "_" + std::string(formats::sh_codec_name(codec));
    out["svo" + suffix] = formats::lookup_bytes(v, formats::LookupIndex::svo, codec);
    out["grid_lattice" + suffix] =
        v.grid_lattice.empty() ? nlohmann::json(nullptr)
                               : nlohmann::json(formats::lookup_bytes(v, formats::LookupIndex::grid_lattice, codec));
  }
  return out;
}

// What the runtime traces: triangles, and the bytes of the tracing sections per triangle (issue #14).
nlohmann::json tracing_json(const ProbesInfo& in) {
  const formats::ProbeVolume& v = in.volume;
  const std::size_t triangles = v.trace_triangles.size() + in.tracing.faces.size();
  const std::size_t bytes = formats::tracing_bytes(v) + in.tracing.nodes.size_bytes() + in.tracing.faces.size_bytes() +
                            in.tracing.vertices.size_bytes();
  return {{"triangles", triangles},
          {"bytes", bytes},
          {"bytes_per_triangle", triangles > 0 ? double(bytes) / double(triangles) : 0.0},
          {"layout", formats::has_float_tracing(v) ? "float (1.1-1.3)" : "compact"}};
}

// What streams (docs/RUNTIME.md "Streaming cells"): a streaming runtime loads every byte of the file but the
// cells' tracing ranges whole, at load; each cell's tracing is read when the cell loads and takes a block of
// the device budget. Null without split tracing.
nlohmann::json streaming_json(const ProbesInfo& in) {
  const formats::ProbeVolume& v = in.volume;
  if (v.cell_tracing.empty()) return nullptr;
  std::vector<std::uint64_t> sizes;
  std::uint64_t total = 0;
  for (const formats::CellTracing& t : v.cell_tracing) {
    sizes.push_back(formats::cell_tracing_bytes(t));
    total += sizes.back();
  }
  std::sort(sizes.begin(), sizes.end());
  const auto with_faces = std::size_t(std::count_if(sizes.begin(), sizes.end(), [](std::uint64_t b) { return b > 0; }));
  return {{"global_bytes", in.file_size - total},
          {"cell_tracing_bytes", total},
          {"cells_with_faces", with_faces},
          {"largest_cell_tracing_bytes", sizes.back()},
          {"median_cell_tracing_bytes", with_faces > 0 ? sizes[sizes.size() - with_faces + with_faces / 2] : 0u}};
}

nlohmann::json info_json(const ProbesInfo& in) {
  const formats::ProbeVolume& v = in.volume;
  nlohmann::json sections = nlohmann::json::array();
  for (const formats::SectionEntry& e : in.container.sections) {
    sections.push_back({{"name", formats::section_name(e.type)},
                        {"type", e.type},
                        {"offset", e.offset},
                        {"bytes", e.size},
                        {"element_size", e.element_size},
                        {"elements", e.element_count},
                        {"required", (e.flags & formats::kSectionRequired) != 0}});
  }
  nlohmann::json cells = nlohmann::json::array();
  for (std::size_t k = 0; k < v.cells.size(); ++k) {
    const formats::Cell& c = v.cells[k];
    nlohmann::json cell = {{"index", c.cell_index},
                           {"bounds_min", vec_json(c.bounds_min)},
                           {"bounds_max", vec_json(c.bounds_max)},
                           {"root_node", c.root_node},
                           {"probes", range_json(c.probes)},
                           {"surfel_batches", range_json(c.surfel_batches)},
                           {"svo_leaves", range_json(c.svo_leaves)},
                           {"bytes", formats::cell_bytes(v, k)}};
    if (k < v.cell_tracing.size()) {
      const formats::CellTracing& t = v.cell_tracing[k];
      cell["trace_nodes"] = range_json(t.trace_nodes), cell["trace_faces"] = range_json(t.trace_faces),
      cell["trace_vertices"] = range_json(t.trace_vertices);
    }
    cells.push_back(cell);
  }
  const formats::FileHeader& h = in.container.header;
  return {
      {"file", in.path},
      {"format_version", fmt::format("{}.{}", h.version_major, h.version_minor)},
      {"file_size", in.file_size},
      {"input_hash", fmt::format("{:016x}", h.input_hash)},
      {"settings", settings_json(v.info)},
      {"probes", in.stats.probes},
      {"probe_capacity", v.probes.size()},
      {"nodes", in.stats.nodes},
      {"leaves", in.stats.leaves},
      {"clusters", in.stats.clusters},
      {"octree_elements", v.octree.size()},
      {"max_depth", in.stats.max_depth},
      {"depth_histogram", in.stats.probes_per_depth},
      {"surfel_batches", in.stats.surfel_batches},
      {"batch_capacity", v.surfel_batches.size()},
      {"surfels", in.stats.surfels},
      {"svo",
       {{"nodes", v.svo_nodes.size()}, {"leaf_voxels", in.stats.svo_leaf_voxels}, {"payloads", v.svo_leaves.size()}}},
      {"leaf_queue", v.leaf_entries.empty() ? nlohmann::json(nullptr)
                                            : nlohmann::json{{"segment_capacity", v.leaf_header.segment_capacity},
                                                             {"pull_origin", v.leaf_header.pull_origin},
                                                             {"counts", v.leaf_header.count}}},
      {"lookup_bytes", lookup_bytes_json(v)},
      {"sections", sections},
      {"tracing", tracing_json(in)},
      {"cell_depth", v.cell_depth},
      {"streaming", streaming_json(in)},
      {"cells", cells}};
}

void print_text(const ProbesInfo& in) {
  const formats::ProbeVolume& v = in.volume;
  const gpu::VolumeInfo& s = v.info;
  const formats::FileHeader& h = in.container.header;
  fmt::print("file         {} (.probes {}.{}, {} bytes, input hash {:016x})\n", in.path, h.version_major,
             h.version_minor, in.file_size, h.input_hash);
  fmt::print("placement    {}, root ({:.4g}, {:.4g}, {:.4g}) size {:.4g}, max depth {}, svo depth {}\n",
             placement_name(s.placement), s.root_min.x, s.root_min.y, s.root_min.z, s.root_size, s.max_depth,
             s.svo_depth);
  fmt::print("surfels      {} lattice, {} per probe, split below {:.4g} / at {:.4g}\n", lattice_name(s.lattice),
             s.surfels_per_probe, s.split_low, s.split_high);
  fmt::print("probes       {} of {} allocated\n", in.stats.probes, v.probes.size());
  fmt::print("octree       {} nodes, {} leaves, {} clusters, max depth {}\n", in.stats.nodes, in.stats.leaves,
             in.stats.clusters, in.stats.max_depth);
  for (std::size_t depth = 0; depth < in.stats.probes_per_depth.size(); ++depth) {
    fmt::print("  depth {:<2}   {} probes\n", depth, in.stats.probes_per_depth[depth]);
  }
  fmt::print("batches      {} of {} allocated, {} surfels\n", in.stats.surfel_batches, v.surfel_batches.size(),
             in.stats.surfels);
  fmt::print("svo          {} nodes, {} leaf voxels, {} payloads\n", v.svo_nodes.size(), in.stats.svo_leaf_voxels,
             v.svo_leaves.size());
  const double per_probe = 1.0 / double(std::max(in.stats.probes, 1));
  const std::uint64_t svo_bytes = formats::lookup_bytes(v, formats::LookupIndex::svo);
  fmt::print("lookup       {} B through the SVO ({:.0f} B per probe)", svo_bytes, double(svo_bytes) * per_probe);
  if (!v.grid_lattice.empty()) {
    const std::uint64_t grid_bytes = formats::lookup_bytes(v, formats::LookupIndex::grid_lattice);
    fmt::print(", {} B through the grid lattice ({:.0f} B per probe)", grid_bytes, double(grid_bytes) * per_probe);
  }
  const formats::LookupIndex index =
      v.grid_lattice.empty() ? formats::LookupIndex::svo : formats::LookupIndex::grid_lattice;
  fmt::print("; with compact probes {} B (l2), {} B (l1)\n", formats::lookup_bytes(v, index, formats::ShCodec::l2),
             formats::lookup_bytes(v, index, formats::ShCodec::l1));
  fmt::print("sections     {:<18} {:>10} {:>12} {:>10}\n", "name", "offset", "bytes", "elements");
  for (const formats::SectionEntry& e : in.container.sections) {
    fmt::print("             {:<18} {:>10} {:>12} {:>10}{}\n", formats::section_name(e.type), e.offset, e.size,
               e.element_count, (e.flags & formats::kSectionRequired) != 0 ? "" : "  (optional)");
  }
  if (v.lighting) {
    const nlohmann::json tracing = tracing_json(in);
    fmt::print("tracing      {} triangles, {} bytes, {:.1f} B per triangle ({} layout)\n",
               tracing["triangles"].get<std::size_t>(), tracing["bytes"].get<std::size_t>(),
               tracing["bytes_per_triangle"].get<double>(), tracing["layout"].get<std::string>());
  }
  fmt::print("cells        {} (depth {})\n", v.cells.size(), v.cell_depth);
  if (const nlohmann::json streaming = streaming_json(in); !streaming.is_null())
    fmt::print(
        "streaming    {} B load whole; {} B of tracing in {} cells with faces stream (largest {} B, median {} B)\n",
        streaming["global_bytes"].get<std::uint64_t>(), streaming["cell_tracing_bytes"].get<std::uint64_t>(),
        streaming["cells_with_faces"].get<std::size_t>(), streaming["largest_cell_tracing_bytes"].get<std::uint64_t>(),
        streaming["median_cell_tracing_bytes"].get<std::uint64_t>());
  for (std::size_t k = 0; k < v.cells.size(); ++k) {
    const formats::Cell& c = v.cells[k];
    std::string tracing;
    if (k < v.cell_tracing.size()) {
      const formats::CellTracing& t = v.cell_tracing[k];
      tracing = fmt::format(", {} trace faces ({} B with {} nodes and {} vertices)", t.trace_faces.count,
                            t.trace_nodes.byte_size + t.trace_faces.byte_size + t.trace_vertices.byte_size,
                            t.trace_nodes.count, t.trace_vertices.count);
    }
    fmt::print("  cell {:<5} {:>10} B  root node {:<5} {} probes ({} B), {} batches ({} B), {} svo leaves ({} B){}\n",
               c.cell_index, formats::cell_bytes(v, k), c.root_node, c.probes.count, c.probes.byte_size,
               c.surfel_batches.count, c.surfel_batches.byte_size, c.svo_leaves.count, c.svo_leaves.byte_size, tracing);
  }
}

} // namespace

int run_info_probes(const std::string& path, bool json) {
  ProbesInfo in;
  in.path = path;
  // Mapped, the tracing sections read in place: a world larger than memory prints too (file_mapping.h).
  const formats::MappedReadGuard guard("probebake", path);
  const formats::FileMapping file = formats::FileMapping::of(path);
  in.file_size = file.bytes().size();
  in.container = formats::parse_container(
      file.bytes(), path, [&](const std::string& section, long long, const std::string& message) {
        fmt::print(stderr, "probebake: warning: {}: {}: {} (run probebake validate)\n", path, section, message);
      });
  in.volume = formats::decode_probes(in.container, path, formats::TraceSections::leave_in_bytes);
  in.tracing = formats::tracing_in(in.container, path);
  in.stats = formats::compute_stats(in.volume);
  if (json) {
    std::puts(info_json(in).dump(2).c_str());
  } else {
    print_text(in);
  }
  return 0;
}

} // namespace probebake::cli
