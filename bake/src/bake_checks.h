// The bake's checks of its input (bake_checks.cpp); check_settings is public (bake.h).
#pragma once

#include <string>

#include "probebake/bake/bake.h"
#include "probebake/scene/scene.h"

namespace probebake::bake::detail {

// Throws Error(input) "bake: <reason>".
[[noreturn]] void bake_fail(const std::string& reason);
// The scene has area and a size and offset that 32-bit positions resolve (Error(input) otherwise).
void check_scene(const scene::Scene& scene);
// The clearance is at most half the scene's size (Error(usage) otherwise).
void check_clearance(const scene::Scene& scene, const BakeSettings& s);

} // namespace probebake::bake::detail
