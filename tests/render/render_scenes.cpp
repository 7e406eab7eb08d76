#include "render_scenes.h"

#include <cmath>
#include <filesystem>
#include <random>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "engine/dataset.h"
#include "scene/scene_file.h"

namespace nph::test {

void writeCodedBasemap(const std::string& path) {
  constexpr int kW = 720, kH = 360;
  std::vector<float> rgb(std::size_t(kW) * kH * 3);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const std::size_t o = (std::size_t(y) * kW + std::size_t(x)) * 3;
      rgb[o] = float((x + 0.5) / kW);
      rgb[o + 1] = float((y + 0.5) / kH);
      rgb[o + 2] = ((x / 20 + y / 20) % 2) != 0 ? 0.6f : 0.2f;  // 10° squares
    }
  }
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(kW, kH, 3, OIIO::TypeDesc::FLOAT);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) || !out->close()) {
    throw std::runtime_error("writeCodedBasemap: " + path);
  }
}

void decodeBasemapColour(float r, float g, double& lon_deg, double& lat_deg) {
  lon_deg = double(r) * 360.0 - 180.0;
  lat_deg = 90.0 - double(g) * 180.0;
}

double codedBasemapBlue(double lon_deg, double lat_deg) {
  const int x = int((lon_deg + 180.0) / 360.0 * 720.0), y = int((90.0 - lat_deg) / 180.0 * 360.0);
  return ((x / 20 + y / 20) % 2) != 0 ? 0.6 : 0.2;
}

glm::dvec2 projectedPixel(const scene::Camera& cam, const glm::dvec3& world) {
  const glm::dvec4 clip = cam.clipFromView() * cam.viewFromWorld() * glm::dvec4(world, 1.0);
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return {0.5 * (ndc.x + 1.0) * cam.width, 0.5 * (1.0 - ndc.y) * cam.height};
}

glm::dvec2 locateCodedLonLat(const scene::RgbaImage& frame, const scene::Camera& cam, glm::dvec2 target, double blue) {
  const auto decoded = [&](int x, int y) {
    const float* p = &frame.rgba[(std::size_t(y) * std::size_t(cam.width) + std::size_t(x)) * 4];
    const double light = double(p[2]) / blue;
    double lon = 0.0, lat = 0.0;
    decodeBasemapColour(float(double(p[0]) / light), float(double(p[1]) / light), lon, lat);
    return glm::dvec2(lon, lat);
  };
  glm::ivec2 best(-1);
  double bestErr = 1e300;
  for (int y = 1; y + 1 < cam.height; ++y) {
    for (int x = 1; x + 1 < cam.width; ++x) {
      const double e = glm::length(decoded(x, y) - target);
      if (e < bestErr) {
        bestErr = e;
        best = {x, y};
      }
    }
  }
  // One Newton step on the decoded field: d(lon, lat)/d(px) by central differences.
  const glm::dvec2 ddx = 0.5 * (decoded(best.x + 1, best.y) - decoded(best.x - 1, best.y));
  const glm::dvec2 ddy = 0.5 * (decoded(best.x, best.y + 1) - decoded(best.x, best.y - 1));
  const glm::dvec2 step = glm::inverse(glm::dmat2(ddx, ddy)) * (target - decoded(best.x, best.y));
  return glm::dvec2(best) + glm::dvec2(0.5) + step;
}

datagen::WrfHurricaneSpec smallStormSpec(datagen::WrfProjection projection) {
  datagen::WrfHurricaneSpec spec;
  spec.nx = 80;
  spec.ny = 72;
  spec.nz = 20;
  spec.ntimes = 1;
  spec.dx_m = 5000.0;
  spec.projection = projection;
  return spec;
}

scene::LonLat stormCentreLonLat(const datagen::WrfTruth& truth, const datagen::WrfHurricaneSpec& spec) {
  const auto [lon, lat] = datagen::stormCentreLonLat(truth, spec.dx_m);
  return {lon, lat};
}

std::unique_ptr<engine::Session> openSession(const std::string& scene_json, const std::string& data_path) {
  auto j = nlohmann::json::parse(scene_json);
  j["data"]["path"] = data_path;
  scene::SceneDescription s = scene::parseSceneText(j.dump(), "<test scene>");
  return std::make_unique<engine::Session>(engine::Dataset::open(data_path), s);
}

DemoView demoView(const ExtinctionVolumes& v, int width, int height, double distance_scale) {
  DemoView d;
  d.frame = volume::frameOf(v, 8.0);
  scene::CameraSpec spec;
  spec.preset = scene::CameraPreset::Oblique;
  spec.fov_deg = 40.0;
  spec.distance_scale = distance_scale;
  d.camera = scene::cameraFor(spec, d.frame, width, height);
  return d;
}

render::RenderOutput renderDemoView(const ExtinctionVolumes& v, const DemoView& d, const render::RenderSettings& rs,
                                    volume::Reconstruction reconstruction, volume::Detail detail,
                                    double dlm_texel_voxels) {
  auto tex =
      render::VolumeTextures::upload(v, d.frame, "coarse-storm", {.reconstruction = reconstruction, .detail = detail});
  render::DeepLightMap dlm;
  lighting::DlmSettings ds;
  ds.empty_space_skipping = rs.empty_space_skipping;
  ds.texel_voxels = dlm_texel_voxels;
  dlm.build(tex, -d.sun.toSun(), ds);
  render::CloudRenderer renderer;
  return renderer.render(tex, dlm, d.camera, d.sun, rs);
}

}  // namespace nph::test
