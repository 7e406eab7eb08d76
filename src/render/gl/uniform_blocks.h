#pragma once
// std140 uniform blocks shared by several passes, each declared once as a C++ struct with
// static_asserts on size and offsets (STYLE.md 4, after Filament's UibStructs.h; issue #17 item 4).
//
// std140 rules used here (GL 4.5 core spec §7.6.2.2): a float/int/bool takes 4 bytes aligned to 4
// (a bool is stored as a 32-bit word, non-zero = true); a vec2/ivec2 8 bytes aligned to 8; a
// vec3/ivec3 12 bytes aligned to 16, so a scalar may fill the fourth word after it; the block size
// is rounded up to 16. Each struct below mirrors its GLSL block member for member: the GLSL name
// of every member and its offset are listed in kMembers, and the GL test
// UniformBlocks.MatchTheLinkedPrograms checks each one against the driver's layout
// (GL_OFFSET, GL_BUFFER_DATA_SIZE) of every program that uses the block — a member added, moved
// or retyped on one side only fails there, not as a silently wrong picture.
//
// The blocks replace the groups of plain uniforms that several programs share (light space,
// volume): a program that does not read every member of a group has no inactive uniform to trip
// the strict-uniform check (program.h), and a group is uploaded once per change, not per program.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <glm/glm.hpp>

#include "render/gl/bindings.h"
#include "render/gl/objects.h"

namespace nph::gl {

/// One member of a uniform block: its GLSL name and its std140 byte offset in the C++ struct.
struct BlockMember {
  const char* glsl_name;
  std::size_t offset;
};

/// glsl/dlm/light_space.glsl `LightSpaceBlock`: the deep light map's light space
/// (scene/light_space.h), read by the DLM passes, the look-up and the ray caster.
struct LightSpaceBlock {
  static constexpr unsigned kBinding = binding::UBO_LIGHT_SPACE;
  static constexpr const char* kGlslName = "LightSpaceBlock";
  glm::vec3 origin_m{0.0f};  ///< u_ls_origin_m: world position of light-space (0, 0, 0)
  float depth_m = 0.0f;      ///< u_ls_depth_m: length of every light ray
  glm::vec3 u{0.0f};         ///< u_ls_u
  float pad_u = 0.0f;
  glm::vec3 v{0.0f};  ///< u_ls_v
  float pad_v = 0.0f;
  glm::vec3 w{0.0f};  ///< u_ls_w: the direction the sunlight travels
  float pad_w = 0.0f;
  glm::vec2 texel_m{0.0f};  ///< u_ls_texel_m: du, dv
  glm::ivec2 texels{0};     ///< u_ls_texels: nu, nv
};
static_assert(offsetof(LightSpaceBlock, origin_m) == 0 && offsetof(LightSpaceBlock, depth_m) == 12);
static_assert(offsetof(LightSpaceBlock, u) == 16 && offsetof(LightSpaceBlock, v) == 32 &&
              offsetof(LightSpaceBlock, w) == 48);
static_assert(offsetof(LightSpaceBlock, texel_m) == 64 && offsetof(LightSpaceBlock, texels) == 72);
static_assert(sizeof(LightSpaceBlock) == 80, "std140 size of LightSpaceBlock");
inline constexpr BlockMember kLightSpaceMembers[] = {{"u_ls_origin_m", offsetof(LightSpaceBlock, origin_m)},
                                                     {"u_ls_depth_m", offsetof(LightSpaceBlock, depth_m)},
                                                     {"u_ls_u", offsetof(LightSpaceBlock, u)},
                                                     {"u_ls_v", offsetof(LightSpaceBlock, v)},
                                                     {"u_ls_w", offsetof(LightSpaceBlock, w)},
                                                     {"u_ls_texel_m", offsetof(LightSpaceBlock, texel_m)},
                                                     {"u_ls_texels", offsetof(LightSpaceBlock, texels)}};

/// glsl/dlm/volume.glsl `VolumeBlock`: where the extinction volumes sit and what they hold
/// (render/dlm/volume_textures.h), read by every pass that samples them.
struct VolumeBlock {
  static constexpr unsigned kBinding = binding::UBO_VOLUME;
  static constexpr const char* kGlslName = "VolumeBlock";
  glm::vec3 box_min_m{0.0f};        ///< u_box_min_m: world AABB of the volume
  std::int32_t brick_voxels = 0;    ///< u_brick_voxels: occupancy brick side [voxels]
  glm::vec3 box_size_m{0.0f};       ///< u_box_size_m
  std::uint32_t has_ice = 0;        ///< u_has_ice (bool): absent phases are never fetched
  glm::ivec3 voxels{0};             ///< u_voxels
  std::uint32_t has_water = 0;      ///< u_has_water (bool)
  std::int32_t reconstruction = 0;  ///< u_reconstruction: volume::Reconstruction (0 trilinear, 1 cubic)
  float reach_voxels = 1.0f;        ///< u_reach_voxels: reachVoxels(reconstruction) + the detail's reach
  std::int32_t detail = 0;          ///< u_detail: volume::Detail (0 none, 1 subtle, 2 full)
  float detail_amplitude = 0.0f;    ///< u_detail_amplitude (volume/detail.h)
  glm::vec3 noise_period_m{1.0f};   ///< u_noise_period_m: world metres per noise tile
  /// u_packed_beta_unit_per_m: β's unit in the packed RGBA16F texture (VolumeTextures::hasPacked)
  float packed_beta_unit_per_m = 0.0f;
  glm::vec3 displacement_m{0.0f};  ///< u_displacement_m: displacement cap per axis
  /// u_packed_only (bool): every pass reads β and the column depths from the packed texture (no
  /// separate ice, water and column-depth textures: VolumeStorage::Compact)
  std::uint32_t packed_only = 0;
  glm::vec4 noise_stats_ra{0.0f, 1.0f, 0.0f, 1.0f};  ///< u_noise_stats_ra: (mean, half range) of r, a
  glm::vec4 noise_stats_gs{0.0f, 1.0f, 0.0f, 1.0f};  ///< u_noise_stats_gs: of g, the stratiform term
  glm::vec4 noise_stats_c{0.0f, 1.0f, 0.0f, 0.0f};   ///< u_noise_stats_c: of the convective term
  /// u_detail_flow: (τ_a, τ_b [s], phase a's weight, wind 1/0) of the noise's advection (volume/detail.h
  /// DetailFlow); (0, 0, 1, 0) without a wind: the world-fixed noise.
  glm::vec4 detail_flow{0.0f, 0.0f, 1.0f, 0.0f};
};
static_assert(offsetof(VolumeBlock, box_min_m) == 0 && offsetof(VolumeBlock, brick_voxels) == 12);
static_assert(offsetof(VolumeBlock, box_size_m) == 16 && offsetof(VolumeBlock, has_ice) == 28);
static_assert(offsetof(VolumeBlock, voxels) == 32 && offsetof(VolumeBlock, has_water) == 44);
static_assert(offsetof(VolumeBlock, reconstruction) == 48 && offsetof(VolumeBlock, reach_voxels) == 52);
static_assert(offsetof(VolumeBlock, detail) == 56 && offsetof(VolumeBlock, detail_amplitude) == 60);
static_assert(offsetof(VolumeBlock, noise_period_m) == 64 && offsetof(VolumeBlock, displacement_m) == 80);
static_assert(offsetof(VolumeBlock, packed_beta_unit_per_m) == 76 && offsetof(VolumeBlock, packed_only) == 92);
static_assert(offsetof(VolumeBlock, noise_stats_ra) == 96 && offsetof(VolumeBlock, noise_stats_gs) == 112);
static_assert(offsetof(VolumeBlock, noise_stats_c) == 128 && offsetof(VolumeBlock, detail_flow) == 144);
static_assert(sizeof(VolumeBlock) == 160, "std140 size of VolumeBlock");
inline constexpr BlockMember kVolumeMembers[] = {
    {"u_box_min_m", offsetof(VolumeBlock, box_min_m)},
    {"u_brick_voxels", offsetof(VolumeBlock, brick_voxels)},
    {"u_box_size_m", offsetof(VolumeBlock, box_size_m)},
    {"u_has_ice", offsetof(VolumeBlock, has_ice)},
    {"u_voxels", offsetof(VolumeBlock, voxels)},
    {"u_has_water", offsetof(VolumeBlock, has_water)},
    {"u_reconstruction", offsetof(VolumeBlock, reconstruction)},
    {"u_reach_voxels", offsetof(VolumeBlock, reach_voxels)},
    {"u_detail", offsetof(VolumeBlock, detail)},
    {"u_detail_amplitude", offsetof(VolumeBlock, detail_amplitude)},
    {"u_noise_period_m", offsetof(VolumeBlock, noise_period_m)},
    {"u_packed_beta_unit_per_m", offsetof(VolumeBlock, packed_beta_unit_per_m)},
    {"u_displacement_m", offsetof(VolumeBlock, displacement_m)},
    {"u_packed_only", offsetof(VolumeBlock, packed_only)},
    {"u_noise_stats_ra", offsetof(VolumeBlock, noise_stats_ra)},
    {"u_noise_stats_gs", offsetof(VolumeBlock, noise_stats_gs)},
    {"u_noise_stats_c", offsetof(VolumeBlock, noise_stats_c)},
    {"u_detail_flow", offsetof(VolumeBlock, detail_flow)}};

/// std140 mat3: three columns, each padded to a vec4 (GL 4.5 §7.6.2.2 rules 5 and 4).
struct Std140Mat3 {
  glm::vec4 columns[3]{};
  Std140Mat3() = default;
  explicit Std140Mat3(const glm::mat3& m)
      : columns{glm::vec4(m[0], 0.0f), glm::vec4(m[1], 0.0f), glm::vec4(m[2], 0.0f)} {}
};
static_assert(sizeof(Std140Mat3) == 48);

/// glsl/render/clouds.comp `RaycastBlock`: the eye pass's view, light and switches, set per
/// dispatch (render/raycast/cloud_renderer.cpp). Bools are 32-bit words (0 or 1).
struct RaycastBlock {
  static constexpr unsigned kBinding = binding::UBO_RAYCAST;
  static constexpr const char* kGlslName = "RaycastBlock";
  glm::mat4 view_from_clip{1.0f};    ///< u_view_from_clip: inverse projection
  Std140Mat3 world_from_view;        ///< u_world_from_view: view axes in world
  glm::vec3 cam_pos_m{0.0f};         ///< u_cam_pos_m
  float step_m = 0.0f;               ///< u_step_m: eye-ray step Δ
  glm::vec3 to_sun{0.0f};            ///< u_to_sun: unit, towards the sun
  float min_transmittance = 0.0f;    ///< u_min_transmittance: early ray termination
  glm::vec3 sun_radiance{0.0f};      ///< u_sun_radiance: colour · intensity
  float g_ice = 0.0f;                ///< u_g_ice: HG asymmetry of ice
  glm::vec3 sky_radiance{0.0f};      ///< u_sky_radiance: upper hemisphere (clear sky), radiance
  float g_water = 0.0f;              ///< u_g_water: HG asymmetry of water
  glm::vec3 ocean_albedo{0.0f};      ///< u_ocean_albedo: ground albedo outside the basemap
  std::uint32_t jitter = 0;          ///< u_jitter (bool)
  glm::vec2 basemap_min_m{0.0f};     ///< u_basemap_min_m
  glm::vec2 basemap_max_m{0.0f};     ///< u_basemap_max_m
  glm::ivec2 size{0};                ///< u_size: image width, height [pixels]
  std::uint32_t has_host_depth = 0;  ///< u_has_host_depth (bool)
  std::uint32_t skip_empty = 0;      ///< u_skip_empty (bool)
  std::uint32_t shadows = 0;         ///< u_shadows (bool)
  std::uint32_t has_basemap = 0;     ///< u_has_basemap (bool)
  std::uint32_t count_samples = 0;   ///< u_count_samples (bool)
  std::uint32_t globe = 0;           ///< u_globe (bool): rays in ECEF, GlobeBlock valid
  glm::vec3 below_radiance{0.0f};    ///< u_below_radiance: lower hemisphere (ground bounce), radiance
  float ms_extinction_scale = 1.0f;  ///< u_ms_extinction_scale: octave series a
  float ms_energy_scale = 0.0f;      ///< u_ms_energy_scale: octave series b
  float ms_anisotropy_scale = 1.0f;  ///< u_ms_anisotropy_scale: octave series c
  std::int32_t octaves = 1;          ///< u_octaves: octave series N (1 = single scattering)
  float height_exaggeration = 1.0f;  ///< u_height_exaggeration: e of the volume frame
  std::uint32_t atmosphere = 0;      ///< u_atmosphere (bool): AtmosphereBlock and its tables valid
  std::uint32_t write_passes = 0;    ///< u_write_passes (bool): fill the compositing-pass images
  std::int32_t cloud_ms_model = 0;   ///< u_cloud_ms_model: lighting::MultipleScattering (0 … 3)
  float step_growth_max = 1.0f;      ///< u_step_growth_max: adaptive steps up to this × Δ (1 = fixed)
  glm::vec2 subpixel{0.5f};          ///< u_subpixel: this sample's position inside the pixel [0, 1)²
  std::uint32_t sample_index = 0;    ///< u_sample_index: k of samples_per_pixel; k > 0 averages into the images
  /// u_jitter_index: the sample's index in the jitter and sub-pixel sequence, k + RenderSettings::
  /// sample_offset (the temporal accumulation gives each frame its own; = sample_index without it)
  std::uint32_t jitter_index = 0;
};
static_assert(offsetof(RaycastBlock, world_from_view) == 64 && offsetof(RaycastBlock, cam_pos_m) == 112 &&
              offsetof(RaycastBlock, step_m) == 124);
static_assert(offsetof(RaycastBlock, to_sun) == 128 && offsetof(RaycastBlock, sun_radiance) == 144 &&
              offsetof(RaycastBlock, sky_radiance) == 160 && offsetof(RaycastBlock, ocean_albedo) == 176 &&
              offsetof(RaycastBlock, jitter) == 188);
static_assert(offsetof(RaycastBlock, basemap_min_m) == 192 && offsetof(RaycastBlock, size) == 208 &&
              offsetof(RaycastBlock, skip_empty) == 220 && offsetof(RaycastBlock, globe) == 236);
static_assert(offsetof(RaycastBlock, below_radiance) == 240 && offsetof(RaycastBlock, ms_extinction_scale) == 252 &&
              offsetof(RaycastBlock, octaves) == 264 && offsetof(RaycastBlock, height_exaggeration) == 268);
static_assert(offsetof(RaycastBlock, atmosphere) == 272 && offsetof(RaycastBlock, write_passes) == 276 &&
              offsetof(RaycastBlock, cloud_ms_model) == 280 && offsetof(RaycastBlock, step_growth_max) == 284);
static_assert(offsetof(RaycastBlock, subpixel) == 288 && offsetof(RaycastBlock, sample_index) == 296 &&
              offsetof(RaycastBlock, jitter_index) == 300);
static_assert(sizeof(RaycastBlock) == 304, "std140 size of RaycastBlock, rounded to 16");
inline constexpr BlockMember kRaycastMembers[] = {
    {"u_view_from_clip", offsetof(RaycastBlock, view_from_clip)},
    {"u_world_from_view", offsetof(RaycastBlock, world_from_view)},
    {"u_cam_pos_m", offsetof(RaycastBlock, cam_pos_m)},
    {"u_step_m", offsetof(RaycastBlock, step_m)},
    {"u_to_sun", offsetof(RaycastBlock, to_sun)},
    {"u_min_transmittance", offsetof(RaycastBlock, min_transmittance)},
    {"u_sun_radiance", offsetof(RaycastBlock, sun_radiance)},
    {"u_g_ice", offsetof(RaycastBlock, g_ice)},
    {"u_sky_radiance", offsetof(RaycastBlock, sky_radiance)},
    {"u_g_water", offsetof(RaycastBlock, g_water)},
    {"u_ocean_albedo", offsetof(RaycastBlock, ocean_albedo)},
    {"u_jitter", offsetof(RaycastBlock, jitter)},
    {"u_basemap_min_m", offsetof(RaycastBlock, basemap_min_m)},
    {"u_basemap_max_m", offsetof(RaycastBlock, basemap_max_m)},
    {"u_size", offsetof(RaycastBlock, size)},
    {"u_has_host_depth", offsetof(RaycastBlock, has_host_depth)},
    {"u_skip_empty", offsetof(RaycastBlock, skip_empty)},
    {"u_shadows", offsetof(RaycastBlock, shadows)},
    {"u_has_basemap", offsetof(RaycastBlock, has_basemap)},
    {"u_count_samples", offsetof(RaycastBlock, count_samples)},
    {"u_globe", offsetof(RaycastBlock, globe)},
    {"u_below_radiance", offsetof(RaycastBlock, below_radiance)},
    {"u_ms_extinction_scale", offsetof(RaycastBlock, ms_extinction_scale)},
    {"u_ms_energy_scale", offsetof(RaycastBlock, ms_energy_scale)},
    {"u_ms_anisotropy_scale", offsetof(RaycastBlock, ms_anisotropy_scale)},
    {"u_octaves", offsetof(RaycastBlock, octaves)},
    {"u_height_exaggeration", offsetof(RaycastBlock, height_exaggeration)},
    {"u_atmosphere", offsetof(RaycastBlock, atmosphere)},
    {"u_write_passes", offsetof(RaycastBlock, write_passes)},
    {"u_cloud_ms_model", offsetof(RaycastBlock, cloud_ms_model)},
    {"u_step_growth_max", offsetof(RaycastBlock, step_growth_max)},
    {"u_subpixel", offsetof(RaycastBlock, subpixel)},
    {"u_sample_index", offsetof(RaycastBlock, sample_index)},
    {"u_jitter_index", offsetof(RaycastBlock, jitter_index)}};

/// glsl/render/globe.glsl `GlobeBlock`: the globe view's mapping (render/raycast/globe.h), read
/// only when RaycastBlock::globe is set.
struct GlobeBlock {
  static constexpr unsigned kBinding = binding::UBO_GLOBE;
  static constexpr const char* kGlslName = "GlobeBlock";
  Std140Mat3 local_from_ecef;           ///< u_local_from_ecef: rows east, north, up
  glm::vec3 cap_axis{0.0f};             ///< u_cap_axis: unit ECEF of the footprint centre
  float cap_min_dot_m = 0.0f;           ///< u_cap_min_dot_m: (R + z_min)·cos α
  glm::vec3 sphere_c_m2{0.0f};          ///< u_sphere_c_m2: |o|² − r² (ground, lens top) [m²]
  float lipschitz_h = 0.0f;             ///< u_lipschitz_h: world-xy m per ECEF m, upper bound
  glm::vec3 limb_radiance{0.0f};        ///< u_limb_radiance
  float earth_radius_m = 0.0f;          ///< u_earth_radius_m
  glm::vec2 ab_min_rad{0.0f};           ///< u_ab_min_rad: rotated lon/lat box of the table
  glm::vec2 ab_max_rad{0.0f};           ///< u_ab_max_rad
  std::uint32_t has_globe_basemap = 0;  ///< u_has_globe_basemap (bool)
  // Terrain on the globe (glsl/render/globe_terrain.glsl; CloudRenderer::updateGlobeBlock):
  float terrain_cap_min_dot_m = 0.0f;  ///< u_terrain_cap_min_dot_m: (R + min − 1 m)·cos α_table
  float terrain_rate = 1.0f;           ///< u_terrain_rate: bound of |df/dt| along a ray
  float terrain_edge_m = 1.0f;         ///< u_terrain_edge_m: the table's margin (heights ramp to 0)
  glm::vec2 terrain_c_m2{0.0f};        ///< u_terrain_c_m2: |o|² − r², r = R + max, R + min − 1 m
  std::uint32_t pad[2] = {0, 0};       ///< to a multiple of 16 bytes (std140 block rounding)
};
static_assert(offsetof(GlobeBlock, cap_axis) == 48 && offsetof(GlobeBlock, cap_min_dot_m) == 60 &&
              offsetof(GlobeBlock, sphere_c_m2) == 64 && offsetof(GlobeBlock, lipschitz_h) == 76);
static_assert(offsetof(GlobeBlock, limb_radiance) == 80 && offsetof(GlobeBlock, earth_radius_m) == 92 &&
              offsetof(GlobeBlock, ab_min_rad) == 96 && offsetof(GlobeBlock, ab_max_rad) == 104 &&
              offsetof(GlobeBlock, has_globe_basemap) == 112);
static_assert(offsetof(GlobeBlock, terrain_cap_min_dot_m) == 116 && offsetof(GlobeBlock, terrain_rate) == 120 &&
              offsetof(GlobeBlock, terrain_edge_m) == 124 && offsetof(GlobeBlock, terrain_c_m2) == 128);
static_assert(sizeof(GlobeBlock) == 144, "std140 size of GlobeBlock, rounded to 16");
inline constexpr BlockMember kGlobeMembers[] = {
    {"u_local_from_ecef", offsetof(GlobeBlock, local_from_ecef)},
    {"u_cap_axis", offsetof(GlobeBlock, cap_axis)},
    {"u_cap_min_dot_m", offsetof(GlobeBlock, cap_min_dot_m)},
    {"u_sphere_c_m2", offsetof(GlobeBlock, sphere_c_m2)},
    {"u_lipschitz_h", offsetof(GlobeBlock, lipschitz_h)},
    {"u_limb_radiance", offsetof(GlobeBlock, limb_radiance)},
    {"u_earth_radius_m", offsetof(GlobeBlock, earth_radius_m)},
    {"u_ab_min_rad", offsetof(GlobeBlock, ab_min_rad)},
    {"u_ab_max_rad", offsetof(GlobeBlock, ab_max_rad)},
    {"u_has_globe_basemap", offsetof(GlobeBlock, has_globe_basemap)},
    {"u_terrain_cap_min_dot_m", offsetof(GlobeBlock, terrain_cap_min_dot_m)},
    {"u_terrain_rate", offsetof(GlobeBlock, terrain_rate)},
    {"u_terrain_edge_m", offsetof(GlobeBlock, terrain_edge_m)},
    {"u_terrain_c_m2", offsetof(GlobeBlock, terrain_c_m2)}};

/// glsl/render/clouds.comp `TerrainBlock` (issue 14): the ground's height field
/// (volume/terrain_field.h; the march of glsl/common/terrain.glsl) and the far basemap that
/// carries the ground beyond the near one (item 4, no void, flat view only). The globe marches the
/// same height field (glsl/render/globe_terrain.glsl, with GlobeBlock's terrain members).
struct TerrainBlock {
  static constexpr unsigned kBinding = binding::UBO_TERRAIN;
  static constexpr const char* kGlslName = "TerrainBlock";
  glm::ivec2 size{1};                 ///< u_terrain_size: mass points nx, ny
  glm::vec2 cell_m{1.0f};             ///< u_terrain_cell_m: world dx, dy
  float exaggeration = 1.0f;          ///< u_terrain_exaggeration
  float fade_m = 1.0f;                ///< u_terrain_fade_m
  float max_m = 0.0f;                 ///< u_terrain_max_m: highest world height (≥ 0)
  float min_m = 0.0f;                 ///< u_terrain_min_m: lowest world height (≤ 0)
  float lipschitz = 0.0f;             ///< u_terrain_lipschitz: slope bound
  std::uint32_t has_terrain = 0;      ///< u_has_terrain (bool): displaced ground
  glm::vec2 far_basemap_min_m{0.0f};  ///< u_far_basemap_min_m
  glm::vec2 far_basemap_max_m{0.0f};  ///< u_far_basemap_max_m
  std::uint32_t has_far_basemap = 0;  ///< u_has_far_basemap (bool)
  /// u_city_lights: the night side's lights, k of glsl/common/night_lights.glsl (0 = none; both views)
  float city_lights = 0.0f;
  /// The far height field (a user DEM beyond the domain, scene/dem.h; flat view only):
  glm::ivec2 far_terrain_size{1};      ///< u_far_terrain_size: its pixels
  glm::vec2 far_terrain_min_m{0.0f};   ///< u_far_terrain_min_m: its world rectangle's south-west corner
  glm::vec2 far_terrain_cell_m{1.0f};  ///< u_far_terrain_cell_m: its pixel size
  std::uint32_t has_far_terrain = 0;   ///< u_has_far_terrain (bool)
  /// Ground detail (glsl/common/ground_tint.glsl; style knobs ground_tint, snow_line_m):
  std::uint32_t ground_tint = 0;  ///< u_ground_tint (bool): snow and rock from the terrain
  float snow_line_m = 2700.0f;    ///< u_snow_line_m [m above MSL]
  std::uint32_t pad[3] = {};      ///< to a multiple of 16 bytes (std140 block rounding)
};
static_assert(offsetof(TerrainBlock, cell_m) == 8 && offsetof(TerrainBlock, exaggeration) == 16 &&
              offsetof(TerrainBlock, lipschitz) == 32 && offsetof(TerrainBlock, has_terrain) == 36);
static_assert(offsetof(TerrainBlock, far_basemap_min_m) == 40 && offsetof(TerrainBlock, far_basemap_max_m) == 48 &&
              offsetof(TerrainBlock, has_far_basemap) == 56 && offsetof(TerrainBlock, city_lights) == 60);
static_assert(offsetof(TerrainBlock, far_terrain_size) == 64 && offsetof(TerrainBlock, far_terrain_min_m) == 72 &&
              offsetof(TerrainBlock, far_terrain_cell_m) == 80 && offsetof(TerrainBlock, has_far_terrain) == 88);
static_assert(offsetof(TerrainBlock, ground_tint) == 92 && offsetof(TerrainBlock, snow_line_m) == 96);
static_assert(sizeof(TerrainBlock) == 112, "std140 size of TerrainBlock, rounded to 16");
inline constexpr BlockMember kTerrainMembers[] = {{"u_terrain_size", offsetof(TerrainBlock, size)},
                                                  {"u_terrain_cell_m", offsetof(TerrainBlock, cell_m)},
                                                  {"u_terrain_exaggeration", offsetof(TerrainBlock, exaggeration)},
                                                  {"u_terrain_fade_m", offsetof(TerrainBlock, fade_m)},
                                                  {"u_terrain_max_m", offsetof(TerrainBlock, max_m)},
                                                  {"u_terrain_min_m", offsetof(TerrainBlock, min_m)},
                                                  {"u_terrain_lipschitz", offsetof(TerrainBlock, lipschitz)},
                                                  {"u_has_terrain", offsetof(TerrainBlock, has_terrain)},
                                                  {"u_far_basemap_min_m", offsetof(TerrainBlock, far_basemap_min_m)},
                                                  {"u_far_basemap_max_m", offsetof(TerrainBlock, far_basemap_max_m)},
                                                  {"u_has_far_basemap", offsetof(TerrainBlock, has_far_basemap)},
                                                  {"u_city_lights", offsetof(TerrainBlock, city_lights)},
                                                  {"u_far_terrain_size", offsetof(TerrainBlock, far_terrain_size)},
                                                  {"u_far_terrain_min_m", offsetof(TerrainBlock, far_terrain_min_m)},
                                                  {"u_far_terrain_cell_m", offsetof(TerrainBlock, far_terrain_cell_m)},
                                                  {"u_has_far_terrain", offsetof(TerrainBlock, has_far_terrain)},
                                                  {"u_ground_tint", offsetof(TerrainBlock, ground_tint)},
                                                  {"u_snow_line_m", offsetof(TerrainBlock, snow_line_m)}};

/// glsl/atmosphere/model.glsl `AtmosphereBlock`: the atmosphere's constants (atmosphere/atmosphere.h
/// Parameters) and the sky-view table's observer and sun (render/atmosphere/atmosphere_luts.h).
struct AtmosphereBlock {
  static constexpr unsigned kBinding = binding::UBO_ATMOSPHERE;
  static constexpr const char* kGlslName = "AtmosphereBlock";
  glm::vec3 rayleigh_scattering_per_m{0.0f};    ///< u_rayleigh_scattering_per_m
  float bottom_radius_m = 0.0f;                 ///< u_bottom_radius_m
  glm::vec3 mie_scattering_per_m{0.0f};         ///< u_mie_scattering_per_m
  float top_radius_m = 0.0f;                    ///< u_top_radius_m
  glm::vec3 mie_extinction_per_m{0.0f};         ///< u_mie_extinction_per_m
  float rayleigh_scale_height_m = 0.0f;         ///< u_rayleigh_scale_height_m
  glm::vec3 ozone_absorption_per_m{0.0f};       ///< u_ozone_absorption_per_m
  float mie_scale_height_m = 0.0f;              ///< u_mie_scale_height_m
  glm::vec3 ground_albedo{0.0f};                ///< u_ground_albedo
  float mie_g = 0.0f;                           ///< u_mie_g
  glm::vec3 sky_view_to_sun{0.0f, 0.0f, 1.0f};  ///< u_sky_view_to_sun
  float ozone_center_m = 0.0f;                  ///< u_ozone_center_m
  float ozone_half_width_m = 0.0f;              ///< u_ozone_half_width_m
  float sun_angular_radius_rad = 0.0f;          ///< u_sun_angular_radius_rad
  float sky_view_radius_m = 0.0f;               ///< u_sky_view_radius_m
  std::uint32_t multiple_scattering = 0;        ///< u_multiple_scattering (bool)
};
static_assert(offsetof(AtmosphereBlock, bottom_radius_m) == 12 &&
              offsetof(AtmosphereBlock, mie_scattering_per_m) == 16 && offsetof(AtmosphereBlock, top_radius_m) == 28 &&
              offsetof(AtmosphereBlock, mie_extinction_per_m) == 32);
static_assert(offsetof(AtmosphereBlock, ozone_absorption_per_m) == 48 &&
              offsetof(AtmosphereBlock, ground_albedo) == 64 && offsetof(AtmosphereBlock, sky_view_to_sun) == 80 &&
              offsetof(AtmosphereBlock, ozone_half_width_m) == 96 &&
              offsetof(AtmosphereBlock, multiple_scattering) == 108);
static_assert(sizeof(AtmosphereBlock) == 112, "std140 size of AtmosphereBlock");
inline constexpr BlockMember kAtmosphereMembers[] = {
    {"u_rayleigh_scattering_per_m", offsetof(AtmosphereBlock, rayleigh_scattering_per_m)},
    {"u_bottom_radius_m", offsetof(AtmosphereBlock, bottom_radius_m)},
    {"u_mie_scattering_per_m", offsetof(AtmosphereBlock, mie_scattering_per_m)},
    {"u_top_radius_m", offsetof(AtmosphereBlock, top_radius_m)},
    {"u_mie_extinction_per_m", offsetof(AtmosphereBlock, mie_extinction_per_m)},
    {"u_rayleigh_scale_height_m", offsetof(AtmosphereBlock, rayleigh_scale_height_m)},
    {"u_ozone_absorption_per_m", offsetof(AtmosphereBlock, ozone_absorption_per_m)},
    {"u_mie_scale_height_m", offsetof(AtmosphereBlock, mie_scale_height_m)},
    {"u_ground_albedo", offsetof(AtmosphereBlock, ground_albedo)},
    {"u_mie_g", offsetof(AtmosphereBlock, mie_g)},
    {"u_sky_view_to_sun", offsetof(AtmosphereBlock, sky_view_to_sun)},
    {"u_ozone_center_m", offsetof(AtmosphereBlock, ozone_center_m)},
    {"u_ozone_half_width_m", offsetof(AtmosphereBlock, ozone_half_width_m)},
    {"u_sun_angular_radius_rad", offsetof(AtmosphereBlock, sun_angular_radius_rad)},
    {"u_sky_view_radius_m", offsetof(AtmosphereBlock, sky_view_radius_m)},
    {"u_multiple_scattering", offsetof(AtmosphereBlock, multiple_scattering)}};

/// A uniform buffer holding one `Block`, bound to the block's binding point (bindings.h).
template <class Block>
class UniformBuffer {
 public:
  UniformBuffer() = default;
  static UniformBuffer create(const Block& contents, std::string_view label) {
    UniformBuffer b;
    b.buffer_ = Buffer::create(sizeof(Block), &contents).label(label);
    return b;
  }
  void update(const Block& contents) { buffer_.upload(0, sizeof(Block), &contents); }
  /// glBindBufferBase(GL_UNIFORM_BUFFER, Block::kBinding, ...): every program that declares the
  /// block reads this buffer until something else is bound there.
  void bind() const { glBindBufferBase(GL_UNIFORM_BUFFER, Block::kBinding, buffer_.id()); }
  explicit operator bool() const { return bool(buffer_.id()); }

 private:
  Buffer buffer_;
};

}  // namespace nph::gl
