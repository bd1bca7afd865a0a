// The GPU sampling pass (shaders/include/probebake/sample_irradiance.glsl) against the CPU reference
// probe_index::sample_irradiance at fixed pseudo-random points. Tolerance: 1e-4 of the CPU value's largest channel
// (floored at 1e-6 of the brightest value in the set), per channel. Points whose biased lookup position lies
// within 1e-3 voxel of an SVO voxel face are left out: there, float rounding of a different but equally valid
// evaluation order (GPU division is allowed 2.5 ulp) may pick the neighbouring voxel, a different stencil.
#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/formats/grid_lattice.h"
#include "probebake/formats/sh_codec.h"
#include "probebake/probe_index/grid_lookup.h"
#include "probebake/probe_index/lookup.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using SamplingTest = RuntimeTest;

struct Points {
  std::vector<glm::vec3> positions, normals;
};

bool near_voxel_face(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal) {
  const glm::vec3 biased = position + normal * probe_index::normal_bias(volume.info);
  const glm::vec3 t = (biased - volume.info.root_min) / volume.info.root_size * float(1 << volume.info.svo_depth);
  const glm::vec3 distance = glm::abs(t - glm::round(t));
  return std::min({distance.x, distance.y, distance.z}) < 1e-3f;
}

glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> gauss;
  for (;;) {
    const glm::vec3 v(gauss(rng), gauss(rng), gauss(rng));
    if (glm::length(v) > 1e-3f) return glm::normalize(v);
  }
}

// `count` points in the root cube grown by 5 % on every side, random normals, plus points on the y = 0 plane
// (the Cornell box floor) facing up.
Points make_points(const formats::ProbeVolume& volume, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-0.05f, 1.05f);
  const gpu::VolumeInfo& info = volume.info;
  Points points;
  while (points.positions.size() < count) {
    const bool on_floor = points.positions.size() % 4 == 0;
    glm::vec3 p = info.root_min + info.root_size * glm::vec3(unit(rng), unit(rng), unit(rng));
    glm::vec3 n = random_unit(rng);
    if (on_floor) {
      p.y = 0.0f;
      n = glm::vec3(0.0f, 1.0f, 0.0f);
    }
    if (near_voxel_face(volume, p, n)) continue;
    points.positions.push_back(p);
    points.normals.push_back(n);
  }
  return points;
}

// `all` less the points whose grid lookup position lies within 1e-3 of a lattice cell's face (where rounding
// may pick the neighbouring cell).
Points away_from_lattice_faces(const formats::ProbeVolume& volume, const Points& all) {
  const std::optional<formats::GridLatticeView> lattice = formats::grid_lattice_view(volume);
  EXPECT_TRUE(lattice);
  if (!lattice) return {};
  const gpu::GridLatticeHeader h = lattice->header;
  Points points;
  for (std::size_t i = 0; i < all.positions.size(); ++i) {
    const glm::vec3 g =
        formats::grid_lattice_coordinates(h, all.positions[i] + all.normals[i] * probe_index::grid_normal_bias(h));
    const glm::vec3 distance = glm::abs(g - glm::round(g));
    if (std::min({distance.x, distance.y, distance.z}) < 1e-3f) continue;
    points.positions.push_back(all.positions[i]);
    points.normals.push_back(all.normals[i]);
  }
  return points;
}

struct Comparison {
  float max_relative = 0.0f;
  std::size_t cpu_misses = 0, gpu_misses = 0, mismatches = 0, lit = 0;
};

// The GPU's lookups by `method` against the CPU's (`cpu`, with `cpu_misses`).
Comparison compare(const std::vector<glm::vec3>& cpu, std::size_t cpu_misses, runtime::Volume& gpu_volume,
                   const Points& points, runtime::SampleMethod method = runtime::SampleMethod::svo) {
  runtime::SampleStats gpu_stats;
  auto gpu = gpu_volume.sample_irradiance(points.positions, points.normals, &gpu_stats, method);
  EXPECT_TRUE(gpu.ok()) << gpu.status().message;
  Comparison c;
  if (!gpu.ok()) return c;
  c.cpu_misses = cpu_misses;
  c.gpu_misses = gpu_stats.misses;
  float brightest = 0.0f;
  for (const glm::vec3& e : cpu) brightest = std::max(brightest, std::max({e.x, e.y, e.z}));
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    const glm::vec3 g = gpu.value()[i], e = cpu[i];
    const float scale = std::max(std::max({std::abs(e.x), std::abs(e.y), std::abs(e.z)}), 1e-6f * brightest);
    const glm::vec3 diff = glm::abs(g - e);
    const float relative =
        scale > 0.0f ? std::max({diff.x, diff.y, diff.z}) / scale : std::max({diff.x, diff.y, diff.z});
    c.max_relative = std::max(c.max_relative, relative);
    c.mismatches += relative > 1e-4f ? 1 : 0;
    c.lit += std::max({e.x, e.y, e.z}) > 0.0f ? 1 : 0;
  }
  std::printf(
      "[sampling] %zu points: %zu lit, misses CPU %zu GPU %zu, max relative difference %.3g, gpu %.3f ms in %zu "
      "dispatch(es)\n",
      cpu.size(), c.lit, c.cpu_misses, c.gpu_misses, double(c.max_relative), gpu_stats.gpu_ms, gpu_stats.dispatches);
  return c;
}

void expect_gpu_equals_cpu(runtime::Context& context, const formats::ProbeVolume& volume, std::size_t count) {
  auto uploaded = runtime::Volume::upload(context, volume);
  ASSERT_TRUE(uploaded.ok()) << uploaded.status().message;
  ASSERT_TRUE(uploaded->run_frame().ok());
  const Points points = make_points(volume, count, 42);
  std::vector<glm::vec3> cpu(points.positions.size());
  probe_index::SamplerStats cpu_stats;
  probe_index::sample_irradiance(volume, points.positions, points.normals, cpu, &cpu_stats, 1);
  const Comparison c = compare(cpu, cpu_stats.misses, uploaded.value(), points);
  EXPECT_EQ(c.mismatches, 0u);
  EXPECT_LE(c.max_relative, 1e-4f);
  EXPECT_EQ(c.gpu_misses, c.cpu_misses);
  EXPECT_GT(c.lit, count / 10); // the test is about lit points, not only misses
}

TEST_F(SamplingTest, CornellOctreeMatchesTheCpuSampler) {
  expect_gpu_equals_cpu(context(), baked_cornell_octree(), 20000);
}
TEST_F(SamplingTest, LeakOctreeMatchesTheCpuSampler) { expect_gpu_equals_cpu(context(), baked_leak_octree(), 20000); }
TEST_F(SamplingTest, CornellGridMatchesTheCpuSampler) { expect_gpu_equals_cpu(context(), baked_cornell_grid(), 20000); }

// The grid engine's lookup (sample_grid.glsl) against probe_index::sample_irradiance_grid on the same points,
// less those within 1e-3 of a lattice cell's face (where rounding may pick the neighbouring cell); a volume
// without a lattice is refused.
TEST_F(SamplingTest, GridEngineMatchesTheCpuSampler) {
  const formats::ProbeVolume& volume = baked_cornell_grid();
  const Points points = away_from_lattice_faces(volume, make_points(volume, 20000, 42));
  std::vector<glm::vec3> cpu;
  probe_index::SamplerStats cpu_stats;
  for (std::size_t i = 0; i < points.positions.size(); ++i)
    cpu.push_back(probe_index::sample_irradiance_grid(volume, points.positions[i], points.normals[i], &cpu_stats));
  auto uploaded = runtime::Volume::upload(context(), volume);
  ASSERT_TRUE(uploaded.ok()) << uploaded.status().message;
  EXPECT_NE(uploaded->buffers().grid_lattice.buffer, VK_NULL_HANDLE);
  const Comparison c = compare(cpu, cpu_stats.misses, uploaded.value(), points, runtime::SampleMethod::grid);
  EXPECT_EQ(c.mismatches, 0u);
  EXPECT_LE(c.max_relative, 1e-4f);
  EXPECT_EQ(c.gpu_misses, c.cpu_misses);
  EXPECT_GT(c.lit, points.positions.size() / 2);

  auto octree = runtime::Volume::upload(context(), baked_cornell_octree());
  ASSERT_TRUE(octree.ok()) << octree.status().message;
  const auto refused =
      octree->sample_irradiance(points.positions, points.normals, nullptr, runtime::SampleMethod::grid);
  EXPECT_EQ(refused.status().code, runtime::StatusCode::unsupported) << refused.status().message;
}

// Compact probes (UploadOptions::probe_code): the GPU's lookups through the points and codes the probe code
// pass writes after each frame equal the CPU's lookups of the live probes read back and sent through the same
// code (formats::with_sh_codec). The volume starts black and relights over three frames, so that the codes
// must follow the light update, not the upload.
void expect_codes_follow_the_probes(runtime::Context& context, const formats::ProbeVolume& volume,
                                    formats::ShCodec codec, runtime::SampleMethod method) {
  runtime::UploadOptions options;
  options.probe_code = codec;
  auto uploaded = runtime::Volume::upload(context, with_zero_irradiance(volume), options);
  ASSERT_TRUE(uploaded.ok()) << uploaded.status().message;
  const runtime::VolumeBuffers buffers = uploaded->buffers();
  const auto slots = VkDeviceSize(volume.info.probe_capacity);
  EXPECT_EQ(buffers.probe_points.size, slots * 16);
  EXPECT_EQ(buffers.probe_codes.size, slots * VkDeviceSize(formats::sh_codec_bytes(codec)));
  for (int frame = 0; frame < 3; ++frame) ASSERT_TRUE(uploaded->run_frame().ok());
  auto live = uploaded->read_back();
  ASSERT_TRUE(live.ok()) << live.status().message;
  ASSERT_GT(brightest_dc(live.value()), 0.0f); // relit
  const formats::ProbeVolume coded = formats::with_sh_codec(live.value(), codec);
  const Points svo_points = make_points(volume, 5000, 7);
  const Points points =
      method == runtime::SampleMethod::grid ? away_from_lattice_faces(volume, svo_points) : svo_points;
  std::vector<glm::vec3> cpu(points.positions.size());
  probe_index::SamplerStats cpu_stats;
  for (std::size_t i = 0; i < cpu.size(); ++i)
    cpu[i] = method == runtime::SampleMethod::grid
                 ? probe_index::sample_irradiance_grid(coded, points.positions[i], points.normals[i], &cpu_stats)
                 : probe_index::sample_irradiance(coded, points.positions[i], points.normals[i], &cpu_stats);
  const Comparison c = compare(cpu, cpu_stats.misses, uploaded.value(), points, method);
  EXPECT_EQ(c.mismatches, 0u);
  EXPECT_LE(c.max_relative, 1e-4f);
  EXPECT_EQ(c.gpu_misses, c.cpu_misses);
  EXPECT_GT(c.lit, points.positions.size() / 10);
}

TEST_F(SamplingTest, CompactProbesMatchTheCpuDecodeThroughTheSvo) {
  for (formats::ShCodec codec : {formats::ShCodec::l2, formats::ShCodec::l1})
    expect_codes_follow_the_probes(context(), baked_cornell_octree(), codec, runtime::SampleMethod::svo);
}

TEST_F(SamplingTest, CompactProbesMatchTheCpuDecodeThroughTheGridEngine) {
  for (formats::ShCodec codec : {formats::ShCodec::l2, formats::ShCodec::l1})
    expect_codes_follow_the_probes(context(), baked_cornell_grid(), codec, runtime::SampleMethod::grid);
}

TEST_F(SamplingTest, FloatProbesAllocateNoCodes) {
  auto uploaded = runtime::Volume::upload(context(), baked_cornell_octree());
  ASSERT_TRUE(uploaded.ok()) << uploaded.status().message;
  EXPECT_EQ(uploaded->buffers().probe_points.buffer, VK_NULL_HANDLE);
  EXPECT_EQ(uploaded->buffers().probe_codes.buffer, VK_NULL_HANDLE);
  const auto frame = uploaded->run_frame();
  ASSERT_TRUE(frame.ok());
  for (const runtime::PassTime& pass : frame->passes) EXPECT_NE(pass.name, "probe_codes");
}

TEST_F(SamplingTest, VolumeWithoutSvoMissesEverywhere) {
  const formats::ProbeVolume empty = formats::make_empty_volume(baked_cornell_octree().info);
  auto uploaded = runtime::Volume::upload(context(), empty);
  ASSERT_TRUE(uploaded.ok()) << uploaded.status().message;
  const Points points = make_points(baked_cornell_octree(), 1000, 3);
  runtime::SampleStats stats;
  auto result = uploaded->sample_irradiance(points.positions, points.normals, &stats);
  ASSERT_TRUE(result.ok()) << result.status().message;
  EXPECT_EQ(stats.misses, points.positions.size());
  for (const glm::vec3& e : result.value()) EXPECT_EQ(e, glm::vec3(0.0f));
}

TEST_F(SamplingTest, BatchesLargerThanOneDispatchAreSplit) {
  const formats::ProbeVolume& volume = baked_cornell_octree();
  const Points base = make_points(volume, 10000, 9);
  Points points;
  const std::size_t count = (std::size_t(1) << 20) + 5000; // one more dispatch than the per-dispatch limit
  points.positions.reserve(count);
  points.normals.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    points.positions.push_back(base.positions[i % base.positions.size()]);
    points.normals.push_back(base.normals[i % base.normals.size()]);
  }
  auto uploaded = runtime::Volume::upload(context(), volume);
  ASSERT_TRUE(uploaded.ok()) << uploaded.status().message;
  runtime::SampleStats stats;
  auto gpu = uploaded->sample_irradiance(points.positions, points.normals, &stats);
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  EXPECT_EQ(stats.dispatches, 2u);
  EXPECT_EQ(stats.samples, count);
  std::vector<glm::vec3> cpu(base.positions.size());
  probe_index::sample_irradiance(volume, base.positions, base.normals, cpu, nullptr, 1);
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const glm::vec3 e = cpu[i % cpu.size()], g = gpu.value()[i];
    const float scale = std::max({std::abs(e.x), std::abs(e.y), std::abs(e.z), 1e-6f});
    mismatches += glm::length(g - e) / scale > 2e-4f ? 1 : 0;
  }
  EXPECT_EQ(mismatches, 0u);
  std::printf("[sampling] %zu lookups in %zu dispatches: gpu %.2f ms, cpu (with copies) %.2f ms\n", count,
              stats.dispatches, stats.gpu_ms, stats.cpu_ms);
}

} // namespace
} // namespace probebake::test
