// reference_irradiance: paths split into fixed chunks per point, each chunk with its own random stream,
// run in parallel and summed in index order (deterministic for any thread count).
#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/core.h>
#include <glm/vec3.hpp>

#include "probebake/common/parallel.h"
#include "path_tracer.h"
#include "probebake/eval/reference.h"
#include "probebake/formats/error.h"
#include "sampling.h"

namespace probebake::bake {
namespace {

constexpr int kChunk = 64; // paths per task: small enough to spread one point's paths over many threads

struct Moments {
  glm::dvec3 sum{0.0};
  glm::dvec3 sum_squares{0.0};
  glm::dvec3 direct{0.0};           // sum of the direct parts
  glm::dvec3 indirect_squares{0.0}; // sum of the squared indirect parts (total - direct)

  void add(const Moments& m) {
    sum += m.sum;
    sum_squares += m.sum_squares;
    direct += m.direct;
    indirect_squares += m.indirect_squares;
  }
};

// Standard error of the mean of n samples with this sum and sum of squares.
glm::dvec3 standard_error(const glm::dvec3& sum, const glm::dvec3& sum_squares, double n) {
  const glm::dvec3 mean = sum / n;
  const glm::dvec3 variance = glm::max((sum_squares - n * mean * mean) / (n - 1.0), glm::dvec3(0.0));
  return glm::sqrt(variance / n);
}

Moments trace_chunk(const detail::PathContext& context, const SamplePoint& point, std::uint64_t seed, std::uint64_t key,
                    int paths) {
  detail::Pcg32 rng(seed, key);
  Moments m;
  for (int i = 0; i < paths; ++i) {
    const detail::PathEstimate path = detail::irradiance_path(context, point, rng);
    const glm::dvec3 e(path.total), direct(path.direct), indirect = e - direct;
    m.sum += e;
    m.sum_squares += e * e;
    m.direct += direct;
    m.indirect_squares += indirect * indirect;
  }
  return m;
}

} // namespace

void check_reference_settings(const ReferenceSettings& s) {
  if (s.paths < 2) throw Error(ErrorKind::usage, fmt::format("--samples must be at least 2 (got {})", s.paths));
  if (s.threads < 0) throw Error(ErrorKind::usage, "--threads must be >= 0");
  if (s.roulette_after < 1 || s.max_bounces < 1)
    throw Error(ErrorKind::usage, "reference: roulette_after and max_bounces must be >= 1");
}

ReferenceResult reference_irradiance(const scene::Scene& scene, const scene::RayScene& rays,
                                     std::span<const SamplePoint> points, const ReferenceSettings& settings) {
  check_reference_settings(settings);
  const auto start = std::chrono::steady_clock::now();
  const detail::EmitterTable emitters(scene);
  const detail::PathContext context{
      &scene, &rays, &emitters, scene::ray_epsilon(scene), settings.roulette_after, settings.max_bounces};
  const std::size_t chunks = (std::size_t(settings.paths) + kChunk - 1) / kChunk;
  std::vector<Moments> moments(points.size() * chunks);
  parallel_for(moments.size(), settings.threads, [&](std::size_t task) {
    const std::size_t p = task / chunks, c = task % chunks;
    const int paths = std::min(kChunk, settings.paths - int(c) * kChunk);
    // Keyed by (point, chunk): more paths extend a point's streams, fewer points keep the others' streams.
    moments[task] = trace_chunk(context, points[p], settings.seed, (std::uint64_t(p) << 24) ^ c, paths);
  });

  ReferenceResult result;
  const double n = settings.paths;
  for (std::size_t p = 0; p < points.size(); ++p) {
    Moments m;
    for (std::size_t c = 0; c < chunks; ++c) m.add(moments[p * chunks + c]);
    result.irradiance.emplace_back(m.sum / n);
    result.standard_error.emplace_back(standard_error(m.sum, m.sum_squares, n));
    result.direct.emplace_back(m.direct / n);
    result.indirect_standard_error.emplace_back(standard_error(m.sum - m.direct, m.indirect_squares, n));
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

std::vector<glm::vec3> indirect_irradiance(const ReferenceResult& reference) {
  std::vector<glm::vec3> out(reference.irradiance.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = reference.irradiance[i] - reference.direct.at(i);
  return out;
}

} // namespace probebake::bake
