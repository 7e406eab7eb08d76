#include "lighting/knobs.h"

#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace nph::lighting {
namespace {

using Q = QualitySettings;
using S = StyleSettings;

// The table. One accepted range per knob, for scene files and the C API alike (until issue 17 the
// API and the scene parser each had their own, and they had drifted):
// - step_voxels, dlm_step_voxels [0.01, 10] voxels: the union of both old ranges, so no scene
//   file or host call that worked before is refused. The bench's converged reference marches at
//   1/8 voxel; 0.01 leaves room for convergence studies, 10 voxels skips most of a cloud.
// - dlm_resolution [16, 4096] texels: the node texture holds texels² × dlm_max_nodes × 8 bytes,
//   2 GiB at 4096² and the presets' 16 nodes. Scene files accepted up to 16384 (32 GiB), which no
//   GPU this runs on can allocate; the C API's 4096 is kept.
// - dlm_max_nodes [2, 256]: at the reference preset's 1024² texels 256 nodes are again 2 GiB; the
//   C API's old cap of 64 refused budgets scene files could use.
// - dlm_epsilon [0, 1]: ε = 0 is valid (every sample a node until the budget runs out; the stress
//   suite's epsilon_0 case), 1 is the whole range of I; the C API refused ε < 1e-5 for no reason
//   the DLM has.
// - early_termination_transmittance [0, 1]: any transmittance (the C API capped it at 0.5).
// - style knobs keep the C API's ranges: |g| < 1 for a normalised Henyey–Greenstein phase,
//   the sky light's scale up to 10 × the analytic clear sky (issue 12; it was a radiance before).
//
// Presets (values in draft, broadcast, reference order) were chosen from the run-time/error sweep
// of `nephele-bench accuracy` (docs/accuracy.md): the DLM step and the view step are the knobs that
// buy time at a small error against the converged reference of the same model; ε below 0.01 and
// the scatter-map resolution change little; a node budget under 16 costs time (overflowed texels
// are re-marched) instead of saving it. Draft is the interactive preview (one-voxel steps in the
// view and the light, looser ε); reference is for comparisons with the CPU references
// (quarter-voxel steps, tight ε, long node lists).
// clang-format off
constexpr std::array kKnobs{
    Knob{.name = "step_voxels", .unit = "voxels", .min = 0.01, .max = 10.0, .field = &Q::step_voxels,
         .preset = {1.0, 0.5, 0.25}, .doc = "ray-march step in voxel sizes"},
    // Adaptive steps (issue 19; Muth 2026 §3.4.3 eq. 3.6; glsl/render/clouds.comp adaptiveStep):
    // far away (a pixel's footprint) and in thin cloud (τ ≤ 0.05 per step) the view step grows up
    // to this factor, never across an occupancy brick's face. 1 (fixed) in every preset, by
    // measurement with two-stream (BM_EyePassDefaults in tests/bench/frame_benchmark.cpp,
    // docs/benchmarks.md "Eye-pass defaults"): 4 gives the demo storm 2.1x CPU in the ray cast at
    // ≤ 2 8-bit levels, the coarse storm 1.3x with single values 202 levels off the CPU reference,
    // and on small storms seen from afar steps of a pixel's footprint pass thin cloud edges inside
    // occupied bricks (144 levels on 1-3 % of the values, AdaptiveStepsTest), beyond the broadcast
    // golden tolerance.
    Knob{.name = "step_growth_max", .unit = "steps", .min = 1.0, .max = 16.0, .field = &Q::step_growth_max,
         .preset = {1.0, 1.0, 1.0}, .doc = "adaptive view steps grow up to this × step_voxels far away and in thin cloud (1: fixed)"},
    Knob{.name = "dlm_step_voxels", .unit = "voxels", .min = 0.01, .max = 10.0, .field = &Q::dlm_step_voxels,
         .preset = {1.0, 0.5, 0.25}, .doc = "deep light map march step in voxel sizes"},
    // The adaptive light step (issue 19, session 16; glsl/dlm/march.comp, DlmSettings::step_growth_max):
    // runs of up to this many steps where the occupancy brick's (max, min) bound β, within a per-ray
    // error budget of ε/2 against the fixed step. 1 (fixed) in every preset for now, by measurement
    // (BM_DlmAdaptiveStep in tests/bench/frame_benchmark.cpp, docs/benchmarks.md "The adaptive
    // light step"): 4 makes the map build 1.24-1.38x cheaper in CPU on the smooth and the coarse
    // storm but not the cellular one of make demo (1.01x; its runs are cut by brick faces and
    // slice centres, and llvmpipe's 8 lock-step lanes pay for the longest), at max 1 8-bit level
    // on its flat shot. Pass 3's runs end at the scatter-slice centres (4 steps apart).
    Knob{.name = "dlm_step_growth_max", .unit = "steps", .min = 1, .max = 16, .field = &Q::dlm_step_growth_max,
         .preset = {1, 1, 1}, .doc = "adaptive light steps: up to this many dlm steps at once in uniform cloud (1: fixed)"},
    Knob{.name = "dlm_texel_voxels", .unit = "voxels", .min = 0.1, .max = 16.0, .field = &Q::dlm_texel_voxels,
         .preset = {1.0, 1.0, 1.0}, .doc = "deep light map texel size in voxel sizes"},
    Knob{.name = "dlm_resolution", .unit = "texels", .min = 16, .max = 4096, .field = &Q::dlm_resolution,
         .preset = {512, 512, 1024}, .doc = "cap on deep light map texels per side"},
    Knob{.name = "dlm_epsilon", .unit = "1", .min = 0.0, .max = 1.0, .field = &Q::dlm_epsilon,
         .preset = {0.04, 0.01, 0.0025}, .doc = "Lokovic–Veach error bound of the stored I(depth)"},
    Knob{.name = "dlm_max_nodes", .unit = "nodes", .min = 2, .max = 256, .field = &Q::dlm_max_nodes,
         .preset = {16, 16, 32}, .doc = "node budget per deep light map texel"},
    // The light cache (issue 19 item 1b; glsl/dlm/light_cache.comp): the map's sunlight baked per
    // world cell of this many voxels, read with one trilinear fetch per eye-pass sample instead of
    // the four-texel node-list look-up; 0 keeps the look-up (the reference path, the reference
    // preset's). 2 (half the grid's resolution) in draft and broadcast, by measurement under the
    // two-stream default (BM_EyePassDefaults in tests/bench/frame_benchmark.cpp, docs/benchmarks.md
    // "Eye-pass defaults"): the ray cast gains 1.63-1.65x CPU on the demo and the coarse storm,
    // for p99 ≤ 1 8-bit level against the direct look-up (max 1 level on the demo, 5 on 0.02 % of
    // the coarse storm's values) and the golden images within their broadcast tolerance; ¼ gains
    // little more (1.71-1.75x) for max 8 levels. (With the octave series the coarse storm's error
    // was 55 levels: its sun term carried the sharp cloud tops.)
    Knob{.name = "light_cache_voxels", .unit = "voxels", .min = 0.0, .max = 8.0, .field = &Q::light_cache_voxels,
         .preset = {2.0, 2.0, 0.0}, .doc = "light cache cell in voxel sizes (0: the deep light map's look-up per sample)"},
    Knob{.name = "early_termination_transmittance", .unit = "1", .min = 0.0, .max = 1.0,
         .field = &Q::early_termination_transmittance,
         .preset = {0.02, 0.01, 0.001}, .doc = "a ray stops below this transmittance"},
    Knob{.name = "empty_space_skipping", .unit = "", .min = 0, .max = 1, .field = &Q::empty_space_skipping,
         .preset = {1, 1, 1}, .doc = "skip empty bricks of the occupancy grid"},
    Knob{.name = "jitter", .unit = "", .min = 0, .max = 1, .field = &Q::jitter,
         .preset = {1, 1, 1}, .doc = "jittered ray start (deterministic per pixel) against banding"},
    Knob{.name = "shadows", .unit = "", .min = 0, .max = 1, .field = &Q::shadows,
         .preset = {1, 1, 1}, .doc = "cloud shadows on the ground"},
    Knob{.name = "samples_per_pixel", .unit = "", .min = 1, .max = 1024, .field = &Q::samples_per_pixel,
         .preset = {1, 1, 1}, .doc = "eye-pass samples per pixel at sub-pixel positions, averaged (anti-aliasing; the DLM is built once)"},
    // Reduced-resolution clouds (issue 19 item 4; glsl/render/clouds.comp upsampleClouds): the
    // clouds are marched at 1/s of the width and height and upsampled to the full resolution,
    // guided by the full-resolution geometry, under the ground and sky drawn at full resolution.
    // Presets by measurement (docs/benchmarks.md "Reduced-resolution clouds"): ½ moves the golden
    // scenes' frames by max 0.022 (flat) and 0.055 (globe), above the broadcast preset's error
    // budget (the golden tolerance, max 0.015), so broadcast and reference keep 1; draft, the
    // interactive preset (`nephele view`'s Q, the plugin examples), takes ½.
    Knob{.name = "cloud_resolution", .unit = "divisor", .min = 1, .max = 4, .field = &Q::cloud_resolution,
         .preset = {2, 1, 1}, .doc = "clouds marched at 1/s of the width and height and upsampled, depth-aware (1: every pixel)"},
    // The extinction filter (volume/reconstruction.h; issue 13). Trilinear is data-true but shows
    // the grid of coarse models as terraces and blocks; the cubic B-spline removes them (docs/
    // rendering.md "Reconstruction") at 8 texture fetches per sample instead of 1. "auto" (every
    // preset) takes cubic on grids of kCubicFromSpacing_m and coarser, trilinear on finer ones.
    // cubic_interpolating evaluates the same spline on coefficients that make it pass through the
    // voxels (volume/spline_coefficients.h): smooth and data-true at the voxel centres.
    Knob{.name = "reconstruction", .unit = "", .min = 0, .max = 3, .field = &Q::reconstruction,
         .preset = {2, 2, 2}, .doc = "extinction filter: trilinear (data-true), cubic B-spline (no grid artefacts, lowers peaks), auto (cubic on grids of 4 km and coarser), or cubic_interpolating (smooth spline through the voxels)",
         .choices = kReconstructionChoices},
    // Procedural sub-grid detail (volume/detail.h; issue 13, Muth 2026 §3.3.1): none is the
    // data-true field; subtle and full add turbulent displacement and regime-adaptive density that
    // redistributes (never adds) extinction inside each model cell (docs/detail.md).
    Knob{.name = "detail", .unit = "", .min = 0, .max = 2, .field = &Q::detail,
         .preset = {0, 0, 0}, .doc = "sub-grid detail: none (data-true), subtle or full (procedural, mass-preserving)",
         .choices = volume::kDetailNames},
    // The multiple-scattering term (issue 12; glsl/common/cloud_light.glsl cloudSunFactor). The
    // two-stream term has no fitted constant and halves the octaves' error against the path tracer
    // on the accuracy scenes at the same cost (docs/accuracy.md "Issue 12, third phase"). It reads
    // the column depths through the extinction's own reconstruction filter (volume/column_depth.h),
    // so the cubic B-spline keeps the model grid out of its light as well
    // (ReconstructionTest.CubicLowersTheGridArtefactsOfTheCoarseStorm).
    // radiance_volume (sixteenth session): the Monte Carlo radiance volume traced on the GPU with
    // the map (render/dlm/radiance_volume.h), an option: docs/accuracy.md "Sixteenth session".
    Knob{.name = "multiple_scattering", .unit = "", .min = 0, .max = 3, .field = &Q::multiple_scattering,
         .preset = {2, 2, 2}, .doc = "multiple scattering: single (none), octaves (fitted series), two_stream (column δ-Eddington) or radiance_volume (GPU Monte Carlo volume)",
         .choices = kMultipleScatteringNames},
    // The radiance volume's photons (thirty-first session, docs/accuracy.md): per column of its
    // 4 × 4 × 2-voxel cells, at least 65 536 in all. 64 keeps the accuracy scenes' count and gives
    // the demo storm 10⁶ (4 a column had mottled its canopy); the noise falls as 1/√n, the build
    // time grows as n (the CPU twin on llvmpipe: 31 s for the demo storm at 64).
    Knob{.name = "radiance_volume_photons", .unit = "photons per column", .min = 1, .max = 4096,
         .field = &Q::radiance_volume_photons, .preset = {16, 64, 256},
         .doc = "photons of the radiance volume per column of its cells (at least 65 536): less noise, longer "
                "build; read with multiple_scattering radiance_volume only"},
    Knob{.name = "g_ice", .unit = "1", .min = -0.99, .max = 0.99, .field = &S::g_ice,
         .doc = "Henyey–Greenstein asymmetry of ice in the eye pass"},
    Knob{.name = "g_water", .unit = "1", .min = -0.99, .max = 0.99, .field = &S::g_water,
         .doc = "Henyey–Greenstein asymmetry of droplets in the eye pass"},
    Knob{.name = "ambient_r", .unit = "clear sky = 1", .min = 0.0, .max = 10.0, .field = Vec3Component{&S::ambient, 0},
         .doc = "sky light scale, red (1 = the analytic clear sky at the sun's elevation)"},
    Knob{.name = "ambient_g", .unit = "clear sky = 1", .min = 0.0, .max = 10.0, .field = Vec3Component{&S::ambient, 1},
         .doc = "sky light scale, green (1 = the analytic clear sky at the sun's elevation)"},
    Knob{.name = "ambient_b", .unit = "clear sky = 1", .min = 0.0, .max = 10.0, .field = Vec3Component{&S::ambient, 2},
         .doc = "sky light scale, blue (1 = the analytic clear sky at the sun's elevation)"},
    Knob{.name = "atmosphere", .unit = "", .min = 0, .max = 1, .field = &S::atmosphere,
         .doc = "physically based sky, sunlight and aerial perspective (0: uniform ambient sky)"},
    Knob{.name = "terrain", .unit = "", .min = 0, .max = 1, .field = &S::terrain,
         .doc = "ground displaced by the model's terrain height (WRF HGT, ICON HSURF), exaggerated as the clouds"},
    Knob{.name = "ground_tint", .unit = "", .min = 0, .max = 1, .field = &S::ground_tint,
         .doc = "synthesised ground detail on the terrain: snow above snow_line_m, bare rock on slopes over 30–45°, blended over the imagery (0: the imagery as it is)"},
    Knob{.name = "snow_line_m", .unit = "m", .min = 0.0, .max = 6000.0, .field = &S::snow_line_m,
         .doc = "snow line of ground_tint, above mean sea level"},
    Knob{.name = "city_lights", .unit = "E/π", .min = 0.0, .max = 1.0, .field = &S::city_lights,
         .doc = "night side: city lights (basemap.night_lights, default Marble's citylights.jpg) at this fraction of E/π; 0 = off"},
};
// clang-format on

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;  // clang 14 has no C++20 aggregate deduction (P1816)

[[noreturn]] void wrongGroup(const Knob& k, const char* what) {
  throw UsageError(fmt::format("knob {} is not a {} knob", k.name, what));
}

std::string number(double x) { return fmt::format("{:g}", x); }

std::string valueText(const Knob& k, double v, bool json) {
  if (k.type() == KnobType::Boolean) return json ? (v != 0.0 ? "true" : "false") : (v != 0.0 ? "1" : "0");
  if (k.type() == KnobType::Choice) {
    const std::string_view name = k.choices[std::size_t(v)];
    return json ? fmt::format("\"{}\"", name) : fmt::format("{} ({})", number(v), name);
  }
  return number(v);
}

}  // namespace

std::string choiceList(const Knob& k, std::string_view last_separator) {
  std::string out;
  for (std::size_t i = 0; i < k.choices.size(); ++i) {
    out += fmt::format("{}\"{}\"", i == 0 ? "" : (i + 1 == k.choices.size() ? last_separator : ", "), k.choices[i]);
  }
  return out;
}

QualitySettings::QualitySettings() {
  for (const Knob& k : kKnobs) {
    if (k.group() == KnobGroup::Quality) k.set(*this, k.preset[std::size_t(Preset::Broadcast)]);
  }
}

QualitySettings qualityPreset(Preset preset) {
  QualitySettings q;
  q.preset = std::string(kPresetNames[std::size_t(preset)]);
  for (const Knob& k : kKnobs) {
    if (k.group() == KnobGroup::Quality) k.set(q, k.preset[std::size_t(preset)]);
  }
  return q;
}

QualitySettings qualityPreset(std::string_view name) {
  for (std::size_t i = 0; i < kPresetNames.size(); ++i) {
    if (name == kPresetNames[i]) return qualityPreset(Preset(i));
  }
  throw InputError(fmt::format("quality preset '{}': expected \"draft\", \"broadcast\" or \"reference\"", name));
}

lighting::DlmSettings dlmSettingsFor(const QualitySettings& q) {
  lighting::DlmSettings d;
  d.epsilon = q.dlm_epsilon;
  d.step_voxels = q.dlm_step_voxels;
  d.step_growth_max = q.dlm_step_growth_max;
  d.texel_voxels = q.dlm_texel_voxels;
  d.max_nodes = q.dlm_max_nodes;
  d.max_texels = q.dlm_resolution;
  d.empty_space_skipping = q.empty_space_skipping;
  d.light_cache_voxels = q.light_cache_voxels;
  return d;
}

RenderSettings renderSettingsFor(const QualitySettings& q, const StyleSettings& style) {
  RenderSettings r;
  // "auto" needs the grid: engine::Session sets the filter of the uploaded volume.
  r.reconstruction = reconstructionOf(q, {0.0, 0.0});
  r.detail = detailOf(q);
  static_cast<StyleSettings&>(r) = style;
  r.step_voxels = q.step_voxels;
  r.step_growth_max = q.step_growth_max;
  r.min_transmittance = q.early_termination_transmittance;
  r.jitter = q.jitter;
  r.samples_per_pixel = q.samples_per_pixel;
  r.cloud_resolution = q.cloud_resolution;
  r.empty_space_skipping = q.empty_space_skipping;
  r.shadows = q.shadows;
  r.multiple_scattering = MultipleScattering(q.multiple_scattering);
  r.radiance_volume_photons_per_column = q.radiance_volume_photons;
  return r;
}

KnobGroup Knob::group() const {
  return std::holds_alternative<double S::*>(field) || std::holds_alternative<Vec3Component>(field) ||
                 std::holds_alternative<bool S::*>(field)
             ? KnobGroup::Style
             : KnobGroup::Quality;
}

KnobType Knob::type() const {
  if (std::holds_alternative<int Q::*>(field)) return choices.empty() ? KnobType::Integer : KnobType::Choice;
  if (std::holds_alternative<bool Q::*>(field) || std::holds_alternative<bool S::*>(field)) return KnobType::Boolean;
  return KnobType::Number;
}

bool Knob::accepts(double value) const {
  if (!(value >= min && value <= max)) return false;  // also refuses NaN
  return type() == KnobType::Number || value == std::floor(value);
}

double Knob::get(const QualitySettings& q) const {
  return std::visit(
      Overloaded{[&](double Q::*m) { return q.*m; }, [&](int Q::*m) { return double(q.*m); },
                 [&](bool Q::*m) { return q.*m ? 1.0 : 0.0; }, [&](auto) -> double { wrongGroup(*this, "quality"); }},
      field);
}

double Knob::get(const StyleSettings& s) const {
  return std::visit(
      Overloaded{[&](double S::*m) { return s.*m; }, [&](Vec3Component c) { return (s.*c.vector)[c.component]; },
                 [&](bool S::*m) { return s.*m ? 1.0 : 0.0; }, [&](auto) -> double { wrongGroup(*this, "style"); }},
      field);
}

void Knob::set(QualitySettings& q, double v) const {
  std::visit(Overloaded{[&](double Q::*m) { q.*m = v; }, [&](int Q::*m) { q.*m = int(v); },
                        [&](bool Q::*m) { q.*m = v != 0.0; }, [&](auto) { wrongGroup(*this, "quality"); }},
             field);
}

void Knob::set(StyleSettings& s, double v) const {
  std::visit(Overloaded{[&](double S::*m) { s.*m = v; }, [&](Vec3Component c) { (s.*c.vector)[c.component] = v; },
                        [&](bool S::*m) { s.*m = v != 0.0; }, [&](auto) { wrongGroup(*this, "style"); }},
             field);
}

double Knob::defaultValue() const {
  return group() == KnobGroup::Quality ? preset[std::size_t(Preset::Broadcast)] : get(StyleSettings{});
}

std::span<const Knob> knobs() { return kKnobs; }

const Knob* findKnob(std::string_view name) {
  for (const Knob& k : kKnobs) {
    if (k.name == name) return &k;
  }
  return nullptr;
}

std::string sceneFileQualityMarkdown() {
  std::string md = "| field | type | unit | draft | broadcast | reference | meaning |\n|---|---|---|---|---|---|---|\n";
  for (const Knob& k : kKnobs) {
    if (k.group() != KnobGroup::Quality) continue;
    std::string type = k.type() == KnobType::Boolean
                           ? "boolean"
                           : fmt::format("{} in [{}, {}]", k.type() == KnobType::Integer ? "integer" : "number",
                                         number(k.min), number(k.max));
    if (k.type() == KnobType::Choice) type = "string: " + choiceList(k, " or ");
    md += fmt::format("| `{}` | {} | {} | {} | {} | {} | {} |\n", k.name, type, k.unit.empty() ? "—" : k.unit,
                      valueText(k, k.preset[0], true), valueText(k, k.preset[1], true), valueText(k, k.preset[2], true),
                      k.doc);
  }
  return md;
}

std::string sceneFileStyleMarkdown() {
  std::string md = "| field | type | unit | default | meaning |\n|---|---|---|---|---|\n";
  for (const Knob& k : kKnobs) {
    if (k.group() != KnobGroup::Style) continue;
    std::string type = k.type() == KnobType::Boolean
                           ? "boolean"
                           : fmt::format("{} in [{}, {}]", k.type() == KnobType::Integer ? "integer" : "number",
                                         number(k.min), number(k.max));
    if (k.type() == KnobType::Choice) type = "string: " + choiceList(k, " or ");
    md += fmt::format("| `{}` | {} | {} | {} | {} |\n", k.name, type, k.unit.empty() ? "—" : k.unit,
                      valueText(k, k.defaultValue(), true), k.doc);
  }
  return md;
}

std::string apiParametersMarkdown() {
  std::string md = "| name | range | default | unit | what |\n| --- | --- | --- | --- | --- |\n";
  for (const Knob& k : kKnobs) {
    std::string range = k.type() == KnobType::Boolean ? "0/1" : fmt::format("{}–{}", number(k.min), number(k.max));
    if (k.type() == KnobType::Integer) range += ", integer";
    if (k.type() == KnobType::Choice) {
      range.clear();
      for (std::size_t i = 0; i < k.choices.size(); ++i)
        range += fmt::format("{}{} = {}", i ? ", " : "", i, k.choices[i]);
    }
    const std::string def = valueText(k, k.defaultValue(), false);
    md += fmt::format("| `{}` | {} | {} | {} | {} |\n", k.name, range,
                      k.group() == KnobGroup::Quality ? "preset (" + def + ")" : def, k.unit.empty() ? "—" : k.unit,
                      k.doc);
  }
  return md;
}

}  // namespace nph::lighting
