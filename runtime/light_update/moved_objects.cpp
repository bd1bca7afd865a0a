// LightUpdatePass after objects moved (light_update_pass.h): the moved boxes and their (box, light) shadow pairs
// into RelightChanges, and light_mark_moved's dispatch.
#include <cstddef>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/pipelines.h"
#include "light_update/light_update_pass.h"

namespace probebake::runtime::detail {
namespace {

// Whether `light` can light a point of the box as light_relight pads it (segment_meets_box): it has
// intensity and no range, or is directional, or its range ball (with probebake_light_reaches' margin) meets
// the box. A shadow ray from a point the light reaches runs inside that ball, so it meets no box the ball
// does not.
bool light_reaches_box(const gpu::PunctualLight& light, const gpu::MovedBox& box) {
  if (light.intensity == glm::vec3(0.0f)) return false;
  if (light.type == gpu::LIGHT_DIRECTIONAL || !(light.range > 0.0f)) return true;
  const glm::vec3 pad = 1e-4f * (box.upper - box.lower) + glm::vec3(1e-6f);
  const glm::vec3 nearest = glm::clamp(light.position, box.lower - pad, box.upper + pad);
  const glm::vec3 d = nearest - light.position;
  return glm::dot(d, d) <= light.range * light.range * 1.001f;
}

} // namespace

void LightUpdatePass::objects_moved(std::span<const Box> boxes, std::span<const gpu::PunctualLight> lights,
                                    bool retrace) {
  relight_everything_ = true; // limited to the shadow pairs' records where they fit (upload_moved_boxes)
  retrace_moved_ = retrace_moved_ || retrace;
  shadow_lights_.assign(lights.begin(), lights.end());
  for (const Box& box : boxes) {
    if (moved_boxes_.size() < gpu::RELIGHT_MAX_MOVED_BOXES) {
      moved_boxes_.push_back({box.min, 0.0f, box.max, 0.0f});
      continue;
    }
    gpu::MovedBox& last = moved_boxes_.back();
    last.lower = glm::min(last.lower, box.min), last.upper = glm::max(last.upper, box.max);
  }
}

void LightUpdatePass::upload_moved_boxes(VkCommandBuffer cmd) {
  const std::uint32_t count = std::uint32_t(moved_boxes_.size());
  vkCmdUpdateBuffer(cmd, relight_changes_.get(), offsetof(gpu::RelightChanges, moved_boxes), sizeof(count), &count);
  vkCmdUpdateBuffer(cmd, relight_changes_.get(), offsetof(gpu::RelightChanges, boxes), count * sizeof(gpu::MovedBox),
                    moved_boxes_.data());
  shadow_pairs_.clear(); // capacity RELIGHT_MAX_SHADOW_PAIRS, reserved once
  shadow_pairs_fit_ = true;
  for (std::uint32_t b = 0; b < count && shadow_pairs_fit_; ++b)
    for (std::uint32_t l = 0; l < shadow_lights_.size() && shadow_pairs_fit_; ++l) {
      if (!light_reaches_box(shadow_lights_[l], moved_boxes_[b])) continue;
      shadow_pairs_fit_ = shadow_pairs_.size() < gpu::RELIGHT_MAX_SHADOW_PAIRS;
      if (shadow_pairs_fit_) shadow_pairs_.push_back({b, l});
    }
  const auto used = std::uint32_t(shadow_pairs_.size());
  vkCmdUpdateBuffer(cmd, relight_changes_.get(), offsetof(gpu::RelightChanges, shadow_pairs), sizeof(used), &used);
  if (used > 0) // at most 32 KiB: within vkCmdUpdateBuffer's 64 KiB
    vkCmdUpdateBuffer(cmd, relight_changes_.get(), offsetof(gpu::RelightChanges, pairs), used * sizeof(gpu::ShadowPair),
                      shadow_pairs_.data());
}

void LightUpdatePass::record_mark_moved(VkCommandBuffer cmd) {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, device_.compute_pipelines().kernel(Kernel::light_mark_moved));
  dispatch_groups(cmd, device_, probe_capacity_);
  barrier(cmd, kComputeReadWrite, kComputeReadWrite); // light_trace reads the flags
  moved_boxes_.clear();
}

} // namespace probebake::runtime::detail
