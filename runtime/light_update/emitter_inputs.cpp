#include "light_update/emitter_inputs.h"

#include <algorithm>
#include <string>

#include "light_update/light_inputs.h"

namespace probebake::runtime::detail {
EmitterInputs::EmitterInputs(std::span<const gpu::EmitterPatch> patches) {
  for (const gpu::EmitterPatch& p : patches)
    if (p.emitter == materials_.size()) materials_.push_back(p.material);
  gpu::EmitterScale as_baked{};
  as_baked.scale = glm::vec3(1.0f);
  scales_.assign(materials_.size(), as_baked);
}

int EmitterInputs::emitter_of(int material) const {
  const auto found = std::find(materials_.begin(), materials_.end(), material);
  return found == materials_.end() ? -1 : int(found - materials_.begin());
}

Status EmitterInputs::check(std::span<const EmitterStrength> strengths) const {
  for (std::size_t i = 0; i < strengths.size(); ++i) {
    const std::string which = "run_frame: emitters[" + std::to_string(i) + "]";
    if (emitter_of(strengths[i].material) < 0)
      return {StatusCode::invalid_argument,
              which + ": material " + std::to_string(strengths[i].material) + " is no emitter of this volume (" +
                  std::to_string(materials_.size()) +
                  " emitters, Volume::emitter_materials(); a volume baked with --emitters-in-probes has none)"};
    if (!finite_non_negative(strengths[i].scale))
      return {StatusCode::invalid_argument, which + ": scale is not finite and >= 0"};
  }
  return {};
}

bool EmitterInputs::apply(std::span<const EmitterStrength> strengths) {
  bool changed = false;
  for (const EmitterStrength& strength : strengths) {
    gpu::EmitterScale& s = scales_[std::size_t(emitter_of(strength.material))];
    changed = changed || strength.scale != s.scale;
    s.scale = strength.scale; // listed twice: the last one
  }
  return changed;
}

} // namespace probebake::runtime::detail
