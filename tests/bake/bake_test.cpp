// The bake on generated scenes: placement rules, relocation, SVO, determinism, validity.
#include <algorithm>
#include <cmath>
#include <thread>

#include <tbb/global_control.h>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/bake/ray_scene.h"
#include "probebake/formats/error.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "probebake/formats/volume_stats.h"
#include "probebake/samples/geometry.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

std::string violations(const formats::ValidationReport& r) {
  std::string out;
  for (const auto& v : r.violations) out += v.invariant + " @" + v.section + "[" + std::to_string(v.index) + "] " + v.message + "\n";
  return out;
}

void expect_valid(const formats::ProbeVolume& v) {
  const formats::ValidationReport report = formats::validate(v);
  EXPECT_TRUE(report.valid()) << violations(report);
}

// No probe inside geometry, none closer to a surface than the clearance (checked independently).
void expect_probes_outside_geometry(const scene::Scene& s, const bake::BakeResult& r) {
  const scene::RayScene rays(s);
  for (std::size_t i = 0; i < r.volume.probes.size(); ++i) {
    const gpu::Probe& p = r.volume.probes[i];
    if (p.link == 0) continue;
    EXPECT_FALSE(inside_geometry(rays, p.position)) << "probe " << i;
    EXPECT_GE(nearest_surface(rays, p.position), 0.99f * r.report.clearance) << "probe " << i;
  }
}

TEST(Bake, CornellOctreeIsValidSparseAndDeeperNearGeometry) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell");
  const bake::BakeResult r = bake::bake(s, test_settings());
  expect_valid(r.volume);
  expect_probes_outside_geometry(s, r);
  EXPECT_GT(r.report.probes, 8);
  EXPECT_LT(r.report.probes, 512); // the 21^3 grid has 9261
  // Deeper leaves where geometry is dense: probes at max depth are nearer to surfaces on average.
  const scene::RayScene rays(s);
  const int max_depth = test_settings().max_depth;
  double near_deep = 0, near_shallow = 0;
  int deep = 0, shallow = 0;
  for (const gpu::Probe& p : r.volume.probes) {
    if (p.link == 0) continue;
    const double nearest = nearest_surface(rays, p.position);
    EXPECT_GT(nearest, 0.0);
    (p.depth == max_depth ? near_deep : near_shallow) += nearest;
    (p.depth == max_depth ? deep : shallow) += 1;
  }
  ASSERT_GT(deep, 0);
  ASSERT_GT(shallow, 0);
  EXPECT_LT(near_deep / deep, near_shallow / shallow);
}

TEST(Bake, HitFractionRuleHolds) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell_rule");
  bake::BakeSettings settings = test_settings();
  const bake::BakeResult r = bake::bake(s, settings);
  for (const gpu::Probe& p : r.volume.probes) {
    if (p.link == 0) continue;
    EXPECT_GE(p.hit_fraction, settings.split_low);                                     // else freed
    if (p.depth < settings.max_depth) {
      EXPECT_LT(p.hit_fraction, settings.split_high); // else split
    }
  }
}

TEST(Bake, GridPlacesNCubedProbesOrFreesThoseInsideGeometry) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell_grid");
  bake::BakeSettings settings = test_settings();
  settings.placement = bake::Placement::grid;
  settings.grid_resolution = 9;
  const bake::BakeResult r = bake::bake(s, settings);
  expect_valid(r.volume);
  EXPECT_EQ(r.report.probes + r.report.freed_probes, 9 * 9 * 9);
  EXPECT_GT(r.report.moved_probes, 0); // the blocks cut through some cells
  expect_probes_outside_geometry(s, r);
}

TEST(Bake, DeterministicAcrossThreadCounts) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell_det");
  std::vector<std::vector<std::uint8_t>> files;
  for (const int threads : {1, 2, 8, 2}) {
    bake::BakeSettings settings = test_settings();
    settings.threads = threads;
    const bake::BakeResult r = bake::bake(s, settings);
    ASSERT_GT(r.report.moved_probes, 0); // the SDF (OpenVDB, its own TBB loops) ran too
    files.push_back(formats::write_probes(r.volume));
  }
  for (std::size_t i = 1; i < files.size(); ++i) EXPECT_EQ(files[0], files[i]) << "run " << i;
  // The runtime lighting sections (BVH included) are on by default and part of the compared bytes.
  const formats::ContainerView view = formats::parse_container(files[0], "a");
  EXPECT_EQ(view.header.version_minor, 1);
  EXPECT_EQ(view.sections.back().type, static_cast<std::uint32_t>(formats::SectionType::emitter_patches));
  bake::BakeSettings one = test_settings(), two = test_settings();
  one.threads = 1;
  two.threads = 2;
  EXPECT_EQ(bake::bake_input_hash(s, one), bake::bake_input_hash(s, two)); // threads are not an input
}

// Embree's "threads=1" device setting used to pin oneTBB's global concurrency to one thread for the whole
// process; building the ray scene must leave every core to the bake.
TEST(Bake, RayScenesDoNotPinTheProcessToOneThread) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell_threads");
  const std::size_t before = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  const scene::RayScene rays(s);
  EXPECT_EQ(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism), before);
  if (std::thread::hardware_concurrency() > 1) {
    EXPECT_GT(before, 1u);
  }
}

TEST(Bake, ProbeCentreOnAWallIsMoved) {
  // Furnace cube [-0.5, 0.5]^3 plus a wall through its centre: the root probe (max depth 0) sits on it.
  samples::SceneBuilder builder = samples::furnace({.albedo = 0.5f, .emission = 1.0f});
  const auto white = builder.add_material({.name = "wall"});
  const auto wall = builder.add_mesh("wall", samples::box({-0.01f, -0.5f, -0.5f}, {0.01f, 0.5f, 0.5f}, samples::Facing::outward), white);
  builder.add_mesh_node("wall", wall);
  const scene::Scene s = load_generated(builder, "wall");
  bake::BakeSettings settings = test_settings();
  settings.max_depth = 0;
  const bake::BakeResult r = bake::bake(s, settings);
  expect_valid(r.volume);
  ASSERT_EQ(r.report.probes, 1);
  EXPECT_EQ(r.report.dead_probes, 1);
  EXPECT_EQ(r.report.moved_probes, 1);
  const glm::vec3 p = r.volume.probes[0].position;
  EXPECT_GE(std::abs(p.x) - 0.01f, 0.99f * r.report.clearance);
  expect_probes_outside_geometry(s, r);
}

TEST(Bake, SingleTriangleGivesAValidSmallFile) {
  const scene::Scene s = load_generated(samples::triangle(), "triangle");
  bake::BakeSettings settings = test_settings();
  settings.placement = bake::Placement::grid;
  settings.grid_resolution = 4;
  const bake::BakeResult r = bake::bake(s, settings);
  expect_valid(r.volume);
  EXPECT_GT(r.report.probes, 0);
  EXPECT_LT(formats::write_probes(r.volume).size(), 64u * 1024u);
}

// Zero probes is never a silent success: the octree frees every probe around a lone triangle (hit
// fractions below LOW), and the bake says so instead of writing a file that answers nothing.
TEST(Bake, NoProbesPlacedIsAnInputError) {
  const scene::Scene s = load_generated(samples::triangle(), "triangle_octree");
  try {
    bake::bake(s, test_settings());
    ADD_FAILURE() << "a bake without probes succeeded";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_NE(std::string(e.what()).find("no probes placed"), std::string::npos) << e.what();
  }
}

// Over the whole range a glTF node scale can express, a bake either writes a file that validates, with
// probes, or refuses with the reason; never an internal error, a silent empty file or an invalid one.
TEST(Bake, ExtremeScalesBakeValidOrAreRefusedWithTheReason) {
  struct Case {
    float scale, offset;
    const char* refusal; // nullptr: must bake valid
  };
  for (const Case c : {Case{1e-12f, 0, "across, below"}, Case{1e-5f, 0, "across, below"}, Case{1e-3f, 0, nullptr},
                       Case{1e6f, 0, nullptr}, Case{1e9f, 0, "across, above"}, Case{1e30f, 0, "across, above"},
                       Case{1, 1e3f, nullptr}, Case{1, 1e5f, "from the origin"}}) {
    SCOPED_TRACE(::testing::Message() << "scale " << c.scale << " offset " << c.offset);
    samples::SceneBuilder builder = samples::cornell();
    builder.wrap_roots("scaled", {.translation = glm::vec3(c.offset), .scale = glm::vec3(c.scale)});
    const scene::Scene s = load_generated(builder, "cornell_scaled");
    bake::BakeSettings settings = test_settings();
    settings.max_depth = 2;
    try {
      const bake::BakeResult r = bake::bake(s, settings);
      EXPECT_EQ(c.refusal, nullptr) << "baked";
      expect_valid(r.volume);
      EXPECT_GT(r.report.probes, 0);
    } catch (const Error& e) {
      ASSERT_NE(c.refusal, nullptr) << e.what();
      EXPECT_EQ(e.kind(), ErrorKind::input);
      EXPECT_NE(std::string(e.what()).find(c.refusal), std::string::npos) << e.what();
    }
  }
}

TEST(Bake, OnlyDegenerateTrianglesAreRefused) {
  samples::SceneBuilder builder;
  const auto material = builder.add_material({.name = "grey"});
  samples::MeshData collinear;
  collinear.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  collinear.normals.assign(3, glm::vec3(0, 1, 0));
  collinear.indices = {0, 1, 2};
  builder.add_mesh_node("flat", builder.add_mesh("flat", collinear, material));
  const scene::Scene s = load_generated(builder, "degenerate");
  try {
    bake::bake(s, test_settings());
    ADD_FAILURE() << "baked";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("degenerate geometry"), std::string::npos) << e.what();
  }
}

TEST(Bake, EveryGeneratedSceneBakesValid) {
  struct Case { const char* name; samples::SceneBuilder builder; };
  std::vector<Case> cases;
  cases.push_back({"furnace", samples::furnace({.albedo = 0.99f, .emission = 1.0f})});
  cases.push_back({"leak", samples::leak()});
  cases.push_back({"plane_light", samples::plane_light()});
  for (auto& c : cases) {
    const scene::Scene s = load_generated(c.builder, c.name);
    for (bake::Placement placement : {bake::Placement::octree, bake::Placement::grid}) {
      bake::BakeSettings settings = test_settings();
      settings.placement = placement;
      settings.grid_resolution = 6;
      SCOPED_TRACE(c.name);
      // A lone plane gives no octree probes: a cube touching it sees it in 1/6 of its directions,
      // below the default LOW of 0.25 (the thesis's rule, kept as specified), and the bake refuses.
      if (std::string(c.name) == "plane_light" && placement == bake::Placement::octree) {
        EXPECT_THROW(bake::bake(s, settings), Error);
        continue;
      }
      const bake::BakeResult r = bake::bake(s, settings);
      expect_valid(r.volume);
      expect_probes_outside_geometry(s, r);
      EXPECT_GT(r.report.probes, 0);
    }
  }
}

TEST(Bake, LatticesAndSurfelStorage) {
  const scene::Scene s = load_generated(samples::cornell(), "cornell_lattice");
  for (bake::Lattice lattice : {bake::Lattice::fibonacci, bake::Lattice::latlong, bake::Lattice::equal_area}) {
    bake::BakeSettings settings = test_settings();
    settings.lattice = lattice;
    settings.store_surfels = true;
    settings.surfels_per_probe = 40; // three batches per probe, the last one partial
    const bake::BakeResult r = bake::bake(s, settings);
    expect_valid(r.volume);
    EXPECT_EQ(formats::compute_stats(r.volume).surfel_batches, 3 * r.report.probes);
  }
}

TEST(Bake, SettingsOutOfRangeAreUsageErrors) {
  const scene::Scene s = load_generated(samples::triangle(), "triangle_settings");
  bake::BakeSettings bad = test_settings();
  bad.max_depth = 13;
  EXPECT_THROW(bake::bake(s, bad), Error);
  bad = test_settings();
  bad.split_low = 0.8f;
  bad.split_high = 0.2f;
  EXPECT_THROW(bake::bake(s, bad), Error);
}

} // namespace
} // namespace probebake::test
