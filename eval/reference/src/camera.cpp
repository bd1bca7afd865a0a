// Pinhole camera: first visible surface per pixel, and reference irradiance images of it.
#include <cmath>
#include <limits>

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

} // namespace

void check_camera(const Camera& c) {
  if (c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384)
    throw Error(ErrorKind::usage, fmt::format("--size must be WxH with 1..16384 each (got {}x{})", c.width, c.height));
  if (!(c.fov_degrees > 0.0f && c.fov_degrees < 180.0f))
    throw Error(ErrorKind::usage, fmt::format("--fov must be in (0, 180) degrees (got {})", c.fov_degrees));
  if (!finite(c.position) || !finite(c.look_at) || !(glm::length(c.look_at - c.position) > 0.0f))
    throw Error(ErrorKind::usage, "--camera and --look-at must be finite and distinct points");
}

CameraFrame::CameraFrame(const Camera& c) : position(c.position), width(c.width), height(c.height) {
  forward = glm::normalize(c.look_at - c.position);
  const glm::vec3 world_up = std::abs(forward.y) > 0.999f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
  right = glm::normalize(glm::cross(forward, world_up));
  up = glm::cross(right, forward);
  tan_half_y = std::tan(glm::radians(c.fov_degrees) / 2.0f);
  aspect = float(c.width) / float(c.height);
}

glm::vec3 CameraFrame::pixel_direction(std::size_t pixel) const {
  const float px = (float(pixel % std::size_t(width)) + 0.5f) / float(width);
  const float py = (float(pixel / std::size_t(width)) + 0.5f) / float(height);
  return glm::normalize(forward + right * ((2.0f * px - 1.0f) * tan_half_y * aspect) +
                        up * ((1.0f - 2.0f * py) * tan_half_y));
}

std::optional<glm::vec3> CameraFrame::project(glm::vec3 p) const {
  const glm::vec3 q = p - position;
  const float z = glm::dot(q, forward);
  if (!(z > 0.0f)) return std::nullopt;
  const float sx = glm::dot(q, right) / (z * tan_half_y * aspect), sy = glm::dot(q, up) / (z * tan_half_y);
  return glm::vec3(0.5f * (sx + 1.0f) * float(width), 0.5f * (1.0f - sy) * float(height), z);
}

std::vector<std::optional<SamplePoint>> camera_surface_points(const scene::RayScene& rays, const Camera& camera,
                                                              std::vector<float>* distances) {
  check_camera(camera);
  const CameraFrame frame(camera);
  const scene::Scene& scene = rays.scene();
  std::vector<std::optional<SamplePoint>> points(std::size_t(camera.width) * std::size_t(camera.height));
  if (distances != nullptr) distances->assign(points.size(), std::numeric_limits<float>::infinity());
  parallel_for(points.size(), 0, [&](std::size_t i) {
    const glm::vec3 dir = frame.pixel_direction(i);
    const auto hit = rays.intersect(camera.position, dir);
    if (hit && distances != nullptr) (*distances)[i] = hit->distance;
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
