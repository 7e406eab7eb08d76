#include "scene/output_image.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "atmosphere/atmosphere.h"
#include "core/error.h"
#include "core/temp_files.h"
#include "scene/colour_output.h"
#include "scene/display_transform.h"
#include "scene/image_codec.h"

namespace nph::scene {

double sunExposureOffsetEv(double sun_elevation_deg) {
  if (!std::isfinite(sun_elevation_deg)) return 0.0;
  constexpr double kMeterAltitude_m = 2000.0;  // a typical cloud base: the light the clouds stand in
  constexpr double kDegToRad = 0.017453292519943295;
  const atmosphere::Parameters earth = atmosphere::Parameters::earth();
  static const double reference =
      atmosphere::horizontalIlluminance(earth, kMeterAltitude_m, kExposureReferenceSunElevationDeg * kDegToRad);
  const double e = atmosphere::horizontalIlluminance(earth, kMeterAltitude_m,
                                                     std::clamp(sun_elevation_deg, -90.0, 90.0) * kDegToRad);
  if (!(e > 0.0)) return 4.0;
  return std::clamp(0.5 * std::log2(reference / e), -1.0, 4.0);
}
namespace fs = std::filesystem;

namespace {

static_assert(display::kToneCurveClamp == int(ToneCurve::Clamp) &&
              display::kToneCurveReinhard == int(ToneCurve::Reinhard) &&
              display::kToneCurveAcesFitted == int(ToneCurve::AcesFitted));

void checkImage(const RgbaImage& img, const std::string& path) {
  const std::size_t n = std::size_t(std::max(img.width, 0)) * std::size_t(std::max(img.height, 0));
  const bool depthOnly = img.rgba.empty() && img.depth_m.size() == n;
  if (img.width <= 0 || img.height <= 0 || (img.rgba.size() != 4 * n && !depthOnly) ||
      !(img.depth_m.empty() || img.depth_m.size() == n)) {
    throw UsageError(fmt::format("{}: inconsistent image {}x{} with {} RGBA floats and {} depths", path, img.width,
                                 img.height, img.rgba.size(), img.depth_m.size()));
  }
  for (const ImageLayer& l : img.layers) {
    if (l.name.empty() || l.channels.empty() || l.values.size() != n * l.channels.size()) {
      throw UsageError(fmt::format("{}: inconsistent layer '{}' with {} channels and {} values", path, l.name,
                                   l.channels.size(), l.values.size()));
    }
  }
}

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// Writes through OpenImageIO (the image codec module, scene/image_codec.h) to
/// `<dir>/.<name>.partial-<pid>-XXXXXX<ext>` and renames onto `path`. The temporary is created
/// exclusively first (temp_files.h): OIIO opens its file with O_CREAT|O_TRUNC, which followed a
/// symlink planted under the old predictable name and overwrote another file.
void writeAtomically(const std::string& path, const image_codec::WriteSpec& spec, const void* pixels,
                     image_codec::Type pixelType) {
  const fs::path final(path);
  const fs::path dir = final.has_parent_path() ? final.parent_path() : fs::path(".");
  temp_files::removeStale(dir, ".partial-");
  const temp_files::Created created =
      temp_files::createExclusive(final, "." + final.stem().string(), ".partial-", final.extension().string());
  ::close(created.fd);
  const fs::path tmp = created.path;
  const temp_files::CleanupRegistration cleanup(tmp);
  auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(fmt::format("{}: cannot write the image: {}", path, why));
  };
  try {
    image_codec::write(tmp.string(), path, spec, pixels, pixelType);
  } catch (const IoError&) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, final, ec);
  if (ec) fail(ec.message());
}
/// 8/16-bit RGBA with straight alpha: our data is straight already, so OIIO must not divide by
/// alpha again (oiio:UnassociatedAlpha).
image_codec::WriteSpec rgbaSpec(const RgbaImage& img, image_codec::Type type) {
  image_codec::WriteSpec spec;
  spec.width = img.width;
  spec.height = img.height;
  spec.channels = 4;
  spec.format = type;
  spec.alpha_channel = 3;
  spec.integers = {{"oiio:UnassociatedAlpha", 1}};
  return spec;
}
}  // namespace

ToneCurve toneCurveFromName(std::string_view name) {
  if (name == "clamp") return ToneCurve::Clamp;
  if (name == "reinhard") return ToneCurve::Reinhard;
  if (name == "aces") return ToneCurve::AcesFitted;
  throw InputError(fmt::format("tone curve '{}': expected \"aces\", \"reinhard\" or \"clamp\"", name));
}

std::string_view toneCurveName(ToneCurve c) {
  switch (c) {
    case ToneCurve::Clamp: return "clamp";
    case ToneCurve::Reinhard: return "reinhard";
    case ToneCurve::AcesFitted: return "aces";
  }
  return "aces";
}

float applyToneCurve(float c, ToneCurve curve) {
  if (!std::isfinite(c)) c = 0.0f;  // NaN and ±inf (−inf would give 0 anyway)
  return display::f32::toneCurve(c, int(curve));
}

float linearToSrgb(float l) { return display::f32::linearToSrgb(l); }

glm::vec3 radianceScale(const ImageOutputOptions& o) {
  // At the neutral white balance the gain is 1 in every channel, exactly (scene/white_balance.h):
  // the scale is then 2^exposure_ev, as it was before the white balance existed.
  return glm::vec3(std::exp2(o.exposure_ev) * whiteBalanceGain(o.white_balance_k, o.white_balance_duv));
}

std::vector<std::uint8_t> encodeSrgb8(const RgbaImage& img, const ImageOutputOptions& o) {
  checkImage(img, "<image>");
  if (img.rgba.empty()) throw InputError("a depth-only image has no colour to encode: write it as .exr");
  const glm::vec3 scale = radianceScale(o);
  const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
  std::vector<std::uint8_t> out(4 * n);
  auto code = [](float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  for (std::size_t p = 0; p < n; ++p) {
    const float* src = &img.rgba[4 * p];
    const float alpha = std::isfinite(src[3]) ? std::clamp(src[3], 0.0f, 1.0f) : 0.0f;
    const std::uint8_t alphaCode = code(alpha);
    out[4 * p + 3] = alphaCode;
    for (int c = 0; c < 3; ++c) {
      // Straight colour is undefined where nothing is covered (α = 0, or α below half a code):
      // write black there, so the PNG carries no colour that no compositor can see.
      float v = 0.0f;
      if (img.content == ImageContent::Data) {
        v = std::isfinite(src[c]) ? src[c] : 0.0f;  // a matte: stored as it is
      } else if (alphaCode > 0) {
        v = linearToSrgb(applyToneCurve(scale[c] * src[c] / alpha, o.tone_curve));
      }
      out[4 * p + std::size_t(c)] = code(v);
    }
  }
  return out;
}

std::vector<float> encodeDisplay(const RgbaImage& img, const ImageOutputOptions& o) {
  checkImage(img, "<image>");
  if (img.rgba.empty()) throw InputError("a depth-only image has no colour to encode: write it as .exr");
  const auto display = DisplayOutput::open(o.ocio_config, o.display, o.view);
  const glm::vec3 scale = radianceScale(o);
  const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
  std::vector<float> rgb(3 * n), out(4 * n);
  for (std::size_t p = 0; p < n; ++p) {
    const float* src = &img.rgba[4 * p];
    const float alpha = std::isfinite(src[3]) ? std::clamp(src[3], 0.0f, 1.0f) : 0.0f;
    out[4 * p + 3] = alpha;
    // Straight colour, as the legacy path (α = 0: black, never seen)
    for (std::size_t c = 0; c < 3; ++c) rgb[3 * p + c] = alpha > 0.0f ? scale[int(c)] * src[c] / alpha : 0.0f;
  }
  display->apply(rgb.data(), n);
  for (std::size_t p = 0; p < n; ++p) {
    for (std::size_t c = 0; c < 3; ++c) out[4 * p + c] = out[4 * p + 3] > 0.0f ? rgb[3 * p + c] : 0.0f;
  }
  return out;
}

void writePng(const RgbaImage& img, const std::string& path, const ImageOutputOptions& o) {
  checkImage(img, path);
  if (img.rgba.empty()) throw InputError(path + ": a depth pass holds distances, not colours: write it as .exr");
  if (!o.display.empty() && img.content == ImageContent::Radiance) {
    const auto display = DisplayOutput::open(o.ocio_config, o.display, o.view);
    const std::vector<float> v = encodeDisplay(img, o);
    const bool wide = display->hdr();  // PQ / HLG: 8 bits would band; PNG has 16
    image_codec::WriteSpec spec = rgbaSpec(img, wide ? image_codec::Type::UInt16 : image_codec::Type::UInt8);
    spec.text = {{"oiio:ColorSpace", display->display() + " / " + display->view()}, {"Software", "nephele"}};
    const float maxCode = wide ? 65535.0f : 255.0f;
    if (wide) {
      std::vector<std::uint16_t> codes(v.size());
      for (std::size_t i = 0; i < v.size(); ++i) codes[i] = static_cast<std::uint16_t>(std::lround(v[i] * maxCode));
      return writeAtomically(path, spec, codes.data(), image_codec::Type::UInt16);
    }
    std::vector<std::uint8_t> codes(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) codes[i] = static_cast<std::uint8_t>(std::lround(v[i] * maxCode));
    return writeAtomically(path, spec, codes.data(), image_codec::Type::UInt8);
  }
  const std::vector<std::uint8_t> codes = encodeSrgb8(img, o);
  image_codec::WriteSpec spec = rgbaSpec(img, image_codec::Type::UInt8);
  spec.text = {{"oiio:ColorSpace", img.content == ImageContent::Data ? "Linear" : "sRGB"}, {"Software", "nephele"}};
  writeAtomically(path, spec, codes.data(), image_codec::Type::UInt8);
}

void writeExr(const RgbaImage& img, const std::string& path, const ImageOutputOptions& o) {
  checkImage(img, path);
  // Channels in order: R G B A (unless depth-only), Z (float: depths need > 65504 m), then each
  // layer's `name.C` (half). One part: Nuke, Fusion, Resolve and OIIO split it by the prefixes.
  struct Channel {
    std::string name;
    image_codec::Type type;
    const float* src;  // first value
    std::size_t stride;
    float scale;
  };
  // Z when asked for, and always with the passes (scene/passes.h) or alone (a depth pass).
  const bool depth = !img.depth_m.empty() && (o.write_depth || img.rgba.empty() || !img.layers.empty());
  // Radiance channels R, G, B carry the exposure and the white balance's gain; a luminance (Y) the
  // exposure alone; alpha, mattes and Z nothing.
  const glm::vec3 scale = radianceScale(o);
  const auto exposure = static_cast<float>(std::exp2(o.exposure_ev));
  auto radianceGain = [&](const std::string& channel) {
    return channel == "R" ? scale[0] : channel == "G" ? scale[1] : channel == "B" ? scale[2] : exposure;
  };
  std::vector<Channel> channels;
  if (!img.rgba.empty()) {
    for (int c = 0; c < 4; ++c) {
      const std::string name(1, "RGBA"[c]);
      channels.push_back({name, image_codec::Type::Half, img.rgba.data() + c, 4,
                          c < 3 && img.content != ImageContent::Data ? radianceGain(name) : 1.0f});
    }
  }
  if (depth) channels.push_back({"Z", image_codec::Type::Float, img.depth_m.data(), 1, 1.0f});
  for (const ImageLayer& l : img.layers) {
    for (std::size_t c = 0; c < l.channels.size(); ++c) {
      const bool alpha = l.channels[c] == "A";
      channels.push_back({l.name + "." + l.channels[c], image_codec::Type::Half, l.values.data() + c, l.channels.size(),
                          l.radiance && !alpha ? radianceGain(l.channels[c]) : 1.0f});
    }
  }
  const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
  const std::size_t nc = channels.size();
  std::vector<float> px(n * nc);
  for (std::size_t p = 0; p < n; ++p) {
    for (std::size_t c = 0; c < nc; ++c) px[p * nc + c] = channels[c].scale * channels[c].src[p * channels[c].stride];
  }
  image_codec::WriteSpec spec;
  spec.width = img.width;
  spec.height = img.height;
  spec.channels = int(nc);
  spec.format = image_codec::Type::Half;
  spec.alpha_channel = img.rgba.empty() ? -1 : 3;
  spec.z_channel = depth ? (img.rgba.empty() ? 0 : 4) : -1;
  spec.text = {{"compression", "zip"}, {"oiio:ColorSpace", "Linear"}, {"Software", "nephele"}};
  bool mixed = false;
  for (const Channel& c : channels) {
    spec.channel_names.push_back(c.name);
    spec.channel_formats.push_back(c.type);
    mixed = mixed || c.type != image_codec::Type::Half;
  }
  if (!mixed) spec.channel_formats.clear();
  if (!o.date_time.empty()) spec.text.emplace_back("DateTime", o.date_time);
  writeAtomically(path, spec, px.data(), image_codec::Type::Float);
}

void writeImage(const RgbaImage& img, const std::string& path, const ImageOutputOptions& o) {
  const std::string ext = lowerExtension(path);
  if (ext == ".exr") return writeExr(img, path, o);
  if (ext == ".png") return writePng(img, path, o);
  throw InputError(fmt::format("{}: output image type '{}' is not supported, expected .exr or .png", path, ext));
}

}  // namespace nph::scene
