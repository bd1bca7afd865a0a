// Stage "gpu_scene" (probebake/bake/gpu_scene.h): the scene as the runtime lighting sections. Each value
// comes from the function the bake's own lighting uses (triangle_normal, shadow_offset, spot_cone,
// emitter_patches, lattice_directions, is_double_sided), so that the GPU works with the numbers the CPU
// bake used.
#include "probebake/bake/gpu_scene.h"

#include <chrono>
#include <cmath>

#include <fmt/core.h>

#include "gpu_bvh.h"
#include "probebake/bake/direct_light.h"
#include "probebake/common/lattice.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
namespace {

using Clock = std::chrono::steady_clock;

// Scene order. Triangles without a normal (zero area in float) are left out: they are never hit.
std::vector<gpu::TraceTriangle> scene_triangles(const scene::Scene& scene) {
  std::vector<gpu::TraceTriangle> triangles;
  triangles.reserve(scene.triangles.size());
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const glm::vec3 normal = scene::triangle_normal(scene, t);
    if (normal == glm::vec3(0.0f)) continue;
    const glm::uvec3 corners = scene.triangles[t];
    gpu::TraceTriangle triangle{};
    triangle.v0 = scene.positions[corners.x];
    triangle.edge1 = scene.positions[corners.y] - triangle.v0;
    triangle.edge2 = scene.positions[corners.z] - triangle.v0;
    triangle.source = int(t);
    triangle.normal = normal;
    triangle.albedo = scene.triangle_albedo[t];
    triangle.emission = scene.triangle_emission[t];
    triangle.flags = scene::is_double_sided(scene, t) ? gpu::TRIANGLE_DOUBLE_SIDED : 0u;
    triangles.push_back(triangle);
  }
  return triangles;
}

// Fields a type does not use stay zero; "no range" (<= 0) is written as 0, which range_window treats
// the same way.
gpu::PunctualLight punctual_light(const scene::Light& light, std::size_t index) {
  gpu::PunctualLight out{};
  out.intensity = light.color * light.intensity; // as DirectLighting::from_light
  if (!std::isfinite(out.intensity.x) || !std::isfinite(out.intensity.y) || !std::isfinite(out.intensity.z)) {
    throw Error(ErrorKind::input, fmt::format("gpu_scene: light {} ('{}'): colour x intensity is not finite", index, light.name));
  }
  if (light.type == scene::LightType::directional) {
    out.type = gpu::LIGHT_DIRECTIONAL;
    out.direction = light.direction;
    return out;
  }
  out.position = light.position;
  out.range = light.range > 0.0f ? light.range : 0.0f;
  out.type = gpu::LIGHT_POINT;
  if (light.type == scene::LightType::spot) {
    out.type = gpu::LIGHT_SPOT;
    out.direction = light.direction;
    const lighting_detail::SpotCone cone = lighting_detail::spot_cone(light);
    out.cos_outer = cone.cos_outer;
    out.spot_scale = cone.scale;
  }
  return out;
}

std::vector<gpu::EmitterPatch> gpu_patches(const scene::Scene& scene, const LightingSettings& lighting) {
  std::vector<gpu::EmitterPatch> patches;
  if (!lighting.emissive_as_lights) return patches; // emitters then reach the runtime through the probes
  for (const lighting_detail::EmitterPatch& p : lighting_detail::emitter_patches(scene, lighting.emitter_samples)) {
    gpu::EmitterPatch out{};
    out.a = p.a, out.b = p.b, out.c = p.c, out.normal = p.normal, out.radiance = p.radiance;
    out.flags = p.double_sided ? gpu::EMITTER_DOUBLE_SIDED : 0u;
    patches.push_back(out);
  }
  return patches;
}

// The lighting rays (ray k of every probe), then the placement lattice (surfel k's direction).
std::vector<glm::vec4> ray_directions(const BakeSettings& settings) {
  std::vector<glm::vec4> directions;
  for (const glm::vec3& d : lattice_directions(Lattice::fibonacci, settings.lighting.rays)) directions.emplace_back(d, 0.0f);
  for (const glm::vec3& d : lattice_directions(settings.lattice, settings.surfels_per_probe)) directions.emplace_back(d, 0.0f);
  return directions;
}

gpu::LightingInfo lighting_info(const scene::Scene& scene, const BakeSettings& settings) {
  gpu::LightingInfo info{};
  info.sky_radiance = settings.lighting.sky_radiance;
  info.rays = settings.lighting.rays;
  info.shadow_offset = lighting_detail::shadow_offset(scene);
  info.emissive_as_lights = settings.lighting.emissive_as_lights ? 1 : 0;
  info.placement_rays = settings.surfels_per_probe;
  return info; // counts: sync_info_counts
}

std::size_t section_bytes(const formats::ProbeVolume& v) {
  return sizeof(gpu::LightingInfo) + v.ray_directions.size() * sizeof(glm::vec4) + v.bvh_nodes.size() * sizeof(gpu::BvhNode) +
         v.trace_triangles.size() * sizeof(gpu::TraceTriangle) + v.punctual_lights.size() * sizeof(gpu::PunctualLight) +
         v.emitter_patches.size() * sizeof(gpu::EmitterPatch);
}

} // namespace

RuntimeLightingReport add_runtime_lighting(const scene::Scene& scene, const BakeSettings& settings, formats::ProbeVolume& volume) {
  RuntimeLightingReport report;
  const std::vector<gpu::TraceTriangle> triangles = scene_triangles(scene);
  const auto start = Clock::now();
  const detail::GpuBvh bvh = detail::build_gpu_bvh(triangles);
  report.bvh_seconds = std::chrono::duration<double>(Clock::now() - start).count();

  volume.bvh_nodes = bvh.nodes;
  volume.trace_triangles.clear();
  volume.trace_triangles.reserve(triangles.size());
  for (std::uint32_t k : bvh.leaf_order) volume.trace_triangles.push_back(triangles[k]);
  volume.punctual_lights.clear();
  for (std::size_t i = 0; i < scene.lights.size(); ++i) volume.punctual_lights.push_back(punctual_light(scene.lights[i], i));
  volume.emitter_patches = gpu_patches(scene, settings.lighting);
  volume.ray_directions = ray_directions(settings);
  volume.lighting = lighting_info(scene, settings);
  formats::sync_info_counts(volume);

  report.written = true;
  report.bvh_nodes = int(volume.bvh_nodes.size());
  report.bvh_depth = bvh.depth;
  report.triangles = int(volume.trace_triangles.size());
  report.left_out_triangles = int(scene.triangles.size() - triangles.size());
  report.lights = int(volume.punctual_lights.size());
  report.emitter_patches = int(volume.emitter_patches.size());
  report.bytes = section_bytes(volume);
  return report;
}

} // namespace probebake::bake
