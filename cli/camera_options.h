// Camera options shared by `probebake reference`, `eval`, `run` and `render`:
// --camera x,y,z --look-at x,y,z --fov deg --size WxH.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "probebake/eval/reference.h"
#include "probebake/scene/scene.h"

namespace probebake::cli {

struct CameraOptions {
  std::vector<float> position;
  std::vector<float> look_at;
  float fov = 60.0f;
  std::string size = "512x512";

  void add_to(CLI::App& app);
  // The camera when --camera was given (--look-at is then required); Error(usage) on bad values.
  std::optional<bake::Camera> camera() const;
  // camera(), else default_camera(scene) at --size when it was given.
  bake::Camera camera_or_default(const scene::Scene& scene) const;

private:
  void parse_size(bake::Camera& camera) const;
  CLI::Option* size_option_ = nullptr;
};

// The scene's first glTF camera at 320 x 240, else one on the +Z side of the bounds looking at their centre
// (the open side of the Cornell boxes).
bake::Camera default_camera(const scene::Scene& scene);

} // namespace probebake::cli
