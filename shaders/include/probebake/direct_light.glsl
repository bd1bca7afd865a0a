// Direct irradiance at a surface point, the GPU twin of lighting/src/direct_light.cpp (docs/LIGHTING.md):
// KHR_lights_punctual lights and the emitter patches (emissive triangles as area lights), each with one
// shadow ray through bvh_trace.glsl. Same formulas as the CPU, so results agree to rounding; with lanes = 1
// also in the same order (light_trace sums lanes' parts, light_relight takes whole sums).
//
// The including shader declares (std430) what bvh_trace.glsl needs, plus PunctualLight probebake_lights[]
// and EmitterPatch probebake_emitter_patches[] (counts in probebake_lighting).
#ifndef PROBEBAKE_DIRECT_LIGHT_GLSL
#define PROBEBAKE_DIRECT_LIGHT_GLSL

#include "probebake/bvh_trace.glsl"

// KHR_lights_punctual range window clamp(1 - (r / range)^4, 0, 1); 1 without a range.
float probebake_range_window(float range, float distance) {
  if (!(range > 0.0)) return 1.0;
  const float q = distance / range;
  return clamp(1.0 - q * q * q * q, 0.0, 1.0);
}

bool probebake_visible(vec3 origin, vec3 target) {
  const vec3 to = target - origin;
  const float dist = length(to);
  return !(dist > 0.0) || !probebake_occluded(origin, to / dist, 0.0, dist);
}

// Whether `light` can light p at all: it has intensity, and p lies inside its range (the range window is 0
// from the range on) or it has none.
bool probebake_light_reaches(PunctualLight light, vec3 p) {
  if (light.intensity == vec3(0.0)) return false;
  if (light.type == LIGHT_DIRECTIONAL || !(light.range > 0.0)) return true;
  const vec3 d = p - light.position;
  return dot(d, d) < light.range * light.range * 1.0001; // a relative margin for rounding; beyond it, exactly 0
}

// The irradiance `light` would give at (p, n) without its shadow ray: 0 where it cannot light p at all.
vec3 probebake_light_unshadowed(PunctualLight light, vec3 p, vec3 n) {
  if (light.intensity == vec3(0.0)) return vec3(0.0);
  if (light.type == LIGHT_DIRECTIONAL) {
    const float cosine = dot(n, -light.direction);
    return cosine <= 0.0 ? vec3(0.0) : light.intensity * cosine;
  }
  const vec3 to = light.position - p;
  const float r2 = dot(to, to);
  if (!(r2 > 0.0)) return vec3(0.0); // the light sits on the point: no defined direction
  const float r = sqrt(r2);
  const vec3 l = to / r;
  const float cosine = dot(n, l);
  if (cosine <= 0.0) return vec3(0.0);
  float attenuation = probebake_range_window(light.range, r) / r2;
  if (light.type == LIGHT_SPOT) {
    const float a = clamp((dot(light.direction, -l) - light.cos_outer) * light.spot_scale, 0.0, 1.0);
    attenuation *= a * a;
  }
  return attenuation == 0.0 ? vec3(0.0) : light.intensity * (cosine * attenuation);
}

// The shadow ray of `light` from (p, n).
bool probebake_light_visible_from(PunctualLight light, vec3 p, vec3 n) {
  const vec3 origin = p + n * probebake_lighting.shadow_offset;
  if (light.type == LIGHT_DIRECTIONAL) return !probebake_occluded(origin, -light.direction, 0.0, 3.0e38);
  return probebake_visible(origin, light.position);
}

vec3 probebake_light_irradiance_of(PunctualLight light, vec3 p, vec3 n) {
  const vec3 e = probebake_light_unshadowed(light, p, n);
  return e == vec3(0.0) || !probebake_light_visible_from(light, p, n) ? vec3(0.0) : e;
}

// ---- Many lights: a budget of shadow rays per record ------------------------------------------------------
// With more lights than `shadow_rays`, the strongest shadow_rays - 1 by unshadowed luminance (the tracked
// light among them when there is one) get their shadow ray, and one of the others is drawn with probability
// proportional to its unshadowed luminance and counted with weight 1 / that probability: an unbiased estimate
// of the whole sum for shadow_rays rays instead of one per light. The draw is weighted reservoir sampling in
// light order from a hash of `seed`, so the same seed gives the same bits. runtime_types.h LightPush.
const int PROBEBAKE_MAX_STRONGEST_LIGHTS = 8;

uint probebake_hash(uint x) { // PCG output permutation (O'Neill 2014)
  x = x * 747796405u + 2891336453u;
  const uint w = ((x >> ((x >> 28u) + 4u)) ^ x) * 277803737u;
  return (w >> 22u) ^ w;
}

float probebake_luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// `tracked` (>= 0) is always exact and its share returned in tracked_share.
//
// Split over `lanes` threads of one record (light_trace: LIGHT_TRACE_LANES), lane `lane` casts the shadow
// rays of every lanes-th item of the sum (a light of the exact sum; of the budgeted one: the tracked light,
// the strongest, the drawn one) and returns that part; the parts add up to the sum, and tracked_share is 0
// except in the lane that owns the tracked light. Every lane draws the same lights from the same seed
// (unshadowed terms only: no ray). lanes = 1 is the whole sum in the order of the CPU twin.
vec3 probebake_punctual_irradiance_share(vec3 p, vec3 n, int shadow_rays, int tracked, uint seed, uint lane, uint lanes,
                                         out vec3 tracked_share) {
  tracked_share = vec3(0.0);
  const int lights = probebake_lighting.lights;
  vec3 e = vec3(0.0);
  if (shadow_rays <= 0 || lights <= shadow_rays) { // one ray per light: the exact sum, in light order
    for (int i = int(lane); i < lights; i += int(lanes)) {
      const vec3 share = probebake_light_irradiance_of(probebake_lights[i], p, n);
      e += share;
      if (i == tracked) tracked_share = share;
    }
    return e;
  }
  const bool has_tracked = tracked >= 0 && tracked < lights;
  const int strongest = min(shadow_rays - 1 - (tracked >= 0 ? 1 : 0), PROBEBAKE_MAX_STRONGEST_LIGHTS);
  int best[PROBEBAKE_MAX_STRONGEST_LIGHTS];
  float best_w[PROBEBAKE_MAX_STRONGEST_LIGHTS];
  for (int k = 0; k < PROBEBAKE_MAX_STRONGEST_LIGHTS; ++k) best[k] = -1, best_w[k] = 0.0;
  for (int i = 0; i < lights && strongest > 0; ++i) { // insertion into a descending list; ties keep light order
    if (i == tracked) continue;
    const float w = probebake_luminance(probebake_light_unshadowed(probebake_lights[i], p, n));
    if (!(w > best_w[strongest - 1])) continue;
    int at = strongest - 1;
    for (; at > 0 && w > best_w[at - 1]; --at) best[at] = best[at - 1], best_w[at] = best_w[at - 1];
    best[at] = i, best_w[at] = w;
  }
  float rest = 0.0, chosen_w = 0.0;
  int chosen = -1;
  uint state = seed;
  for (int i = 0; i < lights; ++i) {
    bool exact = i == tracked;
    for (int k = 0; k < strongest; ++k) exact = exact || best[k] == i;
    if (exact) continue;
    const float w = probebake_luminance(probebake_light_unshadowed(probebake_lights[i], p, n));
    if (!(w > 0.0)) continue;
    rest += w;
    state = probebake_hash(state);
    if (float(state >> 8u) * (1.0 / 16777216.0) * rest < w) chosen = i, chosen_w = w;
  }
  // The items in order: tracked, the strongest, the drawn light; this lane's are item % lanes == lane.
  uint item = 0u;
  if (has_tracked && item++ % lanes == lane) {
    tracked_share = probebake_light_irradiance_of(probebake_lights[tracked], p, n);
    e = tracked_share;
  }
  for (int k = 0; k < strongest; ++k)
    if (best[k] >= 0 && item++ % lanes == lane) e += probebake_light_irradiance_of(probebake_lights[best[k]], p, n);
  if (chosen >= 0 && item++ % lanes == lane) e += probebake_light_irradiance_of(probebake_lights[chosen], p, n) * (rest / chosen_w);
  return e;
}

vec3 probebake_punctual_irradiance_budgeted(vec3 p, vec3 n, int shadow_rays, int tracked, uint seed, out vec3 tracked_share) {
  return probebake_punctual_irradiance_share(p, n, shadow_rays, tracked, seed, 0u, 1u, tracked_share);
}

// The seed of one record's draw in one frame.
uint probebake_record_seed(uint frame_seed, uint slot, uint ray) { return probebake_hash(frame_seed ^ probebake_hash(slot * 65536u + ray)); }

// Unoccluded irradiance of one patch (Lambert's formula after clipping the patch to n's hemisphere) and
// the shadow ray's target (the clipped polygon's vertex mean); false when the patch cannot light p
// (bake's patch_irradiance with plane_margin = shadow_offset).
bool probebake_patch_irradiance(int index, vec3 p, vec3 n, out vec3 irradiance, out vec3 target) {
  irradiance = vec3(0.0);
  target = p;
  const EmitterPatch ep = probebake_emitter_patches[index];
  // In the emitter's plane: nothing; behind it: nothing unless it emits from both sides (the formula does
  // not depend on the winding: the back needs no flip).
  const float side = dot(p - ep.a, ep.normal);
  const bool double_sided = (ep.flags & EMITTER_DOUBLE_SIDED) != 0u;
  if (!(side > 0.0) && !(double_sided && side < 0.0)) return false;
  vec3 v[3] = vec3[3](ep.a - p, ep.b - p, ep.c - p);
  vec3 q[4];
  int count = 0;
  float highest = -3.0e38; // max over the vertices of dot(n, q): how far the patch rises above p's horizon
  for (int i = 0; i < 3; ++i) {
    const vec3 s = v[i], e = v[(i + 1) % 3];
    const float ds = dot(n, s), de = dot(n, e);
    highest = max(highest, ds);
    if (ds >= 0.0) q[count++] = s;
    if ((ds >= 0.0) != (de >= 0.0)) q[count++] = s + (e - s) * (ds / (ds - de));
  }
  // No vertex more than shadow_offset above p's horizon: p is on the emitter itself (or coplanar with it),
  // where `side` is rounding noise and Lambert's formula is singular. Near a corner p keeps its light.
  if (count < 3 || !(highest > probebake_lighting.shadow_offset)) return false;
  float sum = 0.0;
  vec3 centre = vec3(0.0);
  for (int i = 0; i < count; ++i) {
    const vec3 s = q[i], e = q[(i + 1) % count];
    centre += s;
    const vec3 c = cross(s, e);
    const float len = length(c);
    if (!(len > 0.0)) continue;
    sum += atan(len, dot(s, e)) * (dot(n, c) / len);
  }
  const float form = 0.5 * abs(sum); // projected solid angle
  if (!(form > 0.0)) return false;
  irradiance = ep.radiance * form;
  target = p + centre / float(count);
  return true;
}

// Patch `index`'s irradiance at p (unit normal n) at its baked radiance, 0 where the shadow ray from `origin` (p
// lifted by the shadow offset) is blocked.
vec3 probebake_visible_patch_irradiance(int index, vec3 p, vec3 n, vec3 origin) {
  vec3 patch_e, target;
  if (!probebake_patch_irradiance(index, p, n, patch_e, target)) return vec3(0.0);
  const vec3 to = target - origin;
  const float dist = length(to);
  // Stop short of the emitter itself (a relative 1e-3 of the distance).
  if (dist > 0.0 && probebake_occluded(origin, to / dist, 0.0, dist * 0.999)) return vec3(0.0);
  return patch_e;
}

// The host's strength of emitter e (FrameInputs::emitters); the including shader may define it (light_bindings.glsl),
// else every emitter is as baked.
#ifndef PROBEBAKE_EMITTER_SCALE
#define PROBEBAKE_EMITTER_SCALE(e) vec3(1.0)
#endif

// The emitter patches i with i % lanes == lane (all of them with lanes = 1, in the CPU twin's order), each scaled
// by its emitter's strength (1 as baked: the CPU's sum bit for bit); a switched-off emitter casts no shadow ray.
vec3 probebake_emitter_irradiance_share(vec3 p, vec3 n, uint lane, uint lanes) {
  const vec3 origin = p + n * probebake_lighting.shadow_offset;
  vec3 e = vec3(0.0);
  for (int i = int(lane); i < probebake_lighting.emitter_patches; i += int(lanes)) {
    const vec3 scale = PROBEBAKE_EMITTER_SCALE(probebake_emitter_patches[i].emitter);
    if (scale != vec3(0.0)) e += scale * probebake_visible_patch_irradiance(i, p, n, origin);
  }
  return e;
}

#endif // PROBEBAKE_DIRECT_LIGHT_GLSL
