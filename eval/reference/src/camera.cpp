// Pinhole camera: first visible surface per pixel, and reference irradiance images of it.
#include <cmath>

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "probebake/common/parallel.h"
#include "probebake/eval/reference.h"
#include "probebake/formats/error.h"
#include "sampling.h"

namespace probebake::bake {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

struct View {
  glm::vec3 forward, right, up;
  float tan_half_y, aspect;
};

View make_view(const Camera& c) {
  View v;
  v.forward = glm::normalize(c.look_at - c.position);
  // World up is +Y (glTF); looking straight up or down, use -Z as the image's up instead.
  const glm::vec3 world_up = std::abs(v.forward.y) > 0.999f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
  v.right = glm::normalize(glm::cross(v.forward, world_up));
  v.up = glm::cross(v.right, v.forward);
  v.tan_half_y = std::tan(glm::radians(c.fov_degrees) / 2.0f);
  v.aspect = float(c.width) / float(c.height);
  return v;
}

} // namespace

void check_camera(const Camera& c) {
  if (c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384)
    throw Error(ErrorKind::usage, fmt::format("--size must be WxH with 1..16384 each (got {}x{})", c.width, c.height));
  if (!(c.fov_degrees > 0.0f && c.fov_degrees < 180.0f))
    throw Error(ErrorKind::usage, fmt::format("--fov must be in (0, 180) degrees (got {})", c.fov_degrees));
  if (!finite(c.position) || !finite(c.look_at) || !(glm::length(c.look_at - c.position) > 0.0f))
    throw Error(ErrorKind::usage, "--camera and --look-at must be finite and distinct points");
}

std::vector<std::optional<SamplePoint>> camera_surface_points(const scene::RayScene& rays, const Camera& camera) {
  check_camera(camera);
  const View v = make_view(camera);
  const scene::Scene& scene = rays.scene();
  std::vector<std::optional<SamplePoint>> points(std::size_t(camera.width) * std::size_t(camera.height));
  parallel_for(points.size(), 0, [&](std::size_t i) {
    const float px = (float(i % std::size_t(camera.width)) + 0.5f) / float(camera.width);
    const float py = (float(i / std::size_t(camera.width)) + 0.5f) / float(camera.height);
    const glm::vec3 dir = glm::normalize(v.forward + v.right * ((2.0f * px - 1.0f) * v.tan_half_y * v.aspect) +
                                         v.up * ((1.0f - 2.0f * py) * v.tan_half_y));
    const auto hit = rays.intersect(camera.position, dir);
    // The side the ray arrived at; the back of a single-sided surface is inside a solid and shows nothing.
    if (hit && !hit->inside())
      points[i] = SamplePoint{detail::triangle_point(scene, hit->triangle, hit->u, hit->v), hit->facing_normal()};
  });
  return points;
}

Image render_irradiance_image(const scene::Scene& scene, const scene::RayScene& rays, const Camera& camera,
                              const ReferenceSettings& settings) {
  check_reference_settings(settings);
  const auto hits = camera_surface_points(rays, camera);
  std::vector<SamplePoint> points;
  std::vector<std::size_t> pixel_of;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i]) continue;
    points.push_back(*hits[i]);
    pixel_of.push_back(i);
  }
  const ReferenceResult r = reference_irradiance(scene, rays, points, settings);
  Image image{camera.width, camera.height, std::vector<glm::vec3>(hits.size(), glm::vec3(0.0f))};
  for (std::size_t k = 0; k < points.size(); ++k) image.pixels[pixel_of[k]] = r.irradiance[k];
  return image;
}

} // namespace probebake::bake
