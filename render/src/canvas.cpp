#include "canvas.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace probebake::render::detail {

void Canvas::sphere(const bake::CameraFrame& frame, glm::vec3 centre, float radius,
                    const std::function<glm::vec3(glm::vec3)>& colour) {
  const auto at = frame.project(centre);
  if (!at || !(at->z > radius)) return;
  // The sphere's outline is an ellipse that grows towards the image's edges; 1.6x its on-axis radius plus
  // two pixels holds it for fields of view up to about 100 degrees.
  const float pixels = 1.6f * radius / (at->z * frame.tan_half_y) * 0.5f * float(frame.height) + 2.0f;
  const int x0 = std::max(0, int(std::floor(at->x - pixels))),
            x1 = std::min(frame.width - 1, int(std::ceil(at->x + pixels)));
  const int y0 = std::max(0, int(std::floor(at->y - pixels))),
            y1 = std::min(frame.height - 1, int(std::ceil(at->y + pixels)));
  const glm::vec3 to_camera = frame.position - centre;
  const float c = glm::dot(to_camera, to_camera) - radius * radius;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const std::size_t pixel = std::size_t(y) * std::size_t(frame.width) + std::size_t(x);
      const glm::vec3 dir = frame.pixel_direction(pixel);
      const float b = glm::dot(dir, to_camera), disc = b * b - c;
      if (disc < 0.0f) continue;
      const float t = -b - std::sqrt(disc);
      if (!(t > 0.0f) || !(t < depth[pixel])) continue;
      depth[pixel] = t;
      image.pixels[pixel] = colour(glm::normalize(frame.position + t * dir - centre));
    }
}

void Canvas::line(const bake::CameraFrame& frame, glm::vec3 a, glm::vec3 b, glm::vec3 colour) {
  const auto pa = frame.project(a), pb = frame.project(b);
  if (!pa || !pb) return;
  const float length = std::max(std::abs(pb->x - pa->x), std::abs(pb->y - pa->y));
  const int steps = std::clamp(int(std::ceil(2.0f * length)), 1, 4 * (frame.width + frame.height));
  for (int s = 0; s <= steps; ++s) {
    const glm::vec3 p = a + (b - a) * (float(s) / float(steps));
    const auto q = frame.project(p);
    if (!q || q->x < 0.0f || q->y < 0.0f || q->x >= float(frame.width) || q->y >= float(frame.height)) continue;
    const std::size_t pixel = std::size_t(q->y) * std::size_t(frame.width) + std::size_t(q->x);
    const float t = glm::length(p - frame.position);
    if (t < depth[pixel] * 1.001f) depth[pixel] = std::min(depth[pixel], t), image.pixels[pixel] = colour;
  }
}

} // namespace probebake::render::detail
