#pragma once
// CPU reference of the eye pass (glsl/render/clouds.comp) in double precision: the same rays, step,
// sampling rule, phase mix, light and compositing, no jitter (pixel centres), no empty-space
// skipping. The deep light map enters as a function (the GPU map read back, so both use the
// same light): the comparison isolates the ray caster.
#include <functional>

#include <glm/glm.hpp>

#include "lighting/cloud_light.h"
#include "lighting/render_settings.h"
#include "reference/mc_radiance_volume.h"
#include "scene/camera.h"
#include "scene/output_image.h"
#include "scene/sun.h"
#include "volume/column_depth.h"
#include "volume/extinction_volumes.h"
#include "volume/terrain_field.h"
#include "volume/volume_frame.h"

namespace nph::reference {

/// The GPU ray caster's settings (lighting/render_settings.h); the marcher reads step_voxels,
/// min_transmittance, g_ice, g_water, ambient and octaves (no jitter, no empty-space skipping,
/// no ground).
using RayMarchSettings = lighting::RenderSettings;

/// One sample of a view ray with β > 0: its point, the share of the light it sends to the eye
/// that reaches the eye, w = T_acc·(1 − e^{−βΔ}), and β_ice/β.
struct RaySample {
  glm::dvec3 position_m{0.0};
  double weight = 0.0;
  double ice_weight = 0.0;
};
using SampleVisitor = std::function<void(int x, int y, const glm::dvec3& dir, const RaySample& sample)>;
using RayEndVisitor = std::function<void(int x, int y, double transmittance)>;

/// The eye pass's march (pixel-centre rays, step × the smallest voxel side, midpoint samples,
/// stop below `min_transmittance`, β by `reconstruction` and `detail`): `visit` for every sample front to back, `end`
/// once per ray with its final transmittance. Rows run in parallel (TBB): the visitors must only touch their own
/// pixel's data. With `terrain` (present) a ray ends where it meets the displaced ground, as the GPU's does
/// (glsl/common/terrain.glsl, the same code compiled as C++).
void marchSamples(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame, const scene::Camera& camera,
                  double step_voxels, double min_transmittance, const SampleVisitor& visit, const RayEndVisitor& end,
                  volume::Reconstruction reconstruction = volume::Reconstruction::Trilinear,
                  const volume::TerrainField* terrain = nullptr, volume::Detail detail = volume::Detail::None);

/// The sky light a sample scatters towards the eye (glsl/render/clouds.comp skyLightAt):
/// the mean radiance of its Eddington column lit by L_above and L_below (lighting::skyDiffuse, with the
/// exaggeration's vertical diffusion) with g the sample's β-weighted asymmetry.
glm::dvec3 sampleSkyLight(const lighting::SkyLight& sky, const ColumnDepths& depths, const volume::VolumeFrame& frame,
                          const RaySample& sample, const RayMarchSettings& settings);

/// Premultiplied cloud layer (rgb = scattered light, a = 1 − transmittance), row 0 at the top.
/// With settings.terrain, rays end at the volumes' terrain (the GPU's rule). With
/// multiple_scattering = radiance_volume the sun term adds max(J, 0) of `radiance_volume` (l ≤ its
/// max_l; the eye pass's glsl/common/radiance_volume.glsl), none when it is null.
scene::RgbaImage marchCloudLayer(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame,
                                 const scene::Camera& camera, const scene::Sun& sun,
                                 const std::function<double(const glm::dvec3&)>& sunlightAt,
                                 const RayMarchSettings& settings, const McRadianceVolume* radiance_volume = nullptr);

}  // namespace nph::reference
