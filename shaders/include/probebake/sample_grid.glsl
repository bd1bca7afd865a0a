// The grid engine's lookup in GLSL: the GPU twin of probe_index::sample_irradiance_grid
// (probe_index/include/probebake/probe_index/grid_lookup.h), step for step, on a grid bake's lattice
// (.probes format 1.8, section grid_lattice): the cell by arithmetic, its eight probes blended trilinearly,
// weighted by the cells each probe serves, the surface's side and each probe's reach along the axes.
//
// Requires what sample_irradiance.glsl requires (it is included here for the probes buffer and the SH
// evaluation), and the lattice buffer: define PROBEBAKE_BINDING_GRID_LATTICE (and PROBEBAKE_GRID_SET, default
// PROBEBAKE_SET) before the #include and bind the file's grid_lattice section there (Volume::buffers()
// .grid_lattice), or define PROBEBAKE_DECLARE_GRID_BUFFER to 0 and declare GridLatticeHeader probebake_grid
// and GridPoint probebake_grid_points[] yourself.
//
// Entry point: vec3 probebake_sample_irradiance_grid(vec3 position, vec3 normal, out int corners): world
// space metres and a unit normal (a zero normal: a point in a volume); W/m^2, 0 and corners 0 on a miss.
#ifndef PROBEBAKE_SAMPLE_GRID_GLSL
#define PROBEBAKE_SAMPLE_GRID_GLSL

#include "probebake/sample_irradiance.glsl"

#ifndef PROBEBAKE_GRID_SET
#define PROBEBAKE_GRID_SET PROBEBAKE_SET
#endif
#ifndef PROBEBAKE_DECLARE_GRID_BUFFER
#define PROBEBAKE_DECLARE_GRID_BUFFER 1
#endif
#if PROBEBAKE_DECLARE_GRID_BUFFER
#ifndef PROBEBAKE_BINDING_GRID_LATTICE
#error "define PROBEBAKE_BINDING_GRID_LATTICE: the binding of the grid_lattice section"
#endif
layout(std430, set = PROBEBAKE_GRID_SET, binding = PROBEBAKE_BINDING_GRID_LATTICE) readonly buffer ProbebakeGridLattice {
  GridLatticeHeader probebake_grid;
  GridPoint probebake_grid_points[];
};
#endif

float probebake_grid_normal_bias() {
  const vec3 s = probebake_grid.spacing;
  return 0.25 * min(s.x, min(s.y, s.z));
}

// Step 3's reach weight: per axis, 1 until the point comes within an eighth of a spacing / 2 of the first
// surface the probe sees along it, 0 from there past it (offset and reach in spacings).
float probebake_grid_reach_weight(uint reach, vec3 offset) {
  float w = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    const uint q = (reach >> (GRID_REACH_BITS * uint(2 * axis + (offset[axis] < 0.0 ? 1 : 0)))) & GRID_REACH_STEPS;
    if (q == GRID_REACH_STEPS) continue; // no surface within a spacing
    const float ramp = (float(q) / float(GRID_REACH_STEPS) - abs(offset[axis])) / 0.125 + 0.5;
    w *= ramp > 0.0 ? min(ramp, 1.0) : 0.0;
  }
  return w;
}

// Step 3's serve weight of the probe at lattice point q for the point at lattice coordinates g: its cell bits
// blended trilinearly over the centres of the eight cells around q; on the border the missing side takes the
// present side's bits.
float probebake_grid_serve_weight(uint cells, vec3 g, ivec3 q, int n) {
  vec3 o = g - vec3(q);
  for (int axis = 0; axis < 3; ++axis) {
    if (q[axis] == 0) o[axis] = max(o[axis], 0.5);
    if (q[axis] == n - 1) o[axis] = min(o[axis], -0.5);
  }
  const vec3 plus = clamp(o + 0.5, vec3(0.0), vec3(1.0));
  float serve = 0.0;
  for (int octant = 0; octant < 8; ++octant) {
    if (((cells >> uint(octant)) & 1u) == 0u) continue;
    const vec3 w = mix(vec3(1.0) - plus, plus, vec3(octant & 1, (octant >> 1) & 1, (octant >> 2) & 1));
    serve += w.x * w.y * w.z;
  }
  return serve;
}

bool probebake_grid_finite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

vec3 probebake_sample_irradiance_grid(vec3 position, vec3 normal, out int corners) {
  corners = 0;
  const int n = probebake_grid.resolution;
  if (n < 2 || n > GRID_MAX_RESOLUTION || probebake_grid_points.length() < n * n * n ||
      !probebake_grid_finite(position) || !probebake_grid_finite(normal))
    return vec3(0.0);
  const bool volumetric = dot(normal, normal) == 0.0;
  const float bias = volumetric ? 0.0 : probebake_grid_normal_bias();
  const vec3 g = (position + normal * bias - probebake_grid.origin) / probebake_grid.spacing - 0.5;
  const ivec3 c = clamp(ivec3(floor(clamp(g, vec3(0.0), vec3(float(n - 1))))), ivec3(0), ivec3(n - 2));
  const vec3 f = clamp(g - vec3(c), vec3(0.0), vec3(1.0));
  int probes[8];
  float weight[8], floored[8];
  int count = 0;
  float primary = 0.0;
  for (int k = 0; k < 8; ++k) {
    const ivec3 b = ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    const ivec3 q = c + b;
    const GridPoint point = probebake_grid_points[q.x + n * (q.y + n * q.z)];
    const uint index = point.probe_cells & GRID_POINT_PROBE_MASK;
    if (index == GRID_POINT_NO_PROBE || index >= uint(probebake_info.probe_capacity)) continue;
    const float serve = probebake_grid_serve_weight(point.probe_cells >> GRID_POINT_CELLS_SHIFT, g, q, n);
    if (!probebake_probe_live(int(index)) || !(serve > 0.0)) continue;
    const vec3 at = probebake_probe_position(int(index));
    const vec3 t = mix(vec3(1.0) - f, f, vec3(b));
    const float s = volumetric ? 1.0 : dot(at - position, normal) / bias;
    const float side = s > 0.0 ? min(s, 1.0) : 0.0;
    const float trilinear =
        t.x * t.y * t.z *
        probebake_grid_reach_weight(point.reach, (position + normal * bias - at) / probebake_grid.spacing);
    probes[count] = int(index);
    weight[count] = trilinear * serve * side;
    floored[count] = serve * (trilinear + 0.001) * (side + 0.001);
    primary += weight[count];
    ++count;
  }
  // The floor fades in as the weights vanish (below 0.01), so the lookup stays continuous.
  const float fade = max(0.0, 1.0 - primary / 0.01);
  float sum = 0.0;
  for (int i = 0; i < count; ++i) sum += weight[i] + fade * floored[i];
  if (!(sum > 0.0)) return vec3(0.0);
  float y[9];
  probebake_sh_basis(normal, y);
  vec3 e = vec3(0.0);
  for (int i = 0; i < count; ++i) {
    const float w = weight[i] + fade * floored[i];
    if (!(w > 0.0)) continue;
    e += (w / sum) * max(probebake_evaluate_probe_sh(probes[i], y), vec3(0.0));
    ++corners;
  }
  return e;
}

#endif // PROBEBAKE_SAMPLE_GRID_GLSL
