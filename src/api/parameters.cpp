// The named parameters of set_parameter / get_parameter (docs/plugin-api.md has the list).
// The lighting knobs — quality and style — are the rows of the knob table (lighting/knobs.h),
// with the names and ranges scene files use: quality knobs go through Session::setQuality (the DLM
// is rebuilt when its key changes), style knobs through Session::setStyle. The sun's intensity and
// the output parameters belong to the API and are listed here.
#include <cmath>
#include <string_view>

#include <fmt/format.h>

#include "api/handles.h"
#include "api/renderer.h"
#include "lighting/knobs.h"

namespace nph::api {

namespace {

struct Parameter {
  std::string_view name;
  double min, max;
  bool integer;
  double (*get)(const Renderer&);
  void (*set)(Renderer&, double);
};

using R = Renderer;
constexpr double kMaxSunIntensity = 1000.0;

// clang-format off
const Parameter kParameters[] = {
    {"sun_intensity", 0.0, kMaxSunIntensity, false,
     [](const R& r) { return r.session().sun().intensity; },
     [](R& r, double v) { scene::Sun s = r.session().sun(); s.intensity = v; r.session().setSun(s); }},
    {"exposure_ev", -20.0, 20.0, false,
     [](const R& r) { return r.composite().exposure_ev; },
     [](R& r, double v) { r.composite().exposure_ev = v; }},
    {"white_balance_k", scene::kMinWhiteBalanceK, scene::kMaxWhiteBalanceK, false,
     [](const R& r) { return r.composite().white_balance_k; },
     [](R& r, double v) { r.composite().white_balance_k = v; }},
    {"white_balance_duv", -scene::kMaxWhiteBalanceDuv, scene::kMaxWhiteBalanceDuv, false,
     [](const R& r) { return r.composite().white_balance_duv; },
     [](R& r, double v) { r.composite().white_balance_duv = v; }},
    {"display_transform", 0, 1, true,
     [](const R& r) { return r.composite().display ? 1.0 : 0.0; },
     [](R& r, double v) { r.composite().display = v != 0.0; }},
    {"ground", 0, 1, true,
     [](const R& r) { return r.ground() ? 1.0 : 0.0; },
     [](R& r, double v) { r.ground() = v != 0.0; }},
    // set_time's fractional index between two timesteps (engine/dataset.h TimeBlend): 1 carries
    // both along their winds (the default, kDefaultTimeBlend), 0 cross-fades.
    {"time_interpolation", 0, 1, true,
     [](const R& r) { return r.session().timeBlend() == engine::TimeBlend::Motion ? 1.0 : 0.0; },
     [](R& r, double v) { r.session().setTimeBlend(v != 0.0 ? engine::TimeBlend::Motion : engine::TimeBlend::Linear); }},
    // Temporal accumulation for interactive hosts (render/raycast/temporal_accumulation.h): N > 0
    // folds each frame's jitter into a reprojected history of up to N frames; 0 (the default)
    // renders every frame on its own, as a render farm needs.
    {"temporal_history", 0, 64, true,
     [](const R& r) { return double(r.session().renderSettings().temporal_history); },
     [](R& r, double v) { r.session().renderSettings().temporal_history = int(v); }},
};
// clang-format on

const Parameter* findParameter(std::string_view name) {
  for (const auto& e : kParameters) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

[[noreturn]] void unknown(std::string_view name) {
  std::string names;
  for (const auto& k : lighting::knobs()) names += fmt::format("{}{}", names.empty() ? "" : ", ", k.name);
  for (const auto& p : kParameters) names += fmt::format(", {}", p.name);
  throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("unknown parameter '{}'; known: {}", name, names));
}

[[noreturn]] void outOfRange(std::string_view name, double value, bool integer, double min, double max) {
  throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("parameter {} = {}: expected {} in [{}, {}]", name, value,
                                                         integer ? "an integer" : "a number", min, max));
}

}  // namespace

void Renderer::setParameter(std::string_view name, double value) {
  if (const lighting::Knob* k = lighting::findKnob(name)) {
    if (!k->accepts(value)) outOfRange(name, value, k->type() != lighting::KnobType::Number, k->min, k->max);
    if (k->group() == lighting::KnobGroup::Quality) {
      lighting::QualitySettings q = session().quality();
      k->set(q, value);
      session().setQuality(q);
    } else {
      lighting::StyleSettings s = session().style();
      k->set(s, value);
      session().setStyle(s);
    }
    return;
  }
  const auto* e = findParameter(name);
  if (e == nullptr) unknown(name);
  if (!(value >= e->min && value <= e->max) || (e->integer && value != std::floor(value))) {
    outOfRange(name, value, e->integer, e->min, e->max);
  }
  e->set(*this, value);
}

double Renderer::parameter(std::string_view name) const {
  if (const lighting::Knob* k = lighting::findKnob(name)) {
    return k->group() == lighting::KnobGroup::Quality ? k->get(session().quality()) : k->get(session().style());
  }
  const auto* e = findParameter(name);
  if (e == nullptr) unknown(name);
  return e->get(*this);
}

}  // namespace nph::api
