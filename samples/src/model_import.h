// Internal: another glTF model as triangles grouped by material (for SceneBuilder::add_model).
#pragma once

#include "probebake/samples/scene_builder.h"

#include <filesystem>
#include <vector>

namespace probebake::samples {

struct ImportedPart {
  Material material;
  MeshData geometry; // in the model's scene space (its node transforms applied)
};

struct ImportedModel {
  std::vector<ImportedPart> parts; // one per material used, in material order; never empty
};

// Reads a .glb or .gltf with probebake's scene loader (so exactly what the bake accepts, Draco included).
// Throws Error(input) on a missing, malformed or unsupported file, or one without triangles.
ImportedModel import_model(const std::filesystem::path& path);

} // namespace probebake::samples
