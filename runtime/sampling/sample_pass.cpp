#include "sampling/sample_pass.h"

#include <algorithm>
#include <array>
#include <chrono>

#include "core/allocator.h"
#include "core/commands.h"
#include "core/error.h"
#include "core/pipelines.h"
#include "probebake/runtime_types.h"
#include "sampling/sample_bindings.h"

namespace probebake::runtime::detail {
namespace {

constexpr std::size_t kMaxBatch = std::size_t(1) << 20; // bounds staging memory per call (48 MiB)
constexpr VkBufferUsageFlags kQueryUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
constexpr VkBufferUsageFlags kResultUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;

// Buffers of one run, sized for the largest batch of that run.
struct BatchBuffers {
  Buffer queries, results, queries_host, results_host;
  BatchBuffers(Allocator& allocator, std::size_t batch)
      : queries(allocator.create_buffer(batch * sizeof(gpu::SampleQuery), kQueryUsage, MemoryUse::device,
                                        "sample queries")),
        results(allocator.create_buffer(batch * sizeof(gpu::SampleResult), kResultUsage, MemoryUse::device,
                                        "sample results")),
        queries_host(allocator.create_buffer(batch * sizeof(gpu::SampleQuery), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                             MemoryUse::upload, "sample queries (host)")),
        results_host(allocator.create_buffer(batch * sizeof(gpu::SampleResult), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                             MemoryUse::readback, "sample results (host)")) {}
};

void write_queries(void* mapped, std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) {
  auto* queries = static_cast<gpu::SampleQuery*>(mapped);
  for (std::size_t i = 0; i < positions.size(); ++i) queries[i] = {positions[i], 0.0f, normals[i], 0.0f};
}

// Copies the results out and counts them into `stats`; `flags` (empty or out.size()) gets each one's.
void read_results(const void* mapped, std::span<glm::vec3> out, std::span<std::uint32_t> flags, SampleStats& stats) {
  const auto* results = static_cast<const gpu::SampleResult*>(mapped);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = results[i].irradiance;
    const bool miss = (results[i].probes_used & ~gpu::SAMPLE_RESULT_NOT_LIT) == 0;
    const bool not_lit = (results[i].probes_used & gpu::SAMPLE_RESULT_NOT_LIT) != 0;
    stats.misses += miss ? 1 : 0;
    stats.not_lit += not_lit ? 1 : 0;
    if (!flags.empty()) flags[i] = (miss ? kSampleMiss : 0u) | (not_lit ? kSampleNotLit : 0u);
  }
}

} // namespace

SamplePass::SamplePass(Device& device, const GpuVolume& volume) : device_(device), volume_(volume) {
  const std::size_t by_range = device.info.max_storage_buffer_range / sizeof(gpu::SampleQuery);
  max_batch_ = std::max<std::size_t>(1, std::min(by_range, kMaxBatch));
  static_assert(gpu::SAMPLE_BINDING_COUNT >= gpu::SAMPLE_ALL_BINDING_COUNT &&
                gpu::SAMPLE_BINDING_COUNT >= gpu::SAMPLE_GRID_BINDING_COUNT); // the pool holds the three sets
  pool_ = make_descriptor_pool(device.vk(), 3, gpu::SAMPLE_BINDING_COUNT);
  set_ = allocate_set(device.vk(), pool_.get(), device.compute_pipelines().set_layout(Layout::sample));
  grid_set_ = allocate_set(device.vk(), pool_.get(), device.compute_pipelines().set_layout(Layout::sample_grid));
  all_set_ = allocate_set(device.vk(), pool_.get(), device.compute_pipelines().set_layout(Layout::sample_all));
}

void SamplePass::run(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals, std::span<glm::vec3> out,
                     SampleStats& stats, SampleMethod method, std::span<std::uint32_t> flags) {
  const auto start = std::chrono::steady_clock::now();
  const bool all_probes = method == SampleMethod::all_probes, grid = method == SampleMethod::grid;
  if (all_probes && volume_.elements(Section::lighting_info) == 0)
    fail(StatusCode::unsupported, "the all-probe sampler traces visibility rays: the volume has no lighting sections "
                                  "(baked with --no-runtime-lighting)");
  if (grid && volume_.elements(Section::grid_lattice) == 0)
    fail(StatusCode::unsupported, "the grid sampler reads a grid bake's lattice: the volume has none (bake with "
                                  "--placement grid and --grid 2..255)");
  stats.samples += positions.size();
  if (positions.empty()) return;
  Pipelines& pipelines = device_.compute_pipelines();
  const Layout layout_id = all_probes ? Layout::sample_all : grid ? Layout::sample_grid : Layout::sample;
  const VkPipelineLayout layout = pipelines.layout(layout_id);
  const VkPipeline pipeline = pipelines.kernel(all_probes ? Kernel::sample_all_probes
                                               : grid     ? Kernel::sample_grid
                                                          : Kernel::sample_irradiance);
  const VkDescriptorSet set = all_probes ? all_set_ : grid ? grid_set_ : set_;
  const std::size_t batch = std::min(max_batch_, positions.size());
  BatchBuffers buffers(*device_.allocator, batch);
  // The previous run has completed: the sets are idle.
  if (all_probes) {
    std::array<VkBuffer, gpu::SAMPLE_ALL_BINDING_COUNT> bindings{};
    bindings[gpu::SAMPLE_ALL_BINDING_QUERIES] = buffers.queries.get();
    bindings[gpu::SAMPLE_ALL_BINDING_RESULTS] = buffers.results.get();
    write_storage_buffers(device_.vk(), set, bindings);
  } else if (grid) {
    std::array<VkBuffer, gpu::SAMPLE_GRID_BINDING_COUNT> bindings{};
    bindings[gpu::SAMPLE_GRID_BINDING_QUERIES] = buffers.queries.get();
    bindings[gpu::SAMPLE_GRID_BINDING_RESULTS] = buffers.results.get();
    bindings[gpu::SAMPLE_GRID_BINDING_LATTICE] = volume_.binding(Section::grid_lattice);
    // Read only with SamplePush.code_bands; otherwise any buffer satisfies the binding.
    bindings[gpu::SAMPLE_GRID_BINDING_PROBE_POINTS] = code_bands_ ? points_ : buffers.results.get();
    bindings[gpu::SAMPLE_GRID_BINDING_PROBE_CODES] = code_bands_ ? codes_ : buffers.results.get();
    write_storage_buffers(device_.vk(), set, bindings);
  } else {
    std::array<VkBuffer, gpu::SAMPLE_BINDING_COUNT> bindings{};
    bindings[gpu::SAMPLE_BINDING_QUERIES] = buffers.queries.get();
    bindings[gpu::SAMPLE_BINDING_RESULTS] = buffers.results.get();
    // Read only with SamplePush.streaming; otherwise any buffer satisfies the binding.
    bindings[gpu::SAMPLE_BINDING_RECORD_SLOTS] =
        record_slots_ != VK_NULL_HANDLE ? record_slots_ : buffers.results.get();
    bindings[gpu::SAMPLE_BINDING_PROBE_POINTS] = code_bands_ ? points_ : buffers.results.get();
    bindings[gpu::SAMPLE_BINDING_PROBE_CODES] = code_bands_ ? codes_ : buffers.results.get();
    write_storage_buffers(device_.vk(), set, bindings);
  }
  PassTimer timer(device_, 1);

  for (std::size_t first = 0; first < positions.size(); first += batch) {
    const std::size_t count = std::min(batch, positions.size() - first);
    write_queries(buffers.queries_host.mapped(), positions.subspan(first, count), normals.subspan(first, count));
    Submission submission(device_);
    const VkCommandBuffer cmd = submission.cmd();
    timer.reset(cmd);
    barrier(cmd, kAnyDeviceAccess, kAnyDeviceAccess); // earlier frames' writes and the last batch's reads
    const VkBufferCopy queries{0, 0, count * sizeof(gpu::SampleQuery)};
    vkCmdCopyBuffer(cmd, buffers.queries_host.get(), buffers.queries.get(), 1, &queries);
    barrier(cmd, kTransferWrite, kComputeRead);
    const gpu::SamplePush push{static_cast<std::uint32_t>(count),
                               record_slots_ != VK_NULL_HANDLE && layout_id == Layout::sample ? 1u : 0u,
                               all_probes ? 0u : code_bands_, 0};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    bind_sets_and_push(cmd, layout, volume_.volume_set(), set, push);
    timer.begin(cmd, 0);
    dispatch_groups(
        cmd, device_,
        static_cast<std::uint32_t>((count + gpu::RUNTIME_WORKGROUP_SIZE - 1) / gpu::RUNTIME_WORKGROUP_SIZE));
    timer.end(cmd, 0);
    barrier(cmd, kComputeWrite, kTransferRead);
    const VkBufferCopy results{0, 0, count * sizeof(gpu::SampleResult)};
    vkCmdCopyBuffer(cmd, buffers.results.get(), buffers.results_host.get(), 1, &results);
    barrier(cmd, kTransferWrite, kHostRead);
    submission.submit_and_wait();

    read_results(buffers.results_host.mapped(), out.subspan(first, count),
                 flags.empty() ? flags : flags.subspan(first, count), stats);
    const double ms = timer.read_ms(1)[0];
    if (ms >= 0.0) stats.gpu_ms = (stats.gpu_ms < 0.0 ? 0.0 : stats.gpu_ms) + ms;
    ++stats.dispatches;
  }
  stats.cpu_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace probebake::runtime::detail
