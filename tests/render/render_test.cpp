// The render library against answers known without it: a point light over a black plane (final view =
// I cos(theta) / r^2, indirect view 0), a probe's sphere seen head-on (its SH at the normal facing the
// camera), the same sphere hidden by a wall, a relocated probe in its documented colour.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "bake_test_util.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/formats/error.h"
#include "probebake/formats/octree.h"
#include "probebake/render/render.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

render::IndirectSampler cpu_lookup(const formats::ProbeVolume& volume) {
  return [&volume](std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) {
    std::vector<glm::vec3> out(positions.size());
    probe_index::sample_irradiance(volume, positions, normals, out);
    return out;
  };
}

struct Baked {
  scene::Scene scene;
  std::unique_ptr<scene::RayScene> rays;
  formats::ProbeVolume volume;
};

const Baked& cornell() {
  static const Baked baked = [] {
    Baked b;
    b.scene = load_generated(samples::cornell(), "render-cornell");
    b.rays = std::make_unique<scene::RayScene>(b.scene);
    b.volume = bake::bake(b.scene, test_settings()).volume;
    return b;
  }();
  return baked;
}

render::RenderInputs inputs_of(const Baked& b, const bake::Camera& camera) {
  render::RenderInputs in;
  in.scene = &b.scene, in.rays = b.rays.get(), in.volume = &b.volume, in.camera = camera;
  in.indirect = cpu_lookup(b.volume);
  return in;
}

// A camera `distance` from `target` along +Z, looking at it, with a pixel centre on the axis.
bake::Camera facing(glm::vec3 target, float distance) {
  bake::Camera c;
  c.position = target + glm::vec3(0.0f, 0.0f, distance);
  c.look_at = target;
  c.width = c.height = 33;
  c.fov_degrees = 30.0f;
  return c;
}

glm::vec3 centre_pixel(const bake::Image& image) {
  return image.pixels[std::size_t(image.height / 2) * std::size_t(image.width) + std::size_t(image.width / 2)];
}

TEST(Render, FinalViewOfAPointLightOverABlackPlaneIsInverseSquare) {
  samples::PlaneLightOptions options; // 10 x 10 m at y = 0, 100 cd at (0, 1, 0), albedo 0
  Baked b;
  b.scene = load_generated(samples::plane_light(options), "render-plane");
  b.rays = std::make_unique<scene::RayScene>(b.scene);
  bake::BakeSettings settings = test_settings();
  settings.placement = bake::Placement::grid; // a lone plane gives no octree probes (bake_test.cpp)
  settings.grid_resolution = 4;
  b.volume = bake::bake(b.scene, settings).volume;
  bake::Camera camera;
  camera.position = {0.3f, 2.5f, 1.5f}, camera.look_at = {0.0f, 0.0f, 0.0f}, camera.width = 48, camera.height = 40;
  render::Renderer renderer(inputs_of(b, camera));
  const bake::Image final_image = renderer.render(render::View::final),
                    indirect = renderer.render(render::View::indirect);
  const bake::CameraFrame frame(camera);
  int checked = 0;
  for (std::size_t i = 0; i < final_image.pixels.size(); ++i) {
    const glm::vec3 d = frame.pixel_direction(i);
    const float t = -camera.position.y / d.y;
    const glm::vec3 p = camera.position + t * d;
    if (!(t > 0.0f) || std::abs(p.x) > 4.9f || std::abs(p.z) > 4.9f) continue;
    const glm::vec3 to_light = glm::vec3(0.0f, options.height, 0.0f) - p;
    const float r = glm::length(to_light), expected = options.intensity * (options.height / r) / (r * r);
    ASSERT_NEAR(final_image.pixels[i].x, expected, 1e-3f * expected) << "pixel " << i;
    ASSERT_EQ(indirect.pixels[i], glm::vec3(0.0f)) << "a black plane reflects nothing into the probes";
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

// The live probe at a cube centre with the largest cube that a camera 3 radii in front of it sees unoccluded.
int visible_probe(const Baked& b, bool relocated) {
  int best = -1;
  float best_size = 0.0f;
  formats::for_each_leaf(b.volume, [&](const formats::NodeCube& leaf) {
    const int element = b.volume.octree[std::size_t(leaf.node)];
    if (element >= 0) return;
    const glm::vec3 p = b.volume.probes[std::size_t(~element)].position;
    if ((glm::length(p - leaf.centre()) > 1e-4f * leaf.size) != relocated || !(leaf.size > best_size)) return;
    const float distance = 0.3f * leaf.size + 0.05f;
    if (b.rays->occluded(p, {0.0f, 0.0f, 1.0f}, 0.0f, distance)) return;
    best = ~element, best_size = leaf.size;
  });
  return best;
}

// The reference views are the path tracer at each pixel's hit: in a furnace (albedo R, emission L on every
// face) irradiance is pi L / (1 - R) everywhere, of which the emission seen directly is pi L.
TEST(Render, ReferenceViewsOfAFurnaceAreItsAnalyticIrradiance) {
  Baked b;
  b.scene = load_generated(samples::furnace({.albedo = 0.5f}), "render-furnace");
  b.rays = std::make_unique<scene::RayScene>(b.scene);
  render::RenderInputs in;
  in.scene = &b.scene, in.rays = b.rays.get();
  in.camera = {glm::vec3(0.1f, 0.05f, 0.3f), glm::vec3(0.0f, 0.0f, -0.5f), 90.0f, 16, 16};
  in.reference.paths = 256;
  render::Renderer renderer(in);
  const bake::Image total = renderer.render(render::View::reference);
  const bake::Image indirect = renderer.render(render::View::reference_indirect);
  const float pi = 3.14159265f;
  double mean_total = 0.0, mean_indirect = 0.0;
  for (std::size_t i = 0; i < total.pixels.size(); ++i) {
    mean_total += total.pixels[i].x / double(total.pixels.size());
    mean_indirect += indirect.pixels[i].x / double(total.pixels.size());
  }
  EXPECT_NEAR(mean_total, pi / (1.0 - 0.5), 0.02 * pi / 0.5);
  EXPECT_NEAR(mean_indirect, pi * 0.5 / (1.0 - 0.5), 0.02 * pi / 0.5);
  EXPECT_TRUE(render::is_irradiance_view(render::View::reference));
  EXPECT_FALSE(render::reads_probes(render::View::reference)); // no probe lookup needed
}

TEST(Render, ProbeSphereSeenHeadOnShowsTheProbesIrradianceTowardsTheCamera) {
  const Baked& b = cornell();
  const int probe = visible_probe(b, false);
  ASSERT_GE(probe, 0);
  const gpu::Probe& p = b.volume.probes[std::size_t(probe)];
  const float radius = 0.1f * b.volume.info.root_size / float(1 << p.depth);
  render::Renderer renderer(inputs_of(b, facing(p.position, 3.0f * radius)));
  const glm::vec3 expected = glm::max(probe_index::evaluate_sh(p.irradiance_sh, {0.0f, 0.0f, 1.0f}), glm::vec3(0.0f));
  const glm::vec3 seen = centre_pixel(renderer.render(render::View::probes));
  ASSERT_GT(expected.x + expected.y + expected.z, 0.0f);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(seen[c], expected[c], 1e-3f * (expected.x + expected.y + expected.z)) << "channel " << c;
}

TEST(Render, ProbeBehindAWallIsHidden) {
  const Baked& b = cornell();
  const int probe = visible_probe(b, false);
  ASSERT_GE(probe, 0);
  const glm::vec3 p = b.volume.probes[std::size_t(probe)].position;
  // From behind the back wall (z < -0.28), looking +Z at the probe: the wall is what the ray meets first.
  const bake::Camera camera = facing(p, -(p.z + 0.6f));
  ASSERT_TRUE(b.rays->intersect(camera.position, {0.0f, 0.0f, 1.0f}).has_value());
  formats::ProbeVolume without_probes = b.volume;
  for (gpu::Probe& q : without_probes.probes) q.link = 0;
  render::RenderInputs in = inputs_of(b, camera);
  const glm::vec3 with = centre_pixel(render::Renderer(in).render(render::View::probes));
  in.volume = &without_probes;
  EXPECT_EQ(with, centre_pixel(render::Renderer(in).render(render::View::probes)));
}

TEST(Render, RelocatedProbeIsDrawnInTheRelocationColour) {
  const Baked& b = cornell();
  const int probe = visible_probe(b, true);
  ASSERT_GE(probe, 0) << "the Cornell bake relocates probes out of its blocks";
  const gpu::Probe& p = b.volume.probes[std::size_t(probe)];
  const float radius = 0.1f * b.volume.info.root_size / float(1 << p.depth);
  render::Renderer renderer(inputs_of(b, facing(p.position, 3.0f * radius)));
  const glm::vec3 seen = centre_pixel(renderer.render(render::View::relocation));
  // The sphere faces the camera with a horizontal normal (60 % of the colour), or the line from the cube's
  // centre passes in front of it (the full colour).
  ASSERT_GT(seen.x, 0.0f);
  const glm::vec3 hue = seen / seen.x, expected = render::kRelocatedProbeColour / render::kRelocatedProbeColour.x;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(hue[c], expected[c], 0.02f) << "channel " << c;
  EXPECT_GE(seen.x, 0.59f);
}

TEST(Render, OctreeViewShowsEveryLeafDepthTheCameraSees) {
  const Baked& b = cornell();
  bake::Camera camera;
  camera.position = {0.0f, 0.27f, 1.2f}, camera.look_at = {0.0f, 0.27f, 0.0f}, camera.width = 64, camera.height = 64;
  render::Renderer renderer(inputs_of(b, camera));
  const bake::Image octree = renderer.render(render::View::octree), svo = renderer.render(render::View::svo);
  std::vector<glm::vec3> hues;
  for (const glm::vec3& c : octree.pixels) {
    if (c == glm::vec3(0.0f)) continue;
    const glm::vec3 hue = c / std::max({c.x, c.y, c.z});
    bool known = false;
    for (const glm::vec3& h : hues) known = known || glm::length(h - hue) < 0.01f;
    if (!known) hues.push_back(hue);
    for (int k = 0; k < 3; ++k) ASSERT_TRUE(c[k] >= 0.0f && c[k] <= 1.0f);
  }
  EXPECT_GE(hues.size(), 2u) << "a depth-3 Cornell octree has leaves of several depths";
  for (const glm::vec3& c : svo.pixels)
    for (int k = 0; k < 3; ++k) ASSERT_TRUE(c[k] >= 0.0f && c[k] <= 1.0f);
}

TEST(Render, ViewsTheInputsCannotShowAreRefused) {
  const Baked& b = cornell();
  render::RenderInputs in = inputs_of(b, facing({0.0f, 0.27f, 0.0f}, 1.2f));
  in.volume = nullptr;
  in.indirect = nullptr;
  render::Renderer renderer(in);
  for (render::View view : render::kViews) {
    try {
      renderer.render(view);
      ADD_FAILURE() << render::view_name(view) << " rendered without a volume or a lookup";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::usage) << e.what();
    }
  }
  formats::ProbeVolume grid = b.volume;
  grid.info.placement = gpu::PLACEMENT_GRID;
  in.volume = &grid;
  render::Renderer grid_renderer(in);
  EXPECT_THROW(grid_renderer.render(render::View::octree), Error);
  EXPECT_THROW(grid_renderer.render(render::View::relocation), Error);
  for (render::View view : render::kViews) EXPECT_EQ(render::view_from_name(render::view_name(view)), view);
  EXPECT_FALSE(render::view_from_name("depth").has_value());
}

} // namespace
} // namespace probebake::test
