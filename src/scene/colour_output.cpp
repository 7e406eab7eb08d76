#include "scene/colour_output.h"

#include <OpenColorIO/OpenColorIO.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <tuple>
#include <vector>

#include "core/error.h"

namespace OCIO = OCIO_NAMESPACE;

namespace nph::scene {

struct DisplayOutput::Impl {
  OCIO::ConstCPUProcessorRcPtr cpu;
};

DisplayOutput::DisplayOutput(std::shared_ptr<const Impl> impl, std::string config, std::string display,
                             std::string view, bool hdr)
    : impl_(std::move(impl)),
      config_(std::move(config)),
      display_(std::move(display)),
      view_(std::move(view)),
      hdr_(hdr) {}

std::string defaultOcioConfig() {
  if (const char* env = std::getenv("NEPHELE_OCIO_CONFIG"); env != nullptr && *env != '\0') return env;
  for (const char* candidate : {NEPHELE_OCIO_BUILD_CONFIG, NEPHELE_OCIO_INSTALL_CONFIG}) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
  }
  throw InputError(fmt::format("no OpenColorIO config: neither {} (build tree) nor {} (installed) exists; build the "
                               "target nephele_ocio_config, or set NEPHELE_OCIO_CONFIG",
                               NEPHELE_OCIO_BUILD_CONFIG, NEPHELE_OCIO_INSTALL_CONFIG));
}

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "\"" : ", \"") + n + "\"";
  return s;
}

std::shared_ptr<const DisplayOutput> build(const std::string& path, const std::string& display,
                                           const std::string& view) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(fmt::format("{}: OpenColorIO config not found (output.ocio_config / NEPHELE_OCIO_CONFIG)", path));
  }
  try {
    const OCIO::ConstConfigRcPtr cfg = OCIO::Config::CreateFromFile(path.c_str());
    std::vector<std::string> displays;
    for (int i = 0; i < cfg->getNumDisplays(); ++i) displays.emplace_back(cfg->getDisplay(i));
    if (std::find(displays.begin(), displays.end(), display) == displays.end()) {
      throw InputError(fmt::format("{}: no display \"{}\"; the config has {}", path, display, joined(displays)));
    }
    std::vector<std::string> views;
    for (int i = 0; i < cfg->getNumViews(display.c_str()); ++i) views.emplace_back(cfg->getView(display.c_str(), i));
    const std::string v = view.empty() ? std::string(cfg->getDefaultView(display.c_str())) : view;
    if (std::find(views.begin(), views.end(), v) == views.end()) {
      throw InputError(
          fmt::format("{}: display \"{}\" has no view \"{}\"; it has {}", path, display, v, joined(views)));
    }
    const OCIO::DisplayViewTransformRcPtr t = OCIO::DisplayViewTransform::Create();
    t->setSrc(OCIO::ROLE_SCENE_LINEAR);
    t->setDisplay(display.c_str());
    t->setView(v.c_str());
    auto impl = std::make_shared<DisplayOutput::Impl>();
    impl->cpu = cfg->getProcessor(t)->getDefaultCPUProcessor();
    bool hdr = false;
    const char* spaceName = cfg->getDisplayViewColorSpaceName(display.c_str(), v.c_str());
    if (const OCIO::ConstColorSpaceRcPtr cs = spaceName ? cfg->getColorSpace(spaceName) : nullptr) {
      hdr = std::string(cs->getEncoding()) == "hdr-video";
    }
    return std::make_shared<DisplayOutput>(std::move(impl), path, display, v, hdr);
  } catch (const OCIO::Exception& e) {
    throw InputError(fmt::format("{}: OpenColorIO: {}", path, e.what()));
  }
}

}  // namespace

std::shared_ptr<const DisplayOutput> DisplayOutput::open(const std::string& config, const std::string& display,
                                                         const std::string& view) {
  const std::string path = config.empty() ? defaultOcioConfig() : config;
  static std::mutex mutex;
  static std::map<std::tuple<std::string, std::string, std::string>, std::shared_ptr<const DisplayOutput>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[{path, display, view}];
  if (!slot) slot = build(path, display, view);
  return slot;
}

void DisplayOutput::apply(float* rgb, std::size_t pixels) const {
  for (std::size_t i = 0; i < 3 * pixels; ++i) {
    if (!std::isfinite(rgb[i])) rgb[i] = 0.0f;
  }
  try {
    OCIO::PackedImageDesc desc(rgb, static_cast<long>(pixels), 1, 3);
    impl_->cpu->apply(desc);
  } catch (const OCIO::Exception& e) {
    throw InputError(fmt::format("{}: OpenColorIO display \"{}\" view \"{}\": {}", config_, display_, view_, e.what()));
  }
  for (std::size_t i = 0; i < 3 * pixels; ++i) rgb[i] = std::isfinite(rgb[i]) ? std::clamp(rgb[i], 0.0f, 1.0f) : 0.0f;
}

VideoColourTags DisplayOutput::videoTags() const {
  // The displays of src/scene/ocio/config.ocio, by name (ffmpeg's names for ITU-T H.273 codes).
  if (display_ == "sRGB") return {"bt709", "iec61966-2-1", "bt709"};
  if (display_ == "Rec.1886 Rec.709") return {"bt709", "bt709", "bt709"};
  if (display_ == "Rec.2100-PQ") return {"bt2020", "smpte2084", "bt2020nc"};
  if (display_ == "Rec.2100-HLG") return {"bt2020", "arib-std-b67", "bt2020nc"};
  return {};
}

}  // namespace nph::scene
