#include "run_lighting_changes.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "probebake/sky/sky.h"

namespace probebake::run {

float day_hour(float day_seconds, int frame) {
  const double days = double(frame) / double(kDayFramesPerSecond) / double(day_seconds);
  return float(std::fmod(6.0 + 24.0 * (days - std::floor(days)), 24.0));
}

glm::vec3 day_sun_direction(float hour) {
  const float pi = gpu::SKY_PI;
  const float a = pi * (hour - 6.0f) / 12.0f; // 0 at sunrise, pi at sunset, beyond at night
  const glm::vec3 east(1.0f, 0.0f, 0.0f), noon = sky::direction_from_angles(60.0f, 180.0f); // +Z, 60 degrees up
  return glm::normalize(std::cos(a) * east + std::sin(a) * noon);
}

sky::PhysicalSky day_sky(float hour, float turbidity) { return {day_sun_direction(hour), turbidity}; }

std::optional<std::string> day_cycle_refusal(const runtime::Volume& volume) {
  const std::optional<gpu::SkyHeader> header = volume.sky();
  if (!header || header->kind != gpu::SKY_KIND_PHYSICAL || header->sun_light < 0 ||
      header->sun_light >= int(volume.lights().size()))
    return std::string("--day-cycle: the file has no physical sky with a sun (bake with --sky physical --sun E,A)");
  return std::nullopt;
}

void add_day_cycle(runtime::FrameInputs& in, const runtime::Volume& volume, float day_seconds, int frame) {
  const gpu::SkyHeader header = *volume.sky();
  const sky::PhysicalSky physical = day_sky(day_hour(day_seconds, frame), header.turbidity);
  runtime::SkyInput s;
  s.radiance = glm::vec3(1.0f);
  s.map = sky::physical_sky_map(physical, int(header.width), int(header.height)).texels;
  in.sky = std::move(s);
  if (!in.lights) in.lights.emplace(volume.lights().begin(), volume.lights().end());
  gpu::PunctualLight& sun = (*in.lights)[std::size_t(header.sun_light)];
  sun.direction = -physical.sun_direction;
  sun.intensity = sky::sun_irradiance(physical);
}

bool emitters_on(int period, int frame) { return (frame / period) % 2 == 0; }

std::optional<std::string> emitter_switch_refusal(const runtime::Volume& volume) {
  if (!volume.emitter_materials().empty()) return std::nullopt;
  return std::string("--switch-emitters: the file has no emitters to switch (no emissive material, or baked with "
                     "--emitters-in-probes)");
}

void add_emitter_switch(runtime::FrameInputs& in, const runtime::Volume& volume, int period, int frame) {
  if (frame == 0 || frame % period != 0) return;
  const glm::vec3 scale(emitters_on(period, frame) ? 1.0f : 0.0f);
  for (int material : volume.emitter_materials()) in.emitters.push_back({material, scale});
}

} // namespace probebake::run
