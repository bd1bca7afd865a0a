// Internal: SceneBuilder -> .glb bytes through tinygltf's writer.
#pragma once

#include "probebake/samples/scene_builder.h"

#include <cstdint>
#include <vector>

namespace probebake::samples {

std::vector<std::uint8_t> encode_glb(const SceneBuilder& scene);

} // namespace probebake::samples
