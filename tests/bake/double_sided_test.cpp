// glTF doubleSided in the CPU light transport (bake lighting and the path-traced reference), against
// closed forms: a square emitter seen from both sides, a plane lit from below reflecting onto a receiver
// under it, and the Cornell box with every winding reversed and every material double-sided (the same
// scene by the glTF rule) against the original. Single-sided copies keep today's rule: nothing behind.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/lighting/lighting.h"
#include "probebake/eval/reference.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/samples/geometry.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

constexpr float kPi = 3.14159265f;

// Irradiance on the axis of a uniformly emitting square (radiance L, half side a) at distance h, the
// receiver facing it: four corner rectangles of the view factor table (Howell C-11),
// E = 4 L X/sqrt(1+X^2) atan(X/sqrt(1+X^2)), X = a/h.
double square_irradiance(double radiance, double half_side, double h) {
  const double x = half_side / h, s = std::sqrt(1.0 + x * x);
  return 4.0 * radiance * (x / s) * std::atan(x / s);
}

// Solid angle of that square from the same point: 4 asin(X^2 / (1 + X^2)).
double square_solid_angle(double half_side, double h) {
  const double x2 = (half_side / h) * (half_side / h);
  return 4.0 * std::asin(x2 / (1.0 + x2));
}

// Probes at the given points and nothing else (no octree, no SVO: the hits get no indirect light, which
// these one-surface scenes do not have anyway).
formats::ProbeVolume probes_at(const std::vector<glm::vec3>& positions) {
  formats::ProbeVolume v;
  for (const glm::vec3& p : positions) {
    gpu::Probe probe{};
    probe.position = p;
    probe.link = 1;
    v.probes.push_back(probe);
  }
  return v;
}

// The probe's irradiance DC term, Y0 * sh0 = (1/4) * integral of the incoming radiance over the sphere.
glm::vec3 probe_dc(const gpu::Probe& p) {
  return probe_index::kShY0 * glm::vec3(p.irradiance_sh[0], p.irradiance_sh[1], p.irradiance_sh[2]);
}

// Quadrature error of the probes' Fibonacci lattice for a region of solid angle `omega` whose outline is
// `perimeter` radians long: each ray stands for 4 pi / R sr, and only rays within one lattice spacing of
// the outline can be misclassified; the lattice's low discrepancy makes their errors cancel like a
// random sum at worst, so 3 sqrt(band rays) rays of 4 pi / R sr each, relative to omega.
double lattice_tolerance(int rays, double omega, double perimeter) {
  const double cell = 4.0 * kPi / rays, spacing = std::sqrt(cell);
  const double band_rays = perimeter * spacing / cell;
  return 3.0 * std::sqrt(band_rays) * cell / omega;
}

// The reference's estimate at one point with `sigmas` standard errors of slack (per channel).
void expect_reference(const bake::ReferenceResult& r, std::size_t i, glm::vec3 expected, float sigmas,
                      const char* what) {
  for (int c = 0; c < 3; ++c) {
    const float tolerance = sigmas * r.standard_error[i][c] + 1e-6f * expected[c];
    EXPECT_NEAR(r.irradiance[i][c], expected[c], tolerance) << what << " channel " << c;
  }
}

// ---- (a) A square emitter seen from both sides --------------------------------------------------------------

constexpr float kHalf = 0.5f, kHeight = 0.5f; // X = 1
const glm::vec3 kRadiance(3.0f, 2.0f, 1.0f);

// The square in y = 0, front (and normal) +y.
samples::SceneBuilder square_emitter(bool double_sided) {
  samples::SceneBuilder b("square_emitter");
  const samples::MaterialId m = b.add_material({"emitter", glm::vec3(0.5f), kRadiance, double_sided});
  b.add_mesh_node(
      "square",
      b.add_mesh("square",
                 samples::quad({-kHalf, 0.0f, -kHalf}, {0.0f, 0.0f, 2.0f * kHalf}, {2.0f * kHalf, 0.0f, 0.0f}, 2), m));
  return b;
}

struct SquareResult {
  glm::vec3 reference_front{0.0f}, reference_back{0.0f}, direct_front{0.0f}, direct_back{0.0f};
  glm::vec3 probe_front{0.0f}, probe_back{0.0f};
  std::size_t backface_hits = 0;
};

SquareResult measure_square(bool double_sided) {
  const Loaded l = load(square_emitter(double_sided), double_sided ? "square_double" : "square_single");
  EXPECT_GT(scene::triangle_normal(*l.scene, 0).y, 0.99f);
  const glm::vec3 front(0.0f, kHeight, 0.0f), back(0.0f, -kHeight, 0.0f);
  const std::vector<bake::SamplePoint> points = {{front, {0.0f, -1.0f, 0.0f}}, {back, {0.0f, 1.0f, 0.0f}}};
  const bake::ReferenceResult r = bake::reference_irradiance(*l.scene, *l.rays, points, {.paths = 4096, .seed = 5});
  SquareResult s;
  s.reference_front = r.irradiance[0];
  s.reference_back = r.irradiance[1];
  const double expected = square_irradiance(1.0, kHalf, kHeight);
  expect_reference(r, 0, kRadiance * float(expected), 5.0f, "reference, in front");
  if (double_sided)
    expect_reference(r, 1, kRadiance * float(expected), 5.0f, "reference, behind");
  else
    EXPECT_EQ(r.irradiance[1], glm::vec3(0.0f)) << "reference behind a single-sided emitter";
  // Shading points: the emitter as an area light (the exact polygon formula, one shadow ray per patch).
  lighting::LightingSettings lighting;
  s.direct_front = lighting::direct_irradiance(*l.scene, *l.rays, points[0].position, points[0].normal, lighting);
  s.direct_back = lighting::direct_irradiance(*l.scene, *l.rays, points[1].position, points[1].normal, lighting);
  // Probes: with emissive_as_lights off they carry the emitter's radiance; the DC term is L omega / 4.
  lighting.emissive_as_lights = false;
  lighting.rays = 16384;
  formats::ProbeVolume volume = probes_at({front, back});
  const lighting::LightingReport report = lighting::bake_lighting(*l.scene, *l.rays, volume, lighting);
  s.probe_front = probe_dc(volume.probes[0]);
  s.probe_back = probe_dc(volume.probes[1]);
  s.backface_hits = report.backface_hits;
  std::printf("[double-sided] square emitter (%s), L = (3, 2, 1), X = 1: closed form E = %.5f L; reference front %.5f "
              "+- %.5f, behind %.5f +- %.5f; direct_irradiance front %.6f, behind %.6f; probe DC closed form %.5f L, "
              "front %.5f, behind %.5f; back-face probe rays %zu\n",
              double_sided ? "double-sided" : "single-sided", expected, double(s.reference_front.x / kRadiance.x),
              double(r.standard_error[0].x / kRadiance.x), double(s.reference_back.x / kRadiance.x),
              double(r.standard_error[1].x / kRadiance.x), double(s.direct_front.x / kRadiance.x),
              double(s.direct_back.x / kRadiance.x), square_solid_angle(kHalf, kHeight) / 4.0,
              double(s.probe_front.x / kRadiance.x), double(s.probe_back.x / kRadiance.x), s.backface_hits);
  return s;
}

TEST(DoubleSided, SquareEmitterLightsBothSides) {
  const SquareResult s = measure_square(true);
  const double expected = square_irradiance(1.0, kHalf, kHeight);
  // Lambert's formula is exact; float rounding over 8 patches stays far below 1e-5.
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(s.direct_front[c], kRadiance[c] * expected, 1e-5 * kRadiance[c] * expected);
    EXPECT_NEAR(s.direct_back[c], kRadiance[c] * expected, 1e-5 * kRadiance[c] * expected);
  }
  const double omega = square_solid_angle(kHalf, kHeight);
  // The outline: four great-circle arcs, each seen under 2 atan(a / sqrt(a^2 + h^2)).
  const double perimeter = 8.0 * std::atan(kHalf / std::hypot(kHalf, kHeight));
  const double tolerance = lattice_tolerance(16384, omega, perimeter);
  std::printf("[double-sided] square emitter: probe DC lattice bound %.2f %%\n", 100.0 * tolerance);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(s.probe_front[c], kRadiance[c] * omega / 4.0, tolerance * kRadiance[c] * omega / 4.0);
    // The same lattice sees the same square from the mirror point: mirror-symmetric up to the lattice.
    EXPECT_NEAR(s.probe_back[c], kRadiance[c] * omega / 4.0, tolerance * kRadiance[c] * omega / 4.0);
  }
  EXPECT_EQ(s.backface_hits, 0u);
}

TEST(DoubleSided, SingleSidedSquareEmitterIsDarkBehind) {
  const SquareResult s = measure_square(false);
  const double expected = square_irradiance(1.0, kHalf, kHeight);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.direct_front[c], kRadiance[c] * expected, 1e-5 * kRadiance[c] * expected);
  EXPECT_EQ(s.direct_back, glm::vec3(0.0f));
  EXPECT_GT(s.probe_front.x, 0.0f);
  EXPECT_EQ(s.probe_back, glm::vec3(0.0f));
  EXPECT_GT(s.backface_hits, 0u); // the probe behind it sees the inside of a solid
}

// A point on the emitter itself (a probe ray's hit on the light, a pixel of it) lies in its plane up to
// rounding of either sign, where Lambert's formula is singular: it gets none of the emitter's light, on
// either side; 10 shadow offsets off the plane it gets the closed form again (nearly pi L).
TEST(DoubleSided, PointOnTheEmitterGetsNoneOfItsLight) {
  for (const bool double_sided : {true, false}) {
    const Loaded l = load(square_emitter(double_sided), double_sided ? "square_on_double" : "square_on_single");
    const float offset = 1e-4f * l.scene->bounds.largest_extent();
    for (const float y : {0.0f, 1e-7f, -1e-7f, 0.5f * offset, -0.5f * offset}) {
      const glm::vec3 p(0.1f, y, -0.2f);
      EXPECT_EQ(lighting::direct_irradiance(*l.scene, *l.rays, p, {0.0f, 1.0f, 0.0f}), glm::vec3(0.0f)) << y;
      EXPECT_EQ(lighting::direct_irradiance(*l.scene, *l.rays, p, {0.0f, -1.0f, 0.0f}), glm::vec3(0.0f)) << y;
    }
    const float h = 10.0f * offset;
    const glm::vec3 above = lighting::direct_irradiance(*l.scene, *l.rays, {0.0f, h, 0.0f}, {0.0f, -1.0f, 0.0f});
    const glm::vec3 below = lighting::direct_irradiance(*l.scene, *l.rays, {0.0f, -h, 0.0f}, {0.0f, 1.0f, 0.0f});
    const double expected = square_irradiance(1.0, kHalf, h);
    std::printf("[double-sided] %s square, %.0e m off its plane: closed form %.6f L, front %.6f L, behind %.6f L\n",
                double_sided ? "double-sided" : "single-sided", double(h), expected, double(above.x / kRadiance.x),
                double(below.x / kRadiance.x));
    EXPECT_NEAR(above.x, kRadiance.x * expected, 1e-5 * kRadiance.x * expected);
    if (double_sided)
      EXPECT_NEAR(below.x, kRadiance.x * expected, 1e-5 * kRadiance.x * expected);
    else
      EXPECT_EQ(below, glm::vec3(0.0f));
  }
}

// The margin is about the patch rising above p's horizon, not about p's distance to the emitter's plane:
// on a wall that meets the emitter's edge at a right angle (the corner of an emitting room), the emitter
// fills a quarter sphere whatever the distance to its plane, so half a shadow offset off it the point keeps
// the light it gets two offsets off it.
TEST(DoubleSided, PointOnAWallMeetingTheEmitterKeepsItsLight) {
  const Loaded l = load(square_emitter(true), "square_wall");
  const float offset = 1e-4f * l.scene->bounds.largest_extent();
  const glm::vec3 facing(-1.0f, 0.0f, 0.0f); // a wall in the plane of the square's edge x = a, facing it
  const auto at = [&](float y) { return lighting::direct_irradiance(*l.scene, *l.rays, {kHalf, y, 0.0f}, facing); };
  for (const float sign : {1.0f, -1.0f}) {
    const glm::vec3 near = at(sign * 0.5f * offset), off = at(sign * 2.0f * offset);
    std::printf("[double-sided] wall at the square's edge, %+.1e / %+.1e m off its plane: %.6f / %.6f L\n",
                double(sign * 0.5f * offset), double(sign * 2.0f * offset), double(near.x / kRadiance.x),
                double(off.x / kRadiance.x));
    EXPECT_GT(near.x, 0.1f * kRadiance.x);
    EXPECT_NEAR(near.x, off.x, 1e-3f * off.x);
  }
}

// ---- (b) A plane lit from below --------------------------------------------------------------------------

constexpr float kPlaneHalf = 2.0f, kBelow = 1.0f; // X = 2
constexpr float kLux = 5.0f;
const glm::vec3 kPlaneAlbedo(0.6f, 0.4f, 0.2f);

// A square plane in y = 0, front +y, under a directional light shining straight up at its underside.
samples::SceneBuilder plane_lit_from_below(bool double_sided) {
  samples::SceneBuilder b("plane_below");
  const samples::MaterialId m = b.add_material({"plane", kPlaneAlbedo, glm::vec3(0.0f), double_sided});
  b.add_mesh_node("plane", b.add_mesh("plane",
                                      samples::quad({-kPlaneHalf, 0.0f, -kPlaneHalf}, {0.0f, 0.0f, 2.0f * kPlaneHalf},
                                                    {2.0f * kPlaneHalf, 0.0f, 0.0f}, 2),
                                      m));
  samples::Light sun{.name = "sun", .type = samples::LightType::directional, .intensity = kLux};
  b.add_light_node("sun", b.add_light(sun), {0.0f, -3.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
  return b;
}

struct PlaneResult {
  glm::vec3 underside{0.0f}, receiver{0.0f}, probe{0.0f};
  std::size_t backface_hits = 0;
};

// The underside point gets E from the light; the receiver at depth h under the plane's centre, facing
// up, gets only the plane's reflected radiance rho E / pi over the square: rho E / pi * (closed form).
PlaneResult measure_plane(bool double_sided) {
  const Loaded l = load(plane_lit_from_below(double_sided), double_sided ? "plane_double" : "plane_single");
  EXPECT_GT(scene::triangle_normal(*l.scene, 0).y, 0.99f);
  const std::vector<bake::SamplePoint> points = {{{0.3f, 0.0f, -0.2f}, {0.0f, -1.0f, 0.0f}},
                                                 {{0.0f, -kBelow, 0.0f}, {0.0f, 1.0f, 0.0f}}};
  const bake::ReferenceResult r = bake::reference_irradiance(*l.scene, *l.rays, points, {.paths = 4096, .seed = 6});
  PlaneResult p;
  p.underside = r.irradiance[0];
  p.receiver = r.irradiance[1];
  const glm::vec3 radiance = kPlaneAlbedo * (kLux / kPi);
  const double expected = square_irradiance(1.0, kPlaneHalf, kBelow);
  if (double_sided)
    expect_reference(r, 1, radiance * float(expected), 5.0f, "reference under the plane");
  else
    EXPECT_EQ(r.irradiance[1], glm::vec3(0.0f)) << "reference under a single-sided plane's back";
  // The probe under the plane: sky 0, so its DC term is rho E / pi * omega / 4.
  lighting::LightingSettings lighting;
  lighting.rays = 16384;
  formats::ProbeVolume volume = probes_at({{0.0f, -kBelow, 0.0f}});
  const lighting::LightingReport report = lighting::bake_lighting(*l.scene, *l.rays, volume, lighting);
  p.probe = probe_dc(volume.probes[0]);
  p.backface_hits = report.backface_hits;
  std::printf(
      "[double-sided] plane lit from below (%s), rho = (0.6, 0.4, 0.2), E = 5, X = 2: underside reference %.5f "
      "(closed form %.5f); receiver below: closed form %.5f, reference %.5f +- %.5f; probe DC closed form %.5f, "
      "bake %.5f (red channel); back-face probe rays %zu\n",
      double_sided ? "double-sided" : "single-sided", double(p.underside.x), double(kLux),
      double(radiance.x) * expected, double(p.receiver.x), double(r.standard_error[1].x),
      double(radiance.x) * square_solid_angle(kPlaneHalf, kBelow) / 4.0, double(p.probe.x), p.backface_hits);
  return p;
}

TEST(DoubleSided, PlaneLitFromBelowReflectsDown) {
  const PlaneResult p = measure_plane(true);
  // A point on the underside: exactly the light's E (no path continues: below the plane is open sky).
  EXPECT_NEAR(p.underside.x, kLux, 1e-5f * kLux);
  const glm::vec3 radiance = kPlaneAlbedo * (kLux / kPi);
  const double omega = square_solid_angle(kPlaneHalf, kBelow);
  const double perimeter = 8.0 * std::atan(kPlaneHalf / std::hypot(kPlaneHalf, kBelow));
  const double tolerance = lattice_tolerance(16384, omega, perimeter);
  std::printf("[double-sided] plane lit from below: probe DC lattice bound %.2f %%\n", 100.0 * tolerance);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.probe[c], radiance[c] * omega / 4.0, tolerance * radiance[c] * omega / 4.0);
  EXPECT_EQ(p.backface_hits, 0u);
}

TEST(DoubleSided, SingleSidedPlaneLitFromBelowStaysDark) {
  const PlaneResult p = measure_plane(false);
  // A receiver facing down gets the light whatever surface it lies on (receivers carry their own normal).
  EXPECT_NEAR(p.underside.x, kLux, 1e-5f * kLux);
  EXPECT_EQ(p.probe, glm::vec3(0.0f)); // every probe ray ends inside the solid behind the plane's back
  EXPECT_GT(p.backface_hits, 0u);
}

// ---- (c) The Cornell box reversed and double-sided ---------------------------------------------------

// The same scene by the glTF rule: every triangle's winding reversed (two indices swapped, so the
// geometric normal is exactly negated) and every material double-sided.
scene::Scene reversed_double_sided(scene::Scene s) {
  for (glm::uvec3& t : s.triangles) std::swap(t.y, t.z);
  for (scene::Material& m : s.materials) m.double_sided = true;
  return s;
}

// Not quite the same scene: the light quad hangs 0.5 mm under the ceiling, and a double-sided light also
// emits from its back into that gap (light that escapes through the 0.5 mm slit around it, and grazing
// light on the ceiling next to it). Without the ceiling (its triangles made degenerate: never hit, no
// area) the back of the light faces open sky in both versions and the two scenes are the same.
scene::Scene without_ceiling(scene::Scene s) {
  const float top = s.bounds.max.y;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const glm::uvec3 i = s.triangles[t];
    const auto at_top = [&](std::uint32_t v) { return s.positions[v].y == top; };
    if (at_top(i.x) && at_top(i.y) && at_top(i.z)) s.triangles[t] = glm::uvec3(i.x);
  }
  return s;
}

struct ReferenceComparison {
  std::size_t receivers = 0;
  double worst_sigmas = 0.0; // largest |difference| / combined standard error over receivers and channels
  double mean_original = 0.0, mean_reversed = 0.0;
};

// Receivers spread over the original's surfaces (front sides), the same points and seed in both scenes.
ReferenceComparison compare_reference(const Loaded& original, const Loaded& reversed, int count) {
  const std::vector<bake::SamplePoint> points = bake::surface_sample_points(*original.scene, *original.rays, count, 4);
  const bake::ReferenceSettings settings{.paths = 1024, .seed = 8};
  const bake::ReferenceResult a = bake::reference_irradiance(*original.scene, *original.rays, points, settings);
  const bake::ReferenceResult b = bake::reference_irradiance(*reversed.scene, *reversed.rays, points, settings);
  ReferenceComparison r;
  r.receivers = points.size();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double se = std::hypot(double(a.standard_error[i][c]), double(b.standard_error[i][c]));
      const double d = std::abs(double(a.irradiance[i][c]) - double(b.irradiance[i][c]));
      r.worst_sigmas = std::max(r.worst_sigmas, se > 0.0 ? d / se : (d > 0.0 ? 1e30 : 0.0));
      r.mean_original += a.irradiance[i][c] / double(3 * points.size());
      r.mean_reversed += b.irradiance[i][c] / double(3 * points.size());
    }
  return r;
}

// Open-topped Cornell box: the same random walks (same seed, directions about exactly the same normals)
// in both; only the light samples land elsewhere on the emitter (uniform_triangle_point depends on the
// vertex order), so the estimates differ by less than their combined standard error, not by float noise.
TEST(DoubleSided, ReversedCornellBoxHasTheSameReference) {
  const scene::Scene open = without_ceiling(load_generated(samples::cornell(), "cornell_ds_reference"));
  const Loaded original = adopt(open), reversed = adopt(reversed_double_sided(open));
  const ReferenceComparison r = compare_reference(original, reversed, 160);
  std::printf("[double-sided] cornell (no ceiling) reversed + double-sided vs original: %zu receivers x 1024 paths, "
              "mean irradiance %.5f vs %.5f (relative %.2e), largest difference %.2f combined standard errors\n",
              r.receivers, r.mean_reversed, r.mean_original, r.mean_reversed / r.mean_original - 1.0, r.worst_sigmas);
  ASSERT_GT(r.receivers, 100u);
  EXPECT_GT(r.mean_original, 0.0);
  EXPECT_LT(r.worst_sigmas, 5.0);
  EXPECT_LT(std::abs(r.mean_reversed / r.mean_original - 1.0), 0.01);
}

// The full box: the double-sided light also shines into the gap over it and out through the slit, so
// the reversed box is brighter, by about (slit area x gap radiance) / (light area x L): a few percent.
TEST(DoubleSided, ReversedCornellBoxGainsOnlyTheLightsBackGlow) {
  const Loaded original = load(samples::cornell(), "cornell_ds_full");
  const Loaded reversed = adopt(reversed_double_sided(*original.scene));
  const ReferenceComparison r = compare_reference(original, reversed, 160);
  std::printf("[double-sided] cornell (full) reversed + double-sided vs original: %zu receivers x 1024 paths, mean "
              "irradiance %.5f vs %.5f (relative %.2e), largest difference %.2f combined standard errors\n",
              r.receivers, r.mean_reversed, r.mean_original, r.mean_reversed / r.mean_original - 1.0, r.worst_sigmas);
  EXPECT_GT(r.mean_reversed, r.mean_original);
  EXPECT_LT(r.mean_reversed / r.mean_original - 1.0, 0.05);
  // Next to the light on the ceiling, only the double-sided light's back reaches: 2 mm from its edge the
  // exact polygon formula gives a sizeable share of the light's pi L.
  const glm::vec3 beside(0.0f, original.scene->bounds.max.y, 0.0f);
  scene::Bounds light;
  for (std::size_t t = 0; t < original.scene->triangles.size(); ++t)
    if (original.scene->triangle_emission[t].x > 0.0f)
      for (int k = 0; k < 3; ++k) light.extend(original.scene->positions[original.scene->triangles[t][k]]);
  const glm::vec3 p(light.max.x + 0.002f, beside.y, 0.5f * (light.min.z + light.max.z)), down(0.0f, -1.0f, 0.0f);
  const glm::vec3 ea = lighting::direct_irradiance(*original.scene, *original.rays, p, down);
  const glm::vec3 eb = lighting::direct_irradiance(*reversed.scene, *reversed.rays, p, down);
  std::printf("[double-sided] ceiling 2 mm beside the light: emitter direct %.4f (original) vs %.4f (reversed, "
              "double-sided) W/m^2, red\n",
              double(ea.x), double(eb.x));
  EXPECT_EQ(ea, glm::vec3(0.0f));
  EXPECT_GT(eb.x, 0.01f * kPi * samples::cornell_light_radiance[0]);
}

// The bake's lighting on the same probes (placed in the original, open-topped box): every probe's SH
// equal within float noise, at 1 and 2 threads alike, and the emitters' direct light at shading points.
TEST(DoubleSided, ReversedCornellBoxHasTheSameBakeLighting) {
  const scene::Scene open = without_ceiling(load_generated(samples::cornell(), "cornell_ds_bake"));
  const Loaded original = adopt(open), reversed = adopt(reversed_double_sided(open));
  const bake::BakeSettings settings = test_settings();
  const formats::ProbeVolume placed = bake::bake(*original.scene, settings).volume;
  formats::ProbeVolume a = placed, b = placed, b1 = placed;
  const lighting::LightingReport ra = lighting::bake_lighting(*original.scene, *original.rays, a, settings.lighting);
  const lighting::LightingReport rb = lighting::bake_lighting(*reversed.scene, *reversed.rays, b, settings.lighting);
  lighting::LightingSettings one_thread = settings.lighting;
  one_thread.threads = 1;
  lighting::bake_lighting(*reversed.scene, *reversed.rays, b1, one_thread);
  ASSERT_GT(ra.probes, 10);
  EXPECT_EQ(ra.probes, rb.probes);
  EXPECT_EQ(rb.backface_hits, 0u); // nothing is inside a solid in the double-sided box
  float largest = 0.0f, worst = 0.0f;
  for (const gpu::Probe& p : a.probes) largest = std::max(largest, std::abs(p.irradiance_sh[0]));
  for (std::size_t i = 0; i < a.probes.size(); ++i)
    for (int v = 0; v < gpu::PROBE_SH_FLOATS; ++v) {
      const float x = a.probes[i].irradiance_sh[v], y = b.probes[i].irradiance_sh[v];
      worst = std::max(worst, std::abs(x - y) / std::max(std::abs(x), 1e-3f * largest));
    }
  std::printf("[double-sided] cornell (no ceiling) reversed + double-sided vs original, bake lighting on the same %d "
              "probes: %d vs %d sweeps, back-face rays %zu vs %zu, max relative SH difference %.2e\n",
              ra.probes, rb.iterations, ra.iterations, rb.backface_hits, ra.backface_hits, double(worst));
  EXPECT_LT(worst, 1e-3f);
  EXPECT_EQ(std::memcmp(b.probes.data(), b1.probes.data(), b.probes.size() * sizeof(gpu::Probe)), 0);
  float worst_direct = 0.0f;
  for (const bake::SamplePoint& p : bake::surface_sample_points(*original.scene, *original.rays, 60, 2)) {
    const glm::vec3 ea =
        lighting::direct_irradiance(*original.scene, *original.rays, p.position, p.normal, settings.lighting);
    const glm::vec3 eb =
        lighting::direct_irradiance(*reversed.scene, *reversed.rays, p.position, p.normal, settings.lighting);
    for (int c = 0; c < 3; ++c) worst_direct = std::max(worst_direct, std::abs(eb[c] - ea[c]) / std::max(ea[c], 1e-3f));
  }
  std::printf("[double-sided] cornell (no ceiling) reversed: emitter direct_irradiance at 60 receivers, max relative "
              "difference %.2e\n",
              double(worst_direct));
  EXPECT_LT(worst_direct, 1e-4f);
}

} // namespace
} // namespace probebake::test
