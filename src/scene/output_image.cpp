#include "scene/output_image.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/temp_files.h"
#include "scene/display_transform.h"

namespace nph::scene {
namespace fs = std::filesystem;

namespace {

static_assert(display::kToneCurveClamp == int(ToneCurve::Clamp) &&
              display::kToneCurveReinhard == int(ToneCurve::Reinhard) &&
              display::kToneCurveAcesFitted == int(ToneCurve::AcesFitted));

void checkImage(const RgbaImage& img, const std::string& path) {
  const std::size_t n = std::size_t(std::max(img.width, 0)) * std::size_t(std::max(img.height, 0));
  if (img.width <= 0 || img.height <= 0 || img.rgba.size() != 4 * n ||
      !(img.depth_m.empty() || img.depth_m.size() == n)) {
    throw UsageError(fmt::format("{}: inconsistent image {}x{} with {} RGBA floats and {} depths",
                                 path, img.width, img.height, img.rgba.size(), img.depth_m.size()));
  }
}

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// Writes through OIIO to `<dir>/.<name>.partial-<pid>-XXXXXX<ext>` and renames onto `path`.
/// The temporary is created exclusively first (temp_files.h): OIIO opens its file with
/// O_CREAT|O_TRUNC, which followed a symlink planted under the old predictable name and
/// overwrote another file.
void writeAtomically(const std::string& path, const OIIO::ImageSpec& spec, const void* pixels,
                     OIIO::TypeDesc pixelType) {
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
  auto out = OIIO::ImageOutput::create(path);
  if (!out) fail(OIIO::geterror());
  if (!out->open(tmp.string(), spec)) fail(out->geterror());
  if (!out->write_image(pixelType, pixels)) {
    const std::string why = out->geterror();
    out->close();
    fail(why);
  }
  if (!out->close()) fail(out->geterror());
  out.reset();
  std::error_code ec;
  fs::rename(tmp, final, ec);
  if (ec) fail(ec.message());
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

std::vector<std::uint8_t> encodeSrgb8(const RgbaImage& img, const ImageOutputOptions& o) {
  checkImage(img, "<image>");
  const auto scale = static_cast<float>(std::exp2(o.exposure_ev));
  const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
  std::vector<std::uint8_t> out(4 * n);
  auto code = [](float v) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
  };
  for (std::size_t p = 0; p < n; ++p) {
    const float* src = &img.rgba[4 * p];
    const float alpha = std::isfinite(src[3]) ? std::clamp(src[3], 0.0f, 1.0f) : 0.0f;
    const std::uint8_t alphaCode = code(alpha);
    out[4 * p + 3] = alphaCode;
    for (int c = 0; c < 3; ++c) {
      // Straight colour is undefined where nothing is covered (α = 0, or α below half a code):
      // write black there, so the PNG carries no colour that no compositor can see.
      float v = 0.0f;
      if (alphaCode > 0) v = linearToSrgb(applyToneCurve(scale * src[c] / alpha, o.tone_curve));
      out[4 * p + std::size_t(c)] = code(v);
    }
  }
  return out;
}

void writePng(const RgbaImage& img, const std::string& path, const ImageOutputOptions& o) {
  checkImage(img, path);
  const std::vector<std::uint8_t> codes = encodeSrgb8(img, o);
  OIIO::ImageSpec spec(img.width, img.height, 4, OIIO::TypeDesc::UINT8);
  spec.alpha_channel = 3;
  // Our data is straight already: tell OIIO not to divide by alpha again.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  spec.attribute("oiio:ColorSpace", "sRGB");
  spec.attribute("Software", "nephele");
  writeAtomically(path, spec, codes.data(), OIIO::TypeDesc::UINT8);
}

void writeExr(const RgbaImage& img, const std::string& path, const ImageOutputOptions& o) {
  checkImage(img, path);
  const bool depth = o.write_depth && !img.depth_m.empty();
  const int nc = depth ? 5 : 4;
  const std::size_t n = std::size_t(img.width) * std::size_t(img.height);
  const auto scale = static_cast<float>(std::exp2(o.exposure_ev));
  std::vector<float> px(n * std::size_t(nc));
  for (std::size_t p = 0; p < n; ++p) {
    for (int c = 0; c < 3; ++c) px[p * std::size_t(nc) + std::size_t(c)] = scale * img.rgba[4 * p + std::size_t(c)];
    px[p * std::size_t(nc) + 3] = img.rgba[4 * p + 3];
    if (depth) px[p * std::size_t(nc) + 4] = img.depth_m[p];
  }
  OIIO::ImageSpec spec(img.width, img.height, nc, OIIO::TypeDesc::HALF);
  spec.channelnames = {"R", "G", "B", "A"};
  spec.alpha_channel = 3;
  if (depth) {
    spec.channelnames.push_back("Z");
    spec.channelformats = {OIIO::TypeDesc::HALF, OIIO::TypeDesc::HALF, OIIO::TypeDesc::HALF,
                           OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT};  // depth needs > 65504 m
    spec.z_channel = 4;
  }
  spec.attribute("compression", "zip");
  spec.attribute("oiio:ColorSpace", "Linear");
  spec.attribute("Software", "nephele");
  if (!o.date_time.empty()) spec.attribute("DateTime", o.date_time);
  writeAtomically(path, spec, px.data(), OIIO::TypeDesc::FLOAT);
}

void writeImage(const RgbaImage& img, const std::string& path, const ImageOutputOptions& o) {
  const std::string ext = lowerExtension(path);
  if (ext == ".exr") return writeExr(img, path, o);
  if (ext == ".png") return writePng(img, path, o);
  throw InputError(fmt::format("{}: output image type '{}' is not supported, expected .exr or .png",
                               path, ext));
}

}  // namespace nph::scene
