#pragma once
// The renderer's knobs, defined once. Every user-facing knob is one row of one table (knobs.cpp):
// name, unit, accepted range, per-preset values, target field and doc string. Everything that
// names a knob reads the table instead of spelling it out:
//   - scene files: the keys of `quality.overrides` (scene/scene_file.cpp),
//   - the C API: set_parameter / get_parameter names and ranges (api/parameters.cpp),
//   - the quality presets (qualityPreset below; `nephele view` cycles through kPresetNames),
//   - `nephele-bench accuracy`: the quality knobs it sweeps (accuracy/accuracy_sweep.cpp),
//   - the docs: the tables in docs/scene-file.md and docs/plugin-api.md are generated from it
//     (knobsMarkdown; tests/lighting checks that the committed docs match).
// A new knob is a field in QualitySettings or StyleSettings and a row in the table.
//
// Quality knobs trade time for accuracy (Nes 2008 §5.3.4 ε, step sizes, budgets; the presets
// come from the run-time/error sweep of docs/accuracy.md). Style knobs (phase asymmetry, ambient
// light) change what the picture looks like; presets never touch them, so changing the quality
// keeps the style (engine::Session::setQuality).
#include <algorithm>
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include <glm/glm.hpp>

#include "lighting/dlm_model.h"
#include "lighting/render_settings.h"
#include "volume/detail.h"
#include "volume/reconstruction.h"

namespace nph::lighting {

/// The quality presets, in the order of Knob::preset.
enum class Preset { Draft, Broadcast, Reference };
inline constexpr std::array<std::string_view, 3> kPresetNames{"draft", "broadcast", "reference"};

/// Renderer quality knobs. A default-constructed value is the broadcast preset (from the table).
struct QualitySettings {
  QualitySettings();  ///< the broadcast preset

  std::string preset = "broadcast";  ///< the preset the values started from
  double step_voxels{};              ///< ray-march step in voxel sizes (Muth 2026 §3.4.3)
  double step_growth_max{};          ///< adaptive steps up to this × step_voxels (RenderSettings::step_growth_max)
  int dlm_resolution{};              ///< cap on deep light map texels per side (DlmSettings::max_texels)
  double dlm_epsilon{};              ///< Lokovic–Veach error bound on I(depth) (DlmSettings::epsilon)
  double dlm_step_voxels{};          ///< DLM march step Δ in voxel sizes (DlmSettings::step_voxels)
  int dlm_step_growth_max{};         ///< adaptive DLM step: up to this many Δ per run (DlmSettings::step_growth_max)
  double dlm_texel_voxels{};         ///< DLM texel size in voxel sizes (DlmSettings::texel_voxels)
  int dlm_max_nodes{};               ///< node budget per DLM texel (DlmSettings::max_nodes)
  double light_cache_voxels{};       ///< light cache cell in voxels, 0 = none (DlmSettings::light_cache_voxels)
  double early_termination_transmittance{};  ///< stop a ray below this T
  bool empty_space_skipping{};               ///< skip empty occupancy bricks (DLM and ray caster)
  bool jitter{};                             ///< per-pixel start offset against banding
  bool shadows{};                            ///< cloud shadows on the basemap
  int samples_per_pixel{};                   ///< eye-pass samples per pixel (RenderSettings::samples_per_pixel)
  int cloud_resolution{};         ///< divisor of the clouds' march resolution (RenderSettings::cloud_resolution)
  int reconstruction{};           ///< 0 trilinear, 1 cubic B-spline, 2 auto (reconstructionOf)
  int detail{};                   ///< volume::Detail: 0 none, 1 subtle, 2 full (volume/detail.h)
  int multiple_scattering{};      ///< MultipleScattering: 0 single, 1 octaves, 2 two_stream, 3 radiance_volume
  int radiance_volume_photons{};  ///< per column of its cells (RenderSettings::radiance_volume_photons_per_column)

  bool operator==(const QualitySettings&) const = default;
};

/// The preset `name` ("draft" | "broadcast" | "reference"); InputError otherwise.
QualitySettings qualityPreset(std::string_view name);
QualitySettings qualityPreset(Preset preset);

/// The deep light map settings of `quality` (the transport model keeps DlmSettings' defaults).
lighting::DlmSettings dlmSettingsFor(const QualitySettings& quality);
/// The ray caster's settings: sampling from `quality`, appearance from `style`.
RenderSettings renderSettingsFor(const QualitySettings& quality, const StyleSettings& style);
/// The knob `reconstruction`'s values: the filters of volume/reconstruction.h, then "auto".
/// (cubic_interpolating came later: it follows "auto", so the values of the C API stay as they were.)
inline constexpr std::array<std::string_view, 4> kReconstructionChoices{"trilinear", "cubic", "auto",
                                                                        "cubic_interpolating"};
inline constexpr int kReconstructionAuto = 2;
inline constexpr int kReconstructionCubicInterpolating = 3;

/// "auto" chooses the cubic B-spline on grids this coarse or coarser (the larger horizontal spacing)
/// and trilinear below (issue 13; docs/rendering.md "Reconstruction"). On the 10 km storm trilinear
/// shows every column as a block and the cubic filter removes them; on the 3 km demo hurricane the two
/// differ by ≤ 3 of 255 codes and trilinear keeps the data-true field at half the ray-cast cost.
/// Operational grids are 2–12 km: 4 km falls between the smooth and the blocky look.
inline constexpr double kCubicFromSpacing_m = 4000.0;

/// The extinction filter of `quality` for a grid of horizontal spacing `spacing_m` (x, y) [m]
/// (volume/reconstruction.h): the knob's filter, or for "auto" the one kCubicFromSpacing_m picks.
inline volume::Reconstruction reconstructionOf(const QualitySettings& quality, glm::dvec2 spacing_m) {
  if (quality.reconstruction == kReconstructionAuto)
    return std::max(spacing_m.x, spacing_m.y) >= kCubicFromSpacing_m ? volume::Reconstruction::Cubic
                                                                     : volume::Reconstruction::Trilinear;
  if (quality.reconstruction == kReconstructionCubicInterpolating) return volume::Reconstruction::CubicInterpolating;
  return quality.reconstruction == 1 ? volume::Reconstruction::Cubic : volume::Reconstruction::Trilinear;
}

/// The sub-grid detail of `quality` (volume/detail.h).
inline volume::Detail detailOf(const QualitySettings& quality) {
  return quality.detail == 2   ? volume::Detail::Full
         : quality.detail == 1 ? volume::Detail::Subtle
                               : volume::Detail::None;
}

/// One component of a vector field (ambient_r = component 0 of StyleSettings::ambient).
struct Vec3Component {
  glm::dvec3 StyleSettings::*vector;
  int component;
};

/// The field a knob sets. Its type decides how the knob is read and written: double = a number,
/// int = an integer, bool = 0/1 in the C API and true/false in scene files. An int knob with
/// `choices` is a choice: the index (0 … n − 1) in the C API, the name in scene files.
using KnobField = std::variant<double QualitySettings::*, int QualitySettings::*, bool QualitySettings::*,
                               double StyleSettings::*, Vec3Component, bool StyleSettings::*>;

enum class KnobGroup { Quality, Style };
enum class KnobType { Number, Integer, Boolean, Choice };

struct Knob {
  std::string_view name;  ///< scene-file key (quality.overrides) and C API parameter name
  std::string_view unit;  ///< for the docs ("voxels", "texels", "1" for dimensionless)
  double min = 0.0;       ///< accepted range, inclusive (booleans: 0 and 1)
  double max = 0.0;
  KnobField field;
  std::array<double, 3> preset{};               ///< quality knobs: the value in draft, broadcast, reference
  std::string_view doc;                         ///< one line for the docs tables
  std::span<const std::string_view> choices{};  ///< names of the values 0 … n − 1 (choice knobs)

  KnobGroup group() const;
  KnobType type() const;
  /// In [min, max], and a whole number for integers, booleans and choices.
  bool accepts(double value) const;
  /// The knob's value in `quality` / `style`; UsageError for a knob of the other group.
  double get(const QualitySettings& quality) const;
  double get(const StyleSettings& style) const;
  /// Sets the knob (no range check: see accepts); UsageError for a knob of the other group.
  void set(QualitySettings& quality, double value) const;
  void set(StyleSettings& style, double value) const;
  /// The default: the broadcast preset's value (quality) or StyleSettings{}'s (style).
  double defaultValue() const;
};

/// The names of a choice knob, quoted, comma separated, `last_separator` before the last
/// ("\"trilinear\" or \"cubic\"").
std::string choiceList(const Knob& knob, std::string_view last_separator);

/// Every knob, quality knobs first, in the order of the docs.
std::span<const Knob> knobs();
/// The row named `name`, nullptr when there is none.
const Knob* findKnob(std::string_view name);

/// The docs tables generated from the knob table (Markdown): the quality presets of scene files
/// (docs/scene-file.md) and the knob parameters of the C API (docs/plugin-api.md).
std::string sceneFileQualityMarkdown();
/// The style keys of scene files (the "style" object; docs/scene-file.md).
std::string sceneFileStyleMarkdown();
std::string apiParametersMarkdown();

}  // namespace nph::lighting
