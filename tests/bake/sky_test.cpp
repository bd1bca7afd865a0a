// The sky in the bake and the reference (issue #43): a white sky over an open plane gives pi L (the furnace of
// the sky), the physical sky's map keeps the analytic sky's integral, the probes carry the sky where sealed
// geometry is culled, and environments are read as hostile input.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/bake/bake.h"
#include "probebake/eval/eval.h"
#include "probebake/eval/reference.h"
#include "probebake/formats/error.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/samples/scenes.h"
#include "probebake/sky/sky.h"

namespace probebake::test {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

// Cosine-weighted integral of `radiance` over the upper hemisphere (irradiance on an upward plane), by a
// midpoint rule of 256 x 512 cells.
template <typename Radiance>
glm::dvec3 upward_irradiance(const Radiance& radiance) {
  constexpr int kTheta = 256, kPhi = 512;
  glm::dvec3 sum(0.0);
  for (int j = 0; j < kTheta; ++j)
    for (int i = 0; i < kPhi; ++i) {
      const double theta = 0.5 * std::numbers::pi * (j + 0.5) / kTheta, phi = 2.0 * std::numbers::pi * (i + 0.5) / kPhi;
      const glm::vec3 d(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                        float(std::sin(theta) * std::sin(phi)));
      sum += glm::dvec3(radiance(d)) * std::cos(theta) * std::sin(theta);
    }
  return sum * (0.5 * std::numbers::pi / kTheta) * (2.0 * std::numbers::pi / kPhi);
}

bake::BakeSettings grid_settings(int resolution) {
  bake::BakeSettings s;
  s.placement = bake::Placement::grid; // a flat or open scene: the octree's refinement is not what is tested
  s.grid_resolution = resolution;
  s.threads = 2;
  return s;
}

TEST(Sky, WhiteSkyOverAnOpenPlaneIsPiL) {
  const glm::vec3 radiance(1.0f, 0.5f, 0.25f);
  scene::Scene s = load_generated(samples::plane_light({.intensity = 0.0f}), "sky-furnace");
  scene::set_sky(s, sky::constant_sky(radiance));
  const scene::RayScene rays(s);
  const std::vector<bake::SamplePoint> points = {{{0.1f, 0.0f, 0.2f}, {0, 1, 0}}, {{3.0f, 0.0f, -3.0f}, {0, 1, 0}}};
  bake::ReferenceSettings settings;
  settings.paths = 256;
  const bake::ReferenceResult reference = bake::reference_irradiance(s, rays, points, settings);
  const formats::ProbeVolume volume = bake::bake(s, grid_settings(4)).volume;
  for (std::size_t i = 0; i < points.size(); ++i) {
    // Every path from the plane leaves the scene at once: the reference is pi L exactly, all of it indirect.
    EXPECT_NEAR(reference.irradiance[i].x, kPi * radiance.x, 1e-5f);
    EXPECT_NEAR(reference.irradiance[i].z, kPi * radiance.z, 1e-5f);
    EXPECT_EQ(reference.direct[i], glm::vec3(0.0f));
    // Irradiance of a uniform upper hemisphere is linear in the normal: the probes' L2 SH hold it, up to the
    // plane's edge seen below the horizon and the Fibonacci rays' quadrature (measured 2.5e-4).
    const glm::vec3 e = probe_index::sample_irradiance(volume, points[i].position, points[i].normal);
    std::printf("[sky] furnace point %zu: probes %.6f, pi L %.6f\n", i, double(e.x), double(kPi * radiance.x));
    EXPECT_NEAR(e.x / (kPi * radiance.x), 1.0f, 1e-3f);
    EXPECT_NEAR(e.z / (kPi * radiance.z), 1.0f, 1e-3f);
  }
}

TEST(Sky, PhysicalSkyMapKeepsTheAnalyticIntegral) {
  for (const float elevation : {5.0f, 35.0f, 80.0f}) {
    const sky::PhysicalSky physical{sky::direction_from_angles(elevation, 120.0f), 3.0f};
    const sky::Sky map = sky::physical_sky(physical);
    const glm::dvec3 exact = upward_irradiance([&](glm::vec3 d) { return sky::physical_sky_radiance(physical, d); });
    const glm::dvec3 mapped = upward_irradiance([&](glm::vec3 d) { return map.radiance(d); });
    std::printf("[sky] physical sky at %.0f degrees: upward irradiance %.3f %.3f %.3f klux, map %.3f %.3f %.3f\n",
                double(elevation), exact.x, exact.y, exact.z, mapped.x, mapped.y, mapped.z);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(exact[c], 1.0);                     // daylight: kcd/m^2 over the hemisphere
      EXPECT_NEAR(mapped[c] / exact[c], 1.0, 0.01); // 64 x 32 texels (measured within 0.2 %)
    }
    EXPECT_GT(exact.z, exact.x); // the clear sky is blue
  }
  // The sun's transmittance: brighter and whiter high in the sky than at the horizon.
  const glm::vec3 high = sky::sun_irradiance({sky::direction_from_angles(70.0f, 0.0f), 2.5f});
  const glm::vec3 low = sky::sun_irradiance({sky::direction_from_angles(3.0f, 0.0f), 2.5f});
  EXPECT_GT(high.z, 60.0f);
  EXPECT_LT(high.x, 128.0f);
  EXPECT_GT(high.z / high.x, low.z / low.x);
  EXPECT_EQ(sky::sun_irradiance({sky::direction_from_angles(-5.0f, 0.0f), 2.5f}), glm::vec3(0.0f));
}

TEST(Sky, ReferenceSeesThePhysicalSkyOnAnOpenPlane) {
  const sky::PhysicalSky physical{sky::direction_from_angles(35.0f, 120.0f), 2.5f};
  scene::Scene s = load_generated(samples::plane_light({.size = 1000.0f, .intensity = 0.0f}), "sky-physical");
  scene::set_sky(s, sky::physical_sky(physical));
  ASSERT_EQ(s.sun_light, 1); // after the plane's own (dark) light
  const scene::RayScene rays(s);
  const std::vector<bake::SamplePoint> points = {{{0.0f, 0.0f, 0.0f}, {0, 1, 0}}};
  bake::ReferenceSettings settings;
  settings.paths = 20000;
  const bake::ReferenceResult reference = bake::reference_irradiance(s, rays, points, settings);
  const glm::dvec3 sky_part = upward_irradiance([&](glm::vec3 d) { return s.sky.radiance(d); });
  const glm::vec3 sun = sky::sun_irradiance(physical) * physical.sun_direction.y; // on the plane, unshadowed
  for (int c = 0; c < 3; ++c) {
    const double indirect = reference.irradiance[0][c] - reference.direct[0][c];
    EXPECT_NEAR(indirect, sky_part[c], 4.0 * reference.indirect_standard_error[0][c] + 1e-3 * sky_part[c]) << c;
    EXPECT_NEAR(reference.direct[0][c], sun[c], 1e-3f * sun[c]) << c;
  }
}

// The courtyard's blocks are closed boxes: the bake culls their sealed inner faces and lights the probes from
// the scene without them, which must keep the sky (it once lost it: probes without sky light).
TEST(Sky, ProbesCarryTheSkyWhereSealedGeometryIsCulled) {
  scene::Scene s = load_generated(samples::courtyard(), "sky-courtyard");
  scene::set_sky(s, sky::constant_sky(glm::vec3(1.0f)));
  const scene::RayScene rays(s);
  const bake::BakeResult baked = bake::bake(s, grid_settings(5));
  ASSERT_GT(baked.report.sealed_triangles, 0);
  const std::vector<bake::SamplePoint> points = {{{0.1f, 0.0f, 0.2f}, {0, 1, 0}}, {{3.0f, 0.0f, -3.0f}, {0, 1, 0}}};
  bake::ReferenceSettings settings;
  settings.paths = 4096;
  const bake::ReferenceResult reference = bake::reference_irradiance(s, rays, points, settings);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const float e = probe_index::sample_irradiance(baked.volume, points[i].position, points[i].normal).x;
    const float r = reference.irradiance[i].x;
    std::printf("[sky] courtyard point %zu: probes %.3f, reference %.3f\n", i, double(e), double(r));
    EXPECT_GT(e, 0.8f * r); // a grid of 5^3 over 40 m: coarse, but the sky is there
    EXPECT_LT(e, 1.35f * r);
  }
}

TEST(Sky, EnvironmentIsAveragedDownAndCheckedAsHostileInput) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "probebake-sky-test";
  std::filesystem::create_directories(dir);
  bake::Image image{256, 128, {}};
  for (int j = 0; j < image.height; ++j)
    for (int i = 0; i < image.width; ++i) image.pixels.emplace_back(float(i % 7), float(j), 1.0f);
  bake::write_exr(dir / "env.exr", image);
  const sky::Sky env = sky::environment_sky(dir / "env.exr", 2.0f);
  EXPECT_EQ(env.map.width, sky::kEnvironmentWidth);
  EXPECT_EQ(env.map.height, sky::kEnvironmentHeight);
  EXPECT_EQ(env.colour, glm::vec3(2.0f));
  EXPECT_EQ(env.kind, gpu::SKY_KIND_ENVIRONMENT);
  // Solid-angle weighted means of the source and the map agree (the averaging keeps the integral).
  double source = 0, source_weight = 0, mapped = 0, mapped_weight = 0;
  for (int j = 0; j < image.height; ++j) {
    const double w = std::sin(std::numbers::pi * (j + 0.5) / image.height);
    for (int i = 0; i < image.width; ++i)
      source += w * image.pixels[std::size_t(j * image.width + i)].y, source_weight += w;
  }
  for (int j = 0; j < env.map.height; ++j) {
    const double w = std::sin(std::numbers::pi * (j + 0.5) / env.map.height);
    for (int i = 0; i < env.map.width; ++i)
      mapped += w * env.map.texels[std::size_t(j * env.map.width + i)].y, mapped_weight += w;
  }
  EXPECT_NEAR(mapped / mapped_weight, source / source_weight, 0.01 * source / source_weight);

  bake::write_exr(dir / "square.exr", bake::Image{8, 8, std::vector<glm::vec3>(64, glm::vec3(1.0f))});
  expect_refusal([&] { sky::environment_sky(dir / "square.exr"); }, "twice as wide", "accepted", ErrorKind::input);
  image.pixels[5] = glm::vec3(std::nanf(""), 0.0f, 0.0f);
  bake::write_exr(dir / "nan.exr", image);
  expect_refusal([&] { sky::environment_sky(dir / "nan.exr"); }, "texel (5, 0) channel R", "accepted",
                 ErrorKind::input);
  expect_refusal([&] { sky::environment_sky(dir / "missing.exr"); }, "missing.exr", "accepted", ErrorKind::input);
  std::filesystem::remove_all(dir);
}

// eval caches a reference per scene and settings: another sky is another reference.
TEST(Sky, TheReferenceCacheKeyHoldsTheSky) {
  scene::Scene s = load_generated(samples::plane_light(), "sky-cache-key");
  const std::uint64_t black = bake::reference_hash(s, 100, 1, 64);
  scene::set_sky(s, sky::constant_sky(glm::vec3(1.0f)));
  const std::uint64_t white = bake::reference_hash(s, 100, 1, 64);
  EXPECT_NE(black, white);
  sky::Sky map{glm::vec3(1.0f), {4, 2, std::vector<glm::vec3>(8, glm::vec3(1.0f))}, gpu::SKY_KIND_ENVIRONMENT, {}, {}};
  scene::set_sky(s, map);
  const std::uint64_t flat = bake::reference_hash(s, 100, 1, 64);
  map.map.texels[3] = glm::vec3(2.0f); // one texel brighter: the same colour, another sky
  scene::set_sky(s, map);
  EXPECT_NE(flat, bake::reference_hash(s, 100, 1, 64));
}

TEST(Sky, BadSkySettingsAreUsageErrors) {
  expect_refusal([] { sky::constant_sky(glm::vec3(-1.0f)); }, "finite and >= 0", "accepted", ErrorKind::usage);
  expect_refusal(
      [] {
        sky::physical_sky({glm::vec3(0.0f, 1.0f, 0.0f), 20.0f});
      },
      "turbidity", "accepted", ErrorKind::usage);
  expect_refusal([] { sky::physical_sky({glm::vec3(0.0f), 2.5f}); }, "sun direction", "accepted", ErrorKind::usage);
}

// Rooms with windows (make-scene rooms --windows): the sky reaches the rooms through the windows only. Closed rooms
// bake the same probes with or without a sky (no ray leaves them); with windows rays leave, and the probes gain light.
TEST(Sky, ReachesRoomsOnlyThroughTheirWindows) {
  const auto bake_rooms = [](bool windows, bool sky) {
    scene::Scene s = load_generated(samples::rooms({.count = 2, .detail = 1, .windows = windows}), "sky-rooms");
    if (sky) scene::set_sky(s, sky::constant_sky(glm::vec3(1.0f)));
    bake::BakeSettings settings = grid_settings(6);
    settings.lighting.rays = 64;
    return bake::bake(s, settings);
  };
  const bake::BakeResult closed = bake_rooms(false, false), closed_sky = bake_rooms(false, true);
  const bake::BakeResult open = bake_rooms(true, false), open_sky = bake_rooms(true, true);
  EXPECT_EQ(closed_sky.report.lighting.misses, 0u);
  ASSERT_EQ(closed_sky.volume.probes.size(), closed.volume.probes.size());
  EXPECT_EQ(std::memcmp(closed_sky.volume.probes.data(), closed.volume.probes.data(),
                        closed.volume.probes.size() * sizeof(gpu::Probe)),
            0); // the probes bit for bit (lighting_info differs: its sky radiance)
  EXPECT_GT(open_sky.report.lighting.misses, 0u);
  double gained = 0.0, dc = 0.0;
  for (std::size_t p = 0; p < open.volume.probes.size(); ++p) {
    gained += open_sky.volume.probes[p].irradiance_sh[0] - open.volume.probes[p].irradiance_sh[0];
    dc += open.volume.probes[p].irradiance_sh[0];
  }
  std::printf("[sky] two rooms with windows: %zu of the rays leave, the sky adds %.3g to the probes' mean DC (%.3g)\n",
              open_sky.report.lighting.misses, gained / double(open.volume.probes.size()),
              dc / double(open.volume.probes.size()));
  EXPECT_GT(gained, 0.0);
}

} // namespace
} // namespace probebake::test
