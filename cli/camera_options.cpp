#include "camera_options.h"

#include <algorithm>
#include <cstdio>

#include <glm/trigonometric.hpp>

#include "probebake/formats/error.h"

namespace probebake::cli {

void CameraOptions::add_to(CLI::App& app) {
  app.add_option("--camera", position, "Camera position x,y,z (metres)")->delimiter(',')->expected(3);
  app.add_option("--look-at", look_at, "Point the camera looks at, x,y,z")->delimiter(',')->expected(3);
  app.add_option("--fov", fov, "Vertical field of view, degrees");
  size_option_ = app.add_option("--size", size, "Image size WxH in pixels");
}

std::optional<bake::Camera> CameraOptions::camera() const {
  if (position.empty()) {
    if (!look_at.empty()) throw Error(ErrorKind::usage, "--look-at needs --camera");
    return std::nullopt;
  }
  if (look_at.empty()) throw Error(ErrorKind::usage, "--camera needs --look-at");
  bake::Camera c;
  c.position = {position[0], position[1], position[2]};
  c.look_at = {look_at[0], look_at[1], look_at[2]};
  c.fov_degrees = fov;
  parse_size(c);
  bake::check_camera(c);
  return c;
}

void CameraOptions::parse_size(bake::Camera& c) const {
  char x = 0, end = 0;
  if (std::sscanf(size.c_str(), "%d%c%d%c", &c.width, &x, &c.height, &end) != 3 || (x != 'x' && x != 'X'))
    throw Error(ErrorKind::usage, "--size must be WxH, e.g. 640x480 (got " + size + ")");
}

bake::Camera CameraOptions::camera_or_default(const scene::Scene& scene) const {
  if (std::optional<bake::Camera> c = camera()) return *c;
  bake::Camera c = default_camera(scene);
  if (size_option_ != nullptr && size_option_->count() > 0) parse_size(c);
  bake::check_camera(c);
  return c;
}

bake::Camera default_camera(const scene::Scene& scene) {
  bake::Camera camera;
  camera.width = 320, camera.height = 240;
  if (!scene.cameras.empty()) {
    const scene::SceneCamera& c = scene.cameras.front();
    camera.position = c.position;
    camera.look_at = c.position + c.forward;
    camera.fov_degrees = glm::degrees(c.yfov);
    return camera;
  }
  const glm::vec3 centre = 0.5f * (scene.bounds.min + scene.bounds.max), extent = scene.bounds.max - scene.bounds.min;
  camera.position = centre + glm::vec3(0.0f, 0.0f, 0.5f * extent.z + 1.2f * std::max(extent.x, extent.y));
  camera.look_at = centre;
  camera.fov_degrees = 50.0f;
  return camera;
}

} // namespace probebake::cli
