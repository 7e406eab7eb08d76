#include "reference/ray_marcher.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "lighting/cloud_light.h"
#include "volume/column_depth.h"
#include "volume/extinction_sampler.h"

namespace nph::reference {

void marchSamples(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame, const scene::Camera& camera,
                  double step_voxels, double min_transmittance, const SampleVisitor& visit, const RayEndVisitor& end,
                  volume::Reconstruction reconstruction, const volume::TerrainField* terrain, volume::Detail detail) {
  const volume::ExtinctionSampler sampler(volumes, frame, reconstruction, detail);
  const glm::dvec3 voxel = frame.voxel_size_m;
  const double step = step_voxels * std::min({voxel.x, voxel.y, voxel.z});
  const double reach = volume::reachVoxels(reconstruction) + sampler.detail().reach_voxels;
  const glm::dvec3 lo = frame.min_m() - reach * voxel, hi = frame.max_m() + reach * voxel;  // β is 0 beyond
  tbb::parallel_for(0, camera.height, [&](int y) {
    for (int x = 0; x < camera.width; ++x) {
      const glm::dvec3 dir = camera.rayDirection(x + 0.5, y + 0.5);
      // the angle between neighbouring pixels' rays: the detail's footprint (clouds.comp pixelAngle)
      const double pixelAngle = glm::length(camera.rayDirection(x + 1.5, y + 0.5) - dir);
      const glm::dvec3 o = camera.position_m;
      // Slab test against the grown box.
      double t0 = 0.0, t1 = 1e300;
      for (int a = 0; a < 3; ++a) {
        if (dir[a] == 0.0) {
          if (o[a] < lo[a] || o[a] > hi[a]) t1 = -1.0;
          continue;
        }
        double ta = (lo[a] - o[a]) / dir[a], tb = (hi[a] - o[a]) / dir[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (terrain != nullptr && terrain->present() && t0 < t1) {  // the ground ends the ray (clouds.comp)
        const double ground = terrain->hitDistance(o, dir, 0.0, 3.0e38);
        if (ground >= 0.0) t1 = std::min(t1, ground);
      }
      double T = 1.0;
      const double depthScale = frame.opticalDepthScale(dir);  // the data's τ (VolumeFrame)
      for (double t = t0 + 0.5 * step; t < t1 && T > min_transmittance; t += step) {
        const glm::dvec3 p = o + t * dir;
        const volume::ExtinctionSample b = sampler.at(p, t * pixelAngle);
        const double bt = depthScale * b.total();
        if (bt <= 0.0) continue;
        const double Ts = std::exp(-bt * step);
        visit(x, y, dir, RaySample{p, T * (1.0 - Ts), b.ice_per_m / b.total()});
        T *= Ts;
      }
      end(x, y, T);
    }
  });
}

glm::dvec3 sampleSkyLight(const lighting::SkyLight& sky, const ColumnDepths& depths, const volume::VolumeFrame& frame,
                          const RaySample& sample, const RayMarchSettings& s) {
  const glm::dvec2 tau = columnDepthAt(depths, frame, sample.position_m);
  const double g = s.g_water + (s.g_ice - s.g_water) * sample.ice_weight;
  // The vertical diffusion of the exaggerated world, as the two-stream term's (clouds.comp skyLightAt).
  const double diffusion = lighting::twoStreamSunFrame(1.0, frame.height_exaggeration).z;
  return lighting::skyDiffuse(tau.x, tau.y, g, diffusion, sky.above, sky.below);
}

scene::RgbaImage marchCloudLayer(const ExtinctionVolumes& volumes, const volume::VolumeFrame& frame,
                                 const scene::Camera& camera, const scene::Sun& sun,
                                 const std::function<double(const glm::dvec3&)>& sunlightAt, const RayMarchSettings& s,
                                 const McRadianceVolume* radiance_volume) {
  const bool volumeTerm =
      s.multiple_scattering == lighting::MultipleScattering::RadianceVolume && radiance_volume != nullptr;
  scene::RgbaImage img;
  img.width = camera.width;
  img.height = camera.height;
  img.rgba.assign(std::size_t(img.width) * std::size_t(img.height) * 4, 0.0f);
  std::vector<glm::dvec3> colour(std::size_t(img.width) * std::size_t(img.height), glm::dvec3(0.0));
  const glm::dvec3 lightDir = -sun.toSun();
  const glm::dvec3 sunRadiance = sun.colour * sun.intensity;
  const lighting::SkyLight sky = lighting::skyLightFor(s, sun.elevation_deg, sun.colour, sun.intensity);
  const ColumnDepths depths = columnDepths(volumes, s.reconstruction);
  const glm::dvec3 sunFrame = lighting::twoStreamSunFrame(sun.toSun().z, frame.height_exaggeration);
  const volume::TerrainField terrain = volume::terrainOf(volumes, frame);
  const auto pixel = [&](int x, int y) { return std::size_t(y) * std::size_t(img.width) + std::size_t(x); };
  marchSamples(
      volumes, frame, camera, s.step_voxels, s.min_transmittance,
      [&](int x, int y, const glm::dvec3& dir, const RaySample& smp) {
        // Nes eq. 5.12 mix; single scattering plus the multiple-scattering model (cloud_light.h);
        // the sky light through the columns above and below (glsl/render/clouds.comp skyLightAt).
        // The two-stream term (s.multiple_scattering) reads the column depths and the view's
        // vertical cosine in the data (clouds.comp: −d_z/(e·f(d))).
        const double cosPsi = glm::dot(lightDir, -dir);
        const double muOut = -dir.z / (frame.height_exaggeration * frame.opticalDepthScale(dir) * glm::length(dir));
        double sunFactor = lighting::cloudSunFactor(s, sunlightAt(smp.position_m), cosPsi, smp.ice_weight,
                                                    columnDepthAt(depths, frame, smp.position_m), sunFrame, muOut);
        if (volumeTerm)  // orders ≥ 2 beside the map's single scattering and forward lobe
          sunFactor += radiance_volume->radianceAt(smp.position_m, -glm::normalize(dir), smp.ice_weight, s.g_ice,
                                                   s.g_water, kMcMaxL);
        colour[pixel(x, y)] += smp.weight * (sunRadiance * sunFactor + sampleSkyLight(sky, depths, frame, smp, s));
      },
      [&](int x, int y, double T) {
        glm::dvec3& C = colour[pixel(x, y)];
        if (T <= s.min_transmittance && T < 1.0) {  // renormalised early termination (clouds.comp)
          C /= 1.0 - T;
          T = 0.0;
        }
        float* px = &img.rgba[pixel(x, y) * 4];
        px[0] = float(C.x);
        px[1] = float(C.y);
        px[2] = float(C.z);
        px[3] = float(1.0 - T);
      },
      s.reconstruction, s.terrain ? &terrain : nullptr, s.detail);
  return img;
}

}  // namespace nph::reference
