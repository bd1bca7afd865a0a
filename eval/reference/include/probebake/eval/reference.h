// Ground truth for the probes: a CPU path tracer that estimates diffuse irradiance E at surface points,
// with a standard error per point, and images of it from a pinhole camera (OpenEXR).
//
// Light transport follows the bake's conventions (scene.h, docs/LIGHTING.md): Lambertian surfaces
// (albedo / pi); single-sided surfaces reflect and emit from their front only (the back is black, inside a
// solid), glTF doubleSided ones from both sides with the normal facing the ray; glTF punctual intensities taken as radiometric
// (point/spot: I in W/sr, E = I cos / r^2 with the KHR_lights_punctual range window and spot cone
// falloff; directional: W/m^2); the scene's sky on paths that leave the scene (scene.sky, indirect light like
// the bounces: probes carry it). Estimator: cosine-weighted hemisphere sampling, next-event estimation on
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

#include "probebake/scene/ray_scene.h"
#include "probebake/scene/scene.h"

namespace probebake::bake {

// A point on a surface and the unit normal of the side that receives: the front of a single-sided surface,
// either side of a double-sided one (each side is a receiver of its own).
struct SamplePoint {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
};

struct ReferenceSettings {
  int paths = 1024; // paths per point, >= 2 (the standard error needs two)
  std::uint64_t seed = 1;
  int threads = 0;          // 0 = all cores; results do not depend on it
  int roulette_after = 3;   // bounces traced before Russian roulette starts
  int max_bounces = 100000; // safety net only (a path this long has throughput ~0 unless albedo is 1)
};

// Throws Error(usage) naming the setting when one is out of range.
void check_reference_settings(const ReferenceSettings& settings);

struct ReferenceResult {
  std::vector<glm::vec3> irradiance;     // mean estimate per point, W/m^2 per RGB channel
  std::vector<glm::vec3> standard_error; // standard error of that mean, per channel
  // The direct part of `irradiance`: punctual lights and emitters seen from the point itself (next-event
  // samples at the receiver and the emission its first ray hits). irradiance - direct is the indirect
  // light, what probes hold (docs/LIGHTING.md "What a probe stores").
  std::vector<glm::vec3> direct;
  std::vector<glm::vec3> indirect_standard_error; // standard error of the indirect part's mean, per channel
  double seconds = 0.0;
};

// irradiance - direct, per point.
std::vector<glm::vec3> indirect_irradiance(const ReferenceResult& reference);

ReferenceResult reference_irradiance(const scene::Scene& scene, const scene::RayScene& rays,
                                     std::span<const SamplePoint> points, const ReferenceSettings& settings);

// `count` points spread over the scene's surfaces proportionally to area (stratified along the cumulative
// area of the triangles' sides: the front of a single-sided triangle, both sides of a double-sided one,
// each side with its own normal), without points that lie inside geometry (a point whose slightly offset
// position sees mostly backs of single-sided surfaces over its hemisphere, e.g. floor under a box). The same
// (scene, count, seed) gives the same points. Fewer than `count` only when almost every surface is hidden.
std::vector<SamplePoint> surface_sample_points(const scene::Scene& scene, const scene::RayScene& rays, int count,
                                               std::uint64_t seed);
std::vector<SamplePoint> surface_sample_points(const scene::Scene& scene, int count, std::uint64_t seed);

// Reference points and values as CSV with a header line:
// x,y,z,nx,ny,nz,r,g,b,stderr,direct_r,direct_g,direct_b,indirect_stderr (the stderr columns: the largest
// channel's standard error), floats with 9 significant digits (exact round trip). Written to a temporary
// file and renamed; throws Error(output) when it cannot be written.
void write_reference_csv(const std::filesystem::path& path, std::span<const SamplePoint> points,
                         const ReferenceResult& reference);
// Returns false when the file is missing or not such a CSV (the standard errors come back in every
// channel). A CSV of the 10 columns before the direct part was added is "not such a CSV": eval's cache
// computes it again rather than read it without a direct part.
bool read_reference_csv(const std::filesystem::path& path, std::vector<SamplePoint>& points,
                        ReferenceResult& reference);

// Receivers for `probebake reference --at`: one per line, x,y,z,nx,ny,nz (scene units; the normal picks
// the side of a double-sided surface and is normalised). A first line "x,y,z,nx,ny,nz" or the header of
// write_reference_csv (either version) is skipped, blank lines are skipped, and rows of a reference CSV
// (14 columns, or 10 of the version before the direct part) are read for their first six. Hostile input: the file size is checked before it is read, at most
// kMaxReceivers rows, every number finite. Throws Error(input) "<file>: line N: <reason>".
constexpr std::uintmax_t kMaxReceiverFileBytes = 256ull << 20;
constexpr std::size_t kMaxReceivers = 1'000'000;
std::vector<SamplePoint> read_receivers_csv(const std::filesystem::path& path);

// ---- Images ------------------------------------------------------------------------------------------

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 1.0f};
  glm::vec3 look_at{0.0f};
  float fov_degrees = 60.0f; // vertical field of view
  int width = 256;
  int height = 256;
};

// Throws Error(usage) when the camera is unusable (size, fov, position equal to look_at, non-finite).
void check_camera(const Camera& camera);

// A pinhole camera's frame and its pixel rays: one definition for camera_surface_points and every picture
// drawn over its hits (probebake render's markers). World up is +Y (glTF); looking straight up or down, -Z
// is the image's up instead.
struct CameraFrame {
  explicit CameraFrame(const Camera& camera); // the camera must pass check_camera
  // Unit direction of the ray through the centre of `pixel` (row-major, top row first).
  glm::vec3 pixel_direction(std::size_t pixel) const;
  // Where `p` lands: x to the right and y down in pixels (pixel k spans [k, k + 1)), z its distance along
  // the view axis; nullopt when p is not in front of the camera.
  std::optional<glm::vec3> project(glm::vec3 p) const;

  glm::vec3 position{0.0f}, forward{0.0f}, right{0.0f}, up{0.0f};
  float tan_half_y = 0.0f, aspect = 1.0f;
  int width = 0, height = 0;
};

// Row-major RGB, top row first.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> pixels;
};

// The first surface seen through each pixel's centre with the normal of the side seen, or nothing where
// the ray misses or first meets the back of a single-sided surface. `distances`, when given, receives each
// pixel's distance to its first hit on either side (+inf for a miss): what hides things drawn behind it.
std::vector<std::optional<SamplePoint>> camera_surface_points(const scene::RayScene& rays, const Camera& camera,
                                                              std::vector<float>* distances = nullptr);

// Reference irradiance of the first visible surface per pixel (0 where nothing or the back of a
// single-sided surface is seen);
// settings.paths paths per pixel.
Image render_irradiance_image(const scene::Scene& scene, const scene::RayScene& rays, const Camera& camera,
                              const ReferenceSettings& settings);

// OpenEXR, 32-bit float R, G, B channels. Throws Error(output) when the file cannot be written.
void write_exr(const std::filesystem::path& path, const Image& image);
// Any RGB(A) OpenEXR file. Throws Error(input) when it cannot be read.
Image read_exr(const std::filesystem::path& path);

} // namespace probebake::bake
