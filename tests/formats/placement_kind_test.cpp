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
  // Written out here, not read from the table: a changed row must change this test too.
  struct Expected {
    PlacementKind kind;
    const char* name;
    int file_code;
    bool has_octree, uses_max_depth, uses_grid_resolution;
    float root_pad_clearances;
  };
  const Expected expected[] = {
      {PlacementKind::octree, "octree", gpu::PLACEMENT_OCTREE, true, true, false, 0.0f},
      {PlacementKind::grid, "grid", gpu::PLACEMENT_GRID, false, false, true, 0.0f},
      {PlacementKind::skeleton, "skeleton", gpu::PLACEMENT_SKELETON, false, false, false, 3.0f},
  };
  for (const Expected& e : expected) {
    const PlacementKindInfo& info = placement_kind_info(e.kind);
    EXPECT_EQ(info.name, e.name);
    EXPECT_EQ(info.file_code, e.file_code) << e.name;
    EXPECT_EQ(info.has_octree, e.has_octree) << e.name;
    EXPECT_EQ(info.uses_max_depth, e.uses_max_depth) << e.name;
    EXPECT_EQ(info.uses_grid_resolution, e.uses_grid_resolution) << e.name;
    EXPECT_EQ(info.root_pad_clearances, e.root_pad_clearances) << e.name;
  }
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
