// The Monte Carlo radiance volume seen by the eye (issue 12, sixteenth session; built by
// glsl/dlm/radiance_volume.comp and resolved into seven RGBA32F textures, render/dlm/
// radiance_volume.h). The source function of the light the volume holds, scattered towards the eye
// at x in the direction ω (world, unit, towards the eye):
//   J(x, ω) = ∫ p(ω'·ω) L(x, ω') dω' = Σ_{l ≤ 4} G_l Σ_m c_lm(x) Y_lm(ω)
// by the Funk–Hecke theorem: the Henyey–Greenstein lobe's Legendre moments are g^l, so the eye's
// β-weighted mix has G_l = w·g_ice^l + (1 − w)·g_water^l (Nes 2008 eq. 5.12's mix; the CPU twin
// reference::McRadianceVolume::radianceAt, which is also where the clamp at 0 comes from: a series
// truncated at l = 4 rings below 0 where the light is peaked). c_lm(x) is trilinear between the
// cell centres (GL_LINEAR), held at the edge cells outside (GL_CLAMP_TO_EDGE), as the twin's
// momentsAt. Per unit solar irradiance [1/sr]: the eye pass multiplies by E. Seven fetches and the
// harmonics' recurrence per cloudy sample.
#include "common/spherical_harmonics.glsl"

layout(binding = UNIT_MC_MOMENTS) uniform sampler3D u_mc_moments[7];  // moment k: texture k/4, channel k mod 4
uniform vec3 u_mc_box_min_m;  // the volume's grid: its min corner (the extinction box's)
uniform vec3 u_mc_extent_m;   // and its size, cells × cell size (≥ the box: whole cells)

float radianceVolumeSource(vec3 world_m, vec3 toEye, float iceWeight, float gIce, float gWater) {
  vec3 uvw = (world_m - u_mc_box_min_m) / u_mc_extent_m;
  float y[25];
  shBasis4(toEye, y);
  float c[28];
  for (int t = 0; t < 7; ++t) {
    vec4 v = texture(u_mc_moments[t], uvw);
    c[4 * t] = v.x;
    c[4 * t + 1] = v.y;
    c[4 * t + 2] = v.z;
    c[4 * t + 3] = v.w;
  }
  float j = 0.0, gi = 1.0, gw = 1.0;
  for (int l = 0; l <= 4; ++l) {
    float s = 0.0;
    for (int k = l * l; k < (l + 1) * (l + 1); ++k) s += c[k] * y[k];
    j += (iceWeight * gi + (1.0 - iceWeight) * gw) * s;
    gi *= gIce;
    gw *= gWater;
  }
  return max(j, 0.0);
}
