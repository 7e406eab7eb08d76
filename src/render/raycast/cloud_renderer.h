#pragma once
// The eye pass: ray casting of the ice and water volumes with deep-light-map look-ups, composited
// over the lit basemap (glsl/render/clouds.comp; Nes 2008 §5.4 eq. 5.18, §5.5; Muth 2026 §3.4).
// Two views: the flat map (rays in the world frame of volume/volume_frame.h) and, after
// setGlobe(), the globe (rays in ECEF; render/raycast/globe.h).
//
// Two ways to use it: render() ray casts a scene::Camera and reads the images back (CLI, tests);
// dispatch() ray casts any perspective view (a host's view and projection matrices, optionally
// stopping each ray at the host's depth buffer) and leaves the result in GL textures for the
// caller to composite (the plugin API, the viewer).
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "lighting/render_settings.h"
#include "render/atmosphere/atmosphere_luts.h"
#include "render/dlm/deep_light_map.h"
#include "render/dlm/radiance_volume.h"
#include "render/dlm/volume_textures.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "render/raycast/globe.h"
#include "render/raycast/temporal_accumulation.h"
#include "scene/basemap.h"
#include "scene/camera.h"
#include "scene/output_image.h"
#include "scene/passes.h"
#include "scene/sun.h"

namespace nph::render {

// The ray caster's settings live with the other lighting knobs (GL-free, lighting/render_settings.h).
using lighting::RenderSettings;

/// The eye rays of a perspective view, as the GPU builds them: pixel (px, py) with py down (row 0
/// at the top) maps to NDC (x, y) = (2(px+½)/w − 1, 1 − 2(py+½)/h); its ray leaves the eye along
/// world_from_view · normalize(view_from_clip · (x, y, 0, 1)).
struct ViewRays {
  glm::dvec3 position_m{0.0};
  glm::dmat3 world_from_view{1.0};  ///< rotation: view axes (x right, y up, −z forward) in world
  glm::dmat4 view_from_clip{1.0};   ///< inverse projection (OpenGL convention)
  int width = 0, height = 0;

  /// The rays of scene::Camera::rayDirection (same pixels, same directions).
  static ViewRays fromCamera(const scene::Camera& camera);
  /// A host's view (world → eye, rigid) and perspective projection matrices; `width`×`height`
  /// is the viewport the frame is rendered for.
  static ViewRays fromMatrices(const glm::dmat4& view_from_world, const glm::dmat4& clip_from_view, int width,
                               int height);
};

/// A host depth buffer to stop the rays at (host geometry occludes clouds): a 2-D depth (or R32F)
/// texture of the view's size, GL row order (row 0 at the bottom), window depth in [0, 1] with
/// glDepthRange(0, 1) of the same projection as the ViewRays. texture 0 = none.
struct HostDepth {
  unsigned texture = 0;
};

/// Where sample k of a pixel lies in it, [0, 1)² (RenderSettings::samples_per_pixel): the centre
/// for k = 0, then Roberts' R2 sequence (the plastic number's low-discrepancy lattice,
/// frac(½ + k·(1/φ₂, 1/φ₂²))), so any prefix of the samples covers the pixel evenly.
glm::vec2 subpixelPosition(int k);

struct RenderOutput {
  scene::RgbaImage cloud_layer;              ///< premultiplied linear RGBA: the clouds alone
  scene::RgbaImage frame;                    ///< clouds composited over the lit ground, alpha 1
  std::optional<scene::FramePasses> passes;  ///< ground, sky, shadow matte, depth (setPasses(true))
  double milliseconds = 0.0;                 ///< wall time of the dispatches and the read-back
  double gpu_milliseconds = 0.0;             ///< the dispatches' GPU time (GL_TIME_ELAPSED; ≈ 0 on llvmpipe)
  /// render()'s wall time in its three parts (issue 19, docs/benchmarks.md "Read-back"): set-up and
  /// submission of the dispatches (program look-up, uniform blocks, output targets), the wait for
  /// them to finish, and the copy of the images into host memory.
  double submit_milliseconds = 0.0, wait_milliseconds = 0.0, readback_milliseconds = 0.0;
};

/// What render() copies into host memory, and how (issue 19). On a GPU the read-back, not the ray
/// cast, was most of a batch frame's wall time (docs/benchmarks.md "Read-back"): a caller that
/// writes only the composited frame skips the cloud layer, and the copy goes through a pixel-pack
/// buffer.
struct ReadBack {
  /// RenderOutput::cloud_layer; false leaves it empty (0 × 0) — the frame, and the passes when
  /// setPasses(true), are always read.
  bool cloud_layer = true;
  enum class Path {
    /// PixelBuffer on a GPU, Direct on a software rasteriser (gl::softwareRasteriser): each where
    /// it measured faster, and the pack buffer is not a second host copy of the images on llvmpipe
    Auto,
    /// glGetTextureImage straight into freshly allocated vectors (the path before the
    /// twenty-third session; on llvmpipe a memcpy out of the texture)
    Direct,
    /// all images into one pixel-pack buffer the renderer keeps (GL_PIXEL_PACK_BUFFER), mapped
    /// once and copied into huge-page vectors (core/large_buffer.h): the driver streams the
    /// texels into memory it owns instead of the caller's pageable pages. Bit-identical to Direct;
    /// on the H200 1.5× faster for frame and layer at 1080p (34.8 → 23.3 ms), 2.7× for the frame
    /// alone (24.2 → 8.9 ms). Half floats this way measured 3.8× slower there (the driver converts
    /// on the CPU) and are not offered.
    PixelBuffer,
  };
  Path path = Path::Auto;
};

/// The switches the eye pass is compiled for (issue 19, "Frame time"): glsl/render/clouds.comp and
/// glsl/dlm/volume.glsl take each as a 0/1 define (SPEC_GLOBE …) instead of a uniform branch, so a
/// view pays only for what it draws. CloudRenderer keeps one program per distinct set.
struct EyePassFeatures {
  bool globe = false;        ///< rays in ECEF (setGlobe)
  bool terrain = false;      ///< displaced ground (flat view and globe)
  bool atmosphere = false;   ///< RenderSettings::atmosphere
  bool passes = false;       ///< compositing passes written (setPasses)
  bool detail = false;       ///< sub-grid detail in extinctionAt (VolumeTextures::detail)
  bool cubic = false;        ///< tricubic B-spline reconstruction (VolumeTextures::reconstruction)
  bool detail_wind = false;  ///< the detail's noise advected by U, V (VolumeTextures::hasDetailWind)
  /// the sunlight from the map's light cache (DeepLightMap::hasLightCache), not its look-up
  bool light_cache = false;
  /// one fetch per step from the packed texture (VolumeTextures::hasPacked), not three
  bool packed = false;
  /// The pass's role with reduced-resolution clouds (RenderSettings::cloud_resolution;
  /// clouds.comp SPEC_CLOUD_PASS): 0 march and composite, 1 the reduced march only, 2 the
  /// full-resolution pass over the upsampled clouds. Set by dispatch(), not by features().
  int cloud_pass = 0;
  /// the reprojection depth for the temporal accumulation (clouds.comp SPEC_MOTION_DEPTH, defined
  /// only when on). Set by dispatch() with RenderSettings::temporal_history > 0.
  bool motion_depth = false;
  /// the Monte Carlo radiance volume's term and samplers (multiple_scattering = radiance_volume;
  /// clouds.comp SPEC_RADIANCE_VOLUME, defined only when on, in every baseline)
  bool radiance_volume = false;
  /// {"SPEC_GLOBE", "0|1"}, … for gl::Program::compute.
  gl::Defines defines() const;
};

/// Baselines for benchmarks and tests (issue 19), not user settings: the eye pass as it was before
/// its speed-ups, to measure them against (tests/bench/frame_benchmark.cpp) and to show that they
/// change no bit (tests/render/raycast_gl_test.cpp).
struct EyePassBaseline {
  bool uniform_branches = false;  ///< one program for every view: the switches are uniforms
  bool binary_search = false;     ///< DLM look-up by binary search (glsl/dlm/lookup.glsl)
  /// adaptive steps not clipped at the occupancy brick's face (glsl/render/clouds.comp
  /// stepClippedAtBrick): the first version of RenderSettings::step_growth_max
  bool unclipped_steps = false;
  /// the separate ice, water and column-depth textures even where the packed one serves
  bool separate_textures = false;
  /// the sky term before issue 12's twelfth session, ½·(L_above·T_d(τ_up) + L_below·T_d(τ_down))
  /// (glsl/render/clouds.comp skyLightAt), to measure skyDiffuse's cost against
  bool sky_half_transmittance = false;
  /// two_stream without the once-scattered light's forward lobe (before issue 12's thirteenth
  /// session; glsl/common/cloud_light.glsl forwardLobe), to measure its cost against
  bool no_forward_lobe = false;
  /// reduced-resolution clouds upsampled by the bilinear filter alone, blind to the depth guide
  /// (glsl/render/clouds.comp upsampleClouds), to show what the guide keeps off a ridge
  bool depth_blind_upsampling = false;
};

class CloudRenderer {
 public:
  CloudRenderer();
  /// Sets (uploads) the basemap: linear RGB covering `rect` of the world (row 0 = north).
  /// `city_lights`: the night side's lights on the same pixels (scene::cityLightsIntensity; empty =
  /// none), drawn with RenderSettings::city_lights (glsl/common/night_lights.glsl). The same for
  /// the far basemap and the globe's.
  void setBasemap(const scene::LinearRgbImage& image, const scene::WorldRect& rect,
                  const std::vector<float>& city_lights = {});
  /// Sets the far basemap (issue 14 item 4): drawn on the flat view's ground outside the near
  /// basemap's rectangle, inside `rect` (scene::farBasemapRectangle). Empty image: none.
  void setFarBasemap(const scene::LinearRgbImage& image, const scene::WorldRect& rect,
                     const std::vector<float>& city_lights = {});
  RenderOutput render(const VolumeTextures& volume, const DeepLightMap& dlm, const scene::Camera& camera,
                      const scene::Sun& sun, const RenderSettings& settings, const ReadBack& read_back = {});

  /// Ray casts into cloudLayer() (premultiplied linear RGBA, row 0 = top) and frame() without
  /// reading back. Binds its own program, textures, image units and uniform buffers; the caller
  /// saves and restores GL state if it must (the plugin API does). Returns wall ms incl. glFinish
  /// when `finish`, else the submission time.
  double dispatch(const VolumeTextures& volume, const DeepLightMap& dlm, const ViewRays& view, const scene::Sun& sun,
                  const RenderSettings& settings, HostDepth depth = {}, bool finish = true);
  /// Switches to the globe view: rays (ViewRays, cameras) are then in ECEF; `equirect` is the whole
  /// equirectangular basemap (linear RGB, row 0 = 90°N; empty = ocean albedo everywhere) and
  /// `to_sun_ecef` the direction to the sun (scene::toSunEcef). The DLM stays in the world frame.
  void setGlobe(const GlobeMapping& mapping, const scene::LinearRgbImage& equirect, const glm::dvec3& to_sun_ecef,
                const std::vector<float>& city_lights = {});
  /// Globe: a new sun direction (the world-frame sun given to dispatch() still builds the light).
  void setGlobeSun(const glm::dvec3& to_sun_ecef) { globe_to_sun_ = to_sun_ecef; }
  bool globe() const { return globe_.has_value(); }
  /// Statistics for benchmarks: when on, dispatch() also records the number of volume samples
  /// (extinction look-ups) of every ray (the reduced rays with cloud_resolution > 1);
  /// sampleCount() sums the last dispatch's (a read-back).
  void countSamples(bool on) { count_samples_ = on; }
  /// Compositing passes (scene/passes.h): when on, dispatch() also fills groundPass() (ground
  /// radiance, shadow matte in α) and skyPass() (sky radiance, cloud depth Z in α), and render()
  /// reads them back into RenderOutput::passes. Off by default: two image stores per pixel less.
  void setPasses(bool on) { passes_ = on; }
  bool passes() const { return passes_; }
  std::uint64_t sampleCount() const;
  /// Rays of the last dispatch whose march the GL driver ended before either of its ends (the
  /// volume's far side or early termination): Mesa's llvmpipe stops every loop of a shader once a
  /// SIMD group has made 65 535 loop iterations in all (docs/rendering.md "llvmpipe's loop
  /// limit"), so a long march with a small step loses what lies behind the cut. 0 on drivers
  /// without such a limit. A read-back (it waits for the dispatch).
  std::uint64_t raysCutShort() const;
  /// The GPU time of the last render()'s ray-casting dispatches in ms (a GL_TIME_ELAPSED query;
  /// waits for it), once per render(), then 0. Only render() times itself: dispatch() runs in a
  /// host's context (the plugin API), where a timer query of ours would nest inside the host's own
  /// (GL_INVALID_OPERATION). llvmpipe answers ≈ 0: its queries do not time compute work.
  double lastGpuMs();
  /// Benchmark/test baseline (EyePassBaseline); the default is the fast path.
  void setBaseline(const EyePassBaseline& baseline) { baseline_ = baseline; }
  /// The features the next dispatch() with `volume`, `dlm` and `settings` compiles the eye pass for.
  EyePassFeatures features(const VolumeTextures& volume, const DeepLightMap& dlm, const RenderSettings& settings) const;
  /// Eye-pass programs compiled so far (one per feature set and baseline used).
  std::size_t programCount() const { return programs_.size(); }
  /// The atmosphere's tables (nullptr until a frame with RenderSettings::atmosphere ran).
  const AtmosphereLuts* atmosphere() const { return atmosphere_.get(); }
  /// The air the frames are seen through (RenderSettings::atmosphere): the Earth's by default; a
  /// test atmosphere (tests/atmosphere/homogeneous_atmosphere.h) puts a rendered frame against a
  /// closed form. Its tables are rebuilt on the next frame; the ground's light from below
  /// (horizontalIrradiance) uses the same parameters.
  void setAtmosphere(const atmosphere::Parameters& parameters);
  const atmosphere::Parameters& atmosphereParameters() const { return atmosphere_parameters_; }
  /// Bytes of the ray caster's own GL textures (basemaps, globe tables, output targets and passes;
  /// not the atmosphere's small tables) and of its read-back buffer: issue 19's memory accounting.
  std::size_t textureBytes() const;
  const gl::Texture& cloudLayer() const { return cloud_tex_; }
  const gl::Texture& frame() const { return frame_tex_; }
  const gl::Texture& groundPass() const { return ground_pass_tex_; }
  const gl::Texture& skyPass() const { return sky_pass_tex_; }
  /// The Monte Carlo radiance volume (render/dlm/radiance_volume.h) dispatch() traces for
  /// multiple_scattering = radiance_volume, rebuilt only when its key (volume identity, sun,
  /// settings) changes — with the deep light map; null before the first such frame.
  const RadianceVolume* radianceVolume() const { return radiance_volume_.get(); }
  /// The temporal accumulation's history (RenderSettings::temporal_history): dispatch() starts it
  /// afresh by itself when the deep light map's key (volume, sun direction, light settings), the
  /// sun's intensity or colour, the sampling settings or the size change, and at a cut; the
  /// basemaps and the globe reset it; callers reset it for anything else that changes the picture.
  void resetTemporalHistory() { temporal_.reset(); }
  const TemporalAccumulation& temporal() const { return temporal_; }
  /// The last temporal frame's cloud depth per pixel (R32F, row 0 = top; clouds.comp
  /// SPEC_MOTION_DEPTH): the cloud layer's mean depth along the ray, 0 where no cloud is seen.
  const gl::Texture& motionDepth() const { return motion_depth_tex_; }
  /// Its settings (photons, grid, seed); the phases are RenderSettings::g_ice, g_water and the photons
  /// per column RenderSettings::radiance_volume_photons_per_column.
  void setRadianceVolumeSettings(const RadianceVolumeSettings& settings) { radiance_volume_settings_ = settings; }

 private:
  void updateGlobeBlock(const ViewRays& view, const VolumeTextures& volume, const RenderSettings& settings,
                        double sun_intensity);
  void updateTerrainBlock(const VolumeTextures& volume, const RenderSettings& settings);

  const gl::Program& program(const EyePassFeatures& features);
  /// Copies the frame, the cloud layer (when asked) and the passes (when on) into `out` (render()).
  void readBack(RenderOutput& out, int width, int height, const ReadBack& what);
  /// Binds the output images of a pass (cloud layer, frame, sample counts, passes) for `role`
  /// (EyePassFeatures::cloud_pass).
  void bindImages(int role) const;

  std::map<std::string, gl::Program> programs_;  // by the defines they were built with
  EyePassBaseline baseline_;
  gl::Texture basemap_, far_basemap_, blank_, cloud_tex_, frame_tex_, ground_pass_tex_, sky_pass_tex_;
  bool passes_ = false;
  scene::WorldRect far_basemap_rect_;
  glm::ivec2 target_size_{0};
  // Reduced-resolution clouds (RenderSettings::cloud_resolution > 1): the reduced march's cloud
  // layer and guide (clouds.comp SPEC_CLOUD_PASS 1), read by the full-resolution pass.
  gl::Texture low_cloud_tex_, low_guide_tex_;
  glm::ivec2 low_size_{0};
  glm::ivec2 count_size_{0};  // sample_count_tex_'s size: the rays that march
  scene::WorldRect basemap_rect_;
  std::optional<GlobeMapping> globe_;
  gl::Texture globe_table_, globe_basemap_, sample_count_tex_;
  gl::Buffer raycast_stats_;               // uint: rays the loop limiter cut (raysCutShort)
  gl::Buffer pack_buffer_;                 // render()'s read-back on a GPU (ReadBack::Path::PixelBuffer)
  std::optional<gl::GpuTimer> gpu_timer_;  // the last dispatch's GPU time (lastGpuMs)
  bool gpu_timer_running_ = false;
  bool time_gpu_ = false;  // render() only (lastGpuMs)
  bool count_samples_ = false;
  bool basemap_lights_ = false, far_basemap_lights_ = false, globe_lights_ = false;  // A = city lights
  gl::UniformBuffer<gl::RaycastBlock> raycast_block_;  // clouds.comp's view, light and switches
  gl::UniformBuffer<gl::GlobeBlock> globe_block_;      // globe.glsl's mapping
  gl::UniformBuffer<gl::TerrainBlock> terrain_block_;  // the ground's height field, the far basemap
  std::unique_ptr<AtmosphereLuts> atmosphere_;         // built on the first frame that wants it
  atmosphere::Parameters atmosphere_parameters_ = atmosphere::Parameters::earth();  // atmosphere_'s
  glm::dvec3 globe_to_sun_{0.0, 0.0, 1.0};
  TemporalAccumulation temporal_;  // RenderSettings::temporal_history
  // its layers' inputs (clouds.comp SPEC_MOTION_DEPTH): the cloud's mean depth, the background
  gl::Texture motion_depth_tex_, background_tex_;
  std::unique_ptr<RadianceVolume> radiance_volume_;  // built on the first frame that wants it
  RadianceVolumeSettings radiance_volume_settings_;
};

}  // namespace nph::render
