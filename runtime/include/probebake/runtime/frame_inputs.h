// What the host tells each frame (Volume::run_frame, record_frame): changed boxes and leaf thresholds, punctual
// lights, object poses, the sky, and the frame's limits. Part of the runtime's vocabulary (vocabulary.h).
#pragma once

#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "probebake/gpu_types.h"

namespace probebake::runtime {

// An axis-aligned box in world space (metres), min <= max.
struct Box {
  glm::vec3 min{0.0f};
  glm::vec3 max{0.0f};
};

// Per-frame limits of the costly work (0 = no limit); a leaf over a limit waits for a later frame.
struct FrameLimits {
  int max_memory_entries = 0; // M1/M3 allocations per frame
  int max_light_entries = 0;  // L1/L2 leaves with a probe measured or carried per frame
  // Without the memory update: probes gathered (L2) per frame, a window of probe slots that moves on each
  // frame, so every probe is updated once every k = ceil(capacity / max_gathered_probes) frames, blending
  // with hysteresis^k: a change spreads in as many frames as without a budget, in coarser steps, and the
  // converged irradiance does not depend on it. The cached punctual irradiance follows the window too: a
  // probe outside it only notes that a light change reached it and recomputes its whole sums (at most
  // shadow_rays_per_record rays each) when the window reaches it, so a frame's shadow rays scale with the
  // budget, not with the volume.
  int max_gathered_probes = 0;
  // Probe slots the load trace traces per frame (0 = all in frame 0; RUNTIME.md "Loading without a hitch"), in
  // slot order or nearest UploadOptions::load_focus. A probe not reached yet keeps the bake's irradiance; the
  // records, and so the converged irradiance, are those of a trace at once.
  int max_traced_probes = 0;
  // GPU ms per frame while the load trace lasts (0 = none; replaces max_traced_probes): each window as many
  // slots as fit beside the other passes, by times of returned frames; one slot until then, at least 1. The
  // windows are LightStats::load_window; given back as max_traced_probes they replay the run.
  float frame_ms = 0.0f;
  // Shadow rays per lighting record when a record's whole punctual sum is computed (the first trace, new
  // probes, and every record after an object moved or more than 16 lights changed in a frame); 0 = one per
  // light, exact. With more lights than this, the strongest shadow_rays_per_record - 1 lights by unshadowed
  // irradiance get their ray and one of the others is drawn in proportion to its unshadowed irradiance,
  // weighted by 1 / its probability: unbiased, and the noise of each record averages out over the probe's
  // rays (docs/RUNTIME_INTERNALS.md "Many lights"). A light changed alone is still relit exactly. In [0, 9];
  // sampling needs at least 2 (1 is refused).
  int shadow_rays_per_record = 0;
  // The sky and a light that changes alone frame after frame (the sun of a day cycle) relight their records over
  // this many frames (0 or 1: every record every frame; at most 64; docs/RUNTIME.md "Sky and time of day"): each
  // frame the probe slots s with s % relight_frames == frame % relight_frames take the current sky and light, so
  // a probe lags them by at most relight_frames - 1 frames. Within relight_frames - 1 frames after they stop,
  // every record is what it would be relit every frame; while slots still wait for the light, another light
  // change or a moved object first recomputes every record's whole punctual sum. Emitter strengths
  // (FrameInputs::emitters) are spread the same way.
  int relight_frames = 0;
};

// Where a dynamic object is this frame (format 1.3, gpu::DynamicObject): world_from_object of
// Volume::dynamic_objects()[object], affine (last row 0 0 0 1), finite and invertible. The runtime refits
// the object's world box on the GPU, traces its triangles through it from this frame on, and marks the union
// of its old and new world boxes as changed (the leaves there are measured again).
struct ObjectPose {
  int object = 0;
  glm::mat4 world_from_object{1.0f};
};

// What the host tells one frame. Boxes mark where geometry changed (for a moving object: the union of its
// old and new bounds): the leaves they touch are measured again (L1) or, without a probe, ask for one
// (M1). Thresholds change the leaf rule from this frame on (a volume baked at max depth 1 may refine to 3
// and back); leave them empty to keep the current ones.
// The sky from this frame on (FrameInputs::sky; docs/RUNTIME.md "Sky and time of day"): the radiance of rays that
// leave the scene is `radiance` times the map's lookup (the file's sky section, sky_map.h), or `radiance` alone
// in a file without one. Every value finite and >= 0. Only the records of rays that left the scene are relit
// (light_sky), and only in a frame where the sky differs from the last; the bounces converge from there.
struct SkyInput {
  glm::vec3 radiance{0.0f};        // LightingInfo::sky_radiance
  std::vector<glm::vec3> map = {}; // empty: keep the map; else Volume::sky_texels() texels in sky_map.h's order
};

// An emissive material's strength from this frame on (FrameInputs::emitters; docs/RUNTIME.md "Emitters at run
// time"): its emitted radiance times `scale` per channel (0 switches it off, 1 is the bake's; finite and >= 0).
// `material` is a glTF material index among Volume::emitter_materials(). The records of what its light reaches are
// relit (light_emitters), only in a frame where a strength changed; the bounces converge from there.
struct EmitterStrength {
  int material = 0;
  glm::vec3 scale{1.0f};
};

struct FrameInputs {
  std::vector<Box> changed_boxes; // more than 64 are merged by the host into fewer, larger boxes
  std::optional<int> max_depth;   // [0, 12]
  std::optional<float> split_low; // [0, 1], <= split_high
  std::optional<float> split_high;
  float dead_backface_fraction = 0.5f; // a centre seeing more back faces than this is inside a solid (leaf_rule.h)
  // The punctual lights from this frame on, all of them (empty = none; unset = keep the current ones):
  // moved, added, removed or recoloured, in the file's record (gpu_types.h PunctualLight: position,
  // direction, colour x intensity, range, cone). At most Volume::light_capacity(); every value finite,
  // intensity and range >= 0, type LIGHT_*, a unit direction for spot and directional lights, spot cone
  // cos_outer in [-1, 1] and spot_scale > 0. Only the records that differ from the current ones are
  // uploaded, inside the frame's command buffer. Needs the light update.
  std::optional<std::vector<gpu::PunctualLight>> lights;
  // Dynamic objects that moved (objects not listed keep their pose; at upload every object is at rest).
  // Each object at most once. Needs the light update.
  std::vector<ObjectPose> object_poses;
  std::optional<SkyInput> sky;           // unset: keep the current sky. Needs the light update
  std::vector<EmitterStrength> emitters; // the listed materials' strengths (the others keep theirs). Light update
  FrameLimits limits;
};

} // namespace probebake::runtime
