#include "accuracy/decompose.h"

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "lighting/cloud_light.h"
#include "physics/phase.h"
#include "reference/ray_marcher.h"
#include "render/dlm/volume_textures.h"

namespace nph::accuracy {
namespace {

constexpr double kNoCounterpart = std::numeric_limits<double>::quiet_NaN();

struct ImageMean {
  double mean = 0.0, se = 0.0;
};

// Mean luminance of a traced part and the standard error of that mean (pixels independent).
ImageMean meanLuminance(const GroundTruth& gt) {
  const std::size_t n = gt.image.rgba.size() / 4;
  double sum = 0.0, var = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &gt.image.rgba[4 * i];
    const float* s = &gt.standard_error[3 * i];
    sum += luminance(p[0], p[1], p[2]);
    const double sy = luminance(s[0], s[1], s[2]);
    var += sy * sy;
  }
  return {sum / double(n), std::sqrt(var) / double(n)};
}

// The renderer's parts, per pixel summed over the view ray's samples (luminance).
enum RendererPart : int { kSky = 0, kSingleBeam, kSingleDlm, kMsTerm, kCandidate0 };
constexpr int kCandidates = 3;
constexpr int kRendererParts = kCandidate0 + kCandidates;

// Candidate deep light maps (the forward peak the beam keeps), for the single-scattering term.
std::array<lighting::DlmSettings, kCandidates> candidateDlms(const lighting::DlmSettings& base,
                                                             const reference::RayMarchSettings& m) {
  std::array<lighting::DlmSettings, kCandidates> c{base, base, base};
  // (0) δ-Eddington's forward peak f = g² per medium, no scatter map.
  c[0].forward_peak_ice = m.g_ice * m.g_ice;
  c[0].forward_peak_water = m.g_water * m.g_water;
  c[0].peripheral = false;
  // (1) the same with Nes' peripheral scattering on top.
  c[1].forward_peak_ice = c[0].forward_peak_ice;
  c[1].forward_peak_water = c[0].forward_peak_water;
  // (2) Nes' cone with the eye's HG lobes per medium: CP_HG(θ/4), scatter map on.
  const double q = base.forward_angle_deg / 4.0 * 3.14159265358979323846 / 180.0;
  c[2].forward_peak_ice = physics::cumulativePhase({physics::PhaseModel::HenyeyGreenstein, m.g_ice}, q);
  c[2].forward_peak_water = physics::cumulativePhase({physics::PhaseModel::HenyeyGreenstein, m.g_water}, q);
  return c;
}
constexpr std::array<const char*, kCandidates> kCandidateNames{"DLM keeping f = g² per medium, no scatter map",
                                                               "DLM keeping f = g² per medium + scatter map",
                                                               "DLM cone with the eye's HG per medium"};

}  // namespace

std::vector<SceneDecomposition> decomposeBias(const SweepOptions& o, int part_spp) {
  if (part_spp < 1) throw UsageError("accuracy --decompose: --decompose-spp must be at least 1");
  const std::string cacheDir = groundTruthCacheDir(o);
  const SceneSet set = sweepScenes(o);
  const Variant base = defaultVariant();
  reference::RayMarchSettings march = base.render;
  march.min_transmittance = 0.0;  // no early termination: the parts are the model's, not the cut's
  // The deep light map without its forward cone: the direct beam e^{−τ} exactly (dlm_model.h with
  // CP(0) = 0 and no peripheral passes).
  lighting::DlmSettings beamOnly = base.dlm;
  beamOnly.forward_angle_deg = 0.0;
  beamOnly.peripheral = false;
  std::vector<SceneDecomposition> out;
  for (const AccuracyScene& sc : set.scenes) {
    if (!o.scene_filter.empty() && sc.name.find(o.scene_filter) == std::string::npos) continue;
    const GroundTruth full = groundTruth(sc, base.render, o.ground_truth, cacheDir);
    GroundTruthSettings partSettings = o.ground_truth;
    partSettings.samples_per_pixel = part_spp;
    partSettings.part = TruthPart::SkyOnly;
    const GroundTruth sky = groundTruth(sc, base.render, partSettings, cacheDir);
    partSettings.part = TruthPart::SunOnly;
    partSettings.max_events = 1;
    const GroundTruth sun1 = groundTruth(sc, base.render, partSettings, cacheDir);
    partSettings.max_events = 2;
    const GroundTruth sun2 = groundTruth(sc, base.render, partSettings, cacheDir);
    log::info("{}: truth parts {} / {} / {} (sky {:.0f} s, order 1 {:.0f} s, orders <= 2 {:.0f} s)", sc.name,
              sky.from_cache ? "cached" : "traced", sun1.from_cache ? "cached" : "traced",
              sun2.from_cache ? "cached" : "traced", sky.seconds, sun1.seconds, sun2.seconds);

    const render::VolumeTextures tex = render::VolumeTextures::upload(*sc.volumes, sc.frame, sc.name + "-decompose");
    const auto light = convergedLight(base.dlm, tex, sc, o.reference_dlm_texel_voxels);
    const auto beam = convergedLight(beamOnly, tex, sc, o.reference_dlm_texel_voxels);
    std::array<std::unique_ptr<reference::DlmReference>, kCandidates> candidates;
    const auto candidateSettings = candidateDlms(base.dlm, march);
    for (int c = 0; c < kCandidates; ++c)
      candidates[std::size_t(c)] =
          convergedLight(candidateSettings[std::size_t(c)], tex, sc, o.reference_dlm_texel_voxels);
    const lighting::SkyLight skyLight =
        lighting::skyLightFor(march, sc.sun.elevation_deg, sc.sun.colour, sc.sun.intensity);
    const ColumnDepths depths = columnDepths(*sc.volumes, march.reconstruction);
    const glm::dvec3 toSun = sc.sun.toSun();
    const glm::dvec3 sunFrame = lighting::twoStreamSunFrame(toSun.z, sc.frame.height_exaggeration);
    const glm::dvec3 e = sc.sun.colour * sc.sun.intensity;
    const double ySun = luminance(e.x, e.y, e.z);
    const int w = sc.camera.width, pixels = sc.camera.width * sc.camera.height;
    std::vector<std::array<double, kRendererParts>> sums(std::size_t(pixels), std::array<double, kRendererParts>{});
    reference::marchSamples(
        *sc.volumes, sc.frame, sc.camera, march.step_voxels, 0.0,
        [&](int x, int y, const glm::dvec3& dir, const reference::RaySample& s) {
          auto& t = sums[std::size_t(y) * std::size_t(w) + std::size_t(x)];
          // As reference::marchCloudLayer (the eye pass's CPU twin), term by term.
          const double cosPsi = glm::dot(-toSun, -dir);
          const double muOut =
              -dir.z / (sc.frame.height_exaggeration * sc.frame.opticalDepthScale(dir) * glm::length(dir));
          const glm::dvec2 tau = columnDepthAt(depths, sc.frame, s.position_m);
          const double p = lighting::mixedPhase(cosPsi, s.ice_weight, march.g_ice, march.g_water);
          const double iDlm = light->intensityAt(s.position_m);
          const glm::dvec3 l = reference::sampleSkyLight(skyLight, depths, sc.frame, s, march);
          t[kSky] += s.weight * luminance(l.x, l.y, l.z);
          t[kSingleBeam] += s.weight * ySun * p * beam->intensityAt(s.position_m);
          t[kSingleDlm] += s.weight * ySun * p * iDlm;
          for (int c = 0; c < kCandidates; ++c)
            t[std::size_t(kCandidate0 + c)] +=
                s.weight * ySun * p * candidates[std::size_t(c)]->intensityAt(s.position_m);
          t[kMsTerm] += s.weight * ySun *
                        (lighting::cloudSunFactor(march, iDlm, cosPsi, s.ice_weight, tau, sunFrame, muOut) - p * iDlm);
        },
        [](int, int, double) {});
    std::array<double, kRendererParts> mean{};
    for (const auto& t : sums)
      for (int j = 0; j < kRendererParts; ++j) mean[std::size_t(j)] += t[std::size_t(j)] / double(pixels);

    const ImageMean f = meanLuminance(full), k = meanLuminance(sky), s1 = meanLuminance(sun1), s2 = meanLuminance(sun2);
    auto se = [](std::initializer_list<double> v) {
      double q = 0.0;
      for (double x : v) q += x * x;
      return std::sqrt(q);
    };
    SceneDecomposition d;
    d.scene = sc.name;
    const double cone = mean[kSingleDlm] - mean[kSingleBeam];
    d.parts = {
        {"sky light (sun off)", k.mean, k.se, mean[kSky]},
        {"sun, order 1", s1.mean, s1.se, mean[kSingleBeam]},
        {"sun, order 2", s2.mean - s1.mean, se({s2.se, s1.se}), kNoCounterpart},
        {"sun, orders >= 2", f.mean - k.mean - s1.mean, se({f.se, k.se, s1.se}), cone + mean[kMsTerm]},
        {"  of which the DLM's forward cone", kNoCounterpart, 0.0, cone},
        {fmt::format("  of which the {} term",
                     lighting::kMultipleScatteringNames[std::size_t(march.multiple_scattering)]),
         kNoCounterpart, 0.0, mean[kMsTerm]},
        {"sun, all orders (sky off)", f.mean - k.mean, se({f.se, k.se}), mean[kSingleDlm] + mean[kMsTerm]},
        {"total", f.mean, f.se, mean[kSky] + mean[kSingleDlm] + mean[kMsTerm]},
    };
    for (int c = 0; c < kCandidates; ++c)
      d.parts.insert(d.parts.end() - 1,
                     {fmt::format("candidate: {}: sun, all orders", kCandidateNames[std::size_t(c)]), f.mean - k.mean,
                      se({f.se, k.se}), mean[std::size_t(kCandidate0 + c)] + mean[kMsTerm]});
    for (const DecomposedPart& part : d.parts)
      log::info("{}: {:<36} truth {:9.5f} ± {:.5f}  renderer {:9.5f}", sc.name, part.name, part.truth, part.truth_se,
                part.model);
    out.push_back(std::move(d));
  }
  if (out.empty()) throw UsageError("accuracy --decompose: no scene matches --scenes " + o.scene_filter);
  return out;
}

std::string decompositionMarkdown(const std::vector<SceneDecomposition>& scenes) {
  std::string md =
      "| scene | part | truth (mean Y ± s.e.) | renderer | renderer − truth | share of the total's bias |\n"
      "| --- | --- | ---: | ---: | ---: | ---: |\n";
  for (const SceneDecomposition& d : scenes) {
    const DecomposedPart& total = d.parts.back();
    const double totalGap = total.model - total.truth;
    for (const DecomposedPart& p : d.parts) {
      const bool hasTruth = !std::isnan(p.truth), hasModel = !std::isnan(p.model);
      const std::string truth = hasTruth ? fmt::format("{:.4f} ± {:.4f}", p.truth, p.truth_se) : "—";
      const std::string model = hasModel ? fmt::format("{:.4f}", p.model) : "—";
      std::string gap = "—", share = "—";
      if (hasTruth && hasModel) {
        gap = fmt::format("{:+.4f} ({:+.1f} %)", p.model - p.truth,
                          p.truth != 0.0 ? 100.0 * (p.model / p.truth - 1.0) : 0.0);
        if (totalGap != 0.0) share = fmt::format("{:.0f} %", 100.0 * (p.model - p.truth) / totalGap);
      }
      md += fmt::format("| {} | {} | {} | {} | {} | {} |\n", d.scene, p.name, truth, model, gap, share);
    }
  }
  return md;
}

}  // namespace nph::accuracy
