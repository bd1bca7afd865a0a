// Image receivers of `probebake eval --camera`: the first surface seen through each pixel, scored per
// configuration; with --error-map DIR also written as error images, |probe estimate - reference| per
// channel (so a row's image_mean_error is the mean of its image over the visible pixels), and as HDR-FLIP
// maps (flip.h) of the estimate's picture against the reference's.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "probebake/eval/eval.h"
#include "probebake/eval/flip.h"

namespace probebake::bake::detail {

class ErrorMaps {
public:
  // Traces the camera, computes the reference image (settings.image_paths per pixel, not cached) and,
  // with an error-map folder, writes it as DIR/reference.exr.
  ErrorMaps(const scene::Scene& scene, const scene::RayScene& rays, const EvalSettings& settings);
  // Scores a lookup of irradiance from probes on the image receivers (row.image_*); with a folder, writes
  // DIR/<label>.exr and DIR/<label>.flip.exr (<label>-<sampler> for samplers other than the SVO's) and returns
  // their paths.
  using Lookup = std::function<glm::vec3(glm::vec3 position, glm::vec3 normal)>;
  std::vector<std::filesystem::path> score(EvalRow& row, const Lookup& lookup) const;
  bool writes() const { return !dir_.empty(); }
  std::filesystem::path reference_path() const { return dir_ / "reference.exr"; }
  int pixels() const { return int(points_.size()); }
  double mean_reference() const { return mean_; }
  const FlipExposures& flip_exposures() const { return exposures_; }

private:
  std::filesystem::path dir_;
  Camera camera_;
  std::vector<std::size_t> pixels_; // pixel index of each visible point
  std::vector<SamplePoint> points_;
  std::vector<glm::vec3> reference_;
  std::vector<glm::vec3> direct_;
  double mean_ = 0.0;
  Image reference_image_;   // black where the camera sees nothing
  FlipExposures exposures_; // from the visible pixels: the background would pull the median to 0
  int threads_ = 0;
};

} // namespace probebake::bake::detail
