#include "camera_options.h"

#include <cstdio>

#include "probebake/formats/error.h"

namespace probebake::cli {

void CameraOptions::add_to(CLI::App& app) {
  app.add_option("--camera", position, "Camera position x,y,z (metres)")->delimiter(',')->expected(3);
  app.add_option("--look-at", look_at, "Point the camera looks at, x,y,z")->delimiter(',')->expected(3);
  app.add_option("--fov", fov, "Vertical field of view, degrees");
  app.add_option("--size", size, "Image size WxH in pixels");
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
  char x = 0, end = 0;
  if (std::sscanf(size.c_str(), "%d%c%d%c", &c.width, &x, &c.height, &end) != 3 || (x != 'x' && x != 'X'))
    throw Error(ErrorKind::usage, "--size must be WxH, e.g. 640x480 (got " + size + ")");
  bake::check_camera(c);
  return c;
}

} // namespace probebake::cli
