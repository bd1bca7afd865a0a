#include "objects/object_poses.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>

#include <glm/common.hpp>
#include <glm/matrix.hpp>

#include "core/commands.h"
#include "probebake/dynamic/animation.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {
namespace {

// The first broken property of one pose, or nullptr (glm::mat4 is column-major: m[column][row]).
const char* broken_pose(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return "not finite";
  if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
    return "not affine (last row must be 0 0 0 1)";
  const double det = double(m[0][0]) * (double(m[1][1]) * m[2][2] - double(m[2][1]) * m[1][2]) -
                     double(m[1][0]) * (double(m[0][1]) * m[2][2] - double(m[2][1]) * m[0][2]) +
                     double(m[2][0]) * (double(m[0][1]) * m[1][2] - double(m[1][1]) * m[0][2]);
  if (!(std::abs(det) > 1e-12)) return "singular (|det| of the 3x3 part <= 1e-12)";
  return nullptr;
}

// world_from_object as the shaders' rows (ObjectInstance::world_from_object).
std::array<glm::vec4, 3> rows_of(const glm::mat4& m) {
  return {glm::vec4(m[0][0], m[1][0], m[2][0], m[3][0]), glm::vec4(m[0][1], m[1][1], m[2][1], m[3][1]),
          glm::vec4(m[0][2], m[1][2], m[2][2], m[3][2])};
}

glm::mat4 from_rows(const glm::vec4 (&rows)[3]) {
  glm::mat4 m(1.0f);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = rows[r][c];
  return m;
}

Box box_union(const Box& a, const Box& b) { return {glm::min(a.min, b.min), glm::max(a.max, b.max)}; }

} // namespace

Status check_object_poses(std::span<const ObjectPose> poses, std::size_t objects) {
  std::vector<bool> seen(objects, false);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const int object = poses[i].object;
    const std::string name =
        "run_frame: object pose " + std::to_string(i) + " (object " + std::to_string(object) + "): ";
    if (object < 0 || std::size_t(object) >= objects)
      return {StatusCode::invalid_argument,
              name + "no such dynamic object (the volume has " + std::to_string(objects) + ")"};
    if (seen[std::size_t(object)]) return {StatusCode::invalid_argument, name + "listed twice"};
    seen[std::size_t(object)] = true;
    if (const char* reason = broken_pose(poses[i].world_from_object))
      return {StatusCode::invalid_argument, name + reason};
  }
  return {};
}

Box world_box(const gpu::DynamicObject& object, const glm::mat4& m) {
  const dynamic::WorldBox box = dynamic::world_box(object, m);
  return {box.min, box.max};
}

ObjectPoses::ObjectPoses(Device& device, GpuVolume& volume, std::span<const gpu::DynamicObject> objects)
    : device_(device), volume_(volume), objects_(objects.begin(), objects.end()) {
  poses_.reserve(objects_.size());
  moved_boxes_.reserve(objects_.size()); // check_object_poses: each object at most once per frame
  std::vector<gpu::ObjectInstance> rest(objects_.size());
  for (std::size_t o = 0; o < objects_.size(); ++o) {
    poses_.push_back(from_rows(objects_[o].rest_rows));
    for (int r = 0; r < 3; ++r) rest[o].world_from_object[r] = objects_[o].rest_rows[r];
  }
  Submission submission(device);
  constexpr std::size_t kPiece = 65536 / sizeof(gpu::ObjectInstance); // vkCmdUpdateBuffer's limit
  for (std::size_t o = 0; o < rest.size(); o += kPiece)
    vkCmdUpdateBuffer(submission.cmd(), volume.object_instances(), o * sizeof(gpu::ObjectInstance),
                      std::min(kPiece, rest.size() - o) * sizeof(gpu::ObjectInstance), &rest[o]);
  barrier(submission.cmd(), kTransferWrite, kComputeReadWrite);
  record_refit(submission.cmd());
  submission.submit_and_wait();
}

void ObjectPoses::record_refit(VkCommandBuffer cmd) {
  Pipelines& pipelines = device_.compute_pipelines();
  const gpu::ObjectRefitPush push{static_cast<std::uint32_t>(objects_.size()), 0, 0, 0};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.kernel(Kernel::object_refit));
  bind_sets_and_push(cmd, pipelines.layout(Layout::object), volume_.volume_set(), VK_NULL_HANDLE, push);
  vkCmdDispatch(cmd, (push.objects + gpu::RUNTIME_WORKGROUP_SIZE - 1) / gpu::RUNTIME_WORKGROUP_SIZE, 1, 1);
  // Every later pass traces through the instances; the next frame's uploads overwrite them.
  barrier(cmd, kComputeWrite, kAnyDeviceAccess);
}

int ObjectPoses::record(VkCommandBuffer cmd, std::span<const ObjectPose> poses) {
  int moved = 0;
  moved_boxes_.clear();
  for (const ObjectPose& pose : poses) {
    const auto o = static_cast<std::size_t>(pose.object);
    if (poses_[o] == pose.world_from_object) continue;
    if (moved++ == 0) barrier(cmd, kAnyDeviceAccess, kTransferWrite); // last frame's traces read the rows
    const std::array<glm::vec4, 3> rows = rows_of(pose.world_from_object);
    vkCmdUpdateBuffer(cmd, volume_.object_instances(), o * sizeof(gpu::ObjectInstance), sizeof rows, rows.data());
    moved_boxes_.push_back(
        box_union(world_box(objects_[o], poses_[o]), world_box(objects_[o], pose.world_from_object)));
    poses_[o] = pose.world_from_object;
  }
  if (moved == 0) return 0;
  barrier(cmd, kTransferWrite, kComputeReadWrite);
  record_refit(cmd);
  return moved;
}

} // namespace probebake::runtime::detail
