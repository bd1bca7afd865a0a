// Ground truth for the probes: a CPU path tracer that estimates diffuse irradiance E at surface points,
// with a standard error per point, and images of it from a pinhole camera (OpenEXR).
//
// Light transport follows the bake's conventions (scene.h): Lambertian surfaces (albedo / pi), emitted
// radiance from front faces only, back faces black, glTF punctual intensities taken as radiometric
// (point/spot: I in W/sr, E = I cos / r^2 with the KHR_lights_punctual range window and spot cone
// falloff; directional: W/m^2). Estimator: cosine-weighted hemisphere sampling, next-event estimation on
// punctual lights and on emissive triangles (power-proportional area sampling) combined with BSDF hits
// by multiple importance sampling (power heuristic), Russian roulette after a few bounces (unbiased).
//
// Deterministic: every point's paths come from random streams keyed by (seed, point, chunk of paths), and
// chunks are summed in index order, so results are identical for any thread count.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/bake/ray_scene.h"
#include "probebake/bake/scene.h"

namespace probebake::bake {

// A point on a surface and the unit normal of its visible (front) side.
struct SamplePoint {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
};

struct ReferenceSettings {
  int paths = 1024;          // paths per point, >= 2 (the standard error needs two)
  std::uint64_t seed = 1;
  int threads = 0;           // 0 = all cores; results do not depend on it
  int roulette_after = 3;    // bounces traced before Russian roulette starts
  int max_bounces = 100000;  // safety net only (a path this long has throughput ~0 unless albedo is 1)
};

// Throws Error(usage) naming the setting when one is out of range.
void check_reference_settings(const ReferenceSettings& settings);

struct ReferenceResult {
  std::vector<glm::vec3> irradiance;      // mean estimate per point, W/m^2 per RGB channel
  std::vector<glm::vec3> standard_error;  // standard error of that mean, per channel
  double seconds = 0.0;
};

ReferenceResult reference_irradiance(const scene::Scene& scene, const scene::RayScene& rays,
                                     std::span<const SamplePoint> points, const ReferenceSettings& settings);

// `count` points spread over the scene's surfaces proportionally to area (stratified along the cumulative
// area of the triangles), front sides only, without points that lie inside geometry (a point whose
// slightly offset position sees mostly back faces over its hemisphere, e.g. floor under a box). The same
// (scene, count, seed) gives the same points. Fewer than `count` only when almost every surface is hidden.
std::vector<SamplePoint> surface_sample_points(const scene::Scene& scene, const scene::RayScene& rays, int count,
                                               std::uint64_t seed);
std::vector<SamplePoint> surface_sample_points(const scene::Scene& scene, int count, std::uint64_t seed);

// Reference points and values as CSV with a header line: x,y,z,nx,ny,nz,r,g,b,stderr (stderr: the
// largest channel's standard error), floats with 9 significant digits (exact round trip). Written to a
// temporary file and renamed; throws Error(output) when it cannot be written.
void write_reference_csv(const std::filesystem::path& path, std::span<const SamplePoint> points,
                         const ReferenceResult& reference);
// Returns false when the file is missing or not such a CSV (stderr comes back in every channel).
bool read_reference_csv(const std::filesystem::path& path, std::vector<SamplePoint>& points, ReferenceResult& reference);

// ---- Images ------------------------------------------------------------------------------------------

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 1.0f};
  glm::vec3 look_at{0.0f};
  float fov_degrees = 60.0f;  // vertical field of view
  int width = 256;
  int height = 256;
};

// Throws Error(usage) when the camera is unusable (size, fov, position equal to look_at, non-finite).
void check_camera(const Camera& camera);

// Row-major RGB, top row first.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> pixels;
};

// The first surface seen through each pixel's centre, or nothing where the ray misses or first meets a
// back face.
std::vector<std::optional<SamplePoint>> camera_surface_points(const scene::RayScene& rays, const Camera& camera);

// Reference irradiance of the first visible surface per pixel (0 where nothing or a back face is seen);
// settings.paths paths per pixel.
Image render_irradiance_image(const scene::Scene& scene, const scene::RayScene& rays, const Camera& camera,
                              const ReferenceSettings& settings);

// OpenEXR, 32-bit float R, G, B channels. Throws Error(output) when the file cannot be written.
void write_exr(const std::filesystem::path& path, const Image& image);
// Any RGB(A) OpenEXR file. Throws Error(input) when it cannot be read.
Image read_exr(const std::filesystem::path& path);

} // namespace probebake::bake
