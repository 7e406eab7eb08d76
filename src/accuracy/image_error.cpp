#include "accuracy/image_error.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "scene/display_transform.h"

namespace nph::accuracy {
namespace {

constexpr double kRelMseFloor = 0.01;
constexpr double kDisplayTolerance = 2.0 / 255.0;

// The sRGB transfer function (IEC 61966-2-1), in double: the metric's resolution is not the PNG's.
double srgbEncode(double c) { return scene::display::f64::linearToSrgb(std::clamp(c, 0.0, 1.0)); }

double display(float premultiplied) {
  return srgbEncode(scene::applyToneCurve(std::max(premultiplied, 0.0f), scene::ToneCurve::AcesFitted));
}

}  // namespace

double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

double luminanceNoiseRmse(const std::vector<float>& se) {
  const std::size_t n = se.size() / 3;
  if (n == 0) return 0.0;
  double noise = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = luminance(se[3 * i], se[3 * i + 1], se[3 * i + 2]);
    noise += s * s;
  }
  return std::sqrt(noise / double(n));
}

ImageError compareImages(const scene::RgbaImage& image, const scene::RgbaImage& reference,
                         const std::vector<float>& se) {
  if (image.width != reference.width || image.height != reference.height ||
      image.rgba.size() != reference.rgba.size()) {
    throw UsageError("compareImages: image sizes differ");
  }
  const std::size_t n = std::size_t(image.width) * std::size_t(image.height);
  if (n == 0) throw UsageError("compareImages: empty image");
  if (!se.empty() && se.size() != 3 * n) throw UsageError("compareImages: standard error needs 3 floats per pixel");
  ImageError e;
  double sq = 0.0, rel = 0.0, relNoise = 0.0, abs = 0.0, sumY = 0.0, sumYRef = 0.0;
  std::size_t off = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float* a = &image.rgba[4 * i];
    const float* b = &reference.rgba[4 * i];
    const double ya = luminance(a[0], a[1], a[2]), yb = luminance(b[0], b[1], b[2]);
    const double d = ya - yb;
    sq += d * d;
    sumY += ya;
    sumYRef += yb;
    rel += d * d / (yb * yb + kRelMseFloor);
    if (!se.empty()) {  // the truth's variance in the relMSE (ImageError::rel_mse_noise)
      const double sy = luminance(se[3 * i], se[3 * i + 1], se[3 * i + 2]);  // as luminanceNoiseRmse
      relNoise += sy * sy / (yb * yb + kRelMseFloor);
    }
    abs += std::abs(d);
    e.max_abs = std::max(e.max_abs, std::abs(d));
    e.alpha_max_abs = std::max(e.alpha_max_abs, std::abs(double(a[3]) - double(b[3])));
    bool isOff = false;
    for (int c = 0; c < 3; ++c) isOff = isOff || std::abs(display(a[c]) - display(b[c])) > kDisplayTolerance;
    off += isOff ? 1 : 0;
  }
  const double count = double(n);
  e.rmse = std::sqrt(sq / count);
  e.rel_mse = rel / count;
  e.mean_abs = abs / count;
  e.share_off_2_255 = double(off) / count;
  e.ref_noise_rmse = luminanceNoiseRmse(se);
  e.luminance_bias = sumYRef > 0.0 ? sumY / sumYRef - 1.0 : 0.0;
  if (!se.empty()) e.rel_mse_noise = relNoise / count;
  return e;
}

}  // namespace nph::accuracy
