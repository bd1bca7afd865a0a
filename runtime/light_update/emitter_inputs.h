// The host's emitter strengths (FrameInputs::emitters): checked against the file's emitters (format 1.10, one per
// emissive glTF material), then, when one differs from the current strength, a new scale table for the light
// update (gpu::EmitterScale per emitter, which light_trace and light_emitters apply). Nothing is allocated per
// frame.
#pragma once

#include <span>
#include <vector>

#include "probebake/gpu_types.h"
#include "probebake/runtime/vocabulary.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {

class EmitterInputs {
public:
  // The file's emitter patches (validated: emitters numbered by first patch, one material each).
  explicit EmitterInputs(std::span<const gpu::EmitterPatch> patches);

  const std::vector<int>& materials() const { return materials_; } // emitter k's glTF material
  // ok, or invalid_argument naming a material that is no emitter of the file, or a bad scale.
  Status check(std::span<const EmitterStrength> strengths) const;
  // Takes checked strengths; returns whether one changed, and then scales() holds the new table.
  bool apply(std::span<const EmitterStrength> strengths);
  std::span<const gpu::EmitterScale> scales() const { return scales_; }

private:
  int emitter_of(int material) const; // -1: none
  std::vector<int> materials_;
  std::vector<gpu::EmitterScale> scales_;
};

} // namespace probebake::runtime::detail
