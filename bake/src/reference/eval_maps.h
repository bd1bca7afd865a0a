// Per-configuration error images of `probebake eval --error-map DIR`: |probe estimate - reference| per
// channel at the first surface seen through each pixel.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "probebake/bake/eval.h"

namespace probebake::bake::detail {

class ErrorMaps {
public:
  // Traces the camera, computes the reference image (settings.image_paths per pixel, not cached) and
  // writes it as DIR/reference.exr.
  ErrorMaps(const scene::Scene& scene, const scene::RayScene& rays, const EvalSettings& settings);
  // Writes DIR/<label>.exr for this volume; returns its path.
  std::filesystem::path write(const std::string& label, const formats::ProbeVolume& volume) const;
  std::filesystem::path reference_path() const { return dir_ / "reference.exr"; }

private:
  std::filesystem::path dir_;
  Camera camera_;
  std::vector<std::size_t> pixels_;  // pixel index of each visible point
  std::vector<SamplePoint> points_;
  std::vector<glm::vec3> reference_;
  std::vector<glm::vec3> direct_;
};

} // namespace probebake::bake::detail
