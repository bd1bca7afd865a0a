#include "eval_maps.h"

#include <cmath>

#include <fmt/core.h>

#include "eval_internal.h"
#include "probebake/lighting/lighting.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/formats/error.h"

namespace probebake::bake::detail {

ErrorMaps::ErrorMaps(const scene::Scene& scene, const scene::RayScene& rays, const EvalSettings& s)
    : dir_(s.error_map_dir), camera_(*s.camera) {
  std::error_code ec;
  if (writes()) std::filesystem::create_directories(dir_, ec);
  if (ec) throw Error(ErrorKind::output, fmt::format("{}: cannot create folder: {}", dir_.string(), ec.message()));
  const auto hits = camera_surface_points(rays, camera_);
  for (std::size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i]) continue;
    pixels_.push_back(i);
    points_.push_back(*hits[i]);
    direct_.push_back(lighting::direct_irradiance(scene, rays, hits[i]->position, hits[i]->normal));
  }
  reference_ =
      reference_irradiance(scene, rays, points_, {.paths = s.image_paths, .seed = s.seed, .threads = s.threads})
          .irradiance;
  mean_ = mean_irradiance(reference_);
  if (!writes()) return;
  Image image{camera_.width, camera_.height, std::vector<glm::vec3>(hits.size(), glm::vec3(0.0f))};
  for (std::size_t k = 0; k < points_.size(); ++k) image.pixels[pixels_[k]] = reference_[k];
  write_exr(reference_path(), image);
}

std::optional<std::filesystem::path> ErrorMaps::score(EvalRow& row, const formats::ProbeVolume& volume) const {
  Image image{camera_.width, camera_.height,
              std::vector<glm::vec3>(std::size_t(camera_.width) * std::size_t(camera_.height), glm::vec3(0.0f))};
  double abs_sum = 0.0, squares = 0.0;
  for (std::size_t k = 0; k < points_.size(); ++k) {
    const glm::vec3 estimate =
        direct_[k] + probe_index::sample_irradiance(volume, points_[k].position, points_[k].normal);
    const glm::vec3 error = glm::abs(estimate - reference_[k]);
    image.pixels[pixels_[k]] = error;
    abs_sum += (double(error.x) + double(error.y) + double(error.z)) / 3.0;
    squares += (double(error.x) * error.x + double(error.y) * error.y + double(error.z) * error.z) / 3.0;
  }
  const double n = double(std::max<std::size_t>(points_.size(), 1));
  row.image_mean_error = abs_sum / n;
  row.image_relative_rmse = mean_ > 0.0 ? std::sqrt(squares / n) / mean_ : 0.0;
  if (!writes()) return std::nullopt;
  const std::filesystem::path path = dir_ / (row.label + ".exr");
  write_exr(path, image);
  return path;
}

} // namespace probebake::bake::detail
