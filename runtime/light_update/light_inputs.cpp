#include "light_update/light_inputs.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>

#include "core/commands.h"

namespace probebake::runtime::detail {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The first broken field of one light, or nullptr.
const char* broken_field(const gpu::PunctualLight& l) {
  if (l.type != gpu::LIGHT_POINT && l.type != gpu::LIGHT_SPOT && l.type != gpu::LIGHT_DIRECTIONAL) return "type";
  if (!finite(l.position)) return "position (not finite)";
  if (!finite(l.direction)) return "direction (not finite)";
  if (!finite(l.intensity) || l.intensity.x < 0.0f || l.intensity.y < 0.0f || l.intensity.z < 0.0f)
    return "intensity (not finite or negative)";
  if (!(std::isfinite(l.range) && l.range >= 0.0f)) return "range (not finite or negative)";
  if (l.type == gpu::LIGHT_POINT) return nullptr;
  // The shaders take direction as unit (dot products for cosines).
  const float length =
      std::sqrt(l.direction.x * l.direction.x + l.direction.y * l.direction.y + l.direction.z * l.direction.z);
  if (!(std::abs(length - 1.0f) <= 1e-4f))
    return "direction (not a unit vector within 1e-4)"; // formats::validate's tolerance
  if (l.type != gpu::LIGHT_SPOT) return nullptr;
  if (!(l.cos_outer >= -1.0f && l.cos_outer <= 1.0f)) return "cos_outer (outside [-1, 1])";
  if (!(l.spot_scale > 0.0f && l.spot_scale <= 1000.0f))
    return "spot_scale (outside (0, 1000])"; // 1 / 0.001: bake's floor
  return nullptr;
}

// The fields the light's type does not use set to zero, as the bake writes them (formats::validate checks
// them in the live volume); they change nothing in the lighting.
gpu::PunctualLight canonical(gpu::PunctualLight l) {
  l.pad0 = l.pad1 = l.pad2 = 0.0f;
  if (l.type == gpu::LIGHT_POINT) l.direction = glm::vec3(0.0f);
  if (l.type == gpu::LIGHT_DIRECTIONAL) {
    l.position = glm::vec3(0.0f);
    l.range = 0.0f;
  }
  if (l.type != gpu::LIGHT_SPOT) l.cos_outer = l.spot_scale = 0.0f;
  return l;
}

bool same_bytes(const gpu::PunctualLight& a, const gpu::PunctualLight& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

} // namespace

bool finite_non_negative(const glm::vec3& v) { return finite(v) && v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f; }

void update_buffer(VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize offset, const void* data, std::size_t bytes) {
  constexpr std::size_t kPiece = 65536;
  for (std::size_t done = 0; done < bytes; done += kPiece)
    vkCmdUpdateBuffer(cmd, buffer, offset + done, std::min(kPiece, bytes - done),
                      static_cast<const std::byte*>(data) + done);
}

Status check_lights(std::span<const gpu::PunctualLight> lights, std::size_t capacity) {
  if (lights.size() > capacity)
    return {StatusCode::invalid_argument, "run_frame: " + std::to_string(lights.size()) +
                                              " punctual lights exceed the capacity " + std::to_string(capacity) +
                                              " (the file's lights + UploadOptions::light_headroom)"};
  for (std::size_t i = 0; i < lights.size(); ++i)
    if (const char* field = broken_field(lights[i]))
      return {StatusCode::invalid_argument, "run_frame: punctual light " + std::to_string(i) + ": " + field};
  return {};
}

LightInputs::LightInputs(std::span<const gpu::PunctualLight> file_lights, std::size_t capacity) : capacity_(capacity) {
  current_.reserve(capacity);
  staged_.reserve(capacity);
  changes_.reserve(capacity);
  current_.assign(file_lights.begin(), file_lights.end());
}

int LightInputs::record(VkCommandBuffer cmd, GpuVolume& volume, std::span<const gpu::PunctualLight> host_lights) {
  staged_.clear();
  for (const gpu::PunctualLight& l : host_lights) staged_.push_back(canonical(l)); // within the reserve
  const std::vector<gpu::PunctualLight>& lights = staged_;
  // Records [first, last) differ; records past the old count are new.
  std::size_t first = 0;
  while (first < lights.size() && first < current_.size() && same_bytes(lights[first], current_[first])) ++first;
  std::size_t last = lights.size();
  while (last > first && last <= current_.size() && same_bytes(lights[last - 1], current_[last - 1])) --last;
  const bool count_changed = lights.size() != current_.size();
  changes_.clear();
  if (first == last && !count_changed) return 0;
  // Changed records, and records added or removed past the shorter list (a zero-intensity record, which
  // lights nothing, on the side where they are absent).
  const std::size_t end = count_changed ? std::max(lights.size(), current_.size()) : last;
  first_change_ = first;
  for (std::size_t i = first; i < end; ++i) {
    gpu::LightChange change{};
    if (i < current_.size()) change.before = current_[i];
    if (i < lights.size()) change.after = lights[i];
    changes_.push_back(change);
  }

  // Last frame's passes read the records and the count before they are overwritten.
  barrier(cmd, kAnyDeviceAccess, kTransferWrite);
  if (last > first)
    update_buffer(cmd, volume.buffer(Section::punctual_lights).get(), first * sizeof(gpu::PunctualLight),
                  &lights[first], (last - first) * sizeof(gpu::PunctualLight));
  if (count_changed) {
    const auto count = static_cast<std::int32_t>(lights.size());
    vkCmdUpdateBuffer(cmd, volume.buffer(Section::lighting_info).get(), offsetof(gpu::LightingInfo, lights),
                      sizeof count, &count);
  }
  barrier(cmd, kTransferWrite, kAnyDeviceAccess);
  current_.swap(staged_); // both reserved to the capacity: no allocation
  volume.set_live_elements(Section::punctual_lights, current_.size());
  return static_cast<int>(last - first);
}

} // namespace probebake::runtime::detail
