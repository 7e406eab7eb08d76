#version 450 core
// Deep light map pass 2: the low-resolution light-aligned scatter map (Nes 2008 §5.3.3), built
// slice by slice along the light — one dispatch per slice, each reading the previous one:
//   P_k = P_{k−1}·[T + (1 − T)·CP(θ/4)] + avg4(I_c + P)_{k−1}·(1 − T)·(CP(θ/2) − CP(θ/4)),
// T = exp(−β̄·L_slice) with β̄ the mean of u_slice_samples samples evenly spaced between the two
// slices' centres (one, at the middle, for Nes' short slices; lighting::scatterSliceSamples), I_c the pass-1 DLM
// (central light) at the four neighbouring cells of the previous slice. Neighbours outside the
// map see unshadowed sunlight (I_c = 1, P = 0). See lighting/dlm_model.h.
#include "dlm/volume.glsl"
#include "dlm/light_space.glsl"
#include "dlm/lookup.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = IMAGE_SCATTER_MAP) uniform image3D u_scatter_img;
uniform ivec2 u_cells;
uniform float u_slice_m;
uniform int u_slice;                 // k ≥ 1; slice 0 is cleared to 0
uniform int u_slice_samples;         // β samples per slice (lighting::scatterSliceSamples)
uniform float u_central_fraction;    // CP(θ/4)
uniform float u_optical_depth_scale; // f(light): height exaggeration keeps the data's τ (VolumeFrame)
uniform float u_peripheral_fraction; // CP(θ/2) − CP(θ/4)

vec2 cellCentre(ivec2 cell) { return (vec2(cell) + 0.5) * (u_ls_texel_m * vec2(u_ls_texels)) / vec2(u_cells); }

float lightAt(ivec2 cell, int slice) {
  if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, u_cells))) return 1.0;
  float s = (float(slice) + 0.5) * u_slice_m;
  return dlmIntensityLight(vec3(cellCentre(cell), s)) + imageLoad(u_scatter_img, ivec3(cell, slice)).r;
}

void main() {
  ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(cell, u_cells))) return;
  int k = u_slice;
  // (the detail's noise prefiltered to a scatter cell: detail_field.glsl detailNoiseLod)
  vec2 cellSize = u_ls_texel_m * vec2(u_ls_texels) / vec2(u_cells);
  vec2 beta = vec2(0.0);
  for (int j = 0; j < u_slice_samples; ++j) {
    float at = float(k) + (float(j) + 0.5) / float(u_slice_samples) - 0.5;  // k for one sample
    beta += extinctionAtFootprint(worldFromLight(vec3(cellCentre(cell), at * u_slice_m)), min(cellSize.x, cellSize.y));
  }
  beta /= float(u_slice_samples);
  float T = exp(-(beta.x + beta.y) * u_optical_depth_scale * u_slice_m);
  float Pprev = imageLoad(u_scatter_img, ivec3(cell, k - 1)).r;
  float P = Pprev;
#ifdef DLM_BASELINE_NO_PRUNING
  int clear = 0;
#else
  // A clear cell (T = 1: β = 0 at its centre, most cells of a slice, whose plane crosses the
  // cloud layer in a strip) keeps P_k = P_{k−1} exactly — Pprev·(1 + 0·CP) + avg4·0 — so its four
  // look-ups of the neighbours' light (16 node-list scans) are not needed (issue 19). The update is
  // a loop of at most one pass rather than an if: llvmpipe runs 8 cells in lock-step and executes
  // both sides of a branch under a lane mask, but leaves a loop when no lane is left in it, so a
  // row of clear cells skips the look-ups (on a GPU, the same for a warp of clear cells).
  int clear = T < 1.0 ? 0 : 1;
#endif
  for (int update = clear; update < 1; ++update) {
    float around = 0.25 * (lightAt(cell + ivec2(1, 0), k - 1) + lightAt(cell - ivec2(1, 0), k - 1) +
                           lightAt(cell + ivec2(0, 1), k - 1) + lightAt(cell - ivec2(0, 1), k - 1));
    P = Pprev * (T + (1.0 - T) * u_central_fraction) + around * (1.0 - T) * u_peripheral_fraction;
  }
  imageStore(u_scatter_img, ivec3(cell, k), vec4(P));
}
