#include "accuracy/ground_truth.h"

#include "lighting/cloud_light.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <fmt/format.h>

#include "accuracy/image_error.h"
#include "cache/checksum.h"
#include "core/error.h"
#include "core/log.h"

namespace nph::accuracy {
namespace {

constexpr char kMagic[8] = {'N', 'P', 'H', 'G', 'T', '0', '0', '2'};

class Hasher {
 public:
  template <class T>
  void add(const T& value) {
    const auto* p = reinterpret_cast<const std::byte*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void addFloats(const std::vector<float>& a) {
    add(a.size());
    const auto* p = reinterpret_cast<const std::byte*>(a.data());
    bytes_.insert(bytes_.end(), p, p + a.size() * sizeof(float));
  }
  std::uint64_t digest() const { return cache::xxh64(bytes_); }

 private:
  std::vector<std::byte> bytes_;
};

}  // namespace

reference::PathTracerSettings pathTracerSettingsForGpu(const render::RenderSettings& rs, const scene::Sun& sun,
                                                       const GroundTruthSettings& settings) {
  reference::PathTracerSettings s;
  s.samples_per_pixel = settings.samples_per_pixel;
  s.max_events = settings.max_events;
  s.roulette_after_events = settings.roulette_after_events;
  s.seed = settings.seed;
  s.phase.ice = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, rs.g_ice};
  s.phase.water = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, rs.g_water};
  s.sky_radiance = lighting::skyLightFor(rs, sun.elevation_deg, sun.colour, sun.intensity).above;
  if (settings.part == TruthPart::SkyOnly) s.sun_enabled = false;
  if (settings.part == TruthPart::SunOnly) s.sky_radiance = glm::dvec3(0.0);
  s.ground_enabled = false;
  s.include_background = false;
  s.pixel_jitter = false;
  return s;
}

std::string groundTruthKey(const AccuracyScene& sc, const render::RenderSettings& rs, const GroundTruthSettings& gs) {
  Hasher h;
  const ExtinctionVolumes& v = *sc.volumes;
  h.add(v.nx);
  h.add(v.ny);
  h.add(v.nz);
  h.addFloats(v.ice_per_m);
  h.addFloats(v.water_per_m);
  h.add(sc.frame.voxel_size_m);
  h.add(sc.frame.z_bottom_m);
  h.add(sc.frame.height_exaggeration);  // issue 12: exaggeration keeps the data's optical depth
  const scene::Camera& c = sc.camera;
  h.add(c.position_m);
  h.add(c.target_m);
  h.add(c.up);
  h.add(c.vertical_fov_deg);
  h.add(c.width);
  h.add(c.height);
  h.add(sc.sun.azimuth_deg);
  h.add(sc.sun.elevation_deg);
  h.add(sc.sun.colour);
  h.add(sc.sun.intensity);
  h.add(rs.g_ice);
  h.add(rs.g_water);
  h.add(pathTracerSettingsForGpu(rs, sc.sun, gs).sky_radiance);  // issue 12: E·p units, clear sky
  h.add(gs.samples_per_pixel);
  h.add(gs.max_events);
  h.add(gs.roulette_after_events);
  // The roulette's survival schedule (reference/path_tracer.h): 1 = q_n = n/(n + 1) (thirtieth
  // session); the constant survival before it is not hashed, so its files are traced again.
  if (gs.roulette_after_events > 0) h.add(std::int32_t{1});
  h.add(gs.seed);
  if (gs.part != TruthPart::Full) h.add(gs.part);  // the full truth's keys stay those of the cache
  return cache::toHex(h.digest());
}

GroundTruth groundTruth(const AccuracyScene& sc, const render::RenderSettings& rs, const GroundTruthSettings& gs,
                        const std::string& cache_dir) {
  GroundTruth gt;
  const int w = sc.camera.width, hgt = sc.camera.height;
  const std::size_t n = std::size_t(w) * std::size_t(hgt);
  std::filesystem::create_directories(cache_dir);
  const char* part = gs.part == TruthPart::SkyOnly ? "-sky" : gs.part == TruthPart::SunOnly ? "-sun" : "";
  gt.cache_path =
      (std::filesystem::path(cache_dir) / (sc.name + part + "-" + groundTruthKey(sc, rs, gs) + ".gt")).string();
  gt.image.width = w;
  gt.image.height = hgt;
  if (std::ifstream in{gt.cache_path, std::ios::binary}) {
    char magic[8] = {};
    int fw = 0, fh = 0;
    double truncated = 0.0, rouletted = 0.0, seconds = 0.0;
    in.read(magic, 8);
    in.read(reinterpret_cast<char*>(&fw), sizeof fw);
    in.read(reinterpret_cast<char*>(&fh), sizeof fh);
    in.read(reinterpret_cast<char*>(&truncated), sizeof truncated);
    in.read(reinterpret_cast<char*>(&rouletted), sizeof rouletted);
    in.read(reinterpret_cast<char*>(&seconds), sizeof seconds);
    if (in && std::memcmp(magic, kMagic, 8) == 0 && fw == w && fh == hgt) {
      gt.image.rgba.resize(4 * n);
      gt.standard_error.resize(3 * n);
      in.read(reinterpret_cast<char*>(gt.image.rgba.data()), std::streamsize(4 * n * sizeof(float)));
      in.read(reinterpret_cast<char*>(gt.standard_error.data()), std::streamsize(3 * n * sizeof(float)));
      if (in) {
        gt.from_cache = true;
        gt.truncated_share = truncated;
        gt.rouletted_share = rouletted;
        gt.seconds = seconds;
        gt.noise_rmse = luminanceNoiseRmse(gt.standard_error);
        return gt;
      }
    }
    log::warn("{}: unreadable ground-truth cache, tracing again", gt.cache_path);
  }
  const reference::PathTracerSettings ps = pathTracerSettingsForGpu(rs, sc.sun, gs);
  const reference::PathTracer pt(*sc.volumes, sc.frame, sc.sun, ps);
  const reference::PathTracedImage img = pt.render(sc.camera);
  gt.image.rgba = img.rgba;
  gt.standard_error = img.standard_error;
  gt.seconds = img.stats.seconds;
  gt.truncated_share = img.stats.paths ? double(img.stats.truncated_paths) / double(img.stats.paths) : 0.0;
  gt.rouletted_share = img.stats.paths ? double(img.stats.rouletted_paths) / double(img.stats.paths) : 0.0;
  gt.noise_rmse = luminanceNoiseRmse(gt.standard_error);
  const std::string tmp = gt.cache_path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(kMagic, 8);
    out.write(reinterpret_cast<const char*>(&w), sizeof w);
    out.write(reinterpret_cast<const char*>(&hgt), sizeof hgt);
    out.write(reinterpret_cast<const char*>(&gt.truncated_share), sizeof gt.truncated_share);
    out.write(reinterpret_cast<const char*>(&gt.rouletted_share), sizeof gt.rouletted_share);
    out.write(reinterpret_cast<const char*>(&gt.seconds), sizeof gt.seconds);
    out.write(reinterpret_cast<const char*>(gt.image.rgba.data()), std::streamsize(4 * n * sizeof(float)));
    out.write(reinterpret_cast<const char*>(gt.standard_error.data()), std::streamsize(3 * n * sizeof(float)));
    if (!out) throw IoError(fmt::format("{}: cannot write the ground-truth cache", tmp));
  }
  std::filesystem::rename(tmp, gt.cache_path);
  return gt;
}

}  // namespace nph::accuracy
