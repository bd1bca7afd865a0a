// Dynamic objects' poses (format 1.3, FrameInputs::object_poses; docs/RUNTIME.md "Moving objects"). The
// host's poses are checked, kept for Volume::object_pose(), and recorded into the frame as one
// vkCmdUpdateBuffer of world_from_object per moved object into the ObjectInstance buffer (GpuVolume), then
// object_refit.comp (one thread per object) derives the inverse and the world box that bvh_trace.glsl
// uses. Nothing is allocated per frame; a frame without moves records nothing.
#pragma once

#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <vulkan/vulkan_core.h>

#include "core/device.h"
#include "core/gpu_volume.h"
#include "core/pipelines.h"
#include "probebake/gpu_types.h"
#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

// ok, or invalid_argument naming the first bad pose (its index in `poses` and object) and the reason:
// object out of range, listed twice, not finite, last row not 0 0 0 1, |det| of the 3x3 part <= 1e-12.
Status check_object_poses(std::span<const ObjectPose> poses, std::size_t objects);

// The world box of `object`'s object-space box under `world_from_object` (its 8 corners), unpadded.
Box world_box(const gpu::DynamicObject& object, const glm::mat4& world_from_object);

class ObjectPoses {
public:
  // Writes every object's rest pose into the volume's instance buffer and refits them (one submission).
  ObjectPoses(Device& device, GpuVolume& volume, std::span<const gpu::DynamicObject> objects);

  // Records the checked `poses` that differ from the current ones: barrier (earlier device access ->
  // transfer write), the rows, barrier (-> compute), object_refit, barrier (compute write -> every device
  // access). moved_boxes() then holds the union of each moved object's old and new world boxes. Returns
  // the objects moved (0: nothing recorded).
  int record(VkCommandBuffer cmd, std::span<const ObjectPose> poses);
  std::span<const Box> moved_boxes() const { return moved_boxes_; }

  const glm::mat4& pose(std::size_t object) const { return poses_.at(object); }
  std::size_t count() const { return poses_.size(); }

private:
  void record_refit(VkCommandBuffer cmd);

  Device& device_;
  GpuVolume& volume_;
  std::vector<gpu::DynamicObject> objects_;
  std::vector<glm::mat4> poses_;
  std::vector<Box> moved_boxes_; // reserved to one per object: no allocation per frame
};

} // namespace probebake::runtime::detail
