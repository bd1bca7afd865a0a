#include "runtime_test_util.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <memory>
#include <mutex>
#include <vector>

#include "probebake/bake/bake.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/octree.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

std::atomic<std::uint64_t> g_messages{0};

struct SharedContext {
  std::unique_ptr<runtime::Context> context;
  std::string reason;
};

bool lavapipe_installed() {
  for (const char* dir : {"/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"}) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
      if (entry.path().filename().string().starts_with("lvp_icd")) return true;
  }
  return false;
}

SharedContext& shared() {
  static SharedContext s = [] {
    SharedContext made;
    auto context = runtime::Context::create(validated_options());
    if (context.ok()) {
      made.context = std::make_unique<runtime::Context>(std::move(context).value());
      const runtime::DeviceInfo& d = made.context->device_info();
      std::printf("[runtime] device %s (%s), validation %d, timestamps %d\n", d.name.c_str(), d.type.c_str(),
                  int(d.validation), int(d.timestamps));
    } else {
      made.reason = std::string(runtime::to_string(context.status().code)) + ": " + context.status().message;
    }
    return made;
  }();
  return s;
}

// Destroys the shared context after the last test and checks that its destruction was silent too.
class VulkanEnvironment : public ::testing::Environment {
public:
  void TearDown() override {
    shared().context.reset();
    EXPECT_EQ(validation_messages_total(), 0u) << "validation messages over the whole run";
    std::printf("[runtime] validation messages over the whole run: %llu\n",
                static_cast<unsigned long long>(validation_messages_total()));
  }
};
[[maybe_unused]] ::testing::Environment* const g_environment =
    ::testing::AddGlobalTestEnvironment(new VulkanEnvironment);

} // namespace

formats::ProbeVolume bake_with(const samples::SceneBuilder& builder, const std::string& name,
                               const bake::BakeSettings& settings) {
  const std::vector<std::uint8_t> glb = builder.to_glb();
  const scene::Scene scene = scene::load_scene_from_memory(std::vector<unsigned char>(glb.begin(), glb.end()), name,
                                                           ".", {.require_triangles = true});
  return bake::bake(scene, settings).volume;
}

bake::BakeSettings small_bake_settings() {
  bake::BakeSettings s;
  s.max_depth = 3;
  s.surfels_per_probe = 64;
  s.svo_depth = 4;
  s.lighting.rays = 96;
  return s;
}

formats::ProbeVolume bake_scene(const samples::SceneBuilder& builder, const std::string& name, bool grid, bool full) {
  bake::BakeSettings s = small_bake_settings();
  s.placement = grid ? bake::Placement::grid : bake::Placement::octree;
  s.grid_resolution = 6;
  s.store_surfels = full;
  formats::ProbeVolume volume = bake_with(builder, name, s);
  if (full) formats::init_leaf_queue(volume, 64);
  return volume;
}

Baked bake_generated(const samples::SceneBuilder& builder, const std::string& name, const bake::BakeSettings& settings,
                     std::optional<sky::Sky> sky) {
  Baked b;
  const std::vector<std::uint8_t> glb = builder.to_glb();
  b.scene = std::make_unique<scene::Scene>(scene::load_scene_from_memory(
      std::vector<unsigned char>(glb.begin(), glb.end()), name, ".", {.require_triangles = true, .sky = sky}));
  b.rays = std::make_unique<scene::RayScene>(*b.scene);
  b.settings = settings;
  b.volume = bake::bake(*b.scene, settings).volume;
  return b;
}

runtime::Volume upload_sweeping(runtime::Context& context, const formats::ProbeVolume& volume, int headroom) {
  auto gpu = runtime::Volume::upload(context, volume, {.hysteresis = 0.0f, .light_headroom = headroom});
  if (!gpu.ok()) {
    std::fprintf(stderr, "upload failed: %s\n", gpu.status().message.c_str());
    std::abort();
  }
  return std::move(gpu).value();
}

formats::ProbeVolume read_back(runtime::Volume& volume) {
  auto back = volume.read_back();
  EXPECT_TRUE(back.ok()) << back.status().message;
  return back.ok() ? std::move(back).value() : formats::ProbeVolume{};
}

float brightest_dc(const formats::ProbeVolume& volume) {
  float brightest = 0.0f;
  for (const gpu::Probe& p : volume.probes)
    if (p.link != 0)
      brightest = std::max(
          {brightest, std::abs(p.irradiance_sh[0]), std::abs(p.irradiance_sh[1]), std::abs(p.irradiance_sh[2])});
  return brightest;
}

float max_sh_difference(const formats::ProbeVolume& a, const formats::ProbeVolume& b) {
  float worst = 0.0f;
  for (std::size_t i = 0; i < b.probes.size(); ++i) {
    if (b.probes[i].link == 0) continue;
    for (int v = 0; v < gpu::PROBE_SH_FLOATS; ++v)
      worst = std::max(worst, std::abs(a.probes[i].irradiance_sh[v] - b.probes[i].irradiance_sh[v]));
  }
  return worst / std::max(brightest_dc(b), 1e-30f);
}

formats::ProbeVolume with_zero_irradiance(formats::ProbeVolume volume) {
  for (gpu::Probe& p : volume.probes) std::fill(std::begin(p.irradiance_sh), std::end(p.irradiance_sh), 0.0f);
  return volume;
}

runtime::ContextOptions validated_options() {
  runtime::ContextOptions options;
  options.validation = true;
  options.on_validation_message = [](const runtime::ValidationMessage& m) {
    g_messages.fetch_add(1);
    std::fprintf(stderr, "[validation] %s: %s\n", m.id.c_str(), m.text.c_str());
  };
  return options;
}

runtime::Context* shared_context() { return shared().context.get(); }
const std::string& no_device_reason() { return shared().reason; }
std::uint64_t validation_messages_total() { return g_messages.load(); }

void RuntimeTest::SetUp() {
  if (!shared_context()) {
    if (lavapipe_installed()) FAIL() << "lavapipe is installed but no Vulkan context: " << no_device_reason();
    GTEST_SKIP() << "no Vulkan device on this machine (" << no_device_reason() << ")";
  }
  messages_before_ = validation_messages_total();
}

void RuntimeTest::TearDown() {
  if (!shared_context()) return;
  EXPECT_EQ(validation_messages_total(), messages_before_) << "the validation layer reported messages (see stderr)";
}

const formats::ProbeVolume& baked_cornell_octree() {
  static const formats::ProbeVolume v = bake_scene(samples::cornell(), "cornell", false, false);
  return v;
}
const formats::ProbeVolume& baked_leak_octree() {
  static const formats::ProbeVolume v = bake_scene(samples::leak(), "leak", false, false);
  return v;
}
const formats::ProbeVolume& baked_cornell_grid() {
  static const formats::ProbeVolume v = bake_scene(samples::cornell(), "cornell-grid", true, false);
  return v;
}
const formats::ProbeVolume& baked_cornell_full() {
  static const formats::ProbeVolume v = bake_scene(samples::cornell(), "cornell-full", false, true);
  return v;
}

const formats::ProbeVolume& baked_cornell_dynamic() {
  static const formats::ProbeVolume v = [] {
    samples::CornellOptions options;
    options.dynamic = true;
    return bake_scene(samples::cornell(options), "cornell-dynamic", false, false);
  }();
  return v;
}

int live_probe_count(const formats::ProbeVolume& volume) {
  int live = 0;
  for (const gpu::Probe& p : volume.probes) live += p.link != 0 ? 1 : 0;
  return live;
}

std::string temp_path(const std::string& name) {
  const auto dir = std::filesystem::path(PROBEBAKE_BINARY_DIR) / "test-tmp" / "runtime";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

// ---- HostVulkanObjects ------------------------------------------------------------------------------------
namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL count_host_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  ++g_messages;
  std::printf("[runtime] host validation: %s\n", data->pMessage);
  return VK_FALSE;
}

VkDebugUtilsMessengerCreateInfoEXT host_messenger_info(const VkValidationFeaturesEXT* features) {
  VkDebugUtilsMessengerCreateInfoEXT info{};
  info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  info.pNext = features;
  info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = count_host_message;
  return info;
}

} // namespace

HostVulkanObjects::HostVulkanObjects(bool validation) {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.apiVersion = VK_API_VERSION_1_2;
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  const VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{};
  features.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &sync;
  VkDebugUtilsMessengerCreateInfoEXT messenger_info = host_messenger_info(&features);
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
  if (validation) {
    info.pNext = &messenger_info; // creation and destruction of the instance are covered too
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = &layer;
    info.enabledExtensionCount = 1;
    info.ppEnabledExtensionNames = &extension;
  }
  if (vkCreateInstance(&info, nullptr, &instance) != VK_SUCCESS) return;
  if (validation) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    messenger_info.pNext = nullptr;
    if (!create || create(instance, &messenger_info, nullptr, &messenger) != VK_SUCCESS) return;
  }
  std::uint32_t count = 1;
  const VkResult listed = vkEnumeratePhysicalDevices(instance, &count, &physical_device);
  if ((listed != VK_SUCCESS && listed != VK_INCOMPLETE) || count == 0) return;
  std::uint32_t families = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &families, nullptr);
  std::vector<VkQueueFamilyProperties> props(families);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &families, props.data());
  while (family < families && !(props[family].queueFlags & VK_QUEUE_COMPUTE_BIT)) ++family;
  if (family == families) return;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{};
  queue_info.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue_info.queueFamilyIndex = family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{};
  device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  if (vkCreateDevice(physical_device, &device_info, nullptr, &device) != VK_SUCCESS) return;
  vkGetDeviceQueue(device, family, 0, &queue);
}

HostVulkanObjects::~HostVulkanObjects() {
  if (device) vkDestroyDevice(device, nullptr);
  if (messenger) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance, messenger, nullptr);
  }
  if (instance) vkDestroyInstance(instance, nullptr);
}

} // namespace probebake::test
