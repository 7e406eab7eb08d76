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
//
// Adaptive step (issue 19, u_step_growth > 1): where the occupancy brick bounds β to a narrow range
// [min, max] the march takes m ≤ u_step_growth fine steps at once, with β at the run's midpoint;
// it pushes every fine sample to the compressor all the same (Ic·f^j, P linear between the
// scatter-slice centres, which a run never crosses), so the compressor sees the same lattice and
// its ε bound (Nes 2008 §5.3.4, §5.4) holds for what it is given. That differs from the fine
// march only through β: both products over the run lie in [I·f(max)^m, I·f(min)^m], so a run
// moves I by at most I·m·(f(min) − f(max)) (a^j − b^j ≤ j·(a − b)), and an earlier difference is
// only ever multiplied by factors ≤ 1 afterwards. A run is taken only while the sum of these
// bounds along the ray stays within u_growth_budget, so every sample is within that budget of
// the fixed step's (up to β's half-float rounding): the stored function within ε + budget of it.
// Near cloud edges (min 0 in the brick or a neighbour) and in varying cloud the bound is large
// and the march stays fine; in clear bricks the empty-space skip above already jumps.
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
// The detail's noise is read prefiltered to a map texel (glsl/common/detail_field.glsl
// detailNoiseLod): a texel's ray stands for its whole texel, and octaves finer than it would only
// alias into texel-to-texel streaks of light and shadow.
float dlmTexelFootprint() { return min(u_ls_texel_m.x, u_ls_texel_m.y); }
uniform int u_steps;                 // N: samples n = 0 … N
uniform float u_central_fraction;    // CP(θ/4)
uniform float u_optical_depth_scale; // f(light): height exaggeration keeps the data's τ (VolumeFrame)
uniform bool u_skip_empty;
uniform bool u_only_overflowed;      // retry pass of the overflow rule
uniform int u_step_growth;           // adaptive step: at most this many Δ per run (1: fixed step)
// Counts for DlmStats (issue 19): fine steps marched outside the empty-space skip, those of them
// in runs of m ≥ 2, and the runs — one atomic add each per texel.
// u_cut_short: texels whose march ended before u_steps — the driver's loop limiter (llvmpipe ends
// a shader's loops after 65 535 iterations per SIMD group; docs/rendering.md "llvmpipe's loop
// limit"); the light function beyond the cut is missing. Counted, never silent.
layout(std430, binding = SSBO_DLM_MARCH_STATS) buffer MarchStats { uint u_marched_steps, u_run_steps, u_runs, u_cut_short; };
uniform float u_growth_budget;       // the bound of the adaptive step's difference per ray (above)
// The overflow rule without a read-back (issue 19, "stats read-back optional in the per-frame
// path"; render/dlm/deep_light_map.cpp): a texel that ends over its node budget sets the group
// count x of the next retry's indirect dispatch (slot u_retry_slot, 3 uints: x, y, z; x starts at
// 0), so a retry that nothing needs dispatches no group and the host never waits to find out.
// u_retry_slot < 0: the host reads the counts back instead (the default, with statistics).
layout(std430, binding = SSBO_DLM_RETRY_ARGS) buffer RetryArgs { uint u_retry_args[]; };
uniform int u_retry_slot;
uniform int u_retry_groups_x;        // the retry's group count across the texels

// The step factor T + (1 − T)·CP(θ/4) of one fine step Δ through extinction β.
float stepFactor(float beta) {
  float T = exp(-beta * u_optical_depth_scale * u_step_m);
  return T + (1.0 - T) * u_central_fraction;
}

#ifdef PERIPHERAL
layout(binding = UNIT_SCATTER_MAP) uniform sampler3D u_scatter;  // P at scatter cell centres (pass 2)
uniform float u_scatter_slice_m;
uniform int u_scatter_slices;
uniform int u_slice_steps;
float peripheralAt(vec3 l) {
  vec3 uvw = vec3(l.xy / (u_ls_texel_m * vec2(u_ls_texels)), l.z / (u_scatter_slice_m * float(u_scatter_slices)));
  return texture(u_scatter, uvw).r;
}
#ifndef DLM_BASELINE_SLICE_BREAKS
// Flat runs of the scatter map (issue 19; glsl/dlm/scatter_runs.comp): R[k] per cell column.
layout(binding = UNIT_SCATTER_RUNS) uniform isampler3D u_scatter_runs;
// The four cell columns the bilinear fetch at this texel's u, v blends (GL_CLAMP_TO_EDGE).
ivec4 scatterColumns(vec2 uv) {
  ivec2 cells = textureSize(u_scatter_runs, 0).xy;
  vec2 x = uv / (u_ls_texel_m * vec2(u_ls_texels)) * vec2(cells) - 0.5;
  ivec2 i0 = clamp(ivec2(floor(x)), ivec2(0), cells - 1);
  ivec2 i1 = clamp(ivec2(floor(x)) + 1, ivec2(0), cells - 1);
  return ivec4(i0, i1);
}
// The last slice k ≥ the one at step n such that P along this texel's ray is the same on every
// slice from there to k in all four columns: P(s) is then constant from step n to k's centre.
int flatUntilSlice(ivec4 columns, int n) {
  int k0 = clamp(n / u_slice_steps - (n % u_slice_steps < u_slice_steps / 2 ? 1 : 0), 0, u_scatter_slices - 1);
  int r = min(min(texelFetch(u_scatter_runs, ivec3(columns.xy, k0), 0).r,
                  texelFetch(u_scatter_runs, ivec3(columns.zy, k0), 0).r),
              min(texelFetch(u_scatter_runs, ivec3(columns.xw, k0), 0).r,
                  texelFetch(u_scatter_runs, ivec3(columns.zw, k0), 0).r));
  return r - 1;
}
#endif
#endif

#if !defined(PERIPHERAL) && !defined(UNCOMPRESSED)
// Pass 1 marches only the texels pass 2 reads (issue 19, "nothing computed that a scene does not
// need"). With the scatter map on, pass 1's map has one reader: pass 2 (scatter.comp), which looks
// the central light up at its cell centres, t_c = (c + ½)·n/cells − ½ in texel units along each
// axis, by the bilinear blend of glsl/common/light_blend.glsl — texels floor(t_c) and floor(t_c) + 1.
// Pass 3 clears the counts and re-marches every texel with P added, so no other texel of pass 1 is
// ever read: at 4 × 4 texels per cell, 2 of every 4 texel rows and columns, ¼ of the texels.
// The invocations are compacted — u_pass1_slots per cell and axis, slot k marching texel
// floor(t_c − m) + k — so that the 8 lanes llvmpipe runs in lock-step are 8 needed texels rather
// than a row of the map with every other pair idle. The margin m = kReadMargin [texels] covers the
// float rounding of t_c here and in pass 2: a centre within m of an integer may floor either way
// there, so it takes a third slot (DeepLightMap::build sets u_pass1_slots = 3 on such an axis).
// u_pass1_cells = (0, 0): every texel, one invocation each (no scatter map; DlmBaseline::no_pruning).
uniform ivec2 u_pass1_cells;
uniform ivec2 u_pass1_slots;
const float kReadMargin = 0.01;  // render/dlm/deep_light_map.cpp kPassOneReadMargin
// The texel (of n along one axis) that compacted invocation i marches, −1 for none.
int passOneTexel(int i, int n, int cells, int slots) {
  int c = i / slots, slot = i - c * slots;
  if (c >= cells) return -1;
  float t = (float(c) + 0.5) * (float(n) / float(cells)) - 0.5;
  int lo = int(floor(t - kReadMargin));
  if (slot == 2 && int(floor(t + kReadMargin)) == lo) return -1;
  int a = lo + slot;
  return a >= 0 && a < n ? a : -1;
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
    vec2 beta = extinctionAtFootprint(start + (float(n) + 0.5) * u_step_m * u_ls_w, dlmTexelFootprint());
    float T = exp(-(beta.x + beta.y) * u_optical_depth_scale * u_step_m);
    Ic *= T + (1.0 - T) * u_central_fraction;
    u_light_volume[(n + 1) * layer + idx] = Ic;
  }
}
#else
void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
#ifndef PERIPHERAL
  if (u_pass1_cells.x > 0) {  // the texels pass 2 reads; the others keep count 0 (cleared)
    texel = ivec2(passOneTexel(texel.x, u_ls_texels.x, u_pass1_cells.x, u_pass1_slots.x),
                  passOneTexel(texel.y, u_ls_texels.y, u_pass1_cells.y, u_pass1_slots.y));
    if (any(lessThan(texel, ivec2(0)))) return;
  }
#endif
  if (any(greaterThanEqual(texel, u_ls_texels))) return;
  if (u_only_overflowed && (imageLoad(u_counts, texel).r & DLM_COUNT_UNBOUNDED) == 0u) return;

  vec2 uv = (vec2(texel) + 0.5) * u_ls_texel_m;
  vec3 start = worldFromLight(vec3(uv, 0.0));
  float Ic = 1.0;  // central light, I_0 = 1
#ifdef PERIPHERAL
  float Pcur = peripheralAt(vec3(uv, 0.0));  // P at the last pushed sample
  Compressor c = startCompressor(texel, 0.0, min(Ic + Pcur, 1.0));
#else
  Compressor c = startCompressor(texel, 0.0, Ic);
#endif
#if defined(PERIPHERAL) && !defined(DLM_BASELINE_SLICE_BREAKS)
  ivec4 columns = scatterColumns(uv);
#endif
  float spent = 0.0;  // the adaptive step's bounds so far (u_growth_budget)
  int marched = 0, inRuns = 0, runs = 0;
  int n = 0;
  while (n < u_steps) {
    float s = float(n) * u_step_m;
    vec3 p = start + s * u_ls_w;
    bool empty = u_skip_empty && brickMaxAt(p + 0.5 * u_step_m * u_ls_w) == 0.0;
#ifdef DLM_BASELINE_NO_PRUNING
    if (empty) {
#else
    // The skip as a loop of at most one pass (issue 19), not an if: llvmpipe runs 8 texels in
    // lock-step and evaluates both sides of a branch under a lane mask, so inside the cloud every
    // step paid for the skip's brick exit, slice breaks and extra sample; a loop is left when no
    // lane is in it. Same arithmetic, same map bit for bit (DlmBaseline::no_pruning).
    for (int skip = empty ? 0 : 1; skip < 1; ++skip) {
#endif
      // Jump to the first lattice sample at or past the brick exit: every step in between has
      // β = 0 (the brick max is dilated by the filter's reach), so Ic is unchanged.
      float exit = s + 0.5 * u_step_m + emptySkipDistance(p + 0.5 * u_step_m * u_ls_w, u_ls_w);
      int target = clamp(int(min(ceil(exit / u_step_m), float(u_steps))), n + 1, u_steps);
#ifdef PERIPHERAL
      // P is linear in s between scatter-slice centres (k + ½)·S·Δ (S even): stop at the next one.
      int halfSlice = u_slice_steps / 2;
      int nextBreak = n < halfSlice ? halfSlice : ((n - halfSlice) / u_slice_steps + 1) * u_slice_steps + halfSlice;
#ifndef DLM_BASELINE_SLICE_BREAKS
      // Issue 19: where P is flat (the same on the slices ahead in all four columns the fetch
      // blends) the centres in between are no breakpoints: P is constant up to the centre of the
      // last flat slice, which is the next sample the function needs.
      nextBreak = max(nextBreak, flatUntilSlice(columns, n) * u_slice_steps + halfSlice);
#endif
      target = min(target, nextBreak);
      // Ic + P is linear up to the run's last sample, but the map stores min(Ic + P, 1): where the
      // sum crosses 1 inside the run the chord would cut the corner (by up to half the run's rise
      // in P; with scatter slices a cell wide, 0.037 on the hurricane, DlmReferenceTest). End the
      // run at the first lattice sample past the crossing: within one step of the kink.
      if (target > n + 2) {
        float a = Ic + Pcur - 1.0;
        float b = Ic + peripheralAt(vec3(uv, float(target - 1) * u_step_m)) - 1.0;
        if ((a < 0.0) != (b < 0.0)) {
          int cross = n + int(ceil(a / (a - b) * float(target - 1 - n)));
          target = clamp(cross + 1, n + 2, target);
        }
      }
#endif
      if (target > n + 1) {
        // Both ends of the run are samples: the function is linear in between (constant Ic, linear
        // P), so the compressor's bound at the pushed samples covers the skipped ones.
        n = target - 1;
        s = float(n) * u_step_m;
        p = start + s * u_ls_w;
#ifdef PERIPHERAL
        Pcur = peripheralAt(vec3(uv, s));
        pushSample(c, s, min(Ic + Pcur, 1.0));
#else
        pushSample(c, s, Ic);
#endif
      }
    }
    // The run: m fine steps from n (1 unless the adaptive step may grow here; header).
    int m = 1;
    if (u_step_growth > 1) {
      int end = min(n + u_step_growth, u_steps);
#ifdef PERIPHERAL
      // P is linear in s between scatter-slice centres: a run ends at the next one.
      int halfS = u_slice_steps / 2;
      end = min(end, n < halfS ? halfS : ((n - halfS) / u_slice_steps + 1) * u_slice_steps + halfS);
#endif
      vec3 q = p + 0.5 * u_step_m * u_ls_w;  // the first fine step's midpoint
      if (end - n >= 2 && insideVolume(volumeUvw(q))) {
        // Every fine midpoint q + jΔ (j < m) inside q's brick, whose range bounds their β.
        end = min(end, n + 1 + int(floor(brickExitDistance(q, u_ls_w) / u_step_m - 1e-3)));
        vec2 range = brickRangeAt(q);
        float bound = Ic * float(end - n) * (stepFactor(range.y) - stepFactor(range.x));
        if (end - n >= 2 && spent + bound <= u_growth_budget) {
          m = end - n;
          spent += bound;
        }
      }
    }
    vec2 beta = extinctionAtFootprint(p + 0.5 * float(m) * u_step_m * u_ls_w, dlmTexelFootprint());
    float f = stepFactor(beta.x + beta.y);
#ifdef PERIPHERAL
    float Pend = peripheralAt(vec3(uv, float(n + m) * u_step_m));
#endif
    for (int j = 1; j <= m; ++j) {
      Ic *= f;
      float sj = float(n + j) * u_step_m;
#ifdef PERIPHERAL
      pushSample(c, sj, min(Ic + (j == m ? Pend : mix(Pcur, Pend, float(j) / float(m))), 1.0));
#else
      pushSample(c, sj, Ic);
#endif
    }
    n += m;
    marched += m;
    inRuns += m > 1 ? m : 0;
    runs += m > 1 ? 1 : 0;
#ifdef PERIPHERAL
    Pcur = Pend;
#endif
  }
  if (n < u_steps) atomicAdd(u_cut_short, 1u);  // the loop exits only through its condition
  atomicAdd(u_marched_steps, uint(marched));
  atomicAdd(u_run_steps, uint(inRuns));
  atomicAdd(u_runs, uint(runs));
  int count = finishCompressor(c);
  if (c.overflow && u_retry_slot >= 0) atomicMax(u_retry_args[3 * u_retry_slot], uint(u_retry_groups_x));
  imageStore(u_counts, texel, uvec4(uint(count) | (c.overflow ? DLM_COUNT_UNBOUNDED : 0u)));
  imageStore(u_texel_eps, texel, vec4(u_epsilon));
}
#endif
