#pragma once
// Every binding point and bit flag that C++ and GLSL share, declared once (issue #17 item 4;
// STYLE.md 4, after Filament's binding-point enums shared by C++ and GLSL).
//
// The list below is the single source of truth. cmake/embed_glsl.py reads NPH_GLSL_BINDINGS at
// build time and writes `#define NAME value` for each entry right after the #version line of every
// embedded stage file, so glslangValidator, the driver and this header all see the same numbers;
// C++ sees the entries as constants in nph::gl::binding. Shaders write
// `layout(binding = UNIT_ICE_PER_M) uniform sampler3D u_ice_per_m;` and C++ writes
// `glBindTextureUnit(binding::UNIT_ICE_PER_M, ...)`: no unit, image, buffer or block number is a
// literal on either side.
//
// Prefixes name the GL binding namespace (each has its own numbering, so the same number may
// appear under two prefixes): UNIT_ texture units (samplers, glBindTextureUnit), IMAGE_ image units
// (glBindImageTexture), SSBO_ shader-storage buffers and UBO_ uniform blocks (glBindBufferBase).
// Units only have to be distinct among the names one program uses together; the numbers are those
// the passes used before this header, so captures and logs read as before.
//
// The format is parsed by embed_glsl.py: one `X(NAME, value)` per line, value an integer literal
// valid in both languages (decimal, or hex with a `u` suffix for flags).
// clang-format off
#define NPH_GLSL_BINDINGS(X)                                                                      \
  /* Extinction volumes, glsl/dlm/volume.glsl (render/dlm/volume_textures.cpp) */                \
  X(UBO_VOLUME, 1)              /* VolumeBlock (render/gl/uniform_blocks.h) */                  \
  X(UNIT_ICE_PER_M, 0)          /* sampler3D: ice β_ext [1/m] */                                \
  X(UNIT_WATER_PER_M, 1)        /* sampler3D: water β_ext [1/m] */                              \
  X(UNIT_OCCUPANCY_PER_M, 2)    /* sampler3D: max β per occupancy brick [1/m] */                \
  X(UNIT_DETAIL_CONTROLS, 16)   /* sampler3D: RGBA8 sub-grid detail controls (volume/detail.h) */ \
  X(UNIT_DETAIL_NOISE, 17)      /* sampler3D: RGBA8 periodic noise tile (volume/noise.h) */     \
  X(UNIT_COLUMNS, 18)           /* sampler2D: RG32F per model column: detail mass correction (volume/detail.h), total τ T */ \
  X(UNIT_DETAIL_WIND, 31)       /* sampler3D: RG32F horizontal wind advecting the noise (volume/detail.h) */ \
  X(IMAGE_DETAIL_NOISE, 0)      /* image3D rgba8, written once by glsl/render/noise.comp */     \
  X(IMAGE_DETAIL_MASS, 0)       /* image2D rg32f: half-column masses (detail_mass.comp) */      \
  X(IMAGE_DETAIL_MASS_RANGE, 1) /* iimage2D rg32i: step range per column (detail_mass.comp) */   \
  /* Deep light map, glsl/dlm/{march,scatter,lookup}.glsl (render/dlm/deep_light_map.cpp) */     \
  X(UBO_LIGHT_SPACE, 0)         /* LightSpaceBlock (render/gl/uniform_blocks.h) */              \
  X(UNIT_SCATTER_MAP, 3)        /* sampler3D: peripheral light P per scatter cell (pass 3) */   \
  X(UNIT_DLM_NODES, 4)          /* sampler3D: RG32F (depth, intensity) node list per texel */   \
  X(UNIT_DLM_COUNTS, 5)         /* usampler2D: node count per texel | DLM_COUNT_UNBOUNDED */    \
  X(IMAGE_DLM_NODES, 0)         /* image3D rg32f, written by the compressor */                  \
  X(IMAGE_DLM_COUNTS, 1)        /* uimage2D r32ui */                                            \
  X(IMAGE_DLM_TEXEL_EPSILON, 2) /* image2D r32f: ε each texel was compressed with */            \
  X(IMAGE_SCATTER_MAP, 1)       /* image3D r32f, written by pass 2 (scatter.comp) */            \
  X(IMAGE_SCATTER_RUNS, 2)      /* iimage3D r16i: flat runs of the scatter map (scatter_runs.comp) */ \
  X(UNIT_SCATTER_RUNS, 6)       /* isampler3D: the same, read by pass 3 */                      \
  X(SSBO_LIGHT_VOLUME, 3)       /* float[]: uncompressed light volume (benchmark baseline) */   \
  X(SSBO_DLM_MARCH_STATS, 5)    /* uint[4]: steps marched, in runs, runs (issue 19), marches cut short */ \
  X(SSBO_DLM_RETRY_ARGS, 8)     /* uint[3·D]: indirect dispatch of the overflow rule's retries (issue 19) */ \
  X(IMAGE_LIGHT_CACHE, 0)       /* image3D r16f: the map's sunlight baked per world cell (light_cache.comp) */ \
  X(UNIT_LIGHT_CACHE, 19)       /* sampler3D: the same, read by the eye pass (issue 19) */      \
  X(UNIT_PACKED_VOLUME, 20)     /* sampler3D: RG16F (β_ice, β_water): eye pass; all passes when packed only (issue 19) */ \
  /* Monte Carlo radiance volume, glsl/dlm/radiance_volume*.comp (render/dlm/radiance_volume.cpp) */ \
  X(SSBO_MC_TALLY, 4)           /* uint[]: fixed-point SH tallies, (low, high) words per moment */ \
  X(SSBO_MC_STATS, 5)           /* uint[8]: collided, collisions, rouletted, cut, clamped, paused, cut short */ \
  X(SSBO_MC_PHOTONS, 6)         /* McPhoton[]: each photon's state between dispatches (seventeenth session) */ \
  X(IMAGE_MC_MOMENTS, 0)        /* image3D rgba32f[7]: the resolved moments (units 0–6) */      \
  X(UNIT_MC_MOMENTS, 24)        /* sampler3D[7]: the same, read by the eye pass (units 24–30) */ \
  /* Ray caster, glsl/render/clouds.comp and globe.glsl (render/raycast/cloud_renderer.cpp) */   \
  X(UBO_RAYCAST, 2)             /* RaycastBlock (render/gl/uniform_blocks.h) */                 \
  X(UBO_GLOBE, 3)               /* GlobeBlock (render/gl/uniform_blocks.h) */                   \
  X(UNIT_BASEMAP, 6)            /* sampler2D: flat-map ground albedo, linear RGB */             \
  X(UNIT_HOST_DEPTH, 7)         /* sampler2D: the host's depth buffer [0, 1] */                 \
  X(UNIT_GLOBE_WORLD_XY, 8)     /* sampler2D: RG32F world x, y per rotated lon/lat */           \
  X(UNIT_GLOBE_BASEMAP, 9)      /* sampler2D: equirectangular basemap, linear RGB */            \
  X(UNIT_COLUMN_DEPTH, 14)      /* sampler3D: vertical τ above: R16F (packed only) or RG16F (τ_up, T) (volume/column_depth.h) */ \
  X(UBO_TERRAIN, 5)             /* TerrainBlock (render/gl/uniform_blocks.h) */                 \
  X(UNIT_TERRAIN, 15)           /* sampler2D: R32F terrain height [m] per mass point (issue 14) */ \
  X(UNIT_FAR_TERRAIN, 21)       /* sampler2D: R32F far terrain height [m], a user DEM beyond the domain */ \
  X(UNIT_FAR_BASEMAP, 3)        /* sampler2D: basemap beyond the near one (UNIT_SCATTER_MAP is not in clouds.comp) */ \
  X(IMAGE_CLOUD_LAYER, 0)       /* image2D rgba32f: premultiplied cloud layer */                \
  X(IMAGE_FRAME, 1)             /* image2D rgba32f: clouds over the lit ground */               \
  X(IMAGE_SAMPLE_COUNT, 2)      /* uimage2D r32ui: volume samples per ray (statistics) */       \
  X(SSBO_RAYCAST_STATS, 7)      /* uint[1]: marches the driver's loop limiter ended (llvmpipe) */ \
  X(IMAGE_PASS_GROUND, 3)       /* image2D rgba32f: passes: ground radiance, shadow matte */    \
  X(IMAGE_PASS_SKY, 4)          /* image2D rgba32f: passes: sky radiance, cloud depth Z [m] */   \
  X(IMAGE_LOW_CLOUD_GUIDE, 5)   /* image2D rg32f: reduced-resolution clouds: (α·mean depth, march end) [m] */ \
  X(UNIT_LOW_CLOUD_LAYER, 22)   /* sampler2D: the reduced-resolution cloud layer, read by the upsampling pass */ \
  X(UNIT_LOW_CLOUD_GUIDE, 23)   /* sampler2D: its (α·mean depth, march end), the upsampling's depth guide */ \
  /* Temporal accumulation, glsl/render/temporal.comp (render/raycast/temporal_accumulation.cpp) */ \
  X(IMAGE_MOTION_DEPTH, 6)      /* image2D r32f: clouds.comp's cloud mean depth along the ray [m] (0 = none) */ \
  X(IMAGE_TEMPORAL_BACKGROUND, 7) /* image2D rgba32f: clouds.comp's background (ground + sky, its depth [m]; 0 = far) */ \
  X(UNIT_TEMPORAL_BACKGROUND, 5) /* sampler2D: the same, read by the resolve */                 \
  X(UNIT_TEMPORAL_HISTORY_COUNT, 6) /* sampler2D: the frames in the cloud layer's history */    \
  X(IMAGE_TEMPORAL_COUNT_OUT, 5) /* image2D r32f: the same, written */                          \
  X(UNIT_TEMPORAL_CLOUD, 1)     /* sampler2D: this frame's premultiplied cloud layer */         \
  X(UNIT_TEMPORAL_DEPTH, 2)     /* sampler2D: the cloud layer's mean depth (IMAGE_MOTION_DEPTH) */ \
  X(UNIT_TEMPORAL_HISTORY_BACKGROUND, 3) /* sampler2D: the resolved background so far, (RGB, n) */ \
  X(UNIT_TEMPORAL_HISTORY_CLOUD, 4) /* sampler2D: the resolved cloud layer so far */            \
  X(IMAGE_TEMPORAL_BACKGROUND_OUT, 3) /* image2D rgba32f: the resolved background, (RGB, n) */ \
  X(IMAGE_TEMPORAL_CLOUD_OUT, 4) /* image2D rgba32f: the resolved cloud layer */                \
  /* Atmosphere, glsl/atmosphere/ (render/atmosphere/atmosphere_luts.cpp) */                   \
  X(UBO_ATMOSPHERE, 4)          /* AtmosphereBlock (render/gl/uniform_blocks.h) */             \
  X(UNIT_TRANSMITTANCE_LUT, 10) /* sampler2D: transmittance to the top (r, mu) */              \
  X(UNIT_MULTISCATTERING_LUT, 11) /* sampler2D: Hillaire's Psi_ms (mu_s, r) */                  \
  X(UNIT_SKY_VIEW_LUT, 12)      /* sampler2D: sky radiance seen from the observer */           \
  X(UNIT_SKY_IRRADIANCE_LUT, 13) /* sampler2D: sky irradiance of a level surface (mu_s, h) */  \
  X(IMAGE_ATMOSPHERE_LUT, 0)    /* image2D rgba32f: the LUT a pass writes */                   \
  /* Display passes: glsl/api/composite.frag (api/compositor.cpp), glsl/render/present.frag */  \
  X(UNIT_COMPOSITE_LAYER, 0)    /* sampler2D: the cloud layer composited into the host */       \
  X(UNIT_PRESENT_FRAME, 0)      /* sampler2D: the frame the viewer shows (cli/view.cpp) */      \
  /* Tests and benchmarks: glsl/test, glsl/bench */                                              \
  X(IMAGE_TEST_OUT, 0)          /* image3D rgba32f: gradient3d.comp's output */                 \
  X(SSBO_TEST_POINTS, 0)        /* vec4[]: dlm_lookup.comp's input points */                   \
  X(SSBO_TEST_RESULTS, 1)       /* float[]: dlm_lookup.comp's results */                       \
  X(UNIT_BENCH_VOLUME, 0)       /* sampler3D: fetch3d.comp's volume */                          \
  X(IMAGE_BENCH_SUM, 0)         /* image2D r32f: fetch3d.comp's sums */                         \
  /* Bit flags stored in textures by one side and read by the other */                           \
  X(DLM_COUNT_UNBOUNDED, 0x80000000u)  /* count bit: the texel's ε bound was not kept */        \
  X(DLM_COUNT_MASK, 0x7fffffffu)       /* count bits proper: ~DLM_COUNT_UNBOUNDED */
// clang-format on

#include <string_view>

namespace nph::gl::binding {

#define NPH_GLSL_BINDING_CONSTANT(name, value) inline constexpr unsigned name = value;
NPH_GLSL_BINDINGS(NPH_GLSL_BINDING_CONSTANT)
#undef NPH_GLSL_BINDING_CONSTANT

static_assert(DLM_COUNT_MASK == ~DLM_COUNT_UNBOUNDED, "the count mask is the complement of the flag");

/// Every entry by name, for code that must cover a whole binding namespace (api/gl_state_guard.h).
struct Entry {
  std::string_view name;
  unsigned value;
};
#define NPH_GLSL_BINDING_ENTRY(name, value) Entry{#name, value},
inline constexpr Entry kAll[] = {NPH_GLSL_BINDINGS(NPH_GLSL_BINDING_ENTRY)};
#undef NPH_GLSL_BINDING_ENTRY

/// The highest binding number among the entries whose name starts with `prefix` ("UNIT_",
/// "IMAGE_", "SSBO_", "UBO_"); 0 when there is none.
constexpr unsigned highest(std::string_view prefix) {
  unsigned h = 0;
  for (const Entry& e : kAll) {
    if (e.name.starts_with(prefix) && e.value > h) h = e.value;
  }
  return h;
}

}  // namespace nph::gl::binding
