#include "accuracy/accuracy_sweep.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include <map>
#include "core/error.h"
#include "core/log.h"

#include "reference/dlm_reference.h"
#include "reference/ray_marcher.h"
#include "render/dlm/deep_light_map.h"
#include "render/dlm/volume_textures.h"

namespace nph::accuracy {
namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

constexpr double kReferenceStepVoxels = 0.125;

std::string number(double x) { return fmt::format("{:g}", x); }

// The quality the one-knob-at-a-time sweep starts from: the broadcast preset with the deep light
// map's own budgets (DlmSettings' 1024 texels and 32 nodes, so that no variant is limited by them).
lighting::QualitySettings sweepBase() {
  lighting::QualitySettings q = lighting::qualityPreset(lighting::Preset::Broadcast);
  q.dlm_resolution = lighting::DlmSettings{}.max_texels;
  q.dlm_max_nodes = lighting::DlmSettings{}.max_nodes;
  return q;
}

}  // namespace

Variant defaultVariant() {
  Variant v = variantOf(sweepBase());
  v.knob = "default";
  v.value = "-";
  return v;
}

namespace {

// The CPU reference of the same approximation, converged: the variant's light-transport model
// (forward cone θ, Cornette–Shanks g, scatter map on/off and its cell size) integrated by
// reference::DlmReference (convergedLight) and the eye pass marched with 1/8 voxel steps and no
// early termination. One per distinct model in a scene.
// The converged CPU references of one scene: the light per transport model, the image per light
// and multiple-scattering model.
struct ReferenceCache {
  std::map<std::string, std::unique_ptr<reference::DlmReference>> lights;
  std::map<std::string, scene::RgbaImage> images;
};

const scene::RgbaImage& referenceFor(const Variant& v, const render::VolumeTextures& tex, const AccuracyScene& sc,
                                     ReferenceCache& cache) {
  const std::string lightKey =
      fmt::format("{}/{}/{}/{}/{}/{}", v.dlm.forward_angle_deg, v.dlm.cornette_shanks_g, v.dlm.peripheral,
                  v.dlm.scatter_downsample, v.dlm.scatter_slice_steps, v.dlm.scatter_slice_cells);
  const std::string key = fmt::format("{}/ms{}", lightKey, int(v.render.multiple_scattering));
  if (auto it = cache.images.find(key); it != cache.images.end()) return it->second;
  std::unique_ptr<reference::DlmReference>& light = cache.lights[lightKey];
  if (!light) light = convergedLight(v.dlm, tex, sc);
  reference::RayMarchSettings march = v.render;
  march.step_voxels = kReferenceStepVoxels;
  march.min_transmittance = 0.0;
  return cache.images[key] = reference::marchCloudLayer(
             *sc.volumes, sc.frame, sc.camera, sc.sun, [&](const glm::dvec3& p) { return light->intensityAt(p); },
             march);
}

}  // namespace

std::unique_ptr<reference::DlmReference> convergedLight(const lighting::DlmSettings& dlm,
                                                        const render::VolumeTextures& tex, const AccuracyScene& sc,
                                                        double texel_voxels) {
  // The model of `dlm` without compression, 4 sub-steps per default DLM step (Δ/8 = 1/8 voxel), on
  // the default light space (1 texel per voxel unless asked otherwise) the GPU builder lays out.
  lighting::DlmSettings model = dlm;
  model.texel_voxels = texel_voxels;
  model.step_voxels = lighting::DlmSettings{}.step_voxels;
  render::DeepLightMap layout;  // the light space (texel grid, extent) and step the GPU would use
  lighting::DlmSettings gpu = model;
  gpu.forward_peak_ice = gpu.forward_peak_water = -1.0;  // a CPU-only candidate (--decompose)
  layout.build(tex, -sc.sun.toSun(), gpu);
  lighting::DlmSettings cpu = layout.settings();
  cpu.forward_peak_ice = model.forward_peak_ice;
  cpu.forward_peak_water = model.forward_peak_water;
  constexpr int kRefine = 4;
  return std::make_unique<reference::DlmReference>(*sc.volumes, sc.frame, layout.lightSpace(), cpu,
                                                   layout.stats().step_m, layout.stats().steps, kRefine);
}

Variant variantOf(const lighting::QualitySettings& q) {
  Variant v;
  v.knob = "preset";
  v.value = q.preset;
  v.dlm = lighting::dlmSettingsFor(q);
  v.render = lighting::renderSettingsFor(q, lighting::StyleSettings{});
  v.render.jitter = false;    // pixel-centre rays, like both references
  v.render.sky_below = true;  // the path-traced truth has no ground: sky all round
  // ... and no air: the truth and the CPU reference light the clouds by the analytic clear sky and
  // the unattenuated sun. The GPU's default atmosphere (issue 14) would dim and redden the sun at
  // the clouds, change their sky light and add aerial perspective: 1.6e-2 RMSE against the CPU
  // reference, 32 % of the pixels off by > 2/255, whatever the knobs (twenty-eighth session).
  v.render.atmosphere = false;
  return v;
}

std::string groundTruthCacheDir(const SweepOptions& o) {
  return o.cache_dir.empty() ? (std::filesystem::path(o.out_dir) / "ground-truth").string() : o.cache_dir;
}

SceneSet sweepScenes(const SweepOptions& o) {
  return standardScenes(o.width, o.height, o.quick, (std::filesystem::path(o.out_dir) / "scratch").string());
}

std::vector<Variant> sweepVariants(bool quick) {
  std::vector<Variant> out{defaultVariant()};
  // A quality knob of the knob table (lighting/knobs.h), by its name there.
  auto knob = [&](std::string_view name, const std::vector<double>& values) {
    const lighting::Knob* k = lighting::findKnob(name);
    if (k == nullptr || k->group() != lighting::KnobGroup::Quality)
      throw UsageError(fmt::format("accuracy: no quality knob {}", name));
    for (double x : values) {
      if (!k->accepts(x)) throw UsageError(fmt::format("accuracy: {} = {} is outside the knob's range", name, x));
      lighting::QualitySettings q = sweepBase();
      k->set(q, x);
      Variant v = variantOf(q);
      v.knob = std::string(name);
      v.value = number(x);
      out.push_back(v);
    }
  };
  // A setting of the transport model (DlmSettings) that is no user knob.
  auto model = [&](const std::string& name, const std::vector<double>& values, auto&& apply) {
    for (double x : values) {
      Variant v = defaultVariant();
      v.knob = name;
      v.value = number(x);
      apply(v.dlm, x);
      out.push_back(v);
    }
  };
  using L = std::vector<double>;
  knob("step_voxels", quick ? L{1.0, 0.25} : L{2.0, 1.0, 0.25, 0.125});
  knob("dlm_texel_voxels", quick ? L{2.0} : L{4.0, 2.0, 0.5});
  knob("dlm_step_voxels", quick ? L{1.0} : L{2.0, 1.0, 0.25});
  knob("dlm_step_growth_max", quick ? L{4.0} : L{2.0, 4.0, 8.0});  // issue 19: the adaptive light step
  knob("dlm_epsilon", quick ? L{0.04} : L{0.08, 0.04, 0.02, 0.005, 0.0025});
  knob("light_cache_voxels", quick ? L{0.0} : L{0.0, 1.0, 4.0});   // issue 19: 0 = the map per sample
  knob("multiple_scattering", quick ? L{1.0} : L{0.0, 1.0, 2.0});  // single, octaves, two_stream (issue 12)
  model("scatter_downsample", quick ? L{8.0} : L{2.0, 8.0, 16.0},
        [](lighting::DlmSettings& d, double x) { d.scatter_downsample = int(x); });
  if (!quick) {
    Variant off = defaultVariant();
    off.knob = "scatter_downsample";
    off.value = "off";
    off.dlm.peripheral = false;
    out.push_back(off);
  }
  // The scatter map's slice length as a fraction of its cell width (issue 19; 0: 4 steps Δ).
  model("scatter_slice_cells", quick ? L{0.0} : L{0.0, 0.125, 0.5, 1.0},  // 0.5: the default, for --knobs
        [](lighting::DlmSettings& d, double x) { d.scatter_slice_cells = x; });
  model("forward_angle_deg", quick ? L{30.0} : L{10.0, 30.0, 40.0},
        [](lighting::DlmSettings& d, double x) { d.forward_angle_deg = x; });
  for (std::string_view p : lighting::kPresetNames) out.push_back(variantOf(lighting::qualityPreset(p)));
  return out;
}

const std::vector<std::string>& csvColumns() {
  static const std::vector<std::string> c{"scene",
                                          "knob",
                                          "value",
                                          "dlm_ms",
                                          "raycast_ms",
                                          "total_ms",
                                          "dlm_mean_nodes",
                                          "dlm_unbounded_texels",
                                          "truth_rmse",
                                          "truth_rel_mse",
                                          "truth_mean_abs",
                                          "truth_max_abs",
                                          "truth_share_off_2_255",
                                          "truth_alpha_max_abs",
                                          "truth_noise_rmse",
                                          "truth_bias_rmse",
                                          "truth_truncated_share",
                                          "coverage",
                                          "ref_rmse",
                                          "ref_rel_mse",
                                          "ref_mean_abs",
                                          "ref_max_abs",
                                          "ref_share_off_2_255",
                                          "ref_alpha_max_abs",
                                          "truth_luminance_bias",
                                          "truth_rel_mse_noise"};
  return c;
}

double biasRmse(const ImageError& e) {
  return std::sqrt(std::max(e.rmse * e.rmse - e.ref_noise_rmse * e.ref_noise_rmse, 0.0));
}

void writeCsv(const std::vector<SweepRow>& rows, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw IoError(path + ": cannot write");
  for (std::size_t i = 0; i < csvColumns().size(); ++i) out << (i ? "," : "") << csvColumns()[i];
  out << "\n";
  for (const SweepRow& r : rows) {
    const ImageError& t = r.vs_truth;
    const ImageError& c = r.vs_reference;
    out << fmt::format(
        "{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4f},"
        "{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n",
        r.scene, r.knob, r.value, r.dlm_ms, r.raycast_ms, r.dlm_ms + r.raycast_ms, r.dlm_mean_nodes,
        r.dlm_unbounded_texels, t.rmse, t.rel_mse, t.mean_abs, t.max_abs, t.share_off_2_255, t.alpha_max_abs,
        t.ref_noise_rmse, biasRmse(t), r.truth_truncated_share, r.coverage, c.rmse, c.rel_mse, c.mean_abs, c.max_abs,
        c.share_off_2_255, c.alpha_max_abs, t.luminance_bias, t.rel_mse_noise);
  }
  if (!out) throw IoError(path + ": write failed");
}

std::vector<SweepRow> runSweep(const SweepOptions& o) {
  if (o.runs < 1) throw UsageError("accuracy: --runs must be at least 1");
  const std::string cacheDir = groundTruthCacheDir(o);
  const SceneSet set = sweepScenes(o);
  std::vector<Variant> variants = sweepVariants(o.quick);
  if (!o.knob_filter.empty()) {
    std::erase_if(variants, [&](const Variant& v) { return v.knob.find(o.knob_filter) == std::string::npos; });
    if (variants.empty()) throw UsageError("accuracy: no knob matches --knobs " + o.knob_filter);
  }
  std::vector<SweepRow> rows;
  for (const AccuracyScene& sc : set.scenes) {
    if (!o.scene_filter.empty() && sc.name.find(o.scene_filter) == std::string::npos) continue;
    const GroundTruth gt = groundTruth(sc, defaultVariant().render, o.ground_truth, cacheDir);
    double coverage = 0.0;
    for (std::size_t i = 3; i < gt.image.rgba.size(); i += 4) coverage += double(gt.image.rgba[i]);
    coverage /= double(gt.image.rgba.size() / 4);
    log::info("{}: {}x{}x{} voxels, ground truth {} ({:.0f} s, {:.2g} of paths cut), coverage {:.2f}", sc.name,
              sc.volumes->nx, sc.volumes->ny, sc.volumes->nz, gt.from_cache ? "from cache" : "traced", gt.seconds,
              gt.truncated_share, coverage);
    if (o.write_images) {
      scene::writePng(gt.image, (std::filesystem::path(o.out_dir) / (sc.name + "-truth.png")).string());
    }
    const auto tex = render::VolumeTextures::upload(*sc.volumes, sc.frame, sc.volume_name + "-accuracy");
    render::CloudRenderer renderer;
    ReferenceCache references;  // per model (forward cone, scatter map; multiple scattering)
    for (const Variant& v : variants) {
      std::vector<double> dlmMs, castMs;
      render::RenderOutput out;
      std::unique_ptr<render::DeepLightMap> dlm;
      for (int r = -1; r < o.runs; ++r) {                // run −1 warms up (shader variants, caches): not timed
        dlm = std::make_unique<render::DeepLightMap>();  // a fresh map: the cache key would skip the build
        dlm->build(tex, -sc.sun.toSun(), v.dlm);
        const render::DlmStats& st = dlm->stats();
        out = renderer.render(tex, *dlm, sc.camera, sc.sun, v.render);
        if (r < 0) continue;
        dlmMs.push_back(st.pass1_ms + st.pass2_ms + st.pass3_ms);
        castMs.push_back(out.milliseconds);
      }
      const scene::RgbaImage& cpu = referenceFor(v, tex, sc, references);
      SweepRow row;
      row.scene = sc.name;
      row.knob = v.knob;
      row.value = v.value;
      row.dlm_ms = median(dlmMs);
      row.raycast_ms = median(castMs);
      row.dlm_mean_nodes = dlm->stats().mean_nodes;
      row.dlm_unbounded_texels = dlm->stats().unbounded_texels;
      row.vs_truth = compareImages(out.cloud_layer, gt.image, gt.standard_error);
      row.vs_reference = compareImages(out.cloud_layer, cpu);
      row.truth_truncated_share = gt.truncated_share;
      row.coverage = coverage;
      log::info("  {:>18} {:>6}: dlm {:7.1f} ms  cast {:7.1f} ms  rmse truth {:.4f} ref {:.2e}  off>2/255 {:.3f}  "
                "luminance {:+.1f} %",
                v.knob, v.value, row.dlm_ms, row.raycast_ms, row.vs_truth.rmse, row.vs_reference.rmse,
                row.vs_truth.share_off_2_255, 100.0 * row.vs_truth.luminance_bias);
      if (o.write_images) {
        scene::writePng(
            out.cloud_layer,
            (std::filesystem::path(o.out_dir) / fmt::format("{}-{}-{}.png", sc.name, v.knob, v.value)).string());
      }
      rows.push_back(row);
    }
  }
  return rows;
}

}  // namespace nph::accuracy
