// The runtime's irradiance lookup (Volume::sample_irradiance, on its device) as the pictures' sampler.
#pragma once

#include "probebake/formats/error.h"
#include "probebake/render/render.h"
#include "probebake/runtime/runtime.h"

namespace probebake::cli {

inline render::IndirectSampler runtime_lookup(runtime::Volume& volume) {
  return [&volume](std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) {
    auto values = volume.sample_irradiance(positions, normals);
    if (!values.ok())
      throw Error(ErrorKind::internal, std::string("the runtime's lookup failed: ") + values.status().message);
    return std::move(values).value();
  };
}

} // namespace probebake::cli
