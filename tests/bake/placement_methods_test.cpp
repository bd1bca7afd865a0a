// Every row of the placement kinds table bakes through its own method: the file records the row's code
// and only the settings the row uses, probes sit in octree leaves exactly when the row says so, and the
// bake places what the method (called directly through the placement interface) places.
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/common/lattice.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/placement_kind.h"
#include "probebake/formats/validate.h"
#include "probebake/placement/placement.h"
#include "probebake/samples/scenes.h"
#include "probebake/scene/ray_scene.h"

namespace probebake::test {
namespace {

TEST(PlacementMethods, EachKindNamesItsOwnFunction) {
  EXPECT_EQ(placement::placement_method(formats::PlacementKind::octree), &placement::place_octree);
  EXPECT_EQ(placement::placement_method(formats::PlacementKind::grid), &placement::place_grid);
  for (const formats::PlacementKindInfo& k : formats::placement_kinds())
    EXPECT_NE(placement::placement_method(k.kind), nullptr);
}

TEST(PlacementMethods, EveryKindBakesAsItsRowSays) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell_kinds");
  for (const formats::PlacementKindInfo& k : formats::placement_kinds()) {
    SCOPED_TRACE(std::string(k.name));
    bake::BakeSettings settings = test_settings();
    settings.placement = k.kind;
    settings.grid_resolution = 5;
    settings.lighting.enabled = false;
    settings.runtime_lighting = false;
    const bake::BakeResult r = bake::bake(s, settings);
    EXPECT_TRUE(formats::validate(r.volume).valid());
    const gpu::VolumeInfo& info = r.volume.info;
    EXPECT_EQ(info.placement, k.file_code);
    EXPECT_EQ(info.max_depth, k.uses_max_depth ? settings.max_depth : 0);
    EXPECT_EQ(info.grid_resolution, k.uses_grid_resolution ? settings.grid_resolution : 0);
    ASSERT_GT(r.report.probes, 0);
    for (const gpu::Probe& p : r.volume.probes) {
      if (p.link == 0) continue; // free
      if (k.has_octree) {
        EXPECT_GE(p.node, 0);
      } else {
        EXPECT_EQ(p.node, -1);
      }
    }
    if (!k.has_octree) {
      EXPECT_EQ(r.volume.octree.front(), 0); // a bare root
    }

    // The placement interface on its own places what the bake placed before relocation.
    const scene::RayScene rays(s);
    formats::ProbeVolume volume = formats::make_empty_volume(bake::volume_info(s, settings));
    formats::Octree tree(volume);
    placement::PlacementInput in;
    in.rays = &rays;
    in.settings = {settings.max_depth, settings.split_low, settings.split_high, settings.grid_resolution, 1};
    in.directions = lattice_directions(settings.lattice, settings.surfels_per_probe);
    in.clearance = r.report.clearance;
    const std::vector<placement::PlacedProbe> placed = placement::place(k.kind, in, tree, s.bounds);
    EXPECT_EQ(int(placed.size()), r.report.placed_probes);
  }
}

} // namespace
} // namespace probebake::test
