#pragma once
// CPU reference of the eye pass (glsl/render/clouds.comp) in double precision: the same rays, step,
// sampling rule, phase mix, light and compositing, no jitter (pixel centres), no empty-space
// skipping. The deep light map enters as a function (the GPU map read back, so both use the
// same light): the comparison isolates the ray caster.
#include <functional>

#include <glm/glm.hpp>

#include "lighting/render_settings.h"
#include "scene/camera.h"
#include "scene/output_image.h"
#include "scene/sun.h"
#include "volume/extinction_volumes.h"
#include "volume/volume_frame.h"

namespace nph::reference {

/// The GPU ray caster's settings (lighting/render_settings.h); the marcher reads step_voxels,
/// min_transmittance, g_ice, g_water and ambient (no jitter, no empty-space skipping, no ground).
using RayMarchSettings = lighting::RenderSettings;

/// Premultiplied cloud layer (rgb = scattered light, a = 1 − transmittance), row 0 at the top.
scene::RgbaImage marchCloudLayer(const ExtinctionVolumes& volumes, const scene::VolumeFrame& frame,
                                 const scene::Camera& camera, const scene::Sun& sun,
                                 const std::function<double(const glm::dvec3&)>& sunlightAt,
                                 const RayMarchSettings& settings);

}  // namespace nph::reference
