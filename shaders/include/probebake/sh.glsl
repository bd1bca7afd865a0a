// L2 spherical harmonics of irradiance, the convention of bake/include/probebake/bake/sampler.h (real SH,
// coefficient k = l^2 + l + m, irradiance_sh[3k + c], cosine lobe already convolved in). The order of the
// operations follows bake/src/lighting/stencil.h so that GPU and CPU results agree to rounding.
#ifndef PROBEBAKE_SH_GLSL
#define PROBEBAKE_SH_GLSL

const float PROBEBAKE_SH_Y0 = 0.282094792;  // 1 / (2 sqrt(pi))
const float PROBEBAKE_SH_Y1 = 0.488602512;  // sqrt(3 / (4 pi))
const float PROBEBAKE_SH_Y2 = 1.092548431;  // sqrt(15 / (4 pi))
const float PROBEBAKE_SH_Y20 = 0.315391565; // sqrt(5 / (16 pi))
const float PROBEBAKE_SH_Y22 = 0.546274215; // sqrt(15 / (16 pi))

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
