#include "scene/basemap.h"

#include <OpenImageIO/imageio.h>
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

EquirectangularImage EquirectangularImage::load(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw InputError(fmt::format("{}: basemap image not found (expected an equirectangular "
                                 "satellite image, e.g. Blue Marble from Debian's marble-qt-data)",
                                 path));
  }
  requireRegularFile(path, "a basemap image");  // a FIFO would block the decoder forever
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    throw InputError(fmt::format("{}: cannot read the basemap image: {}", path, OIIO::geterror()));
  }
  const OIIO::ImageSpec spec = in->spec();
  const int w = spec.width, h = spec.height, nc = spec.nchannels;
  if (nc < 1 || nc > 4 || spec.depth > 1) {
    throw InputError(fmt::format("{}: basemap has {} channels, expected 1-4 (grey, RGB, RGBA)", path, nc));
  }
  // The header's size is checked before the decode buffers are allocated.
  limits::requireProductWithin(
      path, "basemap width x height", {std::uint64_t(std::max(w, 0)), std::uint64_t(std::max(h, 0))},
      limits::kMaxBasemapPixels, "limits::kMaxBasemapPixels; downsample the image, e.g. to 8192x4096");
  requireTwoToOne(w, h, path);
  const std::size_t n = std::size_t(w) * std::size_t(h);
  LinearRgbImage img{w, h, std::vector<float>(n * 3)};
  std::vector<float> raw(n * std::size_t(nc));
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, raw.data())) {
    throw InputError(fmt::format("{}: cannot decode the basemap image: {}", path, in->geterror()));
  }
  const bool encoded =
      !(spec.format.basetype == OIIO::TypeDesc::HALF || spec.format.basetype == OIIO::TypeDesc::FLOAT ||
        spec.format.basetype == OIIO::TypeDesc::DOUBLE);
  // 8-bit sources (Blue Marble JPEG): exact table of the 256 codes instead of 3·w·h pow() calls.
  std::array<float, 256> lut{};
  for (int c = 0; c < 256; ++c) lut[std::size_t(c)] = srgbToLinear(float(c) / 255.0f);
  const bool eightBit = spec.format.basesize() == 1;
  auto decode = [&](float v) {
    if (!encoded) return v;
    if (eightBit) return lut[std::size_t(std::clamp(std::lround(v * 255.0f), 0L, 255L))];
    return srgbToLinear(std::clamp(v, 0.0f, 1.0f));
  };
  for (std::size_t p = 0; p < n; ++p) {
    for (int c = 0; c < 3; ++c) {
      const int src = nc >= 3 ? c : 0;
      img.rgb[p * 3 + std::size_t(c)] = decode(raw[p * std::size_t(nc) + std::size_t(src)]);
    }
  }
  log::debug("basemap {}: {}x{} {} channel(s), {}", path, w, h, nc, encoded ? "sRGB decoded" : "linear");
  return EquirectangularImage(std::move(img), path);
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

WorldRect basemapRectangle(const VolumeFrame& frame, double margin_fraction) {
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

namespace {

/// Side of the cells [pixels] whose corners go through PROJ; lon/lat inside are interpolated.
constexpr int kCell_px = 8;
/// Largest accepted interpolation error [deg] (~11 m), checked at every cell's centre; cells
/// that exceed it (near a pole, across a projection's edge) are projected pixel by pixel.
constexpr double kInterpolationTolerance_deg = 1e-4;

}  // namespace

LinearRgbImage reprojectBasemap(const EquirectangularImage& source, const SceneGeoreference& geo, const WorldRect& rect,
                                int width, int height) {
  if (width <= 0 || height <= 0 || !(rect.max_m.x > rect.min_m.x) || !(rect.max_m.y > rect.min_m.y)) {
    throw UsageError(fmt::format("reprojectBasemap: empty request ({}x{} pixels)", width, height));
  }
  LinearRgbImage out{width, height, std::vector<float>(std::size_t(width) * std::size_t(height) * 3)};
  // PROJ costs ~0.3 µs a point; a 4096² basemap would spend seconds in it. Map projections are
  // smooth at the scale of a few pixels, so only the corners of 8×8-pixel cells are projected and
  // lon/lat are interpolated bilinearly inside, with the error checked at each cell's centre.
  const int cx = (width - 1) / kCell_px + 2, cy = (height - 1) / kCell_px + 2;  // node counts
  std::vector<double> nodes(std::size_t(cx) * std::size_t(cy) * 2);
  for (int j = 0; j < cy; ++j) {
    for (int i = 0; i < cx; ++i) {
      const glm::dvec2 w = worldFromBasemapPixel(rect, width, height, double(i * kCell_px), double(j * kCell_px));
      const std::size_t n = (std::size_t(j) * std::size_t(cx) + std::size_t(i)) * 2;
      nodes[n] = w.x;
      nodes[n + 1] = w.y;
    }
  }
  geo.lonLatFromWorldBatch(nodes.data(), std::size_t(cx) * std::size_t(cy));
  const std::size_t cellCount = std::size_t(cx - 1) * std::size_t(cy - 1);
  std::vector<double> centres(cellCount * 2);
  for (int j = 0; j + 1 < cy; ++j) {
    for (int i = 0; i + 1 < cx; ++i) {
      const double half = 0.5 * kCell_px;
      const glm::dvec2 w = worldFromBasemapPixel(rect, width, height, i * kCell_px + half, j * kCell_px + half);
      const std::size_t c = (std::size_t(j) * std::size_t(cx - 1) + std::size_t(i)) * 2;
      centres[c] = w.x;
      centres[c + 1] = w.y;
    }
  }
  geo.lonLatFromWorldBatch(centres.data(), cellCount);

  std::size_t failed = 0, exactCells = 0;
  std::vector<double> exact(std::size_t(kCell_px) * std::size_t(kCell_px) * 2);
  auto put = [&](int px, int py, double lon, double lat) {
    const std::size_t o = (std::size_t(py) * std::size_t(width) + std::size_t(px)) * 3;
    glm::vec3 c(0.0f);
    if (std::isnan(lon) || std::isnan(lat)) {
      ++failed;
    } else {
      c = source.sampleLonLat(lon, std::clamp(lat, -90.0, 90.0));
    }
    out.rgb[o] = c.r;
    out.rgb[o + 1] = c.g;
    out.rgb[o + 2] = c.b;
  };
  for (int j = 0; j + 1 < cy; ++j) {
    for (int i = 0; i + 1 < cx; ++i) {
      const int x0 = i * kCell_px, y0 = j * kCell_px;
      const int x1 = std::min(x0 + kCell_px, width), y1 = std::min(y0 + kCell_px, height);
      auto node = [&](int di, int dj) {
        const std::size_t n = (std::size_t(j + dj) * std::size_t(cx) + std::size_t(i + di)) * 2;
        return glm::dvec2(nodes[n], nodes[n + 1]);
      };
      glm::dvec2 q[4] = {node(0, 0), node(1, 0), node(0, 1), node(1, 1)};
      bool ok = true;
      double lonMin = 1e9, lonMax = -1e9;
      for (const auto& p : q) {
        ok = ok && !std::isnan(p.x);
        lonMin = std::min(lonMin, p.x);
        lonMax = std::max(lonMax, p.x);
      }
      if (ok && lonMax - lonMin > 180.0) {  // the cell straddles the antimeridian: unwrap
        for (auto& p : q) p.x += p.x < 0.0 ? 360.0 : 0.0;
      }
      auto interpolate = [&](double fx, double fy) {
        return glm::mix(glm::mix(q[0], q[1], fx), glm::mix(q[2], q[3], fx), fy);
      };
      if (ok) {
        const std::size_t c = (std::size_t(j) * std::size_t(cx - 1) + std::size_t(i)) * 2;
        const glm::dvec2 mid = interpolate(0.5, 0.5);
        const double dLon = std::abs(normaliseLongitude_deg(mid.x - centres[c]));
        ok = !std::isnan(centres[c]) && dLon < kInterpolationTolerance_deg &&
             std::abs(mid.y - centres[c + 1]) < kInterpolationTolerance_deg;
      }
      if (ok) {
        for (int py = y0; py < y1; ++py) {
          for (int px = x0; px < x1; ++px) {
            const glm::dvec2 ll = interpolate(double(px - x0) / kCell_px, double(py - y0) / kCell_px);
            put(px, py, ll.x, ll.y);
          }
        }
        continue;
      }
      ++exactCells;
      std::size_t n = 0;
      for (int py = y0; py < y1; ++py) {
        for (int px = x0; px < x1; ++px, ++n) {
          const glm::dvec2 w = worldFromBasemapPixel(rect, width, height, px, py);
          exact[2 * n] = w.x;
          exact[2 * n + 1] = w.y;
        }
      }
      geo.lonLatFromWorldBatch(exact.data(), n);
      n = 0;
      for (int py = y0; py < y1; ++py) {
        for (int px = x0; px < x1; ++px, ++n) put(px, py, exact[2 * n], exact[2 * n + 1]);
      }
    }
  }
  if (exactCells > 0) {
    log::debug("basemap {}: {} of {} cells projected pixel by pixel", source.name(), exactCells, cellCount);
  }
  if (failed > 0) {
    log::warn("basemap {}: {} of {} pixels lie outside the projection '{}' and are black", source.name(), failed,
              std::size_t(width) * std::size_t(height), geo.projection().definition());
  }
  return out;
}

}  // namespace nph::scene
