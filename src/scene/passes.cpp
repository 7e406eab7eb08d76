#include "scene/passes.h"

#include <array>

#include <fmt/format.h>

#include "core/error.h"

namespace nph::scene {
namespace {

constexpr std::array<std::pair<Pass, std::string_view>, 6> kPassNames{{{Pass::Beauty, "beauty"},
                                                                       {Pass::Cloud, "cloud"},
                                                                       {Pass::Ground, "ground"},
                                                                       {Pass::Sky, "sky"},
                                                                       {Pass::Shadow, "shadow"},
                                                                       {Pass::Depth, "depth"}}};

void checkPasses(const RgbaImage& frame, const RgbaImage& cloud, const FramePasses& p) {
  const std::size_t n = std::size_t(frame.width) * std::size_t(frame.height);
  if (cloud.width != frame.width || cloud.height != frame.height || p.width != frame.width ||
      p.height != frame.height || p.ground_rgb.size() != 3 * n || p.sky_rgb.size() != 3 * n || p.shadow.size() != n ||
      p.depth_m.size() != n) {
    throw UsageError(fmt::format("compositing passes {}x{} do not match the frame {}x{}", p.width, p.height,
                                 frame.width, frame.height));
  }
}

/// RGB (+ α = 1) or one channel (grey, α = 1) as an RGBA image.
RgbaImage opaque(int w, int h, const std::vector<float>& values, std::size_t channels, ImageContent content) {
  RgbaImage img;
  img.width = w;
  img.height = h;
  img.content = content;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  img.rgba.resize(4 * n);
  for (std::size_t p = 0; p < n; ++p) {
    for (std::size_t c = 0; c < 3; ++c) img.rgba[4 * p + c] = values[p * channels + (channels == 1 ? 0 : c)];
    img.rgba[4 * p + 3] = 1.0f;
  }
  return img;
}

}  // namespace

std::optional<Pass> passFromName(std::string_view name) {
  for (const auto& [pass, n] : kPassNames) {
    if (n == name) return pass;
  }
  return std::nullopt;
}

std::string_view passName(Pass pass) {
  for (const auto& [p, n] : kPassNames) {
    if (p == pass) return n;
  }
  return "beauty";
}

std::string passNames() {
  std::string s;
  for (const auto& [p, n] : kPassNames) s += (s.empty() ? "" : ", ") + std::string(n);
  return s;
}

RgbaImage passImage(Pass pass, const RgbaImage& frame, const RgbaImage& cloud, const FramePasses& p) {
  checkPasses(frame, cloud, p);
  switch (pass) {
    case Pass::Beauty: return frame;
    case Pass::Cloud: return cloud;
    case Pass::Ground: return opaque(p.width, p.height, p.ground_rgb, 3, ImageContent::Radiance);
    case Pass::Sky: return opaque(p.width, p.height, p.sky_rgb, 3, ImageContent::Radiance);
    case Pass::Shadow: return opaque(p.width, p.height, p.shadow, 1, ImageContent::Data);
    case Pass::Depth: {
      RgbaImage img;
      img.width = p.width;
      img.height = p.height;
      img.depth_m = p.depth_m;
      img.content = ImageContent::Data;
      return img;
    }
  }
  return frame;
}

RgbaImage withDepth(const RgbaImage& frame, const FramePasses& p) {
  RgbaImage img = frame;
  img.depth_m = p.depth_m;
  return img;
}

RgbaImage withPassLayers(const RgbaImage& frame, const RgbaImage& cloud, const FramePasses& p) {
  checkPasses(frame, cloud, p);
  RgbaImage img = withDepth(frame, p);
  img.layers.push_back({"cloud", {"R", "G", "B", "A"}, cloud.rgba, true});
  img.layers.push_back({"ground", {"R", "G", "B"}, p.ground_rgb, true});
  img.layers.push_back({"sky", {"R", "G", "B"}, p.sky_rgb, true});
  img.layers.push_back({"shadow", {"Y"}, p.shadow, false});
  return img;
}

}  // namespace nph::scene
