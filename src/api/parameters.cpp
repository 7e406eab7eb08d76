// The named parameters of set_parameter / get_parameter (docs/plugin-api.md has the same table).
// Quality parameters go through Session::setQuality (the DLM is rebuilt when its key changes);
// ray-caster parameters through Session::renderSettings; output parameters stay in the API.
#include <cmath>
#include <string_view>

#include <fmt/format.h>

#include "api/handles.h"
#include "api/renderer.h"

namespace nph::api {

struct ParameterTable {
  struct Entry {
    std::string_view name;
    double min, max;
    bool integer;
    double (*get)(const Renderer&);
    void (*set)(Renderer&, double);
  };

  template <class F>
  static void quality(Renderer& r, F&& change) {
    scene::QualitySettings q = r.session().quality();
    change(q);
    r.session().setQuality(q);
  }

  static const Entry* find(std::string_view name);
};

namespace {

using R = Renderer;
using Q = scene::QualitySettings;
constexpr double kMaxAmbient = 10.0, kMaxSunIntensity = 1000.0;

// clang-format off
const ParameterTable::Entry kParameters[] = {
    {"step_voxels", 0.05, 8.0, false,
     [](const R& r) { return r.session().quality().step_voxels; },
     [](R& r, double v) { ParameterTable::quality(r, [v](Q& q) { q.step_voxels = v; }); }},
    {"dlm_resolution", 16, 4096, true,
     [](const R& r) { return double(r.session().quality().dlm_resolution); },
     [](R& r, double v) { ParameterTable::quality(r, [v](Q& q) { q.dlm_resolution = int(v); }); }},
    {"dlm_epsilon", 1e-5, 1.0, false,
     [](const R& r) { return r.session().quality().dlm_epsilon; },
     [](R& r, double v) { ParameterTable::quality(r, [v](Q& q) { q.dlm_epsilon = v; }); }},
    {"dlm_max_nodes", 2, 64, true,
     [](const R& r) { return double(r.session().quality().dlm_max_nodes); },
     [](R& r, double v) { ParameterTable::quality(r, [v](Q& q) { q.dlm_max_nodes = int(v); }); }},
    {"early_termination_transmittance", 0.0, 0.5, false,
     [](const R& r) { return r.session().quality().early_termination_transmittance; },
     [](R& r, double v) { ParameterTable::quality(r, [v](Q& q) { q.early_termination_transmittance = v; }); }},
    {"empty_space_skipping", 0, 1, true,
     [](const R& r) { return r.session().quality().empty_space_skipping ? 1.0 : 0.0; },
     [](R& r, double v) { ParameterTable::quality(r, [v](Q& q) { q.empty_space_skipping = v != 0.0; }); }},
    {"jitter", 0, 1, true,
     [](const R& r) { return r.session().quality().jitter ? 1.0 : 0.0; },
     [](R& r, double v) { ParameterTable::quality(r, [v](Q& q) { q.jitter = v != 0.0; }); }},
    {"shadows", 0, 1, true,
     [](const R& r) { return r.session().quality().shadows ? 1.0 : 0.0; },
     [](R& r, double v) { ParameterTable::quality(r, [v](Q& q) { q.shadows = v != 0.0; }); }},
    {"g_ice", -0.99, 0.99, false,
     [](const R& r) { return r.session().renderSettings().g_ice; },
     [](R& r, double v) { r.session().renderSettings().g_ice = v; }},
    {"g_water", -0.99, 0.99, false,
     [](const R& r) { return r.session().renderSettings().g_water; },
     [](R& r, double v) { r.session().renderSettings().g_water = v; }},
    {"ambient_r", 0.0, kMaxAmbient, false,
     [](const R& r) { return r.session().renderSettings().ambient.r; },
     [](R& r, double v) { r.session().renderSettings().ambient.r = v; }},
    {"ambient_g", 0.0, kMaxAmbient, false,
     [](const R& r) { return r.session().renderSettings().ambient.g; },
     [](R& r, double v) { r.session().renderSettings().ambient.g = v; }},
    {"ambient_b", 0.0, kMaxAmbient, false,
     [](const R& r) { return r.session().renderSettings().ambient.b; },
     [](R& r, double v) { r.session().renderSettings().ambient.b = v; }},
    {"sun_intensity", 0.0, kMaxSunIntensity, false,
     [](const R& r) { return r.session().sun().intensity; },
     [](R& r, double v) { scene::Sun s = r.session().sun(); s.intensity = v; r.session().setSun(s); }},
    {"exposure_ev", -20.0, 20.0, false,
     [](const R& r) { return r.composite().exposure_ev; },
     [](R& r, double v) { r.composite().exposure_ev = v; }},
    {"display_transform", 0, 1, true,
     [](const R& r) { return r.composite().display ? 1.0 : 0.0; },
     [](R& r, double v) { r.composite().display = v != 0.0; }},
    {"ground", 0, 1, true,
     [](const R& r) { return r.ground() ? 1.0 : 0.0; },
     [](R& r, double v) { r.ground() = v != 0.0; }},
};
// clang-format on

}  // namespace

const ParameterTable::Entry* ParameterTable::find(std::string_view name) {
  for (const auto& e : kParameters) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

namespace {
const ParameterTable::Entry& entry(std::string_view name) {
  const auto* e = ParameterTable::find(name);
  if (e == nullptr) {
    std::string names;
    for (const auto& p : kParameters) names += fmt::format("{}{}", names.empty() ? "" : ", ", p.name);
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("unknown parameter '{}'; known: {}", name, names));
  }
  return *e;
}
}  // namespace

void Renderer::setParameter(std::string_view name, double value) {
  const auto& e = entry(name);
  if (!(value >= e.min && value <= e.max) || (e.integer && value != std::floor(value))) {
    throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("parameter {} = {}: expected {} in [{}, {}]", name, value,
                                                           e.integer ? "an integer" : "a number", e.min, e.max));
  }
  e.set(*this, value);
}

double Renderer::parameter(std::string_view name) const { return entry(name).get(*this); }

}  // namespace nph::api
