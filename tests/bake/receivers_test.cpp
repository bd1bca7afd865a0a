// `probebake eval`'s receivers (what a player can see), coverage, relative-error percentiles, image
// receivers, the invariance of receivers, metrics and the bake under geometry sealed inside solids, both
// sides of double-sided surfaces as receivers, and the Cornell box flipped by make-scene convert --flip
// (the same scene by the glTF rule) against the original: probes, reference and eval errors.
#include <algorithm>
#include <cmath>
#include <fstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/eval/eval.h"
#include "probebake/eval/reference.h"
#include "probebake/samples/flip_gltf.h"
#include "probebake/samples/geometry.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

const scene::Instance& instance(const scene::Scene& s, const std::string& name) {
  const auto it = std::find_if(s.instances.begin(), s.instances.end(),
                               [&](const scene::Instance& i) { return i.node_name == name; });
  if (it == s.instances.end()) throw std::runtime_error("no instance " + name);
  return *it;
}

// The generated Cornell box with a closed cube sealed inside each block, high enough that the floor
// under the (bottomless) blocks subtends less than half of any cube face's hemisphere.
samples::SceneBuilder cornell_with_hidden_cubes() {
  const scene::Scene plain = load_generated(samples::cornell(), "recv_cornell_plain");
  samples::SceneBuilder builder = samples::cornell();
  const samples::MaterialId white = builder.add_material({"hidden", glm::vec3(0.9f), glm::vec3(0.0f)});
  for (const char* block : {"short_block", "tall_block"}) {
    const scene::Bounds b = instance(plain, block).bounds;
    const glm::vec3 extent = b.max - b.min;
    const float half = 0.15f * std::min(extent.x, extent.z);
    const glm::vec3 centre(0.5f * (b.min.x + b.max.x), b.min.y + 0.65f * extent.y, 0.5f * (b.min.z + b.max.z));
    const samples::MeshId mesh = builder.add_mesh(
        std::string("hidden_") + block, samples::box(centre - half, centre + half, samples::Facing::outward), white);
    builder.add_mesh_node(std::string("hidden_") + block, mesh);
  }
  return builder;
}

// A closed 3.6 x 3 x 3.6 m room inside 0.2 m thick walls (outer faces outward, inner faces inward), a
// point light inside and a sun outside.
samples::SceneBuilder closed_room() {
  samples::SceneBuilder builder("closed_room");
  const samples::MaterialId wall = builder.add_material({"wall", glm::vec3(0.7f), glm::vec3(0.0f)});
  samples::MeshData shell = samples::box({-2.0f, -0.2f, -2.0f}, {2.0f, 3.2f, 2.0f}, samples::Facing::outward);
  shell.append(samples::box({-1.8f, 0.0f, -1.8f}, {1.8f, 3.0f, 1.8f}, samples::Facing::inward));
  builder.add_mesh_node("shell", builder.add_mesh("shell", shell, wall));
  builder.add_light_node("lamp", builder.add_light({.name = "lamp", .intensity = 20.0f}), {0.3f, 2.0f, -0.2f});
  builder.add_light_node(
      "sun", builder.add_light({.name = "sun", .type = samples::LightType::directional, .intensity = 1000.0f}),
      {0.0f, 5.0f, 0.0f}, glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f)));
  return builder;
}

bool inside_inner_room(glm::vec3 p) {
  const float e = 1e-4f;
  return std::abs(p.x) <= 1.8f + e && std::abs(p.z) <= 1.8f + e && p.y >= -e && p.y <= 3.0f + e;
}

bake::Receivers receivers_of(const scene::Scene& s, bake::ReceiverMode mode, int count) {
  const scene::RayScene rays(s);
  return bake::make_receivers(s, rays, {.mode = mode, .count = count, .seed = 3});
}

TEST(Receivers, ClosedRoomSeenFromInsideHasNoReceiversOnItsOuterFaces) {
  const scene::Scene s = load_generated(closed_room(), "recv_closed_room");
  const bake::Receivers visible = receivers_of(s, bake::ReceiverMode::visible, 300);
  ASSERT_EQ(visible.points.size(), 300u);
  EXPECT_EQ(visible.regions, 1);
  for (const bake::SamplePoint& p : visible.points) {
    EXPECT_TRUE(inside_inner_room(p.position)) << p.position.x << " " << p.position.y << " " << p.position.z;
    EXPECT_LE(glm::dot(p.normal, p.position - glm::vec3(0.0f, 1.5f, 0.0f)), 0.0f) << "faces into the room";
  }
  // The area receivers put about half their points outside (the outer faces are larger).
  const bake::Receivers area = receivers_of(s, bake::ReceiverMode::area, 300);
  const auto outside = std::count_if(area.points.begin(), area.points.end(),
                                     [](const bake::SamplePoint& p) { return !inside_inner_room(p.position); });
  std::printf("[ closed room ] visible: %zu receivers from %d viewpoints, 0 outside; area: %ld of %zu outside\n",
              visible.points.size(), visible.viewpoints, long(outside), area.points.size());
  EXPECT_GT(outside, 100);
}

TEST(Receivers, VolumeReceiversLieInOpenSpaceInsideTheRoom) {
  const scene::Scene s = load_generated(closed_room(), "recv_closed_room_volume");
  const scene::RayScene rays(s);
  const bake::Receivers volume =
      bake::make_receivers(s, rays, {.mode = bake::ReceiverMode::volume, .count = 50, .seed = 3});
  ASSERT_EQ(volume.points.size(), 50u);
  for (const bake::SamplePoint& p : volume.points) {
    EXPECT_TRUE(inside_inner_room(p.position));
    EXPECT_FALSE(inside_geometry(rays, p.position));
    EXPECT_NEAR(glm::length(p.normal), 1.0f, 1e-5f);
  }
}

TEST(Receivers, NoneInTheGapBetweenTheCornellLightAndTheCeiling) {
  const scene::Scene s = load_generated(samples::cornell(), "recv_cornell_gap");
  const scene::Bounds light = instance(s, "light").bounds;
  const bake::Receivers r = receivers_of(s, bake::ReceiverMode::visible, 1000);
  ASSERT_EQ(r.points.size(), 1000u);
  int above_light = 0;
  for (const bake::SamplePoint& p : r.points)
    // The ceiling over the light, 0.5 mm above its (back) face; the light's own face is a fine receiver.
    if (p.position.y > light.max.y + 2e-4f && p.position.x > light.min.x && p.position.x < light.max.x &&
        p.position.z > light.min.z && p.position.z < light.max.z)
      ++above_light;
  EXPECT_EQ(above_light, 0);
}

TEST(Receivers, SameForAnyThreadCount) {
  const scene::Scene s = load_generated(samples::cornell(), "recv_cornell_threads");
  const scene::RayScene rays(s);
  const auto one = bake::make_receivers(s, rays, {.count = 200, .seed = 5, .threads = 1});
  const auto two = bake::make_receivers(s, rays, {.count = 200, .seed = 5, .threads = 2});
  ASSERT_EQ(one.points.size(), two.points.size());
  EXPECT_EQ(one.viewpoints, two.viewpoints);
  EXPECT_EQ(one.regions, two.regions);
  for (std::size_t i = 0; i < one.points.size(); ++i) {
    EXPECT_EQ(one.points[i].position, two.points[i].position);
    EXPECT_EQ(one.points[i].normal, two.points[i].normal);
  }
  EXPECT_THROW(bake::make_receivers(s, rays, {.count = 0}), Error);
}

TEST(Receivers, CacheKeyIncludesTheReceiverMode) {
  const scene::Scene s = load_generated(samples::triangle(), "recv_triangle");
  const auto visible = bake::reference_hash(s, 100, 1, 64, bake::ReceiverMode::visible);
  EXPECT_NE(visible, bake::reference_hash(s, 100, 1, 64, bake::ReceiverMode::area));
  EXPECT_NE(visible, bake::reference_hash(s, 100, 1, 64, bake::ReceiverMode::volume));
  const glm::vec3 camera(0.1f, 0.5f, 0.2f);
  EXPECT_NE(visible, bake::reference_hash(s, 100, 1, 64, bake::ReceiverMode::visible, std::span(&camera, 1)));
}

// The same geometry with double-sided materials is another scene for the reference (light from the backs)
// and for the receivers (both sides): a cached reference of the single-sided one must not be reused.
TEST(Receivers, CacheKeyIncludesDoubleSidedness) {
  scene::Scene s = load_generated(samples::triangle(), "recv_triangle_sides");
  const auto single = bake::reference_hash(s, 100, 1, 64);
  for (scene::Material& m : s.materials) m.double_sided = !m.double_sided;
  EXPECT_NE(single, bake::reference_hash(s, 100, 1, 64));
}

// ---- Sealed geometry ---------------------------------------------------------------------------------

TEST(HiddenGeometry, SealedCubesLeaveReceiversAndProbeLayoutUnchanged) {
  const scene::Scene plain = load_generated(samples::cornell(), "recv_cornell_a");
  const scene::Scene hidden = load_generated(cornell_with_hidden_cubes(), "recv_cornell_hidden");
  ASSERT_EQ(hidden.triangles.size(), plain.triangles.size() + 24);
  const bake::Receivers a = receivers_of(plain, bake::ReceiverMode::visible, 500);
  const bake::Receivers b = receivers_of(hidden, bake::ReceiverMode::visible, 500);
  EXPECT_EQ(a.viewpoints, b.viewpoints);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].position, b.points[i].position) << i;
    EXPECT_EQ(a.points[i].normal, b.points[i].normal) << i;
  }
  bake::BakeSettings settings = test_settings();
  settings.max_depth = 5;
  settings.lighting.rays = 32;
  const bake::BakeResult pa = bake::bake(plain, settings);
  const bake::BakeResult pb = bake::bake(hidden, settings);
  EXPECT_EQ(pa.report.sealed_triangles, 0);
  EXPECT_EQ(pb.report.sealed_triangles, 24);
  std::printf("[ hidden cubes ] depth 5: %d probes without, %d with\n", pa.report.probes, pb.report.probes);
  EXPECT_EQ(pa.report.probes, pb.report.probes);
  ASSERT_EQ(pa.volume.probes.size(), pb.volume.probes.size());
  for (std::size_t i = 0; i < pa.volume.probes.size(); ++i) {
    EXPECT_EQ(pa.volume.probes[i].position, pb.volume.probes[i].position) << i;
    EXPECT_EQ(pa.volume.probes[i].link, pb.volume.probes[i].link) << i;
    for (int k = 0; k < gpu::PROBE_SH_FLOATS; ++k)
      EXPECT_EQ(pa.volume.probes[i].irradiance_sh[k], pb.volume.probes[i].irradiance_sh[k]) << i;
  }
  EXPECT_EQ(pa.volume.octree, pb.volume.octree);
  EXPECT_EQ(pa.volume.svo_nodes, pb.volume.svo_nodes);
}

bake::EvalResult quick_eval(const samples::SceneBuilder& builder, const std::string& name, bake::EvalSettings s) {
  const auto path = write_generated(builder, name);
  s.use_cache = false;
  s.threads = 2;
  return bake::evaluate(path, s);
}

bake::EvalSettings quick_settings() {
  bake::EvalSettings s;
  s.points = 64;
  s.paths = 64;
  s.configs = bake::quick_sweep();
  return s;
}

TEST(HiddenGeometry, SealedCubesLeaveEveryRowsMetricsUnchanged) {
  const bake::EvalResult a = quick_eval(samples::cornell(), "recv_eval_plain", quick_settings());
  const bake::EvalResult b = quick_eval(cornell_with_hidden_cubes(), "recv_eval_hidden", quick_settings());
  ASSERT_EQ(a.rows.size(), b.rows.size());
  EXPECT_NEAR(a.mean_reference, b.mean_reference, a.reference_noise * a.mean_reference);
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    EXPECT_EQ(a.rows[i].probes, b.rows[i].probes) << a.rows[i].label;
    EXPECT_NEAR(a.rows[i].relative_rmse, b.rows[i].relative_rmse, a.reference_noise) << a.rows[i].label;
    EXPECT_NEAR(a.rows[i].relative_median, b.rows[i].relative_median, a.reference_noise) << a.rows[i].label;
    EXPECT_NEAR(a.rows[i].relative_p95, b.rows[i].relative_p95, a.reference_noise) << a.rows[i].label;
    EXPECT_EQ(a.rows[i].coverage, b.rows[i].coverage) << a.rows[i].label;
  }
}

// ---- Coverage and image receivers --------------------------------------------------------------------

TEST(EvalReceivers, GridCoveringTheSceneHasCoverageOne) {
  bake::EvalSettings s = quick_settings();
  s.configs = {s.configs.back()}; // grid-4
  ASSERT_EQ(s.configs[0].bake.placement, bake::Placement::grid);
  const bake::EvalResult r = quick_eval(samples::cornell(), "recv_eval_grid", s);
  ASSERT_FALSE(r.rows.empty());
  EXPECT_EQ(r.receivers, "visible");
  EXPECT_GT(r.viewpoints, 0);
  EXPECT_EQ(r.points, 64);
  for (const bake::EvalRow& row : r.rows) {
    EXPECT_EQ(row.coverage, 1.0) << row.label << " " << row.sampler;
    EXPECT_EQ(row.misses, 0u);
    EXPECT_GT(row.relative_p95, row.relative_median);
    EXPECT_GT(row.relative_median, 0.0);
  }
}

// Without --camera, the scene's glTF camera does exactly what the same --camera does: it anchors the
// player's region and adds image receivers.
TEST(EvalReceivers, AGltfCameraActsAsTheSameCameraOption) {
  const glm::vec3 position{0.0f, 0.274f, 1.0f}, target{0.0f, 0.274f, 0.0f};
  samples::SceneBuilder builder = samples::cornell();
  builder.add_camera_node("view", position, target, glm::radians(40.0f));
  const auto path = write_generated(builder, "recv_eval_gltf_camera");
  bake::EvalSettings s = quick_settings();
  s.configs = {s.configs.front()};
  s.baseline = s.configs.front().label;
  s.image_paths = 2;
  s.use_cache = false;
  const scene::Scene scene = scene::load_scene(path);
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_NEAR(glm::length(scene.cameras[0].position - position), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::dot(scene.cameras[0].forward, glm::vec3(0, 0, -1)), 1.0f, 1e-5f);
  const bake::EvalResult from_scene = bake::evaluate(path, s);
  s.camera = bake::Camera{.position = position, .look_at = target, .fov_degrees = 40.0f, .width = 128, .height = 128};
  const bake::EvalResult from_option = bake::evaluate(path, s);
  ASSERT_GT(from_scene.image_pixels, 128 * 128 / 2);
  EXPECT_EQ(from_scene.image_pixels, from_option.image_pixels);
  EXPECT_EQ(from_scene.points, from_option.points);
  EXPECT_EQ(from_scene.viewpoints, from_option.viewpoints);
  EXPECT_NEAR(from_scene.rows.front().image_mean_error, from_option.rows.front().image_mean_error,
              1e-4 * from_option.rows.front().image_mean_error);
}

TEST(EvalReceivers, ImageReceiversAverageToTheErrorMapMean) {
  bake::EvalSettings s = quick_settings();
  s.configs = {s.configs.front()};
  s.baseline = s.configs.front().label;
  s.camera = bake::Camera{.position = {0.0f, 0.274f, 1.0f},
                          .look_at = {0.0f, 0.274f, 0.0f},
                          .fov_degrees = 40.0f,
                          .width = 16,
                          .height = 12};
  s.image_paths = 4;
  const auto path = write_generated(samples::cornell(), "recv_eval_image");
  s.error_map_dir = path.parent_path() / "recv_eval_maps";
  s.use_cache = false;
  const bake::EvalResult r = bake::evaluate(path, s);
  ASSERT_GT(r.image_pixels, 16 * 12 / 2);
  const bake::EvalRow& row = r.rows.front();
  const bake::Image map = bake::read_exr(s.error_map_dir / (row.label + ".exr"));
  const scene::Scene scene = scene::load_scene(path);
  const scene::RayScene rays(scene);
  const auto visible = bake::camera_surface_points(rays, *s.camera);
  double sum = 0.0;
  int pixels = 0;
  for (std::size_t i = 0; i < visible.size(); ++i) {
    if (!visible[i]) continue;
    sum += (double(map.pixels[i].x) + double(map.pixels[i].y) + double(map.pixels[i].z)) / 3.0;
    ++pixels;
  }
  EXPECT_EQ(pixels, r.image_pixels);
  EXPECT_GT(row.image_mean_error, 0.0);
  EXPECT_NEAR(row.image_mean_error, sum / pixels, 1e-6 * row.image_mean_error);
  EXPECT_GT(row.image_relative_rmse, 0.0);
  // HDR-FLIP (issue #39): its map beside the error map, its mean over the same pixels, at the exposures
  // of the visible reference.
  const bake::Image flip = bake::read_exr(s.error_map_dir / (row.label + ".flip.exr"));
  ASSERT_EQ(flip.pixels.size(), map.pixels.size());
  double flip_sum = 0.0;
  for (std::size_t i = 0; i < visible.size(); ++i) {
    ASSERT_GE(flip.pixels[i].x, 0.0f);
    ASSERT_LE(flip.pixels[i].x, 1.0f);
    if (visible[i]) flip_sum += flip.pixels[i].x;
  }
  EXPECT_GT(row.image_flip_mean, 0.0);
  EXPECT_LT(row.image_flip_mean, 1.0);
  EXPECT_NEAR(row.image_flip_mean, flip_sum / pixels, 1e-6);
  EXPECT_GE(r.image_flip_exposures.count, 1);
  EXPECT_TRUE(std::isfinite(r.image_flip_exposures.start) && std::isfinite(r.image_flip_exposures.stop));
  EXPECT_EQ(std::count(r.error_maps.begin(), r.error_maps.end(), s.error_map_dir / (row.label + ".flip.exr")), 1);
}

} // namespace
} // namespace probebake::test

// ---- Double-sided surfaces: two receivers per point --------------------------------------------------

namespace probebake::test {
namespace {

// A 2 x 2 m plane at y = 0 (front +Y) with a point light above and one below.
samples::SceneBuilder lit_plane(bool double_sided) {
  samples::SceneBuilder builder("lit_plane");
  const samples::MaterialId grey = builder.add_material({"grey", glm::vec3(0.5f), glm::vec3(0.0f), double_sided});
  builder.add_mesh_node(
      "plane",
      builder.add_mesh("plane", samples::quad({-1.0f, 0.0f, 1.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -2.0f}, 4), grey));
  builder.add_light_node("above", builder.add_light({.name = "above", .intensity = 4.0f}), {0.0f, 1.0f, 0.0f});
  builder.add_light_node("below", builder.add_light({.name = "below", .intensity = 1.0f}), {0.0f, -1.0f, 0.0f});
  return builder;
}

int facing_down(const std::vector<bake::SamplePoint>& points) {
  return int(
      std::count_if(points.begin(), points.end(), [](const bake::SamplePoint& p) { return p.normal.y < -0.999f; }));
}

TEST(Receivers, BothSidesOfADoubleSidedPlaneAreReceivers) {
  const scene::Scene single = load_generated(lit_plane(false), "recv_plane_single");
  const scene::Scene both = load_generated(lit_plane(true), "recv_plane_double");
  for (bake::ReceiverMode mode : {bake::ReceiverMode::area, bake::ReceiverMode::visible}) {
    const bake::Receivers one = receivers_of(single, mode, 400), two = receivers_of(both, mode, 400);
    ASSERT_EQ(one.points.size(), 400u);
    ASSERT_EQ(two.points.size(), 400u);
    EXPECT_EQ(facing_down(one.points), 0) << bake::receiver_mode_name(mode);
    // Equal areas on both sides: about half face down (binomial, 400 draws: 200 +- 10 for 1 sigma).
    EXPECT_GT(facing_down(two.points), 150) << bake::receiver_mode_name(mode);
    EXPECT_LT(facing_down(two.points), 250) << bake::receiver_mode_name(mode);
    for (const bake::SamplePoint& p : two.points) EXPECT_NEAR(std::abs(p.normal.y), 1.0f, 1e-6f);
  }
  // Each side sees its own light: E = I / h^2 straight under it (4 above, 1 below; nothing else to bounce
  // light, point lights are sampled exactly).
  const std::vector<bake::SamplePoint> at = {{{0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}},
                                             {{0.0f, 0.0f, 0.0f}, {0.0f, -1.0f, 0.0f}}};
  bake::ReferenceSettings settings;
  settings.paths = 256;
  const scene::RayScene rays_both(both);
  const bake::ReferenceResult r = bake::reference_irradiance(both, rays_both, at, settings);
  const float up = r.irradiance[0].x, down = r.irradiance[1].x;
  std::printf("[ double-sided plane ] E up %.5f, down %.5f W/m^2 (exact: 4 and 1)\n", up, down);
  EXPECT_NEAR(up, 4.0f, 1e-3f);
  EXPECT_NEAR(down, 1.0f, 1e-3f);
}

TEST(Receivers, CameraSeesTheBackOfADoubleSidedPlaneWithItsFacingNormal) {
  const bake::Camera below{
      .position = {0.1f, -1.0f, 0.2f}, .look_at = {0.0f, 0.0f, 0.0f}, .fov_degrees = 30.0f, .width = 8, .height = 8};
  const scene::Scene single = load_generated(lit_plane(false), "recv_plane_cam_single");
  const scene::Scene both = load_generated(lit_plane(true), "recv_plane_cam_double");
  const scene::RayScene rays_single(single), rays_both(both);
  for (const auto& p : bake::camera_surface_points(rays_single, below))
    EXPECT_FALSE(p.has_value()) << "back of a single-sided plane";
  const auto seen = bake::camera_surface_points(rays_both, below);
  ASSERT_EQ(seen.size(), 64u);
  for (const auto& p : seen) {
    ASSERT_TRUE(p.has_value());
    EXPECT_EQ(p->normal, glm::vec3(0.0f, -1.0f, 0.0f));
  }
}

// ---- The flipped Cornell box: the same scene by the glTF rule -----------------------------------------

std::filesystem::path write_flipped(const samples::SceneBuilder& builder, const std::string& name) {
  const std::filesystem::path original = write_generated(builder, name);
  const std::vector<std::uint8_t> bytes = samples::flip_sides_file(original);
  const std::filesystem::path flipped = original.parent_path() / (name + "_flipped.glb");
  std::ofstream(flipped, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  return flipped;
}

double mean_of(const std::vector<glm::vec3>& v) {
  double sum = 0.0;
  for (const glm::vec3& e : v) sum += (double(e.x) + e.y + e.z) / 3.0;
  return sum / double(std::max<std::size_t>(v.size(), 1));
}

TEST(FlippedCornell, SameReferenceAtTheOriginalsReceivers) {
  const scene::Scene original = scene::load_scene(write_generated(samples::cornell(), "flip_cornell_ref"));
  const scene::Scene flipped = scene::load_scene(write_flipped(samples::cornell(), "flip_cornell_ref"));
  const scene::RayScene rays_a(original), rays_b(flipped);
  const bake::Receivers receivers = bake::make_receivers(original, rays_a, {.count = 64, .seed = 7});
  ASSERT_EQ(receivers.points.size(), 64u);
  bake::ReferenceSettings settings;
  settings.paths = 256;
  const bake::ReferenceResult a = bake::reference_irradiance(original, rays_a, receivers.points, settings);
  const bake::ReferenceResult b = bake::reference_irradiance(flipped, rays_b, receivers.points, settings);
  // Independent estimates (the flipped scene's rays meet other sides, so its paths differ): the means
  // agree within 4 combined standard errors of the mean.
  double variance = 0.0;
  for (std::size_t i = 0; i < a.irradiance.size(); ++i) {
    const double se_a = (a.standard_error[i].x + a.standard_error[i].y + a.standard_error[i].z) / 3.0;
    const double se_b = (b.standard_error[i].x + b.standard_error[i].y + b.standard_error[i].z) / 3.0;
    variance += se_a * se_a + se_b * se_b;
  }
  const double n = double(a.irradiance.size());
  const double mean_a = mean_of(a.irradiance), mean_b = mean_of(b.irradiance);
  std::printf("[ flipped cornell ] reference at 64 receivers x 256 paths: mean %.4f (original) vs %.4f (flipped), "
              "sigma of the difference %.4f\n",
              mean_a, mean_b, std::sqrt(variance) / n);
  EXPECT_GT(mean_a, 0.1);
  EXPECT_NEAR(mean_b, mean_a, 4.0 * std::sqrt(variance) / n);
}

TEST(FlippedCornell, SameProbeCountWithinFivePercent) {
  const scene::Scene original = scene::load_scene(write_generated(samples::cornell(), "flip_cornell_bake"));
  const scene::Scene flipped = scene::load_scene(write_flipped(samples::cornell(), "flip_cornell_bake"));
  const bake::BakeResult a = bake::bake(original, test_settings());
  const bake::BakeResult b = bake::bake(flipped, test_settings());
  std::printf("[ flipped cornell ] probes: %d (original) vs %d (flipped)\n", a.report.probes, b.report.probes);
  EXPECT_GT(a.report.probes, 8);
  EXPECT_LE(std::abs(a.report.probes - b.report.probes), std::max(1, a.report.probes / 20));
}

// The fair pair for eval: the generated light quad is single-sided and 0.5 mm below the ceiling; flipped
// it is double-sided and also emits up into that gap (a different scene). Flipping twice gives the
// original winding with every material double-sided: against it, the once-flipped box differs only in
// which side of every surface is the front. 128 receivers x 512 paths: the gap's light makes the
// reference heavy-tailed (noise ~11 %), and at 64 x 256 its noise alone moved grid-4 by 27 %.
TEST(FlippedCornell, EvalErrorsWithinTenPercent) {
  const auto once = write_flipped(samples::cornell(), "flip_cornell_eval");
  const std::vector<std::uint8_t> twice_bytes = samples::flip_sides_file(once);
  const std::filesystem::path twice = once.parent_path() / "flip_cornell_eval_twice.glb";
  std::ofstream(twice, std::ios::binary)
      .write(reinterpret_cast<const char*>(twice_bytes.data()), std::streamsize(twice_bytes.size()));
  bake::EvalSettings s = quick_settings();
  s.points = 128;
  s.paths = 512;
  s.use_cache = false;
  s.threads = 2;
  const bake::EvalResult a = bake::evaluate(twice, s), b = bake::evaluate(once, s);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  std::printf("[ flipped cornell ] eval: mean reference %.4f (flipped twice) vs %.4f (once), reference noise %.3f\n",
              a.mean_reference, b.mean_reference, a.reference_noise);
  EXPECT_NEAR(b.mean_reference, a.mean_reference,
              4.0 * a.reference_noise / std::sqrt(double(s.points)) * a.mean_reference);
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    std::printf("[ flipped cornell ] %-16s relative RMSE %.4f (twice) vs %.4f (once), probes %d vs %d\n",
                a.rows[i].label.c_str(), a.rows[i].relative_rmse, b.rows[i].relative_rmse, a.rows[i].probes,
                b.rows[i].probes);
    EXPECT_NEAR(b.rows[i].relative_rmse, a.rows[i].relative_rmse, 0.1 * a.rows[i].relative_rmse) << a.rows[i].label;
    EXPECT_EQ(b.rows[i].coverage, a.rows[i].coverage) << a.rows[i].label;
  }
}

} // namespace
} // namespace probebake::test
