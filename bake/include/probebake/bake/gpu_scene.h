// Stage "gpu_scene" of the bake: the runtime lighting sections (format 1.1, docs/FORMAT.md) that let a
// GPU runtime reproduce the bake's lighting (docs/LIGHTING.md) on Vulkan devices without ray-tracing
// extensions: the scene's triangles in a BVH of our own layout (built with Embree's rtcBuildBVH), its
// punctual lights, the emitter patches, the ray directions and the lighting settings.
#pragma once

#include "probebake/bake/bake.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::bake {

// Fills volume.lighting, ray_directions, bvh_nodes, trace_triangles, punctual_lights and
// emitter_patches from the scene and settings.lighting / lattice / surfels_per_probe (replacing what was
// there). Every triangle the bake's RayScene traces is included except zero-area ones (never hit).
// Deterministic: the same scene and settings give the same bytes. Throws Error(internal) when Embree
// fails, Error(input) when a value is not finite.
RuntimeLightingReport add_runtime_lighting(const scene::Scene& scene, const BakeSettings& settings,
                                           formats::ProbeVolume& volume);

} // namespace probebake::bake
