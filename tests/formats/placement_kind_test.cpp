// The placement kinds table (formats/placement_kind.h): one row per enum value in order, names and file
// codes unique and round-tripping, the properties of the two shipped methods, and the validator's use of
// them on sample volumes.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "probebake/formats/placement_kind.h"
#include "probebake/formats/validate.h"
#include "probebake/gpu_types.h"
#include "sample_volumes.h"

namespace probebake::formats {
namespace {

TEST(PlacementKinds, RowIIsKindIAndNamesAndCodesAreUnique) {
  std::set<std::string> names;
  std::set<int> codes;
  std::size_t i = 0;
  for (const PlacementKindInfo& k : placement_kinds()) {
    EXPECT_EQ(static_cast<std::size_t>(k.kind), i++);
    EXPECT_FALSE(k.name.empty());
    names.insert(std::string(k.name));
    codes.insert(k.file_code);
    // A method has a depth limit or a grid resolution or neither, never both.
    EXPECT_FALSE(k.uses_max_depth && k.uses_grid_resolution) << k.name;
  }
  EXPECT_EQ(names.size(), placement_kinds().size());
  EXPECT_EQ(codes.size(), placement_kinds().size()); // the file's code names one method
}

TEST(PlacementKinds, NameParseAndCodeRoundTrip) {
  for (const PlacementKindInfo& k : placement_kinds()) {
    EXPECT_EQ(placement_name(k.kind), k.name);
    ASSERT_EQ(parse_placement(k.name), k.kind);
    ASSERT_NE(placement_kind_for_code(k.file_code), nullptr);
    EXPECT_EQ(placement_kind_for_code(k.file_code)->kind, k.kind);
    EXPECT_EQ(&placement_kind_info(k.kind), &k);
  }
}

TEST(PlacementKinds, RejectsUnknownNamesAndCodes) {
  for (const char* name : {"", "Grid", "OCTREE", "octree ", " grid", "octree|grid", "uniform"}) {
    EXPECT_FALSE(parse_placement(name).has_value()) << '"' << name << '"';
  }
  for (int code : {-1, 3, 99, 1 << 30}) EXPECT_EQ(placement_kind_for_code(code), nullptr) << code;
}

TEST(PlacementKinds, OctreeAndGridProperties) {
  const PlacementKindInfo& octree = placement_kind_info(PlacementKind::octree);
  EXPECT_EQ(octree.name, "octree");
  EXPECT_EQ(octree.file_code, gpu::PLACEMENT_OCTREE);
  EXPECT_TRUE(octree.has_octree);
  EXPECT_TRUE(octree.uses_max_depth);
  EXPECT_FALSE(octree.uses_grid_resolution);
  const PlacementKindInfo& grid = placement_kind_info(PlacementKind::grid);
  EXPECT_EQ(grid.name, "grid");
  EXPECT_EQ(grid.file_code, gpu::PLACEMENT_GRID);
  EXPECT_FALSE(grid.has_octree);
  EXPECT_FALSE(grid.uses_max_depth);
  EXPECT_TRUE(grid.uses_grid_resolution);
  EXPECT_EQ(octree.root_pad_clearances, 0.0f);
  EXPECT_EQ(grid.root_pad_clearances, 0.0f);
  const PlacementKindInfo& skeleton = placement_kind_info(PlacementKind::skeleton);
  EXPECT_EQ(skeleton.name, "skeleton");
  EXPECT_EQ(skeleton.file_code, gpu::PLACEMENT_SKELETON);
  EXPECT_FALSE(skeleton.has_octree);
  EXPECT_FALSE(skeleton.uses_max_depth);
  EXPECT_FALSE(skeleton.uses_grid_resolution);
  EXPECT_EQ(skeleton.root_pad_clearances, 3.0f);
  EXPECT_EQ(placement_names(), "octree|grid|skeleton");
  EXPECT_EQ(placement_names(", "), "octree, grid, skeleton");
}

bool has_rule(const ValidationReport& r, const std::string& rule) {
  for (const Violation& v : r.violations)
    if (v.invariant == rule) return true;
  return false;
}

// The validator reads the table: a grid resolution only where the method uses one, and no code that no
// method writes.
TEST(PlacementKinds, ValidatorChecksGridResolutionAndCodeFromTheTable) {
  for (const testing::Sample sample : {testing::Sample::small, testing::Sample::grid}) {
    ProbeVolume volume = testing::make_sample(sample);
    ASSERT_TRUE(validate(volume).valid());
    const PlacementKindInfo* kind = placement_kind_for_code(volume.info.placement);
    ASSERT_NE(kind, nullptr);
    volume.info.grid_resolution = kind->uses_grid_resolution ? 0 : 3; // wrong either way
    EXPECT_TRUE(has_rule(validate(volume), "grid_resolution")) << kind->name;
  }
  ProbeVolume unknown = testing::make_sample(testing::Sample::small);
  unknown.info.placement = 7;
  EXPECT_TRUE(has_rule(validate(unknown), "volume_info"));
}

} // namespace
} // namespace probebake::formats
