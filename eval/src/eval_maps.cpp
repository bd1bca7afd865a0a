#include "eval_maps.h"

#include <cmath>

#include <fmt/core.h>

#include "eval_internal.h"
#include "probebake/lighting/lighting.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/formats/error.h"

namespace probebake::bake::detail {
namespace {

Image blank(const Camera& camera) {
  return {camera.width, camera.height,
          std::vector<glm::vec3>(std::size_t(camera.width) * std::size_t(camera.height), glm::vec3(0.0f))};
}

} // namespace

ErrorMaps::ErrorMaps(const scene::Scene& scene, const scene::RayScene& rays, const EvalSettings& s)
    : dir_(s.error_map_dir), camera_(*s.camera), threads_(s.threads) {
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
  reference_image_ = blank(camera_);
  for (std::size_t k = 0; k < points_.size(); ++k) reference_image_.pixels[pixels_[k]] = reference_[k];
  exposures_ = bake::flip_exposures(reference_);
  if (writes()) write_exr(reference_path(), reference_image_);
}

std::vector<std::filesystem::path> ErrorMaps::score(EvalRow& row, const Lookup& lookup) const {
  Image error = blank(camera_), estimate = blank(camera_);
  double abs_sum = 0.0, squares = 0.0;
  for (std::size_t k = 0; k < points_.size(); ++k) {
    estimate.pixels[pixels_[k]] = direct_[k] + lookup(points_[k].position, points_[k].normal);
    const glm::vec3 e = glm::abs(estimate.pixels[pixels_[k]] - reference_[k]);
    error.pixels[pixels_[k]] = e;
    abs_sum += (double(e.x) + double(e.y) + double(e.z)) / 3.0;
    squares += (double(e.x) * e.x + double(e.y) * e.y + double(e.z) * e.z) / 3.0;
  }
  const double n = double(std::max<std::size_t>(points_.size(), 1));
  row.image_mean_error = abs_sum / n;
  row.image_relative_rmse = mean_ > 0.0 ? std::sqrt(squares / n) / mean_ : 0.0;
  const std::vector<float> flip_map = hdr_flip(reference_image_, estimate, exposures_, {.threads = threads_});
  double flip_sum = 0.0;
  for (std::size_t pixel : pixels_) flip_sum += flip_map[pixel];
  row.image_flip_mean = flip_sum / n;
  if (!writes()) return {};
  const std::string name = row.sampler == "svo" ? row.label : row.label + "-" + row.sampler;
  const std::filesystem::path error_path = dir_ / (name + ".exr"), flip_path = dir_ / (name + ".flip.exr");
  write_exr(error_path, error);
  Image flip_image = blank(camera_);
  for (std::size_t i = 0; i < flip_map.size(); ++i) flip_image.pixels[i] = glm::vec3(flip_map[i]);
  write_exr(flip_path, flip_image);
  return {error_path, flip_path};
}

} // namespace probebake::bake::detail
