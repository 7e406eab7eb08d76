// The C API and the knob table (lighting/knobs.h): every knob of the table — every scene-file
// quality key and every style knob — is a parameter of set_parameter / get_parameter under the
// same name, with the table's range and default; a quality preset keeps the style.
// usage: nephele_api_knobs_test (the api.data fixture's storm; OSMesa host context)
#include <GL/osmesa.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "lighting/knobs.h"
#include "nephele/nephele.h"

namespace {

class ApiKnobs : public ::testing::Test {
 protected:
  void SetUp() override {
    api_ = static_cast<const nph_api_v1*>(nph_get_api(NPH_API_VERSION));
    ASSERT_NE(api_, nullptr);
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           4,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           5,
                           0};
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    ASSERT_NE(ctx_, nullptr) << "OSMesaCreateContextAttribs(4.5 core) failed";
    buffer_.resize(std::size_t(kSize) * kSize * 4);
    ASSERT_TRUE(OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize));
    ASSERT_EQ(api_->dataset_open(NEPHELE_API_TEST_DATA, &dataset_), NPH_OK) << api_->last_error(nullptr);
    nph_renderer_desc desc = NPH_RENDERER_DESC_INIT;
    desc.get_proc_address = &OSMesaGetProcAddress;
    ASSERT_EQ(api_->renderer_create(dataset_, &desc, &renderer_), NPH_OK) << api_->last_error(dataset_);
  }
  void TearDown() override {
    if (renderer_ != nullptr) {
      EXPECT_EQ(api_->renderer_destroy(renderer_), NPH_OK);
    }
    if (dataset_ != nullptr) {
      EXPECT_EQ(api_->dataset_close(dataset_), NPH_OK);
    }
    if (ctx_ != nullptr) OSMesaDestroyContext(ctx_);
  }
  double get(const std::string& name) {
    double v = -12345.0;
    EXPECT_EQ(api_->get_parameter(renderer_, name.c_str(), &v), NPH_OK) << name << ": " << api_->last_error(renderer_);
    return v;
  }

  static constexpr int kSize = 16;
  const nph_api_v1* api_ = nullptr;
  OSMesaContext ctx_ = nullptr;
  std::vector<unsigned char> buffer_;
  nph_dataset* dataset_ = nullptr;
  nph_renderer* renderer_ = nullptr;
};

TEST_F(ApiKnobs, EveryKnobOfTheTableIsAParameterWithItsRangeAndDefault) {
  using nph::lighting::KnobType;
  for (const nph::lighting::Knob& k : nph::lighting::knobs()) {
    const std::string name(k.name);
    SCOPED_TRACE(name);
    EXPECT_EQ(get(name), k.defaultValue());  // the renderer starts from the broadcast preset
    const double other = k.type() == KnobType::Boolean ? 1.0 - k.defaultValue() : k.max;
    ASSERT_EQ(api_->set_parameter(renderer_, name.c_str(), other), NPH_OK) << api_->last_error(renderer_);
    EXPECT_EQ(get(name), other);
    EXPECT_EQ(api_->set_parameter(renderer_, name.c_str(), k.max + 1.0), NPH_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(api_->set_parameter(renderer_, name.c_str(), k.min - 1.0), NPH_ERROR_INVALID_ARGUMENT);
    if (k.type() != KnobType::Number) {
      EXPECT_EQ(api_->set_parameter(renderer_, name.c_str(), k.min + 0.5), NPH_ERROR_INVALID_ARGUMENT);
    }
    EXPECT_EQ(get(name), other) << "a refused value changed the parameter";
  }
}

// Quality and style are separate (no keep-list in Session::setQuality): a preset resets every
// quality knob and no style knob.
TEST_F(ApiKnobs, QualityPresetKeepsTheStyle) {
  ASSERT_EQ(api_->set_parameter(renderer_, "g_ice", 0.3), NPH_OK);
  ASSERT_EQ(api_->set_parameter(renderer_, "ambient_b", 0.5), NPH_OK);
  ASSERT_EQ(api_->set_parameter(renderer_, "dlm_step_voxels", 2.0), NPH_OK);
  ASSERT_EQ(api_->set_quality_preset(renderer_, "draft"), NPH_OK);
  EXPECT_EQ(get("g_ice"), 0.3);
  EXPECT_EQ(get("ambient_b"), 0.5);
  const nph::lighting::QualitySettings draft = nph::lighting::qualityPreset("draft");
  for (const nph::lighting::Knob& k : nph::lighting::knobs()) {
    if (k.group() == nph::lighting::KnobGroup::Quality) {
      EXPECT_EQ(get(std::string(k.name)), k.get(draft)) << k.name;
    }
  }
}

}  // namespace
