// Shared fixtures of the runtime tests: one validated Vulkan context per process (lavapipe on CI), volumes
// baked in-process from generated scenes, and a per-test check that the validation layer stayed silent.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "probebake/bake/bake.h"
#include "probebake/formats/probe_volume.h"
#include "probebake/runtime/runtime.h"
#include "probebake/samples/scene_builder.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/scene/scene.h"

namespace probebake::test {

// The shared context (validation + synchronization validation on), or nullptr when this machine has no
// Vulkan device at all; the tests then skip. Where lavapipe's ICD is installed, a missing device is a
// failure, not a skip.
runtime::Context* shared_context();
const std::string& no_device_reason();

// Validation messages counted by every context the tests made (survives their destruction).
std::uint64_t validation_messages_total();
runtime::ContextOptions validated_options();

// Runtime test: skips without a device; fails when the test made the validation layer report anything.
class RuntimeTest : public ::testing::Test {
protected:
  void SetUp() override;
  void TearDown() override;
  runtime::Context& context() { return *shared_context(); }

private:
  std::uint64_t messages_before_ = 0;
};

// Small bake settings: max depth 3, 64 surfels, SVO depth 4, 96 rays.
bake::BakeSettings small_bake_settings();

// A generated scene loaded like the CLI loads it and baked with small_bake_settings() (octree or a 6^3 grid;
// `full`: surfel batches and a leaf queue).
formats::ProbeVolume bake_scene(const samples::SceneBuilder& builder, const std::string& name, bool grid = false,
                                bool full = false);

// A generated scene loaded like the CLI loads it and baked with `settings`.
formats::ProbeVolume bake_with(const samples::SceneBuilder& builder, const std::string& name,
                               const bake::BakeSettings& settings);

// A generated scene, its Embree BVH and a bake of it, kept for the lighting tests' CPU references (heap-held:
// the RayScene points at the scene).
struct Baked {
  std::unique_ptr<scene::Scene> scene;
  std::unique_ptr<scene::RayScene> rays;
  bake::BakeSettings settings;
  formats::ProbeVolume volume;
};
Baked bake_generated(const samples::SceneBuilder& builder, const std::string& name, const bake::BakeSettings& settings,
                     std::optional<sky::Sky> sky = std::nullopt);

// The largest |DC term| of any live probe.
float brightest_dc(const formats::ProbeVolume& volume);
// Largest |a - b| over every coefficient of every live probe of b, relative to b's brightest DC term.
float max_sh_difference(const formats::ProbeVolume& a, const formats::ProbeVolume& b);
// Uploads with hysteresis 0 (each frame one Jacobi sweep, as the CPU's) and `headroom` more lights; aborts when
// the upload fails (every test needs its volume: stop rather than use a missing one).
runtime::Volume upload_sweeping(runtime::Context& context, const formats::ProbeVolume& volume, int headroom = 0);
// Volume::read_back, failing the test (and returning an empty volume) when it fails.
formats::ProbeVolume read_back(runtime::Volume& volume);
// The volume with every probe's irradiance zeroed (the start of a light update from nothing).
formats::ProbeVolume with_zero_irradiance(formats::ProbeVolume volume);

// Baked volumes, cached per process (small settings, lighting on).
const formats::ProbeVolume& baked_cornell_octree();
const formats::ProbeVolume& baked_leak_octree();
const formats::ProbeVolume& baked_cornell_grid();
// The same Cornell box bake with surfel batches and a leaf queue (all sections present).
const formats::ProbeVolume& baked_cornell_full();
// The Cornell box with both blocks dynamic (format 1.3: two objects), octree, lighting sections.
const formats::ProbeVolume& baked_cornell_dynamic();

// Probes with link != 0.
int live_probe_count(const formats::ProbeVolume& volume);

// Temporary directory of the runtime tests (created).
std::string temp_path(const std::string& name);

// A host's own instance, device and compute queue, as a game makes them (for Context::borrow). With
// `validation` the instance enables VK_LAYER_KHRONOS_validation with synchronization validation, and its
// messages count in validation_messages_total(). ok() is false when no device could be made.
class HostVulkanObjects {
public:
  explicit HostVulkanObjects(bool validation);
  ~HostVulkanObjects();
  HostVulkanObjects(const HostVulkanObjects&) = delete;
  HostVulkanObjects& operator=(const HostVulkanObjects&) = delete;
  bool ok() const { return queue != VK_NULL_HANDLE; }
  runtime::HostVulkan host() const { return {instance, physical_device, device, queue, family}; }

  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t family = 0;
};

} // namespace probebake::test
