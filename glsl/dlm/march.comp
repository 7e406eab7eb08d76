#version 450 core
// Deep light map passes 1 and 3 (Nes 2008 §5.3.2-5.3.3, Algorithm 3; model in lighting/dlm_model.h).
// One invocation per light-space texel marches its light ray at fixed steps Δ, integrating
// attenuation and central forward scattering (eq. 5.13),
//     I_{n+1} = I_n·[T + (1 − T)·CP(θ/4)],  T = exp(−β(s_n + Δ/2)·Δ),
// and, with PERIPHERAL defined (pass 3), adds the peripheral light P(s) of the scatter map
// before compressing — so the ε bound holds for the final function. The sum is clamped to 1:
// the model adds a cloud's peripheral share to its neighbours without removing it from the
// cloud's own central light, so a clear column beside a bright cloud edge could exceed the
// unobstructed sun (lighting/dlm_model.h). Empty occupancy bricks are
// skipped whole (I is constant there; in pass 3 the skip also stops at scatter-slice centres,
// where P has its breakpoints, so the compressor sees the same piecewise-linear function).
// Instead of copying render-target slices as Nes did on 2008 hardware, nodes are written with
// image stores into layers of a 3-D texture (GL 4.5 compute).
#include "dlm/volume.glsl"
#include "dlm/light_space.glsl"
#ifdef UNCOMPRESSED
// Benchmark baseline: a plain fixed-step light volume — every sample stored, no compression, no
// skipping (tests/bench/dlm_benchmark.cpp compares pass 1 against it).
layout(std430, binding = SSBO_LIGHT_VOLUME) writeonly buffer LightVolume { float u_light_volume[]; };  // [(n·nv + b)·nu + a]
#else
#include "dlm/compress.glsl"
#endif

layout(local_size_x = 8, local_size_y = 8) in;
layout(r32ui, binding = IMAGE_DLM_COUNTS) uniform uimage2D u_counts;  // count | DLM_COUNT_UNBOUNDED: bound not kept
layout(r32f, binding = IMAGE_DLM_TEXEL_EPSILON) uniform image2D u_texel_eps;  // ε this texel was compressed with
uniform float u_step_m;
uniform int u_steps;                 // N: samples n = 0 … N
uniform float u_central_fraction;    // CP(θ/4)
uniform float u_optical_depth_scale; // f(light): height exaggeration keeps the data's τ (VolumeFrame)
uniform bool u_skip_empty;
uniform bool u_only_overflowed;      // retry pass of the overflow rule

#ifdef PERIPHERAL
layout(binding = UNIT_SCATTER_MAP) uniform sampler3D u_scatter;  // P at scatter cell centres (pass 2)
uniform float u_scatter_slice_m;
uniform int u_scatter_slices;
uniform int u_slice_steps;
float peripheralAt(vec3 l) {
  vec3 uvw = vec3(l.xy / (u_ls_texel_m * vec2(u_ls_texels)), l.z / (u_scatter_slice_m * float(u_scatter_slices)));
  return texture(u_scatter, uvw).r;
}
#endif

#ifdef UNCOMPRESSED
void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, u_ls_texels))) return;
  vec3 start = worldFromLight(vec3((vec2(texel) + 0.5) * u_ls_texel_m, 0.0));
  float Ic = 1.0;
  int layer = u_ls_texels.x * u_ls_texels.y, idx = texel.y * u_ls_texels.x + texel.x;
  u_light_volume[idx] = Ic;
  for (int n = 0; n < u_steps; ++n) {
    vec2 beta = extinctionAt(start + (float(n) + 0.5) * u_step_m * u_ls_w);
    float T = exp(-(beta.x + beta.y) * u_optical_depth_scale * u_step_m);
    Ic *= T + (1.0 - T) * u_central_fraction;
    u_light_volume[(n + 1) * layer + idx] = Ic;
  }
}
#else
void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(texel, u_ls_texels))) return;
  if (u_only_overflowed && (imageLoad(u_counts, texel).r & DLM_COUNT_UNBOUNDED) == 0u) return;

  vec2 uv = (vec2(texel) + 0.5) * u_ls_texel_m;
  vec3 start = worldFromLight(vec3(uv, 0.0));
  float Ic = 1.0;  // central light, I_0 = 1
#ifdef PERIPHERAL
  Compressor c = startCompressor(texel, 0.0, min(Ic + peripheralAt(vec3(uv, 0.0)), 1.0));
#else
  Compressor c = startCompressor(texel, 0.0, Ic);
#endif
  int n = 0;
  while (n < u_steps) {
    float s = float(n) * u_step_m;
    vec3 p = start + s * u_ls_w;
    if (u_skip_empty && brickMaxAt(p + 0.5 * u_step_m * u_ls_w) == 0.0) {
      // Jump to the first lattice sample at or past the brick exit: every step in between has
      // β = 0 (the brick max is dilated by the filter's reach), so Ic is unchanged.
      float exit = s + 0.5 * u_step_m + emptySkipDistance(p + 0.5 * u_step_m * u_ls_w, u_ls_w);
      int target = clamp(int(min(ceil(exit / u_step_m), float(u_steps))), n + 1, u_steps);
#ifdef PERIPHERAL
      // P is linear in s between scatter-slice centres (k + ½)·S·Δ (S even): stop at the next one.
      int halfSlice = u_slice_steps / 2;
      int nextBreak = n < halfSlice ? halfSlice : ((n - halfSlice) / u_slice_steps + 1) * u_slice_steps + halfSlice;
      target = min(target, nextBreak);
#endif
      if (target > n + 1) {
        // Both ends of the run are samples: the function is linear in between (constant Ic, linear
        // P), so the compressor's bound at the pushed samples covers the skipped ones.
        n = target - 1;
        s = float(n) * u_step_m;
        p = start + s * u_ls_w;
#ifdef PERIPHERAL
        pushSample(c, s, min(Ic + peripheralAt(vec3(uv, s)), 1.0));
#else
        pushSample(c, s, Ic);
#endif
      }
    }
    vec2 beta = extinctionAt(p + 0.5 * u_step_m * u_ls_w);
    float T = exp(-(beta.x + beta.y) * u_optical_depth_scale * u_step_m);
    Ic *= T + (1.0 - T) * u_central_fraction;
    n++;
    float sn = float(n) * u_step_m;
#ifdef PERIPHERAL
    pushSample(c, sn, min(Ic + peripheralAt(vec3(uv, sn)), 1.0));
#else
    pushSample(c, sn, Ic);
#endif
  }
  int count = finishCompressor(c);
  imageStore(u_counts, texel, uvec4(uint(count) | (c.overflow ? DLM_COUNT_UNBOUNDED : 0u)));
  imageStore(u_texel_eps, texel, vec4(u_epsilon));
}
#endif
