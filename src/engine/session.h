#pragma once
// A rendering session: one dataset, one scene, a current GL context. It keeps the GPU volume,
// the deep light map and the ray caster up to date and redoes only what changed (Nes 2008 §6.3
// table 6.1: a time change costs a volume upload and a DLM build; a camera change costs only the
// ray cast; a sun change costs a DLM build):
//   setTime     → a new (possibly blended, dataset.h) volume only if the timestep pair or the
//                 weight changed; decoded timesteps are kept in a TimestepCache whose background
//                 thread decodes the next ones in the direction of playback (timestep_cache.h)
//                 while the frame is lit and ray cast;
//   setSun / setQuality → the DLM is rebuilt only if its cache key changed (DeepLightMap::build);
//   render / dispatch → ray cast with the camera given.
// All calls must come from the thread whose GL context was current at construction.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "engine/dataset.h"
#include "engine/timestep_cache.h"
#include "lighting/knobs.h"
#include "render/dlm/deep_light_map.h"
#include "render/dlm/volume_textures.h"
#include "render/raycast/cloud_renderer.h"
#include "scene/scene_file.h"
#include "scene/scene_setup.h"

namespace nph::engine {

struct FrameStats {
  double time_index = 0.0;      ///< fractional timestep index rendered
  bool volume_changed = false;  ///< a new volume was uploaded for this frame
  bool dlm_rebuilt = false;     ///< the deep light map was rebuilt for this frame
  double load_ms = 0.0;         ///< decoding/blending timesteps (0 when cached)
  double blocked_ms = 0.0;      ///< of load_ms, waiting for timesteps not yet decoded (stalls)
  double upload_ms = 0.0;
  double dlm_ms = 0.0;
  double raycast_ms = 0.0;
  std::uint64_t dlm_builds = 0, dlm_reuses = 0;  ///< over the session
  std::uint64_t volume_uploads = 0;
};

class Session {
 public:
  /// Loads the scene's timestep (data.timestep / data.time_utc) and prepares the scene (frame,
  /// georeference, camera, sun, basemap). Needs a current GL 4.5 context.
  Session(std::shared_ptr<const Dataset> dataset, scene::SceneDescription scene);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const Dataset& dataset() const { return *dataset_; }
  const scene::SceneDescription& scene() const { return scene_; }
  const scene::PreparedScene& prepared() const { return prepared_; }

  /// Fractional timestep index in [0, count−1] (clamped; UsageError when not finite). A move
  /// forwards or backwards also sets the playback direction the prefetch reads ahead in.
  void setTime(double time_index);
  /// How a fractional time blends its two timesteps (dataset.h TimeBlend; default kDefaultTimeBlend).
  /// A change re-blends the volume at the next render when the time lies between two timesteps.
  void setTimeBlend(TimeBlend blend) { time_blend_ = blend; }
  TimeBlend timeBlend() const { return time_blend_; }
  /// +1 (forwards) or −1: where the prefetch thread reads ahead; 0 (until the time first moves)
  /// reads nothing ahead, so a single-frame render decodes only what it shows.
  void setPlaybackDirection(int direction) { direction_ = direction < 0 ? -1 : direction > 0 ? 1 : 0; }
  double time() const { return time_index_; }
  /// The sun in the world frame (prepared().sun initially).
  void setSun(const scene::Sun& sun);
  /// What prepareScene makes of a scene's camera and sun, for another camera or sun section
  /// (the Python module's Renderer, issue #16): `spec` framed in this session's volume frame at
  /// the output size (scene::cameraFor), carried onto the globe in the globe view; the sun of
  /// `spec` (scene::sunFor) with timestep t's time for `from_time`.
  scene::Camera cameraFor(const scene::CameraSpec& spec) const;
  scene::Sun sunFor(const scene::SunSpec& spec, std::size_t t) const;
  const scene::Sun& sun() const { return sun_; }
  /// Quality (lighting/knobs.h): sampling, DLM error bound and budgets. Keeps the style.
  void setQuality(const lighting::QualitySettings& quality);
  const lighting::QualitySettings& quality() const { return scene_.quality; }
  /// Style (phase functions, ambient light): presets and setQuality never change it.
  void setStyle(const lighting::StyleSettings& style);
  const lighting::StyleSettings& style() const { return style_; }
  /// The ray caster's settings, lighting::renderSettingsFor(quality(), style()); setQuality and
  /// setStyle rebuild them, keeping the host's temporal_history (tests change single fields here).
  render::RenderSettings& renderSettings() { return render_settings_; }
  const render::RenderSettings& renderSettings() const { return render_settings_; }

  /// Brings volume and DLM up to date, then ray casts `camera` and reads the images back
  /// (`read_back`: the cloud layer or not, and how).
  render::RenderOutput render(const scene::Camera& camera, const render::ReadBack& read_back = {});
  /// Brings volume and DLM up to date, then ray casts `view` into renderer().cloudLayer()/frame().
  void dispatch(const render::ViewRays& view, render::HostDepth depth = {});

  const render::CloudRenderer& renderer() const { return renderer_; }
  render::CloudRenderer& renderer() { return renderer_; }
  /// Compositing passes on or off (scene/passes.h); on from the start when the scene's output
  /// asks for them (OutputSpec::wantsPasses).
  void setPasses(bool on) { renderer_.setPasses(on); }
  const render::DeepLightMap& deepLightMap() const { return dlm_; }
  const render::VolumeTextures& volumeTextures() const { return *textures_; }
  const FrameStats& stats() const { return stats_; }

  /// Memory (issue 19, docs/benchmarks.md "Memory"): on, the decoded volumes (the float ice and
  /// water fields, 8 bytes per voxel) are dropped from the timestep cache as soon as the volume is
  /// on the GPU, since a single frame reads them no more; a later change of the volume decodes
  /// again. Off by default: playback, blending and re-visited timesteps re-use the decoded ones.
  /// On in engine::renderSceneFrame(dataset, scene) (`nephele render`). Turning it on also drops
  /// prepared()'s basemap images and city lights (on the GPU since construction; nothing reads
  /// the CPU copies again). With a .nph dataset the frame's timestep (unblended) is then not
  /// decoded at all: the upload decodes it a layer at a time from the file (Dataset::loadSlices:
  /// a zstd stream, no volume-sized buffer besides the texture).
  void setReleaseAfterUpload(bool on);
  /// The decoded-timestep cache: at most this many timesteps are kept (default 4, at least 2).
  void setCacheLimit(std::size_t timesteps);
  /// Read-ahead on/off, its depth and the memory budget of decoded timesteps.
  void setPrefetch(const PrefetchSettings& settings) { timesteps_->setSettings(settings); }
  PrefetchSettings prefetchSettings() const { return timesteps_->settings(); }
  PrefetchStats prefetchStats() const { return timesteps_->stats(); }

 private:
  void update();

  std::shared_ptr<const Dataset> dataset_;
  scene::SceneDescription scene_;
  scene::PreparedScene prepared_;
  scene::Sun sun_;
  lighting::StyleSettings style_;
  render::RenderSettings render_settings_;
  double time_index_ = 0.0;
  TimeBlend time_blend_ = kDefaultTimeBlend;
  int direction_ = 0;
  bool release_after_upload_ = false;
  bool reads_by_layer_ = false;             ///< the dataset gives headers and layers cheaply (a .nph cache)
  std::string volume_key_;                  // identity of the uploaded volume
  std::map<std::string, bool> pair_moves_;  // "identity+second" -> blendHasMotion (update's key)
  std::optional<render::VolumeTextures> textures_;
  std::shared_ptr<const render::NoiseTexture> noise_;  ///< the detail noise tile, generated on first use
  render::DeepLightMap dlm_;
  render::CloudRenderer renderer_;
  std::unique_ptr<TimestepCache> timesteps_;  // declared last: its worker is joined first
  FrameStats stats_;
};

}  // namespace nph::engine
