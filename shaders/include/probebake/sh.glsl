// L2 spherical harmonics of irradiance, the convention of probe_index/include/probebake/probe_index/lookup.h
// (real SH, coefficient k = l^2 + l + m, irradiance_sh[3k + c], cosine lobe already convolved in). The
// basis constants (SH_Y*) are defined once, for C++ and GLSL, in gpu_types.h. The order of the operations
// follows probe_index/include/probebake/probe_index/stencil.h so that GPU and CPU results agree to rounding.
#ifndef PROBEBAKE_SH_GLSL
#define PROBEBAKE_SH_GLSL

#include "probebake/gpu_types.h"

// This file's names for them (used below, and by shaders that include it).
const float PROBEBAKE_SH_Y0 = SH_Y0;
const float PROBEBAKE_SH_Y1 = SH_Y1;
const float PROBEBAKE_SH_Y2 = SH_Y2;
const float PROBEBAKE_SH_Y20 = SH_Y20;
const float PROBEBAKE_SH_Y22 = SH_Y22;

// The nine basis values at unit direction d.
void probebake_sh_basis(vec3 d, out float y[9]) {
  y[0] = PROBEBAKE_SH_Y0;
  y[1] = PROBEBAKE_SH_Y1 * d.y;
  y[2] = PROBEBAKE_SH_Y1 * d.z;
  y[3] = PROBEBAKE_SH_Y1 * d.x;
  y[4] = PROBEBAKE_SH_Y2 * d.x * d.y;
  y[5] = PROBEBAKE_SH_Y2 * d.y * d.z;
  y[6] = PROBEBAKE_SH_Y20 * (3.0 * d.z * d.z - 1.0);
  y[7] = PROBEBAKE_SH_Y2 * d.x * d.z;
  y[8] = PROBEBAKE_SH_Y22 * (d.x * d.x - d.y * d.y);
}

#endif // PROBEBAKE_SH_GLSL
