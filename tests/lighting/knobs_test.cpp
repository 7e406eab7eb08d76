// The knob table (lighting/knobs.h) is the one definition of the renderer's knobs: the presets give
// the values they gave before the table existed, scene files accept exactly its quality rows with
// its ranges, and the docs tables are generated from it. (The C API side: tests/api/api_knobs_test.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "core/error.h"
#include "lighting/dlm_model.h"
#include "lighting/knobs.h"
#include "scene/scene_file.h"

namespace nph::lighting {
namespace {

// The presets as they were written out by hand before issue 17 (scene/scene_file.cpp at 4cc50f4):
// the table must reproduce them exactly, or renders change.
TEST(Knobs, PresetsGiveTheValuesTheyGaveBefore) {
  struct Expected {
    std::string_view name;
    double step, dlm_step, texel, epsilon, early_termination;
    int resolution, nodes;
  };
  const Expected expected[] = {{"draft", 1.0, 1.0, 1.0, 0.04, 0.02, 512, 16},
                               {"broadcast", 0.5, 0.5, 1.0, 0.01, 0.01, 512, 16},
                               {"reference", 0.25, 0.25, 1.0, 0.0025, 0.001, 1024, 32}};
  for (const Expected& e : expected) {
    SCOPED_TRACE(e.name);
    const QualitySettings q = qualityPreset(e.name);
    EXPECT_EQ(q.preset, e.name);
    EXPECT_EQ(q.step_voxels, e.step);
    EXPECT_EQ(q.dlm_step_voxels, e.dlm_step);
    EXPECT_EQ(q.dlm_texel_voxels, e.texel);
    EXPECT_EQ(q.dlm_epsilon, e.epsilon);
    EXPECT_EQ(q.early_termination_transmittance, e.early_termination);
    EXPECT_EQ(q.dlm_resolution, e.resolution);
    EXPECT_EQ(q.dlm_max_nodes, e.nodes);
    EXPECT_TRUE(q.empty_space_skipping);
    EXPECT_TRUE(q.jitter);
    EXPECT_TRUE(q.shadows);
    EXPECT_EQ(q.samples_per_pixel, 1);
  }
  EXPECT_EQ(QualitySettings{}, qualityPreset("broadcast"));
  try {
    (void)qualityPreset("ultra");
    FAIL() << "no error for an unknown preset";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "quality preset 'ultra': expected \"draft\", \"broadcast\" or \"reference\"");
  }
}

// The settings structs' own defaults (RenderSettings is also built field by field in tests and
// references) agree with the table's broadcast column and the default style.
TEST(Knobs, RenderSettingsDefaultsAreTheBroadcastPresetAndDefaultStyle) {
  const RenderSettings d;
  const RenderSettings r = renderSettingsFor(QualitySettings{}, StyleSettings{});
  EXPECT_EQ(r.step_voxels, d.step_voxels);
  EXPECT_EQ(r.min_transmittance, d.min_transmittance);
  EXPECT_EQ(r.jitter, d.jitter);
  EXPECT_EQ(r.empty_space_skipping, d.empty_space_skipping);
  EXPECT_EQ(r.shadows, d.shadows);
  EXPECT_EQ(r.g_ice, d.g_ice);
  EXPECT_EQ(r.g_water, d.g_water);
  EXPECT_EQ(r.ambient, d.ambient);
  EXPECT_EQ(r.ocean_albedo, d.ocean_albedo);
  EXPECT_EQ(r.limb_radiance, d.limb_radiance);
  const lighting::DlmSettings dlm = dlmSettingsFor(qualityPreset("reference"));
  EXPECT_EQ(dlm.epsilon, 0.0025);
  EXPECT_EQ(dlm.step_voxels, 0.25);
  EXPECT_EQ(dlm.max_texels, 1024);
  EXPECT_EQ(dlm.max_nodes, 32);
  EXPECT_EQ(dlm.forward_angle_deg, lighting::DlmSettings{}.forward_angle_deg);  // the model is no knob
}

// The default extinction filter is "auto" in every preset (issue 13): cubic on grids of 4 km and
// coarser (the larger horizontal spacing decides), trilinear on finer ones; an explicit choice
// wins whatever the grid.
TEST(Knobs, AutoReconstructionFollowsTheGridSpacing) {
  using volume::Reconstruction;
  for (std::string_view preset : kPresetNames) EXPECT_EQ(qualityPreset(preset).reconstruction, kReconstructionAuto);
  const QualitySettings q;
  EXPECT_EQ(reconstructionOf(q, {3000.0, 3000.0}), Reconstruction::Trilinear);  // the demo hurricane
  EXPECT_EQ(reconstructionOf(q, {3999.0, 3999.0}), Reconstruction::Trilinear);
  EXPECT_EQ(reconstructionOf(q, {kCubicFromSpacing_m, 2000.0}), Reconstruction::Cubic);
  EXPECT_EQ(reconstructionOf(q, {2000.0, 10000.0}), Reconstruction::Cubic);  // the coarse storm's 10 km
  QualitySettings tri = q, cubic = q;
  tri.reconstruction = 0;
  cubic.reconstruction = 1;
  EXPECT_EQ(reconstructionOf(tri, {10000.0, 10000.0}), Reconstruction::Trilinear);
  EXPECT_EQ(reconstructionOf(cubic, {1000.0, 1000.0}), Reconstruction::Cubic);
  EXPECT_EQ(findKnob("reconstruction")->choices[std::size_t(kReconstructionAuto)], "auto");
}

// Quality and style are separate: a preset never changes the style, a style knob never the quality.
TEST(Knobs, QualityAndStyleAreSeparate) {
  std::set<std::string_view> names;
  for (const Knob& k : knobs()) {
    SCOPED_TRACE(k.name);
    EXPECT_TRUE(names.insert(k.name).second) << "duplicate knob name";
    EXPECT_FALSE(k.doc.empty());
    EXPECT_LT(k.min, k.max);
    EXPECT_TRUE(k.accepts(k.defaultValue()));
    EXPECT_FALSE(k.accepts(k.max + 1.0));
    EXPECT_FALSE(k.accepts(k.min - 1.0));
    EXPECT_FALSE(k.accepts(std::nan("")));
    if (k.type() != KnobType::Number) {
      EXPECT_FALSE(k.accepts(k.min + 0.5));
    }
    if (k.group() == KnobGroup::Quality) {
      for (double v : k.preset) EXPECT_TRUE(k.accepts(v));
      QualitySettings q;
      const double other = k.type() == KnobType::Boolean ? 1.0 - k.get(q) : k.max;
      k.set(q, other);
      EXPECT_EQ(k.get(q), other);
      EXPECT_THROW((void)k.get(StyleSettings{}), UsageError);
    } else {
      for (double v : k.preset) EXPECT_EQ(v, 0.0) << "presets do not set style knobs";
      StyleSettings s;
      k.set(s, k.max);
      EXPECT_EQ(k.get(s), k.max);
      EXPECT_THROW((void)k.get(QualitySettings{}), UsageError);
    }
  }
  EXPECT_EQ(findKnob("ambient_g")->get(StyleSettings{}), 1.0);  // × the clear sky (issue 12)
  EXPECT_EQ(findKnob("no_such_knob"), nullptr);
}

// Scene files: quality.overrides takes every quality row of the table under its name, with the
// table's range and type, and nothing else.
TEST(Knobs, SceneFileOverridesAreTheQualityRows) {
  std::string overrides;
  QualitySettings expected = qualityPreset("draft");
  for (const Knob& k : knobs()) {
    if (k.group() != KnobGroup::Quality) continue;
    // differs from the draft preset: booleans 0, otherwise the top of the range, or its bottom
    // where draft sits at the top (multiple_scattering: two_stream is the last choice)
    const double v = k.type() == KnobType::Boolean ? 0.0 : (k.max != k.preset[0] ? k.max : k.min);
    ASSERT_NE(v, k.preset[0]) << k.name;
    k.set(expected, v);
    const bool choice = k.type() == KnobType::Choice;  // scene files name the choice
    overrides += fmt::format("{}\"{}\": {}", overrides.empty() ? "" : ", ", k.name,
                             k.type() == KnobType::Boolean ? "false"
                             : choice                      ? fmt::format("\"{}\"", k.choices[std::size_t(v)])
                                                           : fmt::format("{}", v));
    // out of range, named with the table's range (a choice: not one of its names)
    const std::string bad = fmt::format(R"({{"quality": {{"overrides": {{"{}": {}}}}}}})", k.name,
                                        k.type() == KnobType::Boolean ? "2"
                                        : choice                      ? "\"no-such-choice\""
                                                                      : fmt::format("{}", k.max * 2 + 1));
    try {
      (void)scene::parseSceneText(bad, "q.json");
      ADD_FAILURE() << "no error for " << bad;
    } catch (const InputError& e) {
      const std::string want =
          k.type() == KnobType::Boolean ? fmt::format("q.json: quality.overrides.{}: expected true or false", k.name)
          : choice ? fmt::format("q.json: quality.overrides.{}: expected {}, got \"no-such-choice\"", k.name,
                                 choiceList(k, " or "))
                   : fmt::format("q.json: quality.overrides.{}: expected {} in [{}, {}]", k.name,
                                 k.type() == KnobType::Integer ? "an integer" : "a number", k.min, k.max);
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what() << "\nexpected: " << want;
    }
  }
  const scene::SceneDescription s = scene::parseSceneText(
      fmt::format(R"({{"quality": {{"preset": "draft", "overrides": {{{}}}}}}})", overrides), "q.json");
  EXPECT_EQ(s.quality, expected);
  // style knobs are no scene-file keys (yet): the API sets them
  EXPECT_THROW((void)scene::parseSceneText(R"({"quality": {"overrides": {"g_ice": 0.5}}})", "q.json"), InputError);
}

// The docs tables are generated from the table; NEPHELE_UPDATE_DOCS=1 rewrites them in place.
// `table` names a second generated table of a file ("style": markers "generated style table").
void checkGeneratedSection(const std::string& relativePath, const std::string& generated,
                           const std::string& table = "") {
  const std::string path = std::string(NEPHELE_SOURCE_DIR) + "/" + relativePath;
  std::ifstream in(path, std::ios::binary);
  ASSERT_TRUE(in) << "cannot read " << path;
  std::stringstream text;
  text << in.rdbuf();
  std::string doc = text.str();
  const std::string kind = table.empty() ? "" : " " + table + " table";
  const std::string begin = "<!-- generated" + kind + " from src/lighting/knobs.cpp: do not edit -->\n";
  const std::string end = "<!-- end of generated " + (table.empty() ? std::string() : table + " ") + "table -->";
  const std::size_t a = doc.find(begin);
  const std::size_t b = doc.find(end, a == std::string::npos ? 0 : a);
  ASSERT_NE(a, std::string::npos) << path << ": no line \"" << begin << "\"";
  ASSERT_NE(b, std::string::npos) << path << ": no line \"" << end << "\" after the begin marker";
  const std::string committed = doc.substr(a + begin.size(), b - a - begin.size());
  if (committed != generated && std::getenv("NEPHELE_UPDATE_DOCS") != nullptr) {
    doc.replace(a + begin.size(), b - a - begin.size(), generated);
    std::ofstream(path, std::ios::binary) << doc;
    std::cout << "NEPHELE_UPDATE_DOCS: rewrote " << path << "\n";
    return;
  }
  EXPECT_EQ(committed, generated) << path << " differs from the knob table; run the test with NEPHELE_UPDATE_DOCS=1 "
                                  << "to regenerate it";
}

TEST(Knobs, DocsTablesAreGeneratedFromTheTable) {
  checkGeneratedSection("docs/scene-file.md", sceneFileQualityMarkdown());
  checkGeneratedSection("docs/scene-file.md", sceneFileStyleMarkdown(), "style");
  checkGeneratedSection("docs/plugin-api.md", apiParametersMarkdown());
  for (const Knob& k : knobs()) {
    const std::string row = fmt::format("| `{}` |", k.name);
    EXPECT_NE((k.group() == KnobGroup::Quality ? sceneFileQualityMarkdown() : sceneFileStyleMarkdown()).find(row),
              std::string::npos)
        << k.name;
    EXPECT_NE(apiParametersMarkdown().find(row), std::string::npos) << k.name;
  }
}

// scatterSliceSteps (lighting/dlm_model.h; docs/benchmarks.md "Scatter-map slice length"): the
// setting's steps where scatter_slice_cells is 0 or asks for less; else the least
// even number of steps whose slice spans that fraction of the scatter cell's narrower side; an
// effective value given back is kept (the GPU builder reports it, the CPU reference reapplies it).
TEST(DlmModel, ScatterSliceSpansTheAskedFractionOfTheCell) {
  LightSpace ls;
  ls.extent_m = {400e3, 300e3};
  ls.texels = {100, 100};  // texels 4 km x 3 km: cells of 4 texels 16 km x 12 km
  DlmSettings s;
  EXPECT_EQ(scatterSliceSteps(s, ls, 125.0), 48) << "the default, half a cell: 6 km of 125 m steps";
  s.scatter_slice_cells = 0.0;
  EXPECT_EQ(scatterSliceSteps(s, ls, 125.0), 4) << "0: the steps alone";
  s.scatter_slice_cells = 0.13;  // 1.56 km: 12.48 steps -> 14, the next even number
  EXPECT_EQ(scatterSliceSteps(s, ls, 125.0), 14);
  s.scatter_slice_cells = 0.01;  // 120 m: less than the 4 steps asked for
  EXPECT_EQ(scatterSliceSteps(s, ls, 125.0), 4);
  s.scatter_slice_cells = 0.5;
  s.scatter_slice_steps = scatterSliceSteps(s, ls, 125.0);
  EXPECT_EQ(scatterSliceSteps(s, ls, 125.0), 48) << "idempotent";
  s.scatter_slice_steps = 64;
  EXPECT_EQ(scatterSliceSteps(s, ls, 125.0), 64) << "never shorter than the steps asked for";
  // One β sample per 16 steps of a slice (the slice's mean β), 1 for Nes' short slices, 64 at most.
  EXPECT_EQ(scatterSliceSamples(4), 1);
  EXPECT_EQ(scatterSliceSamples(16), 1);
  EXPECT_EQ(scatterSliceSamples(18), 2);
  EXPECT_EQ(scatterSliceSamples(48), 3);
  EXPECT_EQ(scatterSliceSamples(1 << 20), 64);
}

}  // namespace
}  // namespace nph::lighting
