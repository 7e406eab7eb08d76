#include "scene/basemap.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/input_file.h"
#include "core/limits.h"
#include "core/log.h"

namespace nph::scene {

// IEC 61966-2-1 (sRGB): linear segment below 0.04045 (encoded) / 0.0031308 (linear).
float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
namespace {

void requireTwoToOne(int w, int h, const std::string& name) {
  if (w < 2 || h < 1 || std::abs(w - 2 * h) > 1) {
    throw InputError(fmt::format("{}: basemap is {}x{} pixels, expected an equirectangular image "
                                 "covering 360°×180° (width = 2·height)",
                                 name, w, h));
  }
}

}  // namespace

EquirectangularImage::EquirectangularImage(LinearRgbImage image, std::string name)
    : image_(std::move(image)), name_(std::move(name)) {
  requireTwoToOne(image_.width, image_.height, name_);
  if (image_.rgb.size() != std::size_t(image_.width) * std::size_t(image_.height) * 3) {
    throw UsageError(fmt::format("{}: {} floats for {}x{} RGB", name_, image_.rgb.size(), image_.width, image_.height));
  }
}

glm::dvec2 equirectUv(double lon_deg, double lat_deg) { return {(lon_deg + 180.0) / 360.0, (90.0 - lat_deg) / 180.0}; }

glm::vec3 EquirectangularImage::sampleLonLat(double lon_deg, double lat_deg) const {
  const int w = image_.width, h = image_.height;
  const glm::dvec2 uv = equirectUv(lon_deg, lat_deg);
  // Pixel-is-area: pixel centres at (i + ½)/w; bilinear between the four nearest centres.
  const double x = uv.x * w - 0.5, y = std::clamp(uv.y * h - 0.5, 0.0, double(h - 1));
  const double xf = std::floor(x), yf = std::floor(y);
  const auto fx = static_cast<float>(x - xf), fy = static_cast<float>(y - yf);
  auto wrapX = [w](double i) { return static_cast<int>(i - double(w) * std::floor(i / double(w))); };
  const int x0 = wrapX(xf), x1 = wrapX(xf + 1.0);
  const int y0 = static_cast<int>(yf), y1 = std::min(y0 + 1, h - 1);
  const glm::vec3 top = glm::mix(image_.at(x0, y0), image_.at(x1, y0), fx);
  const glm::vec3 bottom = glm::mix(image_.at(x0, y1), image_.at(x1, y1), fx);
  return glm::mix(top, bottom, fy);
}

WorldRect basemapRectangle(const volume::VolumeFrame& frame, double margin_fraction) {
  if (!(margin_fraction >= 0.0) || !std::isfinite(margin_fraction)) {
    throw UsageError(fmt::format("basemap margin {} must be a non-negative fraction", margin_fraction));
  }
  const glm::dvec3 s = frame.size_m();
  const double m = margin_fraction * std::max(s.x, s.y);
  return {{-m, -m}, {s.x + m, s.y + m}};
}

glm::dvec2 worldFromBasemapPixel(const WorldRect& r, int width, int height, double px, double py) {
  return {r.min_m.x + (px + 0.5) / width * (r.max_m.x - r.min_m.x),
          r.max_m.y - (py + 0.5) / height * (r.max_m.y - r.min_m.y)};
}

}  // namespace nph::scene
