#include "engine/session.h"

#include <chrono>

#include <fmt/format.h>

#include "core/env.h"
#include "core/error.h"
#include "core/large_buffer.h"
#include "core/log.h"
#include "core/process_memory.h"
#include "render/gl/context.h"

namespace nph::engine {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Session::Session(std::shared_ptr<const Dataset> dataset, scene::SceneDescription scene)
    : dataset_(std::move(dataset)), scene_(std::move(scene)) {
  if (!dataset_) throw UsageError("Session: no dataset");
  timesteps_ = std::make_unique<TimestepCache>(dataset_);
  scene::DataSpec spec;
  if (scene_.data) spec = *scene_.data;
  const std::size_t t = scene::timestepIndexFor(spec, dataset_->times(), dataset_->path());
  time_index_ = double(t);
  logMemoryPhase("start-up");
  // The scene needs the grid, its place and its time, not the volume: a .nph cache gives them from
  // its index (issue 19, memory: no float volume is decoded before the first frame asks for it).
  if (const std::optional<ExtinctionVolumes> header = dataset_->loadHeader(t)) {
    prepared_ = scene::prepareScene(scene_, *header);
    reads_by_layer_ = true;
  } else {
    prepared_ = scene::prepareScene(scene_, *timesteps_->get(t));
  }
  sun_ = prepared_.sun;
  style_ = scene_.style;
  render_settings_ = lighting::renderSettingsFor(scene_.quality, style_);
  if (prepared_.basemap_rect)
    renderer_.setBasemap(prepared_.basemap, *prepared_.basemap_rect, prepared_.basemap_lights);
  renderer_.setPasses(scene_.output.wantsPasses());
  if (prepared_.far_basemap_rect)
    renderer_.setFarBasemap(prepared_.far_basemap, *prepared_.far_basemap_rect, prepared_.far_basemap_lights);
  if (prepared_.to_sun_ecef) {  // globe view (scene_setup.h): rays in ECEF
    renderer_.setGlobe(render::buildGlobeMapping(*prepared_.geo), prepared_.basemap_equirect, *prepared_.to_sun_ecef,
                       prepared_.basemap_equirect_lights);
  }
  logMemoryPhase("scene preparation (basemap reprojected and uploaded)");
}

Session::~Session() = default;

void Session::setReleaseAfterUpload(bool on) {
  release_after_upload_ = on;
  if (!on) return;
  for (scene::LinearRgbImage* image : {&prepared_.basemap, &prepared_.far_basemap, &prepared_.basemap_equirect})
    *image = scene::LinearRgbImage{};
  for (std::vector<float>* lights :
       {&prepared_.basemap_lights, &prepared_.far_basemap_lights, &prepared_.basemap_equirect_lights})
    std::vector<float>().swap(*lights);
  releaseFreedMemory();  // the basemap's decode and reprojection left their pages in the heap
  logMemoryPhase("basemap images dropped");
}

void Session::setCacheLimit(std::size_t timesteps) {
  PrefetchSettings p = timesteps_->settings();
  p.max_timesteps = std::max<std::size_t>(timesteps, 2);
  timesteps_->setSettings(p);
}

void Session::setTime(double time_index) {
  const TimeBracket b = bracketTime(time_index, dataset_->timestepCount());
  const double t = double(b.first) + b.weight;
  if (t != time_index_) direction_ = t > time_index_ ? 1 : -1;
  time_index_ = t;
}

void Session::setSun(const scene::Sun& sun) { sun_ = sun; }

scene::Camera Session::cameraFor(const scene::CameraSpec& spec) const {
  const scene::Camera flat = scene::cameraFor(spec, prepared_.frame, scene_.output.width, scene_.output.height);
  return prepared_.to_sun_ecef ? scene::globeCameraFrom(flat, *prepared_.geo) : flat;  // as prepareScene
}

scene::Sun Session::sunFor(const scene::SunSpec& spec, std::size_t t) const {
  return scene::sunFor(spec, prepared_.geo ? &*prepared_.geo : nullptr, dataset_->times().at(t));
}

void Session::setQuality(const lighting::QualitySettings& quality) {
  scene_.quality = quality;
  const int temporal = render_settings_.temporal_history;  // the host's, not a knob
  render_settings_ = lighting::renderSettingsFor(scene_.quality, style_);
  render_settings_.temporal_history = temporal;
}

void Session::setStyle(const lighting::StyleSettings& style) {
  style_ = style;
  const int temporal = render_settings_.temporal_history;  // the host's, not a knob
  render_settings_ = lighting::renderSettingsFor(scene_.quality, style_);
  render_settings_.temporal_history = temporal;
}

void Session::update() {
  stats_.volume_changed = false;
  stats_.dlm_rebuilt = false;
  stats_.load_ms = stats_.blocked_ms = stats_.upload_ms = stats_.dlm_ms = 0.0;
  stats_.time_index = time_index_;
  const TimeBracket b = bracketTime(time_index_, dataset_->timestepCount());
  // The weight enters the key exactly (17 significant digits round-trip a double): two frames
  // share a volume only when they would blend the same one, so reuse never changes a frame.
  // The filter is part of the key: the occupancy's dilation and the shaders' rule change with it.
  const volume::Reconstruction reconstruction =
      lighting::reconstructionOf(scene_.quality, glm::dvec2(prepared_.frame.voxel_size_m));
  render_settings_.reconstruction = reconstruction;  // the CPU references' filter is the upload's
  // A blend's key names its kind (dataset.h TimeBlend) only where the kinds make different
  // volumes: without U, V or times the motion blend is the linear one bit for bit
  // (blendHasMotion), so switching the setting on such data re-blends and re-lights nothing.
  // Whether a pair moves is learnt when it is first blended (pair_moves_); a pair not learnt yet
  // has never been uploaded, so its key differs from volume_key_ whichever suffix it gets.
  const std::string pair = fmt::format("{}+{}", dataset_->identity(b.first), b.second);
  const auto contentKey = [&] {
    if (b.weight == 0.0) return dataset_->identity(b.first);
    const auto learnt = pair_moves_.find(pair);
    const bool moves = learnt == pair_moves_.end() || learnt->second;
    return fmt::format("{}@{:.17g}{}", pair, b.weight, time_blend_ == TimeBlend::Motion && moves ? "|motion" : "");
  };
  std::string content = contentKey();
  const volume::Detail detail = lighting::detailOf(scene_.quality);
  const std::string filters =
      (reconstruction == volume::Reconstruction::Trilinear
           ? ""
           : fmt::format("|{}", volume::kReconstructionNames[std::size_t(reconstruction)])) +
      (detail == volume::Detail::None ? "" : fmt::format("|detail={}", volume::kDetailNames[std::size_t(detail)]));
  std::string key = content + filters;
  std::vector<std::size_t> pinned{b.first};
  if (b.weight > 0.0) pinned.push_back(b.second);
  timesteps_->prefetch(pinned, direction_);  // the worker reads ahead while this frame is built
  if (key != volume_key_ || !textures_) {
    auto t0 = std::chrono::steady_clock::now();
    const double blocked0 = timesteps_->stats().blocked_ms;
    // A one-shot frame (setReleaseAfterUpload) of a single timestep of a .nph cache reads it
    // layer by layer from the file (a zstd stream) and never holds its floats or codes whole
    // (issue 19, memory); otherwise the decoded volumes of the cache, kept for re-use (a model
    // file's timestep converted once by the constructor stays there until the upload).
    std::unique_ptr<ExtinctionSlices> slices;
    // With the detail on the upload decodes the whole timestep anyway (the controls, the wind
    // that advects the noise): the layer route, whose header has no U, V, would lose the wind.
    if (release_after_upload_ && reads_by_layer_ && b.weight == 0.0 && detail == volume::Detail::None) {
      slices = dataset_->loadSlices(b.first);
    } else {
      const auto a = timesteps_->get(b.first);
      std::shared_ptr<const ExtinctionVolumes> v = a;
      if (b.weight > 0.0) {
        const auto second = timesteps_->get(b.second);
        pair_moves_[pair] = blendHasMotion(*a, *second);
        content = contentKey();
        key = content + filters;
        v = std::make_shared<const ExtinctionVolumes>(blendVolumes(*a, *second, b.weight, time_blend_));
      }
      slices = std::make_unique<VolumeSlices>(std::move(v));
    }
    stats_.load_ms = msSince(t0);
    stats_.blocked_ms = timesteps_->stats().blocked_ms - blocked0;
    logMemoryPhase("volume load");
    t0 = std::chrono::steady_clock::now();
    if (textures_ && textures_->noise()) noise_ = textures_->noise();  // the noise tile is generated once
    textures_.reset();  // free the old volume before uploading the new one
    render::UploadOptions options;
    options.reconstruction = reconstruction;
    options.detail = detail;
    options.noise = noise_;
    options.dem = prepared_.dem ? &*prepared_.dem : nullptr;
    const ExtinctionVolumes& header = slices->volumes();
    textures_.emplace(render::VolumeTextures::upload(*slices, volume::frameOf(header, scene_.height_exaggeration),
                                                     content, options));  // identity() is `key`
    if (textures_->noise()) noise_ = textures_->noise();
    if (release_after_upload_) {
      slices.reset();
      timesteps_->releaseAll();  // the cache's copy, if any (a blend); `slices` held the last other
      releaseFreedMemory();
    }
    logMemoryPhase("volume upload");
    stats_.upload_ms = msSince(t0);
    volume_key_ = key;
    stats_.volume_changed = true;
    ++stats_.volume_uploads;
  }
  if (renderer_.globe()) {  // the sun as seen at the footprint centre, in ECEF
    const glm::dvec3 size = prepared_.frame.size_m();
    renderer_.setGlobeSun(scene::toSunEcef(sun_, *prepared_.geo, {0.5 * size.x, 0.5 * size.y}));
  }
  const auto t0 = std::chrono::steady_clock::now();
  stats_.dlm_rebuilt = dlm_.build(*textures_, -sun_.toSun(), lighting::dlmSettingsFor(scene_.quality));
  if (stats_.dlm_rebuilt) {
    stats_.dlm_ms = msSince(t0);
    if (release_after_upload_) releaseFreedMemory();  // the build's freed scatter map and staging
    logMemoryPhase("deep light map build");
  }
  stats_.dlm_builds = dlm_.builds();  // not stats(): that reads a pending build's counts back
  stats_.dlm_reuses = dlm_.reuses();
}

render::RenderOutput Session::render(const scene::Camera& camera, const render::ReadBack& read_back) {
  dlm_.setStatsReadBack(true);  // the frame is read back anyway: the map's passes timed, its stats logged
  update();
  auto out = renderer_.render(*textures_, dlm_, camera, sun_, render_settings_, read_back);
  stats_.raycast_ms = out.milliseconds;
  logMemoryPhase("ray cast and read-back");
  return out;
}

void Session::dispatch(const render::ViewRays& view, render::HostDepth depth) {
  // The per-frame path (`nephele view`, the plugin API): on a GPU a map build never waits for it to
  // read its statistics back, unless they are logged (issue 19 item 2; DeepLightMap::setStatsReadBack).
  // A software rasteriser keeps them: there the CPU has done the work by the time it would read
  // (nothing to win: docs/benchmarks.md "DLM statistics read-back"), and its loop limiter is what
  // the statistics warn about.
  // NEPHELE_DLM_STATS=on|off overrides the choice (tests run the GPU's path on llvmpipe with off).
  const auto forced = env::get("NEPHELE_DLM_STATS");
  dlm_.setStatsReadBack(forced ? *forced != "off" : log::threshold() >= log::Level::Debug || gl::softwareRasteriser());
  update();
  stats_.raycast_ms = renderer_.dispatch(*textures_, dlm_, view, sun_, render_settings_, depth, /*finish=*/false);
}

}  // namespace nph::engine
