// docs/FORMAT.md cannot drift from the code: its `<!-- layout: X -->` tables must list every field of X
// in order with the exact offsetof/sizeof, the section type table must match the writer, and the
// invariant table must list exactly the validator's invariant ids.
#include <cstddef>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "probebake/formats/bake_part.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/container.h"
#include "probebake/formats/format_version.h"
#include "probebake/sky_map.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "sample_volumes.h"

namespace probebake::formats {
namespace {

using Row = std::vector<std::string>;

struct Field {
  std::string name;
  std::size_t offset;
  std::size_t size;
};

struct Layout {
  std::vector<Field> fields;
  std::size_t size;
};

#define FIELD(T, f) (Field{#f, offsetof(T, f), sizeof(T::f)})

const std::map<std::string, Layout>& code_layouts() {
  static const std::map<std::string, Layout> layouts = {
      {"FileHeader",
       {{FIELD(FileHeader, magic), FIELD(FileHeader, version_major), FIELD(FileHeader, version_minor),
         FIELD(FileHeader, header_size), FIELD(FileHeader, required_features), FIELD(FileHeader, section_count),
         FIELD(FileHeader, section_entry_size), FIELD(FileHeader, cell_depth), FIELD(FileHeader, input_hash),
         FIELD(FileHeader, file_size), FIELD(FileHeader, reserved), FIELD(FileHeader, header_checksum)},
        sizeof(FileHeader)}},
      {"SectionEntry",
       {{FIELD(SectionEntry, type), FIELD(SectionEntry, flags), FIELD(SectionEntry, offset), FIELD(SectionEntry, size),
         FIELD(SectionEntry, alignment), FIELD(SectionEntry, element_size), FIELD(SectionEntry, element_count),
         FIELD(SectionEntry, checksum)},
        sizeof(SectionEntry)}},
      {"VolumeInfo",
       {{FIELD(gpu::VolumeInfo, root_min), FIELD(gpu::VolumeInfo, root_size), FIELD(gpu::VolumeInfo, placement),
         FIELD(gpu::VolumeInfo, max_depth), FIELD(gpu::VolumeInfo, svo_depth), FIELD(gpu::VolumeInfo, lattice),
         FIELD(gpu::VolumeInfo, surfels_per_probe), FIELD(gpu::VolumeInfo, split_low),
         FIELD(gpu::VolumeInfo, split_high), FIELD(gpu::VolumeInfo, grid_resolution),
         FIELD(gpu::VolumeInfo, probe_capacity), FIELD(gpu::VolumeInfo, batch_capacity),
         FIELD(gpu::VolumeInfo, octree_elements), FIELD(gpu::VolumeInfo, svo_nodes), FIELD(gpu::VolumeInfo, svo_leaves),
         FIELD(gpu::VolumeInfo, pad0), FIELD(gpu::VolumeInfo, pad1), FIELD(gpu::VolumeInfo, pad2)},
        sizeof(gpu::VolumeInfo)}},
      {"Probe",
       {{FIELD(gpu::Probe, position), FIELD(gpu::Probe, link), FIELD(gpu::Probe, node), FIELD(gpu::Probe, depth),
         FIELD(gpu::Probe, hit_fraction), FIELD(gpu::Probe, backface_fraction), FIELD(gpu::Probe, irradiance_sh),
         FIELD(gpu::Probe, pad0)},
        sizeof(gpu::Probe)}},
      {"Surfel",
       {{FIELD(gpu::Surfel, position), FIELD(gpu::Surfel, distance), FIELD(gpu::Surfel, normal),
         FIELD(gpu::Surfel, flags), FIELD(gpu::Surfel, albedo), FIELD(gpu::Surfel, pad0), FIELD(gpu::Surfel, radiance),
         FIELD(gpu::Surfel, pad1)},
        sizeof(gpu::Surfel)}},
      {"SurfelBatch",
       {{FIELD(gpu::SurfelBatch, link), FIELD(gpu::SurfelBatch, probe), FIELD(gpu::SurfelBatch, count),
         FIELD(gpu::SurfelBatch, first), FIELD(gpu::SurfelBatch, surfels)},
        sizeof(gpu::SurfelBatch)}},
      {"LeafQueueHeader",
       {{FIELD(gpu::LeafQueueHeader, pull_origin), FIELD(gpu::LeafQueueHeader, segment_capacity),
         FIELD(gpu::LeafQueueHeader, count), FIELD(gpu::LeafQueueHeader, pad0), FIELD(gpu::LeafQueueHeader, pad1),
         FIELD(gpu::LeafQueueHeader, pad2)},
        sizeof(gpu::LeafQueueHeader)}},
      {"LeafEntry", {{FIELD(gpu::LeafEntry, node), FIELD(gpu::LeafEntry, state)}, sizeof(gpu::LeafEntry)}},
      {"SvoLeaf", {{FIELD(gpu::SvoLeaf, probes), FIELD(gpu::SvoLeaf, weights)}, sizeof(gpu::SvoLeaf)}},
      {"Cell",
       {{FIELD(Cell, bounds_min), FIELD(Cell, root_node), FIELD(Cell, bounds_max), FIELD(Cell, cell_index),
         FIELD(Cell, probes), FIELD(Cell, surfel_batches), FIELD(Cell, svo_leaves)},
        sizeof(Cell)}},
      {"CellTracing",
       {{FIELD(CellTracing, trace_nodes), FIELD(CellTracing, trace_faces), FIELD(CellTracing, trace_vertices)},
        sizeof(CellTracing)}},
      {"PartInfo",
       {{FIELD(PartInfo, scene_triangles), FIELD(PartInfo, cell_count), FIELD(PartInfo, tested_triangles),
         FIELD(PartInfo, reserved)},
        sizeof(PartInfo)}},
      {"CellRange",
       {{FIELD(CellRange, first), FIELD(CellRange, count), FIELD(CellRange, byte_offset), FIELD(CellRange, byte_size)},
        sizeof(CellRange)}},
      {"LightingInfo",
       {{FIELD(gpu::LightingInfo, sky_radiance), FIELD(gpu::LightingInfo, rays),
         FIELD(gpu::LightingInfo, shadow_offset), FIELD(gpu::LightingInfo, emissive_as_lights),
         FIELD(gpu::LightingInfo, bvh_nodes), FIELD(gpu::LightingInfo, triangles), FIELD(gpu::LightingInfo, lights),
         FIELD(gpu::LightingInfo, emitter_patches), FIELD(gpu::LightingInfo, placement_rays),
         FIELD(gpu::LightingInfo, dynamic_objects)},
        sizeof(gpu::LightingInfo)}},
      {"BvhNode",
       {{FIELD(gpu::BvhNode, lower), FIELD(gpu::BvhNode, first), FIELD(gpu::BvhNode, upper),
         FIELD(gpu::BvhNode, count)},
        sizeof(gpu::BvhNode)}},
      {"TraceTriangle",
       {{FIELD(gpu::TraceTriangle, v0), FIELD(gpu::TraceTriangle, source), FIELD(gpu::TraceTriangle, edge1),
         FIELD(gpu::TraceTriangle, flags), FIELD(gpu::TraceTriangle, edge2), FIELD(gpu::TraceTriangle, pad1),
         FIELD(gpu::TraceTriangle, normal), FIELD(gpu::TraceTriangle, pad2), FIELD(gpu::TraceTriangle, albedo),
         FIELD(gpu::TraceTriangle, pad3), FIELD(gpu::TraceTriangle, emission), FIELD(gpu::TraceTriangle, pad4)},
        sizeof(gpu::TraceTriangle)}},
      {"TraceTree",
       {{FIELD(gpu::TraceTree, lower), FIELD(gpu::TraceTree, root), FIELD(gpu::TraceTree, scale),
         FIELD(gpu::TraceTree, node_count)},
        sizeof(gpu::TraceTree)}},
      {"TraceNode",
       {{FIELD(gpu::TraceNode, lower), FIELD(gpu::TraceNode, upper), FIELD(gpu::TraceNode, child)},
        sizeof(gpu::TraceNode)}},
      {"TraceFace", {{FIELD(gpu::TraceFace, vertex), FIELD(gpu::TraceFace, material)}, sizeof(gpu::TraceFace)}},
      {"GridLatticeHeader",
       {{FIELD(gpu::GridLatticeHeader, origin), FIELD(gpu::GridLatticeHeader, resolution),
         FIELD(gpu::GridLatticeHeader, spacing), FIELD(gpu::GridLatticeHeader, pad0)},
        sizeof(gpu::GridLatticeHeader)}},
      {"GridPoint", {{FIELD(gpu::GridPoint, probe_cells), FIELD(gpu::GridPoint, reach)}, sizeof(gpu::GridPoint)}},
      {"SkyHeader",
       {{FIELD(gpu::SkyHeader, width), FIELD(gpu::SkyHeader, height), FIELD(gpu::SkyHeader, kind),
         FIELD(gpu::SkyHeader, turbidity), FIELD(gpu::SkyHeader, sun_direction), FIELD(gpu::SkyHeader, sun_light)},
        sizeof(gpu::SkyHeader)}},
      {"TraceVertex",
       {{FIELD(gpu::TraceVertex, x), FIELD(gpu::TraceVertex, y), FIELD(gpu::TraceVertex, z)},
        sizeof(gpu::TraceVertex)}},
      {"TraceMaterial",
       {{FIELD(gpu::TraceMaterial, albedo), FIELD(gpu::TraceMaterial, pad0), FIELD(gpu::TraceMaterial, emission),
         FIELD(gpu::TraceMaterial, pad1)},
        sizeof(gpu::TraceMaterial)}},
      {"DynamicObject",
       {{FIELD(gpu::DynamicObject, lower), FIELD(gpu::DynamicObject, bvh_root), FIELD(gpu::DynamicObject, upper),
         FIELD(gpu::DynamicObject, bvh_node_count), FIELD(gpu::DynamicObject, first_triangle),
         FIELD(gpu::DynamicObject, triangle_count), FIELD(gpu::DynamicObject, gltf_node),
         FIELD(gpu::DynamicObject, pad0), FIELD(gpu::DynamicObject, rest_rows)},
        sizeof(gpu::DynamicObject)}},
      {"PunctualLight",
       {{FIELD(gpu::PunctualLight, position), FIELD(gpu::PunctualLight, type), FIELD(gpu::PunctualLight, direction),
         FIELD(gpu::PunctualLight, range), FIELD(gpu::PunctualLight, intensity), FIELD(gpu::PunctualLight, cos_outer),
         FIELD(gpu::PunctualLight, spot_scale), FIELD(gpu::PunctualLight, pad0), FIELD(gpu::PunctualLight, pad1),
         FIELD(gpu::PunctualLight, pad2)},
        sizeof(gpu::PunctualLight)}},
      {"EmitterPatch",
       {{FIELD(gpu::EmitterPatch, a), FIELD(gpu::EmitterPatch, flags), FIELD(gpu::EmitterPatch, b),
         FIELD(gpu::EmitterPatch, emitter), FIELD(gpu::EmitterPatch, c), FIELD(gpu::EmitterPatch, material),
         FIELD(gpu::EmitterPatch, normal), FIELD(gpu::EmitterPatch, pad3), FIELD(gpu::EmitterPatch, radiance),
         FIELD(gpu::EmitterPatch, pad4)},
        sizeof(gpu::EmitterPatch)}},
  };
  return layouts;
}

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t`");
  const auto last = text.find_last_not_of(" \t`");
  return first == std::string::npos ? "" : text.substr(first, last - first + 1);
}

// Tables of docs/FORMAT.md keyed by the HTML comment above them ("layout: Probe", "invariants", ...);
// header and separator rows dropped.
std::map<std::string, std::vector<Row>> doc_tables() {
  std::ifstream file(PROBEBAKE_FORMAT_DOC);
  EXPECT_TRUE(file) << PROBEBAKE_FORMAT_DOC;
  std::map<std::string, std::vector<Row>> tables;
  std::string line, key;
  int rows_seen = 0;
  while (std::getline(file, line)) {
    if (line.rfind("<!--", 0) == 0) {
      key = trim(line.substr(4, line.find("-->") - 4));
      rows_seen = 0;
      tables[key];
    } else if (!key.empty() && line.rfind("|", 0) == 0) {
      if (rows_seen++ < 2) continue; // header and separator
      Row row;
      std::stringstream cells(line.substr(1));
      std::string cell;
      while (std::getline(cells, cell, '|')) row.push_back(trim(cell));
      tables[key].push_back(row);
    } else if (!key.empty() && rows_seen > 0) {
      key.clear();
    }
  }
  return tables;
}

TEST(FormatDoc, EveryLayoutTableMatchesTheCode) {
  const auto tables = doc_tables();
  for (const auto& [name, layout] : code_layouts()) {
    const auto table = tables.find("layout: " + name);
    ASSERT_NE(table, tables.end()) << "docs/FORMAT.md has no table for " << name;
    ASSERT_EQ(table->second.size(), layout.fields.size()) << name;
    std::size_t expected_offset = 0;
    for (std::size_t i = 0; i < layout.fields.size(); ++i) {
      const Row& row = table->second[i];
      const Field& field = layout.fields[i];
      ASSERT_GE(row.size(), 3u) << name;
      EXPECT_EQ(row[0], field.name) << name;
      EXPECT_EQ(std::stoul(row[1]), field.offset) << name << "." << field.name;
      EXPECT_EQ(std::stoul(row[2]), field.size) << name << "." << field.name;
      EXPECT_EQ(field.offset, expected_offset) << name << "." << field.name << ": the fields must tile the struct";
      expected_offset = field.offset + field.size;
    }
    EXPECT_EQ(expected_offset, layout.size) << name;
  }
  for (const auto& [key, rows] : tables) {
    if (key.rfind("layout: ", 0) == 0 && key != "layout: section_types") {
      EXPECT_TRUE(code_layouts().count(key.substr(8))) << "stale table " << key;
    }
  }
}

TEST(FormatDoc, SectionTypesMatchTheWriter) {
  const std::map<std::string, std::size_t> element_sizes = {{"volume_info", sizeof(gpu::VolumeInfo)},
                                                            {"octree", 4},
                                                            {"probes", sizeof(gpu::Probe)},
                                                            {"surfel_batches", sizeof(gpu::SurfelBatch)},
                                                            {"leaf_queue_header", sizeof(gpu::LeafQueueHeader)},
                                                            {"leaf_entries", sizeof(gpu::LeafEntry)},
                                                            {"probe_index", 4},
                                                            {"svo_nodes", 4},
                                                            {"svo_leaves", sizeof(gpu::SvoLeaf)},
                                                            {"cells", sizeof(Cell)},
                                                            {"lighting_info", sizeof(gpu::LightingInfo)},
                                                            {"ray_directions", 16},
                                                            {"bvh_nodes", sizeof(gpu::BvhNode)},
                                                            {"trace_triangles", sizeof(gpu::TraceTriangle)},
                                                            {"punctual_lights", sizeof(gpu::PunctualLight)},
                                                            {"emitter_patches", sizeof(gpu::EmitterPatch)},
                                                            {"dynamic_objects", sizeof(gpu::DynamicObject)},
                                                            {"trace_trees", sizeof(gpu::TraceTree)},
                                                            {"trace_nodes", sizeof(gpu::TraceNode)},
                                                            {"trace_faces", sizeof(gpu::TraceFace)},
                                                            {"trace_vertices", sizeof(gpu::TraceVertex)},
                                                            {"trace_materials", sizeof(gpu::TraceMaterial)},
                                                            {"cell_tracing", sizeof(CellTracing)},
                                                            {"cell_checksums", 8},
                                                            {"cell_global_checksums", 8},
                                                            {"grid_lattice", 4},
                                                            {"sky", 4}};
  const std::vector<Row> rows = doc_tables()["layout: section_types"];
  ASSERT_EQ(rows.size(), kSectionTypeCount);
  // Between them the four samples hold every section type.
  std::vector<SectionEntry> entries;
  for (testing::Sample sample :
       {testing::Sample::small, testing::Sample::lighting, testing::Sample::dynamic, testing::Sample::compact}) {
    const std::vector<std::uint8_t> bytes = write_probes(testing::make_sample(sample));
    const ContainerView view = parse_container(bytes, testing::sample_name(sample));
    entries.insert(entries.end(), view.sections.begin(), view.sections.end());
  }
  ProbeVolume with_cell_tracing =
      testing::make_sample(testing::Sample::small); // the bake's (gpu_scene_tests) in the writer's layout
  with_cell_tracing.cell_tracing.resize(with_cell_tracing.cells.size());
  const std::vector<std::uint8_t> cell_bytes = write_probes(with_cell_tracing);
  const ContainerView cell_view = parse_container(cell_bytes, "cell_tracing");
  entries.insert(entries.end(), cell_view.sections.begin(), cell_view.sections.end());
  const std::vector<std::uint8_t> sky_bytes = write_probes(testing::make_sample(testing::Sample::sky));
  const ContainerView sky_view = parse_container(sky_bytes, "sky");
  entries.insert(entries.end(), sky_view.sections.begin(), sky_view.sections.end());
  const std::vector<std::uint8_t> lattice_bytes = write_probes(testing::make_sample(testing::Sample::grid_lattice));
  const ContainerView lattice_view = parse_container(lattice_bytes, "grid_lattice");
  entries.insert(entries.end(), lattice_view.sections.begin(), lattice_view.sections.end());
  for (const Row& row : rows) {
    const std::uint32_t id = static_cast<std::uint32_t>(std::stoul(row[1]));
    EXPECT_EQ(section_name(id), row[0]);
    EXPECT_EQ(std::stoul(row[2]), element_sizes.at(row[0])) << row[0];
    bool written = false;
    for (const SectionEntry& entry : entries) {
      if (entry.type != id) continue;
      written = true;
      EXPECT_EQ(entry.element_size, std::stoul(row[2])) << row[0];
      EXPECT_EQ((entry.flags & kSectionRequired) != 0, row[4] == "required") << row[0];
    }
    EXPECT_TRUE(written) << row[0];
  }
}

TEST(FormatDoc, InvariantTableListsExactlyTheValidatorsIds) {
  std::set<std::string> documented, registered;
  const auto tables = doc_tables(); // kept alive: ranging over a member of a temporary would dangle
  for (const Row& row : tables.at("invariants")) documented.insert(row[0]);
  for (const InvariantInfo& info : invariants()) registered.insert(info.id);
  EXPECT_EQ(documented, registered);
}

TEST(FormatDoc, ConstantsMatch) {
  std::map<std::string, std::string> values;
  const auto tables = doc_tables();
  for (const Row& row : tables.at("constants")) values[row[0]] = row[1];
  EXPECT_EQ(values["header size (1.x)"], std::to_string(sizeof(FileHeader)));
  EXPECT_EQ(values["section entry size (1.x)"], std::to_string(sizeof(SectionEntry)));
  EXPECT_EQ(values["section alignment written"], std::to_string(kSectionAlignment));
  EXPECT_EQ(values["maximum section alignment"], std::to_string(kMaxSectionAlignment));
  EXPECT_EQ(values["maximum section count"], std::to_string(kMaxSections));
  EXPECT_EQ(values["REQUIRED flag"], std::to_string(kSectionRequired));
  EXPECT_EQ(values["maximum cell depth"], std::to_string(kMaxCellDepth));
  EXPECT_EQ(values["maximum grid resolution"], std::to_string(kMaxGridResolution));
  EXPECT_EQ(values["maximum surfels per probe"], std::to_string(kMaxSurfelsPerProbe));
  EXPECT_EQ(values["format major"], std::to_string(kFormatVersionMajor));
  EXPECT_EQ(values["format minor"], std::to_string(kFormatVersionMinor));
  EXPECT_EQ(values.size(), 11u);
}

} // namespace
} // namespace probebake::formats
