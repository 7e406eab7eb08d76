// Extinction volumes (Nes 2008 §5.2.1): ice and water β_ext [1/m] as 3-D textures (GL_LINEAR,
// GL_CLAMP_TO_BORDER, border 0), reconstructed by the filter u_reconstruction names
// (volume/reconstruction.h): trilinear between voxel centres, or the tricubic B-spline from 8
// trilinear fetches (Sigg & Hadwiger 2005, GPU Gems 2 ch. 20). The CPU twin is
// volume/extinction_sampler.cpp. β is continuous everywhere: it fades to 0 outside the box (over
// ½ voxel trilinear, 1½ voxels cubic) instead of jumping at the face, so a ray skimming a face
// cannot flip between "cloud" and "clear" on float rounding.
//
// Sub-grid detail (issue 13; volume/detail.h, glsl/common/detail.glsl, detail_field.glsl): with
// u_detail ≠ 0, extinctionAt returns the detailed field β(x + d)·ρ(x + d)·s, d and ρ from the noise
// tile (generated once by glsl/render/noise.comp) addressed in world metres and the RGBA8 controls at
// data resolution, times the per-column mass correction (constant per column); the noise is
// advected with the horizontal model wind between timesteps (u_detail_wind, u_detail_flow) and read
// prefiltered to a footprint (extinctionAtFootprint; its mipmap chain, render/dlm/noise_texture.cpp). u_reach_voxels
// then includes the displacement's reach and the occupancy maxima are × 2·max c (ρ ≤ 2), so
// empty-space skipping stays conservative.
#include "common/math.glsl"
#include "common/ray_box.glsl"
#include "common/detail.glsl"
#include "common/cubic_bspline.glsl"
layout(binding = UNIT_ICE_PER_M) uniform sampler3D u_ice_per_m;
layout(binding = UNIT_WATER_PER_M) uniform sampler3D u_water_per_m;
layout(binding = UNIT_OCCUPANCY_PER_M) uniform sampler3D u_occupancy_per_m;  // per brick: max β (dilated by u_reach_voxels), a lower bound of β (volume/occupancy.h)
layout(binding = UNIT_DETAIL_CONTROLS) uniform sampler3D u_detail_controls;  // RGBA8 (turbulence, convective, fraction, core)
layout(binding = UNIT_DETAIL_NOISE) uniform sampler3D u_detail_noise;        // RGBA8 periodic noise tile, GL_REPEAT
// Per model column (render/dlm/volume_textures.cpp): r the detail's mass correction (texelFetch),
// g the column's total optical depth T (bilinear, clamped to the edge; volume/column_depth.h).
layout(binding = UNIT_COLUMNS) uniform sampler2D u_columns;
// The vertical optical depth above each voxel centre, τ_up (R16F where the packed texture is the
// only copy, else RG16F (τ_up, T)), GL_LINEAR, GL_CLAMP_TO_EDGE (volume/column_depth.h).
layout(binding = UNIT_COLUMN_DEPTH) uniform sampler3D u_column_depth;
layout(binding = UNIT_DETAIL_WIND) uniform sampler3D u_detail_wind;  // RG32F horizontal wind [m/s] advecting the noise
// The packed texture (issue 19; render/dlm/volume_textures.h hasPacked): RG16F (β_ice, β_water in
// units of u_packed_beta_unit_per_m) per voxel, GL_LINEAR, GL_CLAMP_TO_EDGE. With u_packed_only
// (VolumeStorage::Compact, the default upload) it is the only copy of the volume: every pass reads
// β (plainExtinctionAt) from it and the eye pass its column depths from u_column_depth (τ_up) and
// u_columns (T): 6 bytes per voxel (RGB16F would be padded to 8 by the drivers).
layout(binding = UNIT_PACKED_VOLUME) uniform sampler3D u_packed_volume;
// One std140 block, declared in C++ as gl::VolumeBlock (render/gl/uniform_blocks.h): keep the
// members in its order; the GL test UniformBlocks.MatchTheLinkedPrograms checks every offset.
layout(std140, binding = UBO_VOLUME) uniform VolumeBlock {
  vec3 u_box_min_m;      // world AABB of the volume
  int u_brick_voxels;
  vec3 u_box_size_m;
  bool u_has_ice;        // absent phases are never fetched
  ivec3 u_voxels;
  bool u_has_water;
  int u_reconstruction;  // 0 trilinear, 1 cubic B-spline
  float u_reach_voxels;  // voxels a sample reads past its own cell: 1 trilinear, 2 cubic (+ the detail's reach)
  int u_detail;          // 0 none, 1 subtle, 2 full (volume/detail.h)
  float u_detail_amplitude;
  vec3 u_noise_period_m;  // world metres per noise tile
  float u_packed_beta_unit_per_m;  // β's unit in u_packed_volume [1/m] (0: no packed texture)
  vec3 u_displacement_m;  // displacement cap per axis [world m]
  bool u_packed_only;     // β and the column depths exist only in u_packed_volume (no R32F/RG16F copies)
  vec4 u_noise_stats_ra;  // (mean, half range) of noise channels r and a
  vec4 u_noise_stats_gs;  // of channel g and of the stratiform term
  vec4 u_noise_stats_c;   // of the convective term
  vec4 u_detail_flow;     // (τ_a, τ_b [s], phase a's weight, 1 with a wind): the noise's advection (volume/detail.h)
};

// Compile-time specialisation (issue 19, "Frame time"): llvmpipe runs 8 lanes in lock-step and a
// uniform branch still costs its test and keeps both sides' registers alive, so a program built
// with SPEC_DETAIL / SPEC_CUBIC defined (0 or 1; render/raycast/cloud_renderer.cpp
// EyePassFeatures) has these switches as constants and the compiler drops the dead side. Without
// the defines (the DLM passes, the tests' and benchmarks' baseline) the uniforms decide, as before.
// The values must agree with the block's (u_detail, u_reconstruction): same arithmetic either way.
#ifdef SPEC_DETAIL
#define DETAIL_ON (SPEC_DETAIL != 0)
#else
#define DETAIL_ON (u_detail != 0)
#endif
// Whether the detail's noise is advected (the data has U, V; glsl/common/detail_field.glsl): in
// still air one noise read per frame serves both flow phases.
#ifdef SPEC_DETAIL_WIND
#define DETAIL_WIND_ON (SPEC_DETAIL_WIND != 0)
#else
#define DETAIL_WIND_ON (u_detail_flow.w != 0.0)
#endif
#ifdef SPEC_CUBIC
#define RECONSTRUCTION_CUBIC (SPEC_CUBIC != 0)
#else
#define RECONSTRUCTION_CUBIC (u_reconstruction == 1)
#endif

vec3 volumeUvw(vec3 world_m) { return (world_m - u_box_min_m) / u_box_size_m; }

bool insideVolume(vec3 uvw) { return all(greaterThanEqual(uvw, vec3(0.0))) && all(lessThanEqual(uvw, vec3(1.0))); }

// How far the grown box reaches past the volume box on each side [world m]: the filter's reach.
vec3 volumePad_m() { return u_reach_voxels * u_box_size_m / vec3(u_voxels); }

// The volume box grown by the filter's reach: β is exactly 0 beyond it.
bool insideGrownVolume(vec3 uvw) {
  vec3 pad = u_reach_voxels / vec3(u_voxels);
  return all(greaterThanEqual(uvw, -pad)) && all(lessThanEqual(uvw, 1.0 + pad));
}

// Tricubic B-spline of one volume at uvw from 8 trilinear fetches (Sigg & Hadwiger 2005, §20.3):
// per axis, the four B-spline weights of the voxels i−1 … i+2 around the sample are merged
// pairwise into two linear fetches at i−1 + h0 and i+1 + h1 (voxel-centre index units) weighted
// g0 and g1 (glsl/common/cubic_bspline.glsl cubicBSplineFetches, whose weights the CPU's 64-weight
// sum uses too). Voxels outside the grid read the texture's border rule: 0 for the extinction
// volumes (zero border, as in the CPU sum), the edge voxel for the column depths (clamp to edge).
// All channels are filtered (the column depths' (τ_up, τ_down) pair shares one set of fetches);
// the texture must have the extinction volumes' dimensions u_voxels.
vec4 cubicBSplineRgba(sampler3D volume, vec3 uvw) {
  vec3 n = vec3(u_voxels);
  vec3 c = uvw * n - 0.5;  // continuous index, voxel centres at integers
  vec3 i = floor(c);
  vec3 f = c - i;
  vec4 ax = cubicBSplineFetches(f.x), ay = cubicBSplineFetches(f.y), az = cubicBSplineFetches(f.z);
  vec3 g0 = vec3(ax.x, ay.x, az.x), g1 = vec3(ax.y, ay.y, az.y);
  vec3 p0 = (i - 0.5 + vec3(ax.z, ay.z, az.z)) / n;  // (index + ½) / n is the texture coordinate of a voxel centre
  vec3 p1 = (i + 1.5 + vec3(ax.w, ay.w, az.w)) / n;
  vec4 s000 = texture(volume, p0), s100 = texture(volume, vec3(p1.x, p0.y, p0.z));
  vec4 s010 = texture(volume, vec3(p0.x, p1.y, p0.z)), s110 = texture(volume, vec3(p1.x, p1.y, p0.z));
  vec4 s001 = texture(volume, vec3(p0.x, p0.y, p1.z)), s101 = texture(volume, vec3(p1.x, p0.y, p1.z));
  vec4 s011 = texture(volume, vec3(p0.x, p1.y, p1.z)), s111 = texture(volume, p1);
  vec4 z0 = g0.y * (g0.x * s000 + g1.x * s100) + g1.y * (g0.x * s010 + g1.x * s110);
  vec4 z1 = g0.y * (g0.x * s001 + g1.x * s101) + g1.y * (g0.x * s011 + g1.x * s111);
  return g0.z * z0 + g1.z * z1;
}

float cubicBSpline(sampler3D volume, vec3 uvw) { return cubicBSplineRgba(volume, uvw).r; }

float reconstruct(sampler3D volume, vec3 uvw) {
  return RECONSTRUCTION_CUBIC ? cubicBSpline(volume, uvw) : texture(volume, uvw).r;
}

// (β_ice, β_water) of the packed texture at uvw (inside the grown box) in 1/m: the texture clamps
// to the edge, as the column depths need; the extinction's zero border (β fades to 0 over the ½
// voxel outside the box, as GL_CLAMP_TO_BORDER with a zero border gives the R32F textures) is the
// trilinear filter's weight on the texels inside the grid, per axis 1 + min(c, n − 1 − c) clamped
// to [0, 1] for the continuous index c = uvw·n − ½, multiplied onto β. Only the trilinear filter
// has a packed texture (the cubic B-spline reads the zero border at 8 positions).
vec2 packedBeta(vec3 uvw) {
  vec2 s = texture(u_packed_volume, uvw).xy;
  vec3 c = uvw * vec3(u_voxels) - 0.5;
  vec3 inGrid = clamp(1.0 + min(c, vec3(u_voxels) - 1.0 - c), 0.0, 1.0);
  return s * (u_packed_beta_unit_per_m * inGrid.x * inGrid.y * inGrid.z);
}

// (τ_up, τ_down) trilinearly at uvw, clamped to the edge: τ_up from u_column_depth, τ_down = T − τ_up
// with T bilinear from u_columns (the CPU twin: volume/column_depth.h columnDepthAt).
vec2 trilinearColumnDepth(vec3 uvw) {
  float up = texture(u_column_depth, uvw).r;
  return vec2(up, texture(u_columns, uvw.xy).g - up);
}

// (β_ice, β_water, τ_up, τ_down) at uvw: the eye pass's step with the packed texture.
vec4 packedTexel(vec3 uvw) { return vec4(packedBeta(uvw), trilinearColumnDepth(uvw)); }

// (β_ice, β_water) at a world position, without the sub-grid detail.
vec2 plainExtinctionAt(vec3 world_m) {
  vec3 uvw = volumeUvw(world_m);
  if (!insideGrownVolume(uvw)) return vec2(0.0);
  if (u_packed_only) return packedBeta(uvw);
  // ≥ 0: the interpolating spline's coefficients ring below 0 at cloud edges (volume/spline_coefficients.h).
  return max(vec2(u_has_ice ? reconstruct(u_ice_per_m, uvw) : 0.0, u_has_water ? reconstruct(u_water_per_m, uvw) : 0.0),
             vec2(0.0));
}

// The primitives glsl/common/detail_field.glsl reads the volume through (its CPU twin defines the
// same on the voxels: volume/extinction_sampler.cpp).
vec4 detailControlsAt(vec3 uvw) { return texture(u_detail_controls, uvw); }
vec4 detailNoiseAt(vec3 q, float lod) { return textureLod(u_detail_noise, q, lod); }
float columnExtinctionAt(vec2 column_uv, float w) {
  vec3 t = vec3(column_uv, w);
  return (u_has_ice ? texture(u_ice_per_m, t).r : 0.0) + (u_has_water ? texture(u_water_per_m, t).r : 0.0);
}
float detailCorrectionTexel(ivec2 column) {
  return texelFetch(u_columns, clamp(column, ivec2(0), textureSize(u_columns, 0) - 1), 0).r;
}
vec2 detailWindAt(vec3 uvw) { return texture(u_detail_wind, uvw).rg; }
#include "common/detail_field.glsl"

// (β_ice, β_water) at a world position: the field every pass integrates (the detailed field of
// glsl/common/detail_field.glsl when the detail is on). The CPU twin is ExtinctionSampler::at.
// `footprint_m`: the width of the ray there (the eye pass: distance × the angle between
// neighbouring pixels' rays; the DLM: a map texel); the detail's noise is read prefiltered to it
// (detail_field.glsl detailNoiseLod), 0 reads it at full resolution.
vec2 extinctionAtFootprint(vec3 world_m, float footprint_m) {
  if (!DETAIL_ON) return plainExtinctionAt(world_m);
  return detailedExtinctionAt(world_m, footprint_m);
}

vec2 extinctionAt(vec3 world_m) { return extinctionAtFootprint(world_m, 0.0); }

// Max β of the occupancy brick containing `world_m`; in the shell around the box (the filter's
// reach), that of the nearest edge brick (whose dilated max bounds the fading shell); 0 beyond.
float brickMaxAt(vec3 world_m) {
  vec3 uvw = volumeUvw(world_m);
  if (!insideGrownVolume(uvw)) return 0.0;
  ivec3 voxel = clamp(ivec3(floor(uvw * vec3(u_voxels))), ivec3(0), u_voxels - 1);
  return texelFetch(u_occupancy_per_m, voxel / u_brick_voxels, 0).r;
}

// (max, lower bound) of β in the occupancy brick containing `world_m`, which must be inside the
// volume (volume/occupancy.h; the bound is 0 where the filter or the detail allows none).
vec2 brickRangeAt(vec3 world_m) {
  ivec3 voxel = clamp(ivec3(floor(volumeUvw(world_m) * vec3(u_voxels))), ivec3(0), u_voxels - 1);
  return texelFetch(u_occupancy_per_m, voxel / u_brick_voxels, 0).rg;
}

// Distance along `dir` from `world_m` (inside the volume) to the exit of its occupancy brick.
float brickExitDistance(vec3 world_m, vec3 dir) {
  vec3 voxelSize = u_box_size_m / vec3(u_voxels);
  vec3 brickSize = voxelSize * float(u_brick_voxels);
  vec3 rel = world_m - u_box_min_m;
  vec3 brickMin = floor(rel / brickSize) * brickSize;
  vec3 brickMax = min(brickMin + brickSize, u_box_size_m);
  vec3 safeDir = safeDirection(dir);
  vec3 t = mix((brickMin - rel) / safeDir, (brickMax - rel) / safeDir, greaterThan(dir, vec3(0.0)));
  t = mix(t, vec3(kNeverExit_m), equal(dir, vec3(0.0)));
  return max(min(t.x, min(t.y, t.z)), 0.0);
}

// Distance along `dir` over which a ray from `world_m` stays in empty space, given that the
// occupancy at `world_m` is 0: to the exit of its brick inside the volume; 0 in the shell of the
// filter's reach (no skipping there); beyond the shell, to the grown box's entry (kNeverExit_m
// when missed).
float emptySkipDistance(vec3 world_m, vec3 dir) {
  vec3 uvw = volumeUvw(world_m);
  if (insideVolume(uvw)) return brickExitDistance(world_m, dir);
  if (insideGrownVolume(uvw)) return 0.0;
  vec3 pad = volumePad_m();
  vec3 safeDir = safeDirection(dir);
  vec2 t = slabInterval((u_box_min_m - pad - world_m) / safeDir, (u_box_min_m + u_box_size_m + pad - world_m) / safeDir);
  if (t.y < max(t.x, 0.0)) return kNeverExit_m;
  return max(t.x, 0.0);
}
