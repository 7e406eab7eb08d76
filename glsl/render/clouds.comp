#version 450 core
// Cloud ray caster and compositor (Nes 2008 §5.4, eq. 5.18; Muth 2026 §3.4; issue 12).
// One invocation per pixel: the view ray marches the ice and water extinction volumes front to
// back with step Δ from a jittered start (against banding), skipping empty occupancy bricks,
// stopping when the transmittance falls below u_min_transmittance. Each step scatters the
// fraction (1 − T) of the light it receives towards the eye (single-scattering albedo 1):
//   C += T_acc · (1 − T) · L_s,   T_acc *= T,
//   L_s = E_sun · F(I_DLM, ψ) + L_sky · T_d(τ_up) / 2 + L_below · T_d(τ_down) / 2
// Units and conventions: docs/rendering.md "Conventions" (issue 12). E_sun is the sun's irradiance,
// F single scattering E·p_v(ψ)·I_DLM (p_v the β-weighted ice/water Henyey–Greenstein mix, Nes eq.
// 5.12) plus the multiple-scattering term of u_cloud_ms_model [1/sr] (glsl/common/
// cloud_light.glsl cloudSunFactor: the octave series, or by default the column's two-stream
// diffuse light from the column depths), I_DLM the deep light map's sunlight (glsl/dlm/lookup.glsl,
// or its light cache: sampleSunlight below). The sky light:
// the upper hemisphere's clear-sky radiance L_sky reaches the sample through the cloud column
// above it, the lower hemisphere's L_below (ground-reflected light) through the column below, each
// attenuated by the two-stream diffuse transmittance T_d of that column's vertical optical depth
// (volume/column_depth.h), and scattered isotropically on average (½ each hemisphere).
// Height exaggeration keeps the data's optical depth: β is scaled by f(d) = |(d_x, d_y, d_z/e)|
// along the ray (volume::VolumeFrame::opticalDepthScale). Early termination renormalises: a ray
// stopped at T_acc < u_min_transmittance is written as (C/(1 − T_acc), 1), so opaque cloud has α = 1.
// Output: the premultiplied cloud layer (rgb = C, a = 1 − T_acc) and the frame composited over the
// lit ground: C + T_acc · L_ground (Nes eq. 5.18's background term).
// Ground: the plane z = 0 (sea level) textured with the reprojected basemap, a Lambertian surface:
// L_ground = ρ/π · (E_sun·cos θ_sun·I_DLM(ground) + π·L_sky·T_d(τ_up)) — the cloud shadow (Nes
// §5.4.1) and the sky the cloud above hides.
// Globe view (u_globe, render/globe.glsl): the rays are in ECEF, each sample is looked up at its
// world point; the ground is the sphere R (displaced by the terrain inside the data's table:
// render/globe_terrain.glsl) with the whole equirectangular basemap, lit by the true
// sun direction at each point (day/night), shadowed by the DLM inside the footprint; rays that
// miss the Earth see black space with a glow at the limb.
// Atmosphere (u_atmosphere, issue 14; glsl/atmosphere/, Hillaire 2020): the sunlight reaching the
// clouds and the ground is the sun's irradiance times the air's transmittance at that altitude
// (sunlightAt: golden hour, the Earth's shadow); the ground's sky light is the sky irradiance
// table's instead of the uniform ambient; a flat-view ray above the horizon sees the sky-view
// table's radiance, a globe ray into space the atmosphere along it (the limb); the ground and
// the cloud layer are seen through the air in front of them (aerial perspective,
// L = L0·T + L_in). With the atmosphere the clouds' upper-hemisphere sky light is the sky
// irradiance table's at the ray's first cloudy sample, E·E_sky(h, μ_s)/π (a uniform sky of that
// irradiance), instead of the analytic clear sky of issue 12.
#include "common/math.glsl"
#include "common/ray_box.glsl"
#include "common/imagery.glsl"
#include "common/night_lights.glsl"
#include "dlm/volume.glsl"
#include "dlm/light_space.glsl"
#include "dlm/lookup.glsl"
#include "common/cloud_light.glsl"
// The Monte Carlo radiance volume (multiple_scattering = radiance_volume, issue 12 sixteenth
// session): compiled in only for that model (CloudRenderer adds the define), its seven samplers
// with it.
#ifdef SPEC_RADIANCE_VOLUME
#include "common/radiance_volume.glsl"
#endif

layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = IMAGE_CLOUD_LAYER) uniform image2D u_cloud_layer;
layout(rgba32f, binding = IMAGE_FRAME) uniform image2D u_frame;
layout(r32ui, binding = IMAGE_SAMPLE_COUNT) uniform uimage2D u_sample_count;  // statistics: samples per ray
// Rays whose march ended without its exit condition (render/raycast/cloud_renderer.h raysCutShort):
// Mesa's llvmpipe ends every loop of a shader once one SIMD group has taken 65 535 back-edges
// in all its loops together (gallivm LP_MAX_TGSI_LOOP_ITERATIONS; docs/accuracy.md "Seventeenth
// session"), so a long march with a small step loses the cloud behind its cut, silently. Counted.
layout(std430, binding = SSBO_RAYCAST_STATS) buffer RaycastStats { uint raycastCutShort; };
// Compositing passes (issue 15; scene/passes.h), written when u_write_passes: the frame is
// C + T_acc·(ground + sky), so a compositor can rebuild it or lay the clouds over its own map.
layout(rgba32f, binding = IMAGE_PASS_GROUND) uniform image2D u_pass_ground;  // ground radiance, shadow matte
layout(rgba32f, binding = IMAGE_PASS_SKY) uniform image2D u_pass_sky;        // sky radiance, cloud depth Z [m]
#ifdef SPEC_MOTION_DEPTH  // temporal accumulation (glsl/render/temporal.comp): the layers and their depths
layout(r32f, binding = IMAGE_MOTION_DEPTH) uniform image2D u_motion_depth;           // the cloud's mean depth
layout(rgba32f, binding = IMAGE_TEMPORAL_BACKGROUND) uniform image2D u_background;  // (ground + sky, its depth)
#endif
layout(binding = UNIT_BASEMAP) uniform sampler2D u_basemap;  // RGB linear albedo, A city lights, over u_basemap_min..max (world m)
layout(binding = UNIT_HOST_DEPTH) uniform sampler2D u_host_depth;  // host depth, GL rows (0 = bottom), [0, 1]

// One std140 block, declared in C++ as gl::RaycastBlock (render/gl/uniform_blocks.h): keep the
// members in its order; the GL test UniformBlocksMatchTheLinkedPrograms checks every offset.
layout(std140, binding = UBO_RAYCAST) uniform RaycastBlock {
  mat4 u_view_from_clip;      // inverse projection
  mat3 u_world_from_view;     // view axes in world (render/raycast/cloud_renderer.h ViewRays)
  vec3 u_cam_pos_m;
  float u_step_m;
  vec3 u_to_sun;              // unit, towards the sun
  float u_min_transmittance;
  vec3 u_sun_radiance;        // colour · intensity
  float u_g_ice;
  vec3 u_sky_radiance;        // upper hemisphere: clear-sky radiance
  float u_g_water;
  vec3 u_ocean_albedo;        // ground albedo outside the basemap
  bool u_jitter;
  vec2 u_basemap_min_m;
  vec2 u_basemap_max_m;
  ivec2 u_size;
  bool u_has_host_depth;      // stop rays at the host's geometry
  bool u_skip_empty;
  bool u_shadows;
  bool u_has_basemap;
  bool u_count_samples;       // write the number of volume samples per ray (benchmarks)
  bool u_globe;               // rays in ECEF (render/globe.glsl's GlobeBlock)
  vec3 u_below_radiance;      // lower hemisphere: ground-reflected radiance
  float u_ms_extinction_scale;  // octave series a (glsl/common/cloud_light.glsl)
  float u_ms_energy_scale;      // octave series b
  float u_ms_anisotropy_scale;  // octave series c
  int u_octaves;                // octave series N (1 = single scattering)
  float u_height_exaggeration;  // e: β is scaled by |(d_x, d_y, d_z/e)| along a ray
  bool u_atmosphere;          // the physically based atmosphere (AtmosphereBlock and its tables)
  bool u_write_passes;        // fill u_pass_ground and u_pass_sky
  int u_cloud_ms_model;  // lighting::MultipleScattering: 0 single, 1 octaves, 2 two_stream, 3 radiance_volume
  float u_step_growth_max;  // adaptive steps (adaptiveStep below): at most this × u_step_m; 1 = fixed
  vec2 u_subpixel;          // this sample's position in the pixel, [0, 1)² ((0.5, 0.5): the centre)
  uint u_sample_index;      // k of RenderSettings::samples_per_pixel (runningMean below)
  uint u_jitter_index;      // k + RenderSettings::sample_offset: the jitter's (temporal accumulation)
};

// Compile-time specialisation per view (issue 19, "Frame time"; see glsl/dlm/volume.glsl for the
// volume's switches): CloudRenderer builds one program per feature set with SPEC_GLOBE,
// SPEC_TERRAIN, SPEC_ATMOSPHERE and SPEC_PASSES defined to 0 or 1, so the flat view carries no
// globe mapping and a view without terrain, atmosphere or passes none of their code. Without the
// defines the uniforms below decide (the baseline the tests compare the variants with, bit for bit).
#ifdef SPEC_GLOBE
#define VIEW_GLOBE (SPEC_GLOBE != 0)
#else
#define VIEW_GLOBE u_globe
#endif
#ifdef SPEC_ATMOSPHERE
#define ATMOSPHERE_ON (SPEC_ATMOSPHERE != 0)
#else
#define ATMOSPHERE_ON u_atmosphere
#endif
#ifdef SPEC_PASSES
#define WRITE_PASSES (SPEC_PASSES != 0)
#else
#define WRITE_PASSES u_write_passes
#endif

// Reduced-resolution clouds (issue 19 item 4, the knob `cloud_resolution`; docs/rendering.md
// "Reduced-resolution clouds"). The march is the frame's cost and scales with the pixels, while
// the clouds are soft: real-time renderers march them at reduced resolution (Schneider 2015, "The
// real-time volumetric cloudscapes of Horizon Zero Dawn"; Hillaire 2016, "Physically based sky,
// atmosphere and cloud rendering in Frostbite"); Muth 2026 §3.4.9 marches at half resolution
// (1280 × 720 for 2560 × 1440, his Table 4.1) and fills the full resolution by temporal
// accumulation of jittered frames instead of a spatial upsampling. Here the upsampling is spatial,
// so a single still frame needs no history. With SPEC_CLOUD_PASS (CloudRenderer) the pass runs in
// one of three roles:
//   0  march and composite at the image's resolution (the pass as it always was; no define = 0);
//   1  the march only, at W/s × H/s (u_size is the reduced size): one sample's cloud layer (aerial
//      perspective and renormalisation applied) and its guide (α·mean depth, march end), then stop;
//   2  the full-resolution pass: the ground, the sky and the passes as in 0, with the clouds taken
//      from role 1's images by depth-aware upsampling (upsampleClouds below) instead of marched.
// Samples per pixel alternate the two roles, sample k of role 1 then sample k of role 2, which
// folds the composite into the running means as role 0 does: the frame stays the mean of
// C + T·background over the samples.
#ifdef SPEC_CLOUD_PASS
#define CLOUD_PASS SPEC_CLOUD_PASS
#else
#define CLOUD_PASS 0
#endif
#if CLOUD_PASS == 1
layout(rg32f, binding = IMAGE_LOW_CLOUD_GUIDE) uniform image2D u_low_cloud_guide_out;
#elif CLOUD_PASS == 2
layout(binding = UNIT_LOW_CLOUD_LAYER) uniform sampler2D u_low_cloud_layer;  // role 1's cloud layer
layout(binding = UNIT_LOW_CLOUD_GUIDE) uniform sampler2D u_low_cloud_guide;  // role 1's guide
#endif

// The sunlight at a cloud sample (issue 19 item 1b): with SPEC_LIGHT_CACHE = 1 (CloudRenderer, when
// the map was built with DlmSettings::light_cache_voxels > 0) one trilinear fetch from the light
// cache the map baked over the volume's box (glsl/dlm/light_cache.comp); otherwise the map's
// four-texel look-up (glsl/dlm/lookup.glsl), the reference path. The ground's shadow keeps the
// look-up either way: the ground lies outside the cache's box below sea level and on the globe,
// and it is one look-up per pixel, not per step.
#if defined(SPEC_LIGHT_CACHE) && SPEC_LIGHT_CACHE != 0
layout(binding = UNIT_LIGHT_CACHE) uniform sampler3D u_light_cache;  // R16F I_DLM per world cell
float sampleSunlight(vec3 world_m) { return texture(u_light_cache, volumeUvw(world_m)).r; }
#else
float sampleSunlight(vec3 world_m) { return dlmIntensity(world_m); }
#endif

// The packed texture (issue 19 item 3): with SPEC_PACKED = 1 (CloudRenderer, when the upload built
// one: VolumeTextures::hasPacked, the trilinear filter without sub-grid detail) a step reads
// (β_ice, β_water) with one RG16F fetch instead of two R32F fetches (ice, water; Muth 2026 §3.4
// packs the cloud's channels the same way), and (τ_up, τ_down) from τ_up (R16F) and the column's
// total T; glsl/dlm/volume.glsl packedTexel applies the extinction's zero border and β's unit
// (u_packed_beta_unit_per_m: 1e-3, per km, in the half's normal range).
#if defined(SPEC_PACKED) && SPEC_PACKED != 0
#define PACKED_VOLUME true
vec4 packedAt(vec3 world_m) {
  vec3 uvw = volumeUvw(world_m);
  if (!insideGrownVolume(uvw)) return vec4(0.0);
  return packedTexel(uvw);
}
#else
#define PACKED_VOLUME false
vec4 packedAt(vec3 world_m) { return vec4(0.0); }
#endif

#include "render/globe.glsl"
#include "atmosphere/model.glsl"
#include "atmosphere/sky.glsl"

// The light that reaches a point drawn at height h (world z; on the globe, above the sphere) is
// taken at its true altitude h / e: it depends on the air above the real cloud or ground, not on
// the height it is drawn at (an 8× cloud at 10 km is drawn at 80 km, above the air: no golden
// hour on it). Never below the model's ground (the tables are NaN under r = R: the terrain's
// bisection leaves a sea-level point a hair below 0, and land may lie below sea level). Every
// caller goes through these two, so none can forget the division.
float trueAltitude(float drawnHeight_m) { return max(drawnHeight_m, 0.0) / u_height_exaggeration; }
vec3 sunlightAtDrawn(float drawnHeight_m, float sinSunElevation) {
  return sunlightAt(trueAltitude(drawnHeight_m), sinSunElevation);
}
vec3 skyIrradianceAtDrawn(float drawnHeight_m, float sinSunElevation) {
  return skyIrradiance(trueAltitude(drawnHeight_m), sinSunElevation);
}

// The ground's height field (issue 14; glsl/common/terrain.glsl) and the far basemap (item 4). One
// std140 block, declared in C++ as gl::TerrainBlock (render/gl/uniform_blocks.h).
layout(binding = UNIT_TERRAIN) uniform sampler2D u_terrain;  // R32F spline coefficient [m] per lattice point
layout(binding = UNIT_FAR_TERRAIN) uniform sampler2D u_far_terrain;  // R32F height [m]: a DEM beyond the domain
layout(binding = UNIT_FAR_BASEMAP) uniform sampler2D u_far_basemap;  // as u_basemap, over u_far_basemap_min..max
layout(std140, binding = UBO_TERRAIN) uniform TerrainBlock {
  ivec2 u_terrain_size;          // mass points nx, ny
  vec2 u_terrain_cell_m;         // world dx, dy
  float u_terrain_exaggeration;  // the clouds' height exaggeration e
  float u_terrain_fade_m;        // beyond the footprint, heights fall to 0 over this distance
  float u_terrain_max_m;         // highest world height (≥ 0)
  float u_terrain_min_m;         // lowest world height (≤ 0)
  float u_terrain_lipschitz;     // slope bound of the surface
  bool u_has_terrain;            // displaced ground; else the plane z = 0
  vec2 u_far_basemap_min_m;      // the far basemap's world rectangle (item 4: no void)
  vec2 u_far_basemap_max_m;
  bool u_has_far_basemap;
  float u_city_lights;           // the night side's lights: k of common/night_lights.glsl (0 = none)
  ivec2 u_far_terrain_size;      // the far height field (a user DEM, scene/dem.h; flat view only)
  vec2 u_far_terrain_min_m;      // its world rectangle's south-west corner
  vec2 u_far_terrain_cell_m;     // its pixel size
  bool u_has_far_terrain;
  bool u_ground_tint;            // snow and rock from the terrain (common/ground_tint.glsl; style ground_tint)
  float u_snow_line_m;           // its snow line [m above MSL]
};
#ifdef SPEC_TERRAIN
#define HAS_TERRAIN (SPEC_TERRAIN != 0)
#else
#define HAS_TERRAIN u_has_terrain
#endif
#define Vec2 vec2
struct TerrainGrid {
  ivec2 size;
  vec2 cell_m;
  float exaggeration, fade_m, max_m, min_m, lipschitz;
  bool has_far;
  ivec2 far_size;
  vec2 far_min_m, far_cell_m;
};
#define TERRAIN_TEXEL(g, i, j) texelFetch(u_terrain, ivec2(i, j), 0).r
#define TERRAIN_FAR_TEXEL(g, i, j) texelFetch(u_far_terrain, ivec2(i, j), 0).r
#include "common/terrain.glsl"
#include "common/ground_tint.glsl"

TerrainGrid terrainGrid() {
  return TerrainGrid(u_terrain_size, u_terrain_cell_m, u_terrain_exaggeration, u_terrain_fade_m, u_terrain_max_m,
                     u_terrain_min_m, u_terrain_lipschitz, u_has_far_terrain, u_far_terrain_size, u_far_terrain_min_m,
                     u_far_terrain_cell_m);
}
#include "render/globe_terrain.glsl"

// Flat view: distance along the ray to the ground — the displaced terrain, or the plane z = 0
// without terrain (then exactly the division of before, so images without terrain keep their bits).
float flatGroundDistance(vec3 o, vec3 d) {
  if (HAS_TERRAIN) return terrainHitDistance(terrainGrid(), o, d, 0.0, kTerrainMiss_m);
  return d.z < 0.0 ? -o.z / d.z : kTerrainMiss_m;
}

// Ground albedo at a world point of the flat view: the near basemap (the data's footprint plus a
// margin, fine), else the far basemap (item 4: the ground continues beyond, Blue Marble being
// global), else the ocean albedo. dx, dy: the pixel's footprint on the ground (world metres, the
// differentials of the hit point to the next pixel right and down), which picks the mipmap level
// and the anisotropic filter's axis (imagery seen at a slant does not alias; compute shaders have
// no implicit derivatives, so they are given explicitly). The anisotropic taps are the shader's
// (common/imagery.glsl textureAnisotropic), as on the globe: llvmpipe's own filter is wrong for
// strongly elongated footprints (docs/imagery.md "Filtering (flat view)"). A: the night side's city lights
// on the same grid (0 without, and over the ocean albedo; common/night_lights.glsl).
vec4 flatGroundAlbedo(vec2 xy, vec2 dx, vec2 dy) {
  if (u_has_basemap) {
    vec2 extent = u_basemap_max_m - u_basemap_min_m;
    vec2 uv = (xy - u_basemap_min_m) / extent;
    if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)))) {
      // image row 0 = north edge: v = 1 − uv.y, so the v gradients change sign
      return textureAnisotropic(u_basemap, vec2(uv.x, 1.0 - uv.y), footprintClamped(vec2(dx.x, -dx.y) / extent),
                                footprintClamped(vec2(dy.x, -dy.y) / extent));
    }
  }
  if (u_has_far_basemap) {
    vec2 extent = u_far_basemap_max_m - u_far_basemap_min_m;
    vec2 uv = (xy - u_far_basemap_min_m) / extent;
    if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)))) {
      return textureAnisotropic(u_far_basemap, vec2(uv.x, 1.0 - uv.y), footprintClamped(vec2(dx.x, -dx.y) / extent),
                                footprintClamped(vec2(dy.x, -dy.y) / extent));
    }
  }
  return vec4(u_ocean_albedo, 0.0);
}

#include "render/pixel_ray.glsl"

// Ray differentials (Igehy 1999, "Tracing ray differentials", §3: transfer to a surface): the
// hit point at distance t along D on a surface of normal n moves by
//   dP = t·(dD − (dD·n)/(D·n)·D)
// when the direction moves by dD (a pinhole camera: the origin does not move). D·n is kept from
// 0 (grazing rays at the horizon get a long but finite footprint: the coarsest levels).
vec3 surfaceDifferential(vec3 D, vec3 dD, vec3 n, float t) {
  float dn = dot(D, n);
  dn = dn < 0.0 ? min(dn, -1e-4) : max(dn, 1e-4);
  return t * (dD - dot(dD, n) / dn * D);
}

// The pixel's footprint on the globe's ground along one pixel axis (dD: the direction to the next
// pixel's ray minus this one's; g = o + t·D the ground point): the step to where the neighbouring
// rays meet the sphere, a central difference of exact hits when both do, one-sided when only one
// does. Igehy's linear transfer (surfaceDifferential) diverges towards the limb, where the
// neighbour above misses the Earth, and would send limb pixels to the basemap's coarsest levels.
// It stays as the last resort, for a pixel whose neighbours both miss.
vec3 globeFootprint(vec3 o, vec3 D, vec3 dD, vec3 g, float t) {
  float tNext = globeGroundDistance(o, normalize(D + dD)), tPrev = globeGroundDistance(o, normalize(D - dD));
  vec3 next = o + tNext * normalize(D + dD), prev = o + tPrev * normalize(D - dD);
  if (tNext < kNoHit_m && tPrev < kNoHit_m) return 0.5 * (next - prev);
  if (tNext < kNoHit_m) return next - g;
  if (tPrev < kNoHit_m) return g - prev;
  return surfaceDifferential(D, dD, normalize(g), t);
}

// (τ_up, τ_down) at a world point: the column depths reconstructed by the extinction's own filter
// (trilinear or the cubic B-spline between voxel centres), clamped to the edge (the CPU twin:
// volume/column_depth.h columnDepthAt). The same filter matters: trilinear depths under a cubic
// field would put the grid back into the sky light and the two-stream term (issue 13's artefact
// metric: the power at the column spacing).
// The separate RG16F texture holds (τ_up, T); τ_down = T − τ_up after the filter (the column's
// weights sum to 1 under either filter and T is constant along it).
vec2 columnDepthAt(vec3 world_m) {
  vec3 uvw = volumeUvw(world_m);
  if (u_packed_only) return trilinearColumnDepth(uvw);
  // precise: the same arithmetic in the program specialised per feature and the uniform-branch
  // one (EyePassVariants compares them bit for bit); unmarked, the compiler fused the cubic's last
  // multiply-adds with the difference in one program and not in the other (1 ulp).
  precise vec2 upTotal = RECONSTRUCTION_CUBIC ? cubicBSplineRgba(u_column_depth, uvw).rg : texture(u_column_depth, uvw).rg;
  precise float down = upTotal.y - upTotal.x;
  return vec2(upTotal.x, down);
}

// Sky light at a point inside the cloud, scattered isotropically: the mean radiance of the
// Eddington column of depths τ = (τ_up, τ_down) lit by the sky above and the ground's light below,
// its own reflection included (cloud_light.glsl skyDiffuse; uniform sky ⇒ the sky radiance itself,
// the white furnace). diffusionScale: twoStreamSunFrame's vertical diffusion (exaggeration).
vec3 skyLightAt(vec2 tau, float g, float diffusionScale, vec3 skyAbove) {
#ifdef SKY_HALF_TRANSMITTANCE  // benchmark baseline (EyePassBaseline): the former term, no reflection
  return 0.5 * (skyAbove * diffuseTransmittance(tau.x, g) + u_below_radiance * diffuseTransmittance(tau.y, g));
#else
  return skyDiffuse(tau.x, tau.y, g, diffusionScale, skyAbove, u_below_radiance);
#endif
}

// Adaptive steps (issue 19 item 1; Muth 2026 §3.4.3 eq. 3.6: Δt = min(max(t/c_d, Δt_min) +
// Δt_horizon, Δt_length)), larger far away and in thin cloud, never below the fixed step Δ and at
// most u_step_growth_max·Δ (the knob `step_growth_max`; 1 = the fixed step, the reference path):
//   far away:   Δ_far = t·|dΩ_px|, one pixel's footprint at distance t (Muth's t/c_d with c_d the
//               reciprocal of the pixel's angle: a step never shorter than the pixel is wide), so
//               the march's resolution along the ray follows the picture's across it;
//   thin cloud: Δ_thin = τ_step / β_brick, β_brick the occupancy brick's maximum extinction
//               (an upper bound of β in the brick, glsl/dlm/volume.glsl brickMaxAt) scaled along
//               the ray, so that no step's optical depth exceeds τ_step = kThinStepOpticalDepth
//               where the brick is thin; dense bricks keep Δ.
//   Δt = Δ·clamp(max(Δ_far, Δ_thin)/Δ, 1, u_step_growth_max).
// Muth's horizon and length terms are not used: the flat view's rays are clipped by the volume's
// box, and the occupancy's empty-space skipping already jumps clear air.
const float kThinStepOpticalDepth = 0.05;
float adaptiveStep(float t, float pixelAngle, float brickMax_per_m) {
  float far = t * pixelAngle;
  float thin = brickMax_per_m > 0.0 ? kThinStepOpticalDepth / brickMax_per_m : u_step_m * u_step_growth_max;
  return u_step_m * clamp(max(far, thin) / u_step_m, 1.0, u_step_growth_max);
}

// Adaptive steps clipped at the brick (issue 19 item 1, the safe default asked for after the first
// measurement, docs/benchmarks.md "Adaptive steps"): a grown step ends at the face of the occupancy
// brick it starts in, so it never jumps past the first samples of the next brick, where a thin
// cloud can lie just beyond a long empty stretch (the occupancy is dilated by the filter's reach,
// so the brick before such a cloud is occupied, and there the far term grows the step). Inside
// the next brick the step grows again from its own bound. A step is never clipped below Δ: the
// fixed step crosses a face by up to Δ as well. Flat view: the exact distance to the brick's exit
// along the ray (glsl/dlm/volume.glsl brickExitDistance; 0 beyond the box's far faces, so there
// the step is Δ). Globe: the world frame bends along an ECEF ray, so the landing point's brick is
// compared with the start's (one more table mapping per grown step) and a step that would leave
// the brick falls back to Δ. ADAPTIVE_STEPS_UNCLIPPED (render::EyePassBaseline::unclipped_steps,
// benchmarks and tests only) keeps the unclipped step of the first version to measure against.
ivec3 brickIndexAt(vec3 world_m) {
  return ivec3(floor(volumeUvw(world_m) * vec3(u_voxels) / float(u_brick_voxels)));
}
float stepClippedAtBrick(vec3 p, vec3 w, vec3 dir, float step_m) {
  if (VIEW_GLOBE) {
    return all(equal(brickIndexAt(globeWorldFromEcef(p + step_m * dir)), brickIndexAt(w))) ? step_m : u_step_m;
  }
  return max(min(step_m, brickExitDistance(w, dir)), u_step_m);
}

// The Z pass where no cloud is seen: 10^10 m, the value Blender Cycles writes for its background,
// finite so that compositors' depth operations (defocus, depth merge) stay defined.
const float kNoCloudDepth_m = 1.0e10;

// Deterministic per-pixel jitter in [0, 1) (integer hash, Jarzynski & Olano 2020 "PCG").
float pixelHash(uvec2 p) {
  uint v = p.x * 1973u + p.y * 9277u + 26699u;
  v = v * 747796405u + 2891336453u;
  uint w = ((v >> ((v >> 28u) + 4u)) ^ v) * 277803737u;
  return float((w >> 22u) ^ w) / 4294967296.0;
}

// Ray–box entry/exit distances of the volume box grown by the filter's reach (β fades to 0 across it).
vec2 volumeInterval(vec3 o, vec3 d) {
  vec3 pad = volumePad_m();
  vec3 inv = 1.0 / safeDirection(d);
  vec2 t = slabInterval((u_box_min_m - pad - o) * inv, (u_box_min_m + u_box_size_m + pad - o) * inv);
  return vec2(max(t.x, 0.0), t.y);
}

// Samples per pixel (RenderSettings::samples_per_pixel): CloudRenderer dispatches this pass once
// per sample, each at its own sub-pixel position u_subpixel and with its own jitter; sample k > 0
// folds its value into the mean of the k before it, in place (every invocation owns its pixel and
// the dispatches are separated by a barrier), so the images hold the box-filtered pixel after the
// last one. Sample 0 writes its value: one sample per pixel is the pass as it always was.
vec4 runningMean(vec4 previous, vec4 value) { return previous + (value - previous) / float(u_sample_index + 1u); }

#if CLOUD_PASS == 2
// Depth-aware upsampling of the reduced-resolution clouds (role 2 of SPEC_CLOUD_PASS above): joint
// bilateral upsampling (Kopf, Cohen, Lischinski & Uyttendaele 2007, "Joint bilateral upsampling")
// over the 2×2 reduced pixels around this sample, with a binary range kernel on the march's end
// guided by the full-resolution geometry — the nearest-depth upsampling of mixed-resolution
// particle rendering (Bavoil & Sainz 2009, NVIDIA "Fast rendering of opacity-mapped particles
// using DirectX 11 tessellation and mixed resolution"):
//   w_i = b_i · [|e_i − e| ≤ κ·min(e_i, e)],   layer = Σ w_i·layer_i / Σ w_i,
// b_i the bilinear weights, e the distance at which this ray's march ends (the volume's far face,
// the terrain, the globe's ground or the host's geometry: `marchEnd_m`; 0 for a ray that misses
// the volume) and e_i the reduced rays' ends (role 1's guide of the same sample). Where
// all four match, this is the bilinear filter; where a reduced ray ended somewhere else (behind a
// ridge, past a host object's edge), it is left out, so a mountain's near side never takes the
// cloud behind it, nor the sky beside a cloud the cloud's alpha. Where none matches (a thin
// feature narrower than a reduced pixel) the reduced ray whose end is nearest to this one's
// stands in. The premultiplied layer is filtered as is (linear in the radiance); the mean depth
// travels premultiplied as well (α·d̄) and is divided by the filtered α.
// κ: neighbouring rays over smooth ground or through the box's faces end within a few per cent
// of each other except at grazing angles (relative change per reduced pixel ≈ its angle / tan of
// the grazing angle: 1080p/2 ≈ 1.5 mrad, so 10 % is reached below ~1° of grazing), while an
// occluding edge jumps by far more (a ridge 30 km away against the box's far face 100 km
// behind it).
const float kUpsampleDepthTolerance = 0.1;  // κ
struct UpsampledClouds {
  vec4 layer;         // premultiplied (C, α)
  float meanDepth_m;  // d̄ along the ray (0 where α = 0)
};
UpsampledClouds upsampleClouds(vec2 at, float marchEnd_m) {
  ivec2 lowSize = textureSize(u_low_cloud_layer, 0);
  // Reduced pixel coordinates with this sample's reduced rays at the integers: role 1 cast them
  // through reduced position c + u_subpixel (the centres c + ½ for the first sample).
  vec2 q = at * vec2(lowSize) / vec2(u_size) - u_subpixel;
  ivec2 q0 = ivec2(floor(q));
  vec2 f = q - vec2(q0);
  vec4 layerSum = vec4(0.0), nearestLayer = vec4(0.0);
  float depthSum = 0.0, weightSum = 0.0, nearestDepth = 0.0, nearestDifference = 3.0e38;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      ivec2 c = clamp(q0 + ivec2(i, j), ivec2(0), lowSize - 1);
      vec4 layer = texelFetch(u_low_cloud_layer, c, 0);
      vec2 guide = texelFetch(u_low_cloud_guide, c, 0).xy;  // (α·d̄, march end)
      float difference = abs(guide.y - marchEnd_m);
      if (difference < nearestDifference) {
        nearestDifference = difference;
        nearestLayer = layer;
        nearestDepth = guide.x;
      }
#ifdef UPSAMPLE_DEPTH_BLIND  // benchmark/test baseline (EyePassBaseline::depth_blind_upsampling)
      if (true) {
#else
      if (difference <= kUpsampleDepthTolerance * min(guide.y, marchEnd_m)) {
#endif
        float w = (i == 1 ? f.x : 1.0 - f.x) * (j == 1 ? f.y : 1.0 - f.y);
        layerSum += w * layer;
        depthSum += w * guide.x;
        weightSum += w;
      }
    }
  }
  UpsampledClouds u;
  u.layer = weightSum > 0.0 ? layerSum / weightSum : nearestLayer;
  float alphaDepth = weightSum > 0.0 ? depthSum / weightSum : nearestDepth;
  u.meanDepth_m = u.layer.a > 0.0 ? alphaDepth / u.layer.a : 0.0;
  return u;
}
#endif

void main() {
  ivec2 px = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(px, u_size))) return;
  // Same ray as scene::Camera::rayDirection at the pixel centre (row 0 at the top).
  vec2 ndc = vec2(2.0 * (float(px.x) + 0.5) / float(u_size.x) - 1.0, 1.0 - 2.0 * (float(px.y) + 0.5) / float(u_size.y));
  vec2 at = vec2(px) + u_subpixel;  // this sample's image position (the centre: + 0.5)
  vec3 dir = pixelRay(at);
  // The rays one pixel right and down: the ground's footprint for the imagery's filtering.
  vec3 dirDx = pixelRay(at + vec2(1.0, 0.0)) - dir, dirDy = pixelRay(at + vec2(0.0, 1.0)) - dir;
  vec3 origin = u_cam_pos_m;
  float hostDistance = kNoHostGeometry_m;  // distance along the ray to the host's opaque geometry
  if (u_has_host_depth) {
#if CLOUD_PASS == 1  // the host's pixel under this reduced pixel's centre
    ivec2 hostSize = textureSize(u_host_depth, 0);
    ivec2 hostPx = min(ivec2((vec2(px) + 0.5) * vec2(hostSize) / vec2(u_size)), hostSize - 1);
    float d = texelFetch(u_host_depth, ivec2(hostPx.x, hostSize.y - 1 - hostPx.y), 0).r;
#else
    float d = texelFetch(u_host_depth, ivec2(px.x, u_size.y - 1 - px.y), 0).r;
#endif
    if (d < 1.0) {
      vec4 hit = u_view_from_clip * vec4(ndc, 2.0 * d - 1.0, 1.0);
      hostDistance = length(hit.xyz / hit.w);
    }
  }

  vec3 lightDir = -u_to_sun;              // direction the sunlight travels
  float cosPsi = dot(lightDir, -dir);     // scattering angle: sunlight → towards the eye
  // Optical depth per world metre along this ray: the data's, whatever the exaggeration. On the
  // globe the ray's direction in the footprint's local frame (east, north, up) stands for it.
  vec3 dLocal = VIEW_GLOBE ? globeLocalDirection(dir) : dir;
  float depthScale = length(vec3(dLocal.xy, dLocal.z / u_height_exaggeration));
  // The two-stream term's view and sun in the data (glsl/common/cloud_light.glsl
  // twoStreamSunFrame): μ_out = −d_z/(e·f(d)) towards the eye; the sun's world vertical cosine is
  // taken where the ray enters the volume (on the globe the local vertical turns with the point).
  float muOut = -dLocal.z / (u_height_exaggeration * depthScale);

  vec3 C = vec3(0.0);
  float Tacc = 1.0;
  uint samples = 0u;  // extinction look-ups (empty-brick jumps not counted)
  // The globe's ground: the sphere R, or the displaced terrain (it also ends the cloud march: the
  // lens interval stops at it, so clouds behind a mountain are hidden).
  float tGround = VIEW_GLOBE ? (HAS_TERRAIN ? globeTerrainDistance(origin, dir) : globeGroundDistance(origin, dir))
                             : kNoHit_m;
  vec2 span = VIEW_GLOBE ? globeVolumeInterval(origin, dir, tGround) : volumeInterval(origin, dir);
  span.y = min(span.y, hostDistance);
  vec3 twoStreamSun = twoStreamSunFrame(VIEW_GLOBE ? dot(normalize(origin + span.x * dir), u_to_sun) : u_to_sun.z,
                                        u_height_exaggeration);
  // Flat view: the ground along this ray (issue 14). The displaced terrain also ends the cloud
  // march — clouds behind a mountain are hidden by it (without terrain the march is as before).
  float tFlatGround = VIEW_GLOBE ? kTerrainMiss_m : flatGroundDistance(origin, dir);
  if (HAS_TERRAIN && !VIEW_GLOBE) span.y = min(span.y, tFlatGround);
  // The sun's irradiance where this ray meets the clouds: E·T_atm(h, μ_s) at its first cloudy
  // sample (one table look-up per ray; a deck's depth is small next to the 8 km Rayleigh scale
  // height, so the reddening is taken once).
  vec3 sunAtClouds = u_sun_radiance;
  vec3 skyAtClouds = u_sky_radiance;  // the upper hemisphere's radiance there (issue 12's clear sky without the atmosphere)
  bool sunAtCloudsSet = !ATMOSPHERE_ON;
  bool first = u_sample_index == 0u;
#if CLOUD_PASS == 2
  // The clouds from the reduced-resolution march (role 2; upsampleClouds above).
  UpsampledClouds upsampled = upsampleClouds(at, span.x < span.y ? span.y : 0.0);
  C = upsampled.layer.rgb;
  float alpha = upsampled.layer.a;
  Tacc = 1.0 - alpha;
  float meanDepth = upsampled.meanDepth_m;
#else
  float depthSum = 0.0;  // Σ t·(opacity added): the cloud layer's mean depth for aerial perspective
  if (span.x < span.y) {
    // (each sample of a pixel its own offset; sample 0 the one a single sample always had)
    float t = span.x + (u_jitter ? pixelHash(uvec2(px) + u_jitter_index * uvec2(7919u, 6007u)) : 0.5) * u_step_m;
    bool adaptive = u_step_growth_max > 1.0;
    float pixelAngle = length(dirDx);  // radians between neighbouring pixels' rays
    while (t < span.y && Tacc > u_min_transmittance) {
      vec3 p = origin + t * dir;
      vec3 w = VIEW_GLOBE ? globeWorldFromEcef(p) : p;  // the sample in the volume's world frame
      float brickMax = (u_skip_empty || adaptive) ? brickMaxAt(w) : 1.0;
      if (u_skip_empty && brickMax == 0.0) {
        float skip = VIEW_GLOBE ? globeEmptySkip(w) : emptySkipDistance(p, dir);
        if (skip > 0.0) {  // jump whole steps, keeping the jittered lattice
          t += max(ceil(skip / u_step_m), 1.0) * u_step_m;
          continue;
        }
      }
      float step_m = adaptive ? adaptiveStep(t, pixelAngle, brickMax * depthScale) : u_step_m;
#ifndef ADAPTIVE_STEPS_UNCLIPPED
      if (step_m > u_step_m) step_m = stepClippedAtBrick(p, w, dir, step_m);
#endif
      vec4 packedSample = PACKED_VOLUME ? packedAt(w) : vec4(0.0);  // (β_ice, β_water, τ_up, τ_down)
      // (the detail's noise prefiltered to this ray's footprint, t × the pixel angle: no sub-pixel grain)
      vec2 beta = (PACKED_VOLUME ? packedSample.xy : extinctionAtFootprint(w, t * pixelAngle)) * depthScale;
      ++samples;
      float b = beta.x + beta.y;
      if (b > 0.0) {
        if (!sunAtCloudsSet) {
          float muS = VIEW_GLOBE ? dot(normalize(p), u_to_sun) : u_to_sun.z;
          sunAtClouds = u_sun_radiance * sunlightAtDrawn(w.z, muS);
          skyAtClouds = u_sun_radiance * skyIrradianceAtDrawn(w.z, muS) / kPi;
          sunAtCloudsSet = true;
        }
        float T = exp(-b * step_m);
        float iceWeight = beta.x / b;  // Nes eq. 5.12
        // one look-up for the sky light and the two-stream term (in the packed texel already)
        vec2 tau = PACKED_VOLUME ? packedSample.zw : columnDepthAt(w);
        float sun = cloudSunFactor(u_cloud_ms_model, sampleSunlight(w), cosPsi, iceWeight, u_g_ice, u_g_water,
                                   u_octaves, u_ms_extinction_scale, u_ms_energy_scale, u_ms_anisotropy_scale,
                                   tau.x, tau.y, twoStreamSun, muOut);
#ifdef SPEC_RADIANCE_VOLUME
        // the volume's orders ≥ 2 beside the map's single scattering and forward lobe (cloud_light.glsl
        // cloudSunFactor mode 3); its directions are the world's (on the globe: the local frame's)
        if (u_cloud_ms_model == 3) sun += radianceVolumeSource(w, -dLocal, iceWeight, u_g_ice, u_g_water);
#endif
        vec3 L = sunAtClouds * sun + skyLightAt(tau, mix(u_g_water, u_g_ice, iceWeight), twoStreamSun.z, skyAtClouds);
        C += Tacc * (1.0 - T) * L;
        depthSum += Tacc * (1.0 - T) * t;
        Tacc *= T;
      }
      t += step_m;
    }
    // Neither end reached: the loop limiter ended it (a loop exits only through its condition).
    if (t < span.y && Tacc > u_min_transmittance) atomicAdd(raycastCutShort, 1u);
  }
  // Aerial perspective of the cloud layer, taken at its opacity-weighted mean depth d̄ (before the
  // renormalisation below, which rescales C and α but not where the cloud is):
  // C·T(0, d̄) + α·E·L_in(0, d̄) (Hillaire 2020 §5.4 samples his froxels the same way per pixel).
  // In the flat view along the round planet's chord to the cloud's place (atmosphere/sky.glsl
  // aerialPerspectiveOfFlatPoint): clouds 100–300 km away at low views sit behind denser air than
  // the plane-parallel world's, lit by a lower sun.
  float meanDepth = Tacc < 1.0 ? depthSum / (1.0 - Tacc) : 0.0;
  // Renormalised early termination: the medium left behind is assumed to send the mean radiance of
  // what was gathered, C/(1 − T_acc), and to be opaque (docs/rendering.md "Conventions" 4).
  if (Tacc <= u_min_transmittance && Tacc < 1.0) {
    C /= 1.0 - Tacc;
    Tacc = 0.0;
  }
  float alpha = 1.0 - Tacc;
  if (ATMOSPHERE_ON && alpha > 0.0) {
    AtmosphereSegment ap = VIEW_GLOBE ? aerialPerspectiveGlobe(origin, dir, meanDepth, u_to_sun)
                                   : aerialPerspectiveOfFlatPoint(origin.z, dir, meanDepth, u_to_sun);
    C = C * ap.transmittance + alpha * u_sun_radiance * ap.inscattered;
  }
#endif
#if CLOUD_PASS == 1  // this sample alone: the full-resolution pass folds it into the means
  imageStore(u_cloud_layer, px, vec4(C, alpha));
#else
  imageStore(u_cloud_layer, px, first ? vec4(C, alpha) : runningMean(imageLoad(u_cloud_layer, px), vec4(C, alpha)));
#endif
#if CLOUD_PASS != 2
  if (u_count_samples) imageStore(u_sample_count, px, uvec4(samples + (first ? 0u : imageLoad(u_sample_count, px).x)));
#endif
#if CLOUD_PASS == 1
  // The upsampling's guide (role 1), for this sample as the layer: α·d̄ and the march's end.
  imageStore(u_low_cloud_guide_out, px, vec4(alpha * meanDepth, span.x < span.y ? span.y : 0.0, 0.0, 0.0));
  return;  // the ground, the sky and the passes are the full-resolution pass's
#endif

  // Background: the ground (plane z = 0 or the sphere R) or the sky (space on the globe), as two
  // passes: `ground` (the lit ground after the air's transmittance) and `sky` (the sky's radiance,
  // or the air's in-scattering in front of the ground); background = ground + sky. `shadow` is the
  // cloud shadow matte at the ground point: the DLM's transmittance of sunlight, 1 = no shadow.
  vec3 ground = vec3(0.0), sky = u_sky_radiance;
  float shadow = 1.0;
  if (VIEW_GLOBE) {
    if (tGround < kNoHit_m) {
      // The globe's ground (issue 14): the sphere R, displaced by the terrain inside the data's
      // table (render/globe_terrain.glsl), lit as the flat view's ground (Lambertian, normal n,
      // the cloud shadow at the 3-D ground point, the terrain's own shadow V, the sky a tilted
      // surface sees); day and night and the air's altitude follow the local vertical.
      vec3 g = origin + tGround * dir;
      vec3 gn = normalize(g);  // the local vertical
      vec3 n = HAS_TERRAIN ? globeTerrainNormal(g) : gn;
      vec4 imagery = globeAlbedo(g, globeFootprint(origin, dir, dirDx, g, tGround),
                                 globeFootprint(origin, dir, dirDy, g, tGround), u_ocean_albedo);
      vec3 albedo = imagery.rgb;
      if (HAS_TERRAIN && u_ground_tint) {
        albedo = groundTint(albedo, (length(g) - u_earth_radius_m) / u_terrain_exaggeration, dot(n, gn),
                            u_terrain_exaggeration, u_snow_line_m);
      }
      float sunCos = dot(gn, u_to_sun);
      float sunLambert = max(dot(n, u_to_sun), 0.0);
      vec3 gw = globeWorldFromEcef(g);
      shadow = u_shadows && gw.x != kOutsideTable_m ? dlmIntensity(HAS_TERRAIN ? gw : vec3(gw.xy, 0.0)) : 1.0;
      float sunVisible = 1.0, skyView = 1.0;  // V and (1 + n·up)/2
      float drawnHeight = 0.0;
      if (HAS_TERRAIN) {
        vec3 lifted = g + n * (0.01 * min(u_terrain_cell_m.x, u_terrain_cell_m.y));
        if (sunLambert > 0.0 && sunCos > 0.0 && globeTerrainShadows(lifted, u_to_sun)) sunVisible = 0.0;
        skyView = 0.5 * (1.0 + dot(n, gn));
        drawnHeight = length(g) - u_earth_radius_m;
      }
      sky = vec3(0.0);
      if (ATMOSPHERE_ON) {
        ground = albedo / kPi * u_sun_radiance *
                 (sunlightAtDrawn(drawnHeight, sunCos) * sunLambert * shadow * sunVisible +
                  skyIrradianceAtDrawn(drawnHeight, sunCos) * skyView);
      } else {
        ground = albedo / kPi *
                 (u_sun_radiance * sunLambert * shadow * sunVisible + kPi * u_sky_radiance * globeDaylight(sunCos) * skyView);
      }
      // The night side's city lights, emitted: the air below (aerial perspective) and the clouds
      // in front dim them as the lit ground (common/night_lights.glsl). Exactly 0 where the sun is up.
      if (u_city_lights > 0.0) ground += cityLightsRadiance(imagery.a, sunCos, u_sun_radiance, u_city_lights);
    } else {
      sky = ATMOSPHERE_ON ? vec3(0.0) : globeSpace(origin, dir, u_to_sun);
    }
    if (ATMOSPHERE_ON) {  // the air between the eye and the ground, or along the ray into space (the limb)
      AtmosphereSegment ap = aerialPerspectiveGlobe(origin, dir, tGround, u_to_sun);
      ground *= ap.transmittance;
      sky = sky * ap.transmittance + u_sun_radiance * ap.inscattered;
    }
  } else if (tFlatGround < kTerrainMiss_m) {
    // The ground (Nes 2008 §5.5: the basemap under the clouds; Thomann 2021 §5.3: the terrain):
    // a Lambertian surface of albedo ρ with normal n (terrain.glsl; (0, 0, 1) on the plane),
    //   L_ground = ρ/π · (E·cos θ_sun·shadow·V + E_sky·T_d(τ_up)·(1 + n_z)/2),
    // cos θ_sun = max(n·ω_sun, 0); `shadow` the cloud shadow matte: the DLM's transmittance
    // through the clouds at the (3-D) ground point (Nes §5.4.1); V the terrain's own shadow (0
    // where the sun's ray from the point meets a mountain); the sky light through the column
    // above (two-stream T_d) over the part of the sky a tilted surface sees, (1 + n_z)/2.
    vec3 g = origin + tFlatGround * dir;
    vec3 n = HAS_TERRAIN ? terrainNormal(terrainGrid(), g.xy) : vec3(0.0, 0.0, 1.0);
    vec4 imagery = flatGroundAlbedo(g.xy, surfaceDifferential(dir, dirDx, n, tFlatGround).xy,
                                    surfaceDifferential(dir, dirDy, n, tFlatGround).xy);
    vec3 albedo = imagery.rgb;
    if (HAS_TERRAIN && u_ground_tint) {
      albedo = groundTint(albedo, g.z / u_terrain_exaggeration, n.z, u_terrain_exaggeration, u_snow_line_m);
    }
    // The night side's city lights (common/night_lights.glsl), emitted: added before the air's
    // transmittance and the clouds in front dim them. The flat view's sun has one elevation,
    // u_to_sun.z; exactly 0 while it is up.
    vec3 lights = u_city_lights > 0.0 ? cityLightsRadiance(imagery.a, u_to_sun.z, u_sun_radiance, u_city_lights)
                                      : vec3(0.0);
    float sunCos = max(dot(n, u_to_sun), 0.0);
    shadow = u_shadows ? dlmIntensity(g) : 1.0;
    float sunVisible = 1.0;  // V
    if (HAS_TERRAIN && sunCos > 0.0) {
      // Lift the shadow ray's start off the surface by a hundredth of a cell along the normal.
      vec3 start = g + n * (0.01 * min(u_terrain_cell_m.x, u_terrain_cell_m.y));
      if (terrainHitDistance(terrainGrid(), start, u_to_sun, 0.0, kTerrainMiss_m) < kTerrainMiss_m) sunVisible = 0.0;
    }
    float skyView = HAS_TERRAIN ? 0.5 * (1.0 + n.z) : 1.0;
    float skyShadow = (u_shadows ? diffuseTransmittance(columnDepthAt(g).x, u_g_water) : 1.0) * skyView;
    sky = vec3(0.0);
    if (ATMOSPHERE_ON) {
      // The air between the eye and the point stays in the drawn world (docs/atmosphere.md
      // "Height exaggeration and the air"); without terrain the ground is at height 0.
      float drawnHeight = HAS_TERRAIN ? g.z : 0.0;
      ground = albedo / kPi * u_sun_radiance *
                   (sunlightAtDrawn(drawnHeight, u_to_sun.z) * sunCos * shadow * sunVisible +
                    skyIrradianceAtDrawn(drawnHeight, u_to_sun.z) * skyShadow) +
               lights;
      // Beyond the curved planet's horizon the flat ground gives way to what the planet shows in
      // that direction (atmosphere/sky.glsl flatGroundVisibility, roundPlanetAlong).
      AtmosphereSegment ap = aerialPerspectiveFlat(origin.z, dir, tFlatGround, u_to_sun);
      float visible = flatGroundVisibility(origin.z, g.z, tFlatGround * length(dir.xy));
      ground *= ap.transmittance * visible;
      sky = u_sun_radiance *
            (visible < 1.0 ? mix(roundPlanetAlong(origin.z, dir, u_to_sun).inscattered, ap.inscattered, visible)
                           : ap.inscattered);
    } else {
      ground = albedo / kPi * (u_sun_radiance * sunCos * shadow * sunVisible + kPi * u_sky_radiance * skyShadow) +
               lights;
    }
  } else if (ATMOSPHERE_ON) {  // the sky above the flat view's horizon
    sky = u_sun_radiance * flatSkyRadiance(origin.z, dir, u_to_sun);
  }
  vec4 beauty = vec4(C + Tacc * (ground + sky), 1.0);
  imageStore(u_frame, px, first ? beauty : runningMean(imageLoad(u_frame, px), beauty));
#ifdef SPEC_MOTION_DEPTH
  // The temporal accumulation resolves the two layers of the frame apart, each reprojected with
  // its own depth (glsl/render/temporal.comp): the cloud layer at the cloud's mean depth (0 where
  // no cloud is seen), the background (ground + sky, behind the clouds) at the ground's or the
  // host's distance, 0 for the sky (a point at infinity). Over several samples: the means, and the
  // last sample's depths.
  float background_m = min(VIEW_GLOBE ? tGround : float(tFlatGround), hostDistance);
  vec4 background = vec4(ground + sky, background_m < kNoHit_m ? background_m : 0.0);
  if (!first) background.rgb = runningMean(imageLoad(u_background, px), vec4(background.rgb, 0.0)).rgb;
  imageStore(u_background, px, background);
  imageStore(u_motion_depth, px, vec4(alpha > 0.0 ? meanDepth : 0.0));
#endif
  if (WRITE_PASSES) {
    // Z: the cloud's transmittance-weighted mean depth along the camera's view axis (planar depth,
    // as Nuke and Cycles read a Z channel); kNoCloudDepth_m where no cloud is seen.
    vec3 forward = u_world_from_view * vec3(0.0, 0.0, -1.0);
    float z = alpha > 0.0 ? meanDepth * dot(dir, forward) : kNoCloudDepth_m;
    // Over several samples: the mean of radiance and matte; Z the nearest cloud any sample saw.
    vec4 groundPass = vec4(ground, shadow), skyPass = vec4(sky, z);
    if (!first) {
      vec4 previousSky = imageLoad(u_pass_sky, px);
      groundPass = runningMean(imageLoad(u_pass_ground, px), groundPass);
      skyPass = vec4(runningMean(previousSky, skyPass).rgb, min(previousSky.w, z));
    }
    imageStore(u_pass_ground, px, groundPass);
    imageStore(u_pass_sky, px, skyPass);
  }
}
