// What probebake run changes in the lighting over the frames: --day-cycle SECONDS, a volume baked with `--sky
// physical` through a day, the sky map and the sun changing every frame (FrameInputs::sky and lights; docs/RUNTIME.md
// "Sky and time of day"), and --switch-emitters PERIOD, every emitter off and on again (FrameInputs::emitters).
#pragma once

#include <optional>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "probebake/runtime/runtime.h"
#include "probebake/sky/sky.h"

namespace probebake::run {

inline constexpr float kDayFramesPerSecond = 60.0f;

// The hour (0-24) of `frame` when a day lasts `day_seconds` at 60 frames a second, starting at 6:00, and the sun's
// direction then: it rises at 6:00 in the east (+X), culminates at 60 degrees towards +Z at 12:00 and sets at
// 18:00 in the west (-X); below the horizon at night.
float day_hour(float day_seconds, int frame);
glm::vec3 day_sun_direction(float hour);
// The physical sky of `hour` (its sun at day_sun_direction) with the file's turbidity: what the runtime's day and
// the reference of a day-cycle frame (probebake run --reference) are lit by.
sky::PhysicalSky day_sky(float hour, float turbidity);

// Why the volume cannot run a day (no physical sky, no sun light), or nothing.
std::optional<std::string> day_cycle_refusal(const runtime::Volume& volume);
// The frame's sky (map and radiance) and the sun in `in.lights` (the current lights, the sun replaced).
void add_day_cycle(runtime::FrameInputs& in, const runtime::Volume& volume, float day_seconds, int frame);

// Whether the emitters are on in `frame` when they switch every `period` frames: on in [0, P), off in [P, 2P), ...
bool emitters_on(int period, int frame);
// Why the volume has no emitter to switch, or nothing.
std::optional<std::string> emitter_switch_refusal(const runtime::Volume& volume);
// In the frames where they switch, every emitter's strength (1 or 0) in `in.emitters`.
void add_emitter_switch(runtime::FrameInputs& in, const runtime::Volume& volume, int period, int frame);

} // namespace probebake::run
