// probebake-run --samples (run_samples.h).
#include "run_samples.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

namespace probebake::run {
namespace {

struct SamplePoints {
  std::vector<glm::vec3> positions, normals;
};

// Random points in the root cube with random unit normals (fixed seed: the same points every run).
SamplePoints random_points(const gpu::VolumeInfo& info, int count) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss;
  SamplePoints points;
  for (int i = 0; i < count; ++i) {
    points.positions.push_back(info.root_min + info.root_size * glm::vec3(unit(rng), unit(rng), unit(rng)));
    const glm::vec3 n(gauss(rng), gauss(rng), gauss(rng));
    points.normals.push_back(glm::length(n) > 1e-6f ? glm::normalize(n) : glm::vec3(0, 1, 0));
  }
  return points;
}

// runtime::SampleMethod's names, in its order, as time_sampler prints them.
constexpr const char* kSamplerNames[] = {"SVO probe index", "grid lattice", "all probes, thesis 3.2.4"};
// Times one sampler on the points: a warm-up run (lavapipe compiles the shader on first use), then the
// measured one. Prints a line and returns the result.
runtime::Result<std::vector<glm::vec3>> time_sampler(runtime::Volume& volume, const SamplePoints& points,
                                                     runtime::SampleMethod method, runtime::SampleStats& stats) {
  auto warm = volume.sample_irradiance(points.positions, points.normals, nullptr, method);
  if (!warm.ok()) return warm.status();
  auto result = volume.sample_irradiance(points.positions, points.normals, &stats, method);
  if (!result.ok()) return result.status();
  std::printf("samples (%s): %zu lookups, %zu misses, %zu dispatch(es), gpu %.3f ms (%.2f ns per lookup), "
              "cpu %.3f ms (with copies)\n",
              kSamplerNames[static_cast<int>(method)], stats.samples, stats.misses, stats.dispatches, stats.gpu_ms,
              1e6 * stats.gpu_ms / double(std::max<std::size_t>(stats.samples, 1)), stats.cpu_ms);
  return result;
}

} // namespace

runtime::Status run_samples(runtime::Volume& volume, int count, bool compare) {
  const SamplePoints points = random_points(volume.info(), count);
  runtime::SampleStats svo_stats;
  auto svo = time_sampler(volume, points, runtime::SampleMethod::svo, svo_stats);
  if (!svo.ok()) return svo.status();
  if (volume.buffers().grid_lattice.buffer != VK_NULL_HANDLE) {
    runtime::SampleStats grid_stats;
    if (auto grid = time_sampler(volume, points, runtime::SampleMethod::grid, grid_stats); !grid.ok())
      return grid.status();
    std::printf("grid lattice / SVO = %.2fx GPU time\n", grid_stats.gpu_ms / std::max(svo_stats.gpu_ms, 1e-9));
  }
  if (!compare) return {};
  runtime::SampleStats all_stats;
  auto all = time_sampler(volume, points, runtime::SampleMethod::all_probes, all_stats);
  if (!all.ok()) return all.status();
  double diff2 = 0.0, base2 = 0.0;
  const std::vector<glm::vec3>& a = svo.value();
  const std::vector<glm::vec3>& base = all.value();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const glm::dvec3 d = glm::dvec3(a[i] - base[i]), b = glm::dvec3(base[i]);
    diff2 += glm::dot(d, d);
    base2 += glm::dot(b, b);
  }
  std::printf("compare: all-probe loop / SVO = %.1fx GPU time (%.3f ms / %.3f ms); relative RMS difference %.3f\n",
              all_stats.gpu_ms / std::max(svo_stats.gpu_ms, 1e-9), all_stats.gpu_ms, svo_stats.gpu_ms,
              base2 > 0.0 ? std::sqrt(diff2 / base2) : 0.0);
  return {};
}

} // namespace probebake::run
