// The image codec module's loader (scene/image_codec.h): the first candidate that is the module
// wins; a missing or foreign file is an IoError naming the image and every path tried.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "scene/image_codec.h"

namespace nph::scene {
namespace {

/// A shared object that exists but is not the module: libc's, found through dlopen's own symbol.
std::string foreignSharedObject() {
  Dl_info info{};
  EXPECT_NE(::dladdr(reinterpret_cast<void*>(&::dlopen), &info), 0);
  return info.dli_fname != nullptr ? info.dli_fname : "";
}

TEST(ImageCodec, LoadsTheFirstCandidateThatIsTheModule) {
  const std::string foreign = foreignSharedObject();
  ASSERT_FALSE(foreign.empty());
  EXPECT_EQ(image_codec::loadFrom({"/nonexistent/codec.so", foreign, NEPHELE_TEST_IMAGE_CODEC}, "frame.png"),
            NEPHELE_TEST_IMAGE_CODEC);
  EXPECT_EQ(image_codec::modulePath(), NEPHELE_TEST_IMAGE_CODEC) << "the build tree's module, by default";
}

TEST(ImageCodec, NoModuleIsAnIoErrorNamingTheImageAndEveryPathTried) {
  const std::string foreign = foreignSharedObject();
  try {
    image_codec::loadFrom({"/nonexistent/codec.so", foreign}, "out/frame.png");
    FAIL() << "no module, no error";
  } catch (const IoError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("out/frame.png"), std::string::npos) << m;
    EXPECT_NE(m.find("/nonexistent/codec.so"), std::string::npos) << m;
    EXPECT_NE(m.find(foreign + ": not nephele's image codec module"), std::string::npos) << m;
    EXPECT_NE(m.find("NEPHELE_IMAGE_CODEC"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace nph::scene
