#include "render/raycast/cloud_renderer.h"

#include "lighting/cloud_light.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "atmosphere/atmosphere.h"
#include "core/error.h"
#include "core/large_buffer.h"
#include "core/log.h"
#include "render/gl/context.h"
#include "render/gl/debug.h"

namespace nph::render {

gl::Defines EyePassFeatures::defines() const {
  auto bit = [](bool on) { return std::string(on ? "1" : "0"); };
  return {{"SPEC_GLOBE", bit(globe)},           {"SPEC_TERRAIN", bit(terrain)},
          {"SPEC_ATMOSPHERE", bit(atmosphere)}, {"SPEC_PASSES", bit(passes)},
          {"SPEC_DETAIL", bit(detail)},         {"SPEC_DETAIL_WIND", bit(detail_wind)},
          {"SPEC_CUBIC", bit(cubic)},           {"SPEC_LIGHT_CACHE", bit(light_cache)},
          {"SPEC_PACKED", bit(packed)},         {"SPEC_CLOUD_PASS", std::to_string(cloud_pass)}};
}

namespace {
// The radiance volume's define is no uniform branch (its samplers exist only with it): every
// program that draws the model gets it, the uniform-branch baseline too.
void addRadianceVolumeDefine(gl::Defines& d, bool on) {
  if (on) d.emplace_back("SPEC_RADIANCE_VOLUME", "1");
}
}  // namespace

glm::vec2 subpixelPosition(int k) {
  if (k <= 0) return {0.5f, 0.5f};
  constexpr double kPlastic = 1.32471795724474602596;  // φ₂: x³ = x + 1
  const double a = 0.5 + double(k) / kPlastic, b = 0.5 + double(k) / (kPlastic * kPlastic);
  return {float(a - std::floor(a)), float(b - std::floor(b))};
}

CloudRenderer::CloudRenderer()
    : raycast_block_(gl::UniformBuffer<gl::RaycastBlock>::create({}, "raycast block")),
      globe_block_(gl::UniformBuffer<gl::GlobeBlock>::create({}, "globe block")),
      terrain_block_(gl::UniformBuffer<gl::TerrainBlock>::create({}, "terrain block")) {
  blank_ = gl::Texture::create2D(GL_RGBA32F, 1, 1).label("no basemap");
  const float zero[4] = {0, 0, 0, 0};
  glTextureSubImage2D(blank_.id(), 0, 0, 0, 1, 1, GL_RGBA, GL_FLOAT, zero);
}

namespace {
// An imagery texture of the eye pass: RGB the linear albedo, A the night side's city lights on the
// same grid (scene::cityLightsIntensity; 0 without), filtered together. Mipmapped (issue 14 item
// 3): oblique views and the globe's limb see the ground at a slant.
//
// Issue 19 (memory): imagery from 8- or 16-bit integer sources (LinearRgbImage::integer_source:
// Blue Marble's JPEG, PNG and integer GeoTIFFs) is stored as RGBA16F, 8 instead of 16 bytes per
// texel, mips included. Half floats keep 11 significant bits (relative error ≤ 2⁻¹¹ ≈ 0.05 %, far
// below one 8-bit output level), and the texture stays linear, so the sampler's bilinear and
// trilinear taps, glGenerateTextureMipmap and the shader's anisotropic taps
// (glsl/common/imagery.glsl) filter linear light as before. Float sources and images made in
// memory keep RGBA32F: they may carry more than 11 bits (the tests' lon/lat-coded basemaps do).
// Not SRGB8_ALPHA8 even for the 8-bit JPEG: (1) GDAL's warper interpolates the sRGB codes in float
// (scene/basemap.h), so the reprojected texels lie between codes and 8 bits would requantise them
// by up to ½ code; (2) A carries the city lights as a linear intensity in [0, 1], which an 8-bit
// linear alpha would cut to steps of 1/255, coarse against the dim lights (docs/benchmarks.md,
// "Basemap textures in half precision").
GLenum imageryFormat(const scene::LinearRgbImage& image) { return image.integer_source ? GL_RGBA16F : GL_RGBA32F; }

gl::Texture imageryTexture(const scene::LinearRgbImage& image, const std::vector<float>& lights, const char* label) {
  const std::size_t n = std::size_t(image.width) * std::size_t(image.height);
  if (!lights.empty() && lights.size() != n) {
    throw UsageError(
        fmt::format("{}: {} city-light values for {}x{} pixels", label, lights.size(), image.width, image.height));
  }
  gl::Texture t = gl::Texture::create2D(imageryFormat(image), image.width, image.height,
                                        gl::mipLevelsFor(image.width, image.height))
                      .label(label);
  // Uploaded in strips of rows: the interleaved copy is a strip, not a second image (issue 19,
  // memory: 64 MB for the demo's 2048² basemap).
  constexpr int kStripRows = 64;
  const std::size_t w = std::size_t(image.width);
  std::vector<float> rgba(4 * w * std::size_t(std::min(kStripRows, image.height)));
  for (int y0 = 0; y0 < image.height; y0 += kStripRows) {
    const int rows = std::min(kStripRows, image.height - y0);
    const std::size_t first = std::size_t(y0) * w;
    for (std::size_t i = 0; i < std::size_t(rows) * w; ++i) {
      for (std::size_t c = 0; c < 3; ++c) rgba[4 * i + c] = image.rgb[3 * (first + i) + c];
      rgba[4 * i + 3] = lights.empty() ? 0.0f : lights[first + i];
    }
    glTextureSubImage2D(t.id(), 0, 0, y0, image.width, rows, GL_RGBA, GL_FLOAT, rgba.data());
  }
  return t;
}
}  // namespace

void CloudRenderer::setBasemap(const scene::LinearRgbImage& image, const scene::WorldRect& rect,
                               const std::vector<float>& city_lights) {
  temporal_.reset();  // another ground under the clouds
  basemap_lights_ = false;
  if (image.width <= 0 || image.height <= 0) {
    basemap_ = gl::Texture();
    return;
  }
  basemap_ = imageryTexture(image, city_lights, "basemap (linear RGB, city lights)");
  basemap_.mipmapped(GL_CLAMP_TO_EDGE);
  basemap_rect_ = rect;
  basemap_lights_ = !city_lights.empty();
}

void CloudRenderer::setAtmosphere(const atmosphere::Parameters& parameters) {
  atmosphere_parameters_ = parameters;
  atmosphere_.reset();  // the tables of the new air are built by the next frame that wants them
}

void CloudRenderer::setFarBasemap(const scene::LinearRgbImage& image, const scene::WorldRect& rect,
                                  const std::vector<float>& city_lights) {
  temporal_.reset();
  far_basemap_ = gl::Texture();
  far_basemap_lights_ = false;
  if (image.width <= 0 || image.height <= 0) return;
  far_basemap_ = imageryTexture(image, city_lights, "far basemap (linear RGB, city lights)");
  far_basemap_.mipmapped(GL_CLAMP_TO_EDGE);
  far_basemap_rect_ = rect;
  far_basemap_lights_ = !city_lights.empty();
}

void CloudRenderer::setGlobe(const GlobeMapping& m, const scene::LinearRgbImage& equirect,
                             const glm::dvec3& to_sun_ecef, const std::vector<float>& city_lights) {
  temporal_.reset();  // rays in ECEF from now on
  globe_ = m;
  globe_to_sun_ = to_sun_ecef;
  globe_table_ = gl::Texture::create2D(GL_RG32F, m.width, m.height).label("globe lon/lat -> world");
  glTextureSubImage2D(globe_table_.id(), 0, 0, 0, m.width, m.height, GL_RG, GL_FLOAT, m.world_xy_m.data());
  globe_table_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
  globe_basemap_ = gl::Texture();
  globe_lights_ = false;
  if (equirect.width > 0 && equirect.height > 0) {
    globe_basemap_ = imageryTexture(equirect, city_lights, "globe basemap (linear RGB, city lights)");
    globe_lights_ = !city_lights.empty();
    // The whole Earth is seen from far away and at grazing angles towards the limb (the
    // anisotropic taps are the shader's, as for the flat view's basemaps).
    globe_basemap_.mipmapped(GL_REPEAT);  // wraps across the antimeridian in u ...
    glTextureParameteri(globe_basemap_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);  // ... not over the poles in v
  }
}

ViewRays ViewRays::fromCamera(const scene::Camera& camera) {
  return fromMatrices(camera.viewFromWorld(), camera.clipFromView(), camera.width, camera.height);
}

ViewRays ViewRays::fromMatrices(const glm::dmat4& view_from_world, const glm::dmat4& clip_from_view, int width,
                                int height) {
  ViewRays r;
  const glm::dmat4 world_from_view = glm::inverse(view_from_world);
  r.position_m = glm::dvec3(world_from_view[3]);
  r.world_from_view = glm::dmat3(world_from_view);
  r.view_from_clip = glm::inverse(clip_from_view);
  r.width = width;
  r.height = height;
  return r;
}

void CloudRenderer::updateGlobeBlock(const ViewRays& view, const VolumeTextures& volume, const RenderSettings& s,
                                     double sun_intensity) {
  glBindTextureUnit(gl::binding::UNIT_GLOBE_WORLD_XY, globe_ ? globe_table_.id() : blank_.id());
  glBindTextureUnit(gl::binding::UNIT_GLOBE_BASEMAP, globe_basemap_ ? globe_basemap_.id() : blank_.id());
  globe_block_.bind();
  if (!globe_) return;  // clouds.comp reads GlobeBlock only when RaycastBlock::globe is set
  const GlobeMapping& m = *globe_;
  const double o2 = glm::dot(view.position_m, view.position_m);  // double: |o|² − r² cancels
  const double R = volume::kEarthRadius_m;
  gl::GlobeBlock b;
  b.local_from_ecef = gl::Std140Mat3(glm::mat3(m.local_from_ecef));
  b.ab_min_rad = glm::vec2(m.ab_min_rad);
  b.ab_max_rad = glm::vec2(m.ab_max_rad);
  b.earth_radius_m = float(R);
  b.cap_axis = glm::vec3(m.cap_axis);
  b.cap_min_dot_m = float(m.shell_min_m * m.cap_cos);
  b.sphere_c_m2 = glm::vec3(float(o2 - R * R), float(o2 - m.shell_max_m * m.shell_max_m), 0.0f);
  b.lipschitz_h = float(m.horizontal_lipschitz);
  b.has_globe_basemap = globe_basemap_ ? 1u : 0u;
  b.limb_radiance = glm::vec3(s.limb_radiance * sun_intensity);
  // Terrain on the globe (glsl/render/globe_terrain.glsl): the shell of its heights, the table's
  // cone and margin, and the march's rate bound
  //   |df/dt| ≤ 1 + L·L_h + H_max/edge
  // (the radius changes at most 1 m per metre; the world point moves at most L_h world metres per
  // ECEF metre and the surface rises at most L per world metre; the margin's ramp at most
  // H_max/edge per metre), +1 %.
  const volume::TerrainField& t = volume.terrain();
  const double top = R + std::max(t.max_m, 0.0), bottom = R + std::min(t.min_m, 0.0) - 1.0;
  b.terrain_c_m2 = glm::vec2(float(o2 - top * top), float(o2 - bottom * bottom));
  const double edge_m = std::max(m.margin_rad * R, 1.0);
  b.terrain_edge_m = float(edge_m);
  b.terrain_rate = float(1.01 * (1.0 + t.lipschitz * m.horizontal_lipschitz + std::max(t.max_m, -t.min_m) / edge_m));
  // The table's (a, b) box seen from the footprint centre's axis: its farthest point is a corner,
  // cos of its angle cos a·cos b (a, b the rotated lon/lat).
  const double aMax = std::max(std::abs(m.ab_min_rad.x), std::abs(m.ab_max_rad.x));
  const double bMax = std::max(std::abs(m.ab_min_rad.y), std::abs(m.ab_max_rad.y));
  b.terrain_cap_min_dot_m = float(bottom * std::cos(aMax) * std::cos(bMax));
  globe_block_.update(b);
}

void CloudRenderer::updateTerrainBlock(const VolumeTextures& volume, const RenderSettings& s) {
  glBindTextureUnit(gl::binding::UNIT_FAR_BASEMAP, far_basemap_ ? far_basemap_.id() : blank_.id());
  const volume::TerrainField& t = volume.terrain();
  gl::TerrainBlock b;
  b.size = t.size;
  b.cell_m = glm::vec2(t.cell_m);
  b.exaggeration = float(t.exaggeration);
  b.fade_m = float(t.fade_m);
  b.max_m = float(t.max_m);
  b.min_m = float(t.min_m);
  b.lipschitz = float(t.lipschitz);
  // Flat view and globe (render/globe_terrain.glsl) alike.
  b.has_terrain = s.terrain && t.present() ? 1u : 0u;
  // Ground detail (glsl/common/ground_tint.glsl): synthesis, off unless the style asks for it.
  b.ground_tint = s.ground_tint ? 1u : 0u;
  b.snow_line_m = float(s.snow_line_m);
  b.has_far_basemap = far_basemap_ && !globe_ ? 1u : 0u;
  b.far_basemap_min_m = glm::vec2(far_basemap_rect_.min_m);
  b.far_basemap_max_m = glm::vec2(far_basemap_rect_.max_m);
  // A user DEM's far field (scene/dem.h): the flat view's ground beyond the domain. The globe's
  // terrain ends with its table, a few per cent beyond the footprint (docs/terrain.md).
  if (t.hasFar() && !globe_) {
    b.has_far_terrain = 1u;
    b.far_terrain_size = t.far_size;
    b.far_terrain_min_m = glm::vec2(t.far_min_m);
    b.far_terrain_cell_m = glm::vec2(t.far_cell_m);
  }
  // The night side's lights (glsl/common/night_lights.glsl), where any imagery of the view has them.
  const bool lights = globe_ ? globe_lights_ : basemap_lights_ || far_basemap_lights_;
  b.city_lights = lights ? float(s.city_lights) : 0.0f;
  terrain_block_.update(b);
  terrain_block_.bind();
}

std::size_t CloudRenderer::textureBytes() const {
  std::size_t b = 0;
  for (const gl::Texture* t :
       {&basemap_, &far_basemap_, &blank_, &cloud_tex_, &frame_tex_, &ground_pass_tex_, &sky_pass_tex_, &globe_table_,
        &globe_basemap_, &sample_count_tex_, &low_cloud_tex_, &low_guide_tex_, &motion_depth_tex_, &background_tex_})
    b += t->bytes();
  return b + temporal_.textureBytes() + pack_buffer_.size();  // the read-back's pack buffer (a GPU's only)
}

EyePassFeatures CloudRenderer::features(const VolumeTextures& volume, const DeepLightMap& dlm,
                                        const RenderSettings& s) const {
  EyePassFeatures f;
  f.globe = globe_.has_value();
  // The same conditions as the blocks' switches (updateTerrainBlock, dispatch, VolumeTextures).
  f.terrain = s.terrain && volume.terrain().present();
  f.atmosphere = s.atmosphere;
  f.passes = passes_;
  f.detail = volume.detail().on();
  f.detail_wind = f.detail && volume.hasDetailWind();
  f.cubic = volume::cubicWeights(volume.reconstruction());
  f.light_cache = dlm.hasLightCache();
  f.packed = volume.hasPacked() && !baseline_.separate_textures;
  f.radiance_volume = s.multiple_scattering == lighting::MultipleScattering::RadianceVolume;
  return f;
}

const gl::Program& CloudRenderer::program(const EyePassFeatures& features) {
  gl::Defines defines = baseline_.uniform_branches ? gl::Defines{} : features.defines();
  // The role is no uniform branch: the baseline keeps it as a define.
  if (baseline_.uniform_branches && features.cloud_pass != 0)
    defines.emplace_back("SPEC_CLOUD_PASS", std::to_string(features.cloud_pass));
  addRadianceVolumeDefine(defines, features.radiance_volume);
  if (features.motion_depth) defines.emplace_back("SPEC_MOTION_DEPTH", "1");  // only when on: no other key changes
  if (baseline_.binary_search) defines.emplace_back("DLM_LOOKUP_BINARY_SEARCH", "1");
  if (baseline_.unclipped_steps) defines.emplace_back("ADAPTIVE_STEPS_UNCLIPPED", "1");
  if (baseline_.sky_half_transmittance) defines.emplace_back("SKY_HALF_TRANSMITTANCE", "1");
  if (baseline_.no_forward_lobe) defines.emplace_back("NO_FORWARD_LOBE", "1");
  if (baseline_.depth_blind_upsampling && features.cloud_pass == 2) defines.emplace_back("UPSAMPLE_DEPTH_BLIND", "1");
  std::string key;
  for (const auto& [name, value] : defines) key += name + "=" + value + ";";
  auto it = programs_.find(key);
  if (it == programs_.end()) it = programs_.emplace(key, gl::Program::compute("render/clouds.comp", defines)).first;
  return it->second;
}

double CloudRenderer::dispatch(const VolumeTextures& volume, const DeepLightMap& dlm, const ViewRays& view,
                               const scene::Sun& sun, const RenderSettings& s, HostDepth depth, bool finish) {
  const int w = view.width, h = view.height;
  if (w <= 0 || h <= 0 || w > 16384 || h > 16384) {
    throw UsageError(fmt::format("render: image size {}x{} out of range (1..16384)", w, h));
  }
  gl::DebugGroup group("cloud ray caster");
  const auto t0 = std::chrono::steady_clock::now();
  if (target_size_ != glm::ivec2(w, h)) {
    cloud_tex_ = gl::Texture::create2D(GL_RGBA32F, w, h).label("cloud layer");
    frame_tex_ = gl::Texture::create2D(GL_RGBA32F, w, h).label("frame");
    ground_pass_tex_ = gl::Texture();
    sky_pass_tex_ = gl::Texture();
    target_size_ = {w, h};
  }
  if (passes_ && !ground_pass_tex_) {
    ground_pass_tex_ = gl::Texture::create2D(GL_RGBA32F, w, h).label("ground pass, shadow matte");
    sky_pass_tex_ = gl::Texture::create2D(GL_RGBA32F, w, h).label("sky pass, cloud depth");
  }
  // Reduced-resolution clouds (RenderSettings::cloud_resolution; clouds.comp SPEC_CLOUD_PASS):
  // the march at ⌈W/s⌉ × ⌈H/s⌉ (the same field of view: the rays of ViewRays at that size), then
  // the full-resolution pass over its upsampled clouds.
  const int divisor = std::clamp(s.cloud_resolution, 1, 4);
  const glm::ivec2 low{(w + divisor - 1) / divisor, (h + divisor - 1) / divisor};
  if (divisor > 1 && low_size_ != low) {
    low_cloud_tex_ = gl::Texture::create2D(GL_RGBA32F, low.x, low.y).label("cloud layer, reduced resolution");
    low_guide_tex_ = gl::Texture::create2D(GL_RG32F, low.x, low.y).label("cloud guide, reduced resolution");
    low_cloud_tex_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
    low_guide_tex_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
    low_size_ = low;
  }
  const glm::ivec2 marched = divisor > 1 ? low : glm::ivec2(w, h);
  if (count_size_ != marched) {
    sample_count_tex_ = gl::Texture::create2D(GL_R32UI, marched.x, marched.y).label("samples per ray");
    count_size_ = marched;
  }
  // Temporal accumulation (RenderSettings::temporal_history; render/raycast/temporal_accumulation.h):
  // a fresh frame takes the next samples of the sequence and writes its reprojection depth.
  const bool temporal = s.temporal_history > 0 && s.first_sample <= 0;
  int sample_offset = 0;
  if (temporal) {
    // What the picture depends on besides the view: a change starts the history afresh.
    // The map's key holds the volume's identity, the light's settings and the direction it was
    // built for; the sun given here lights the ground and the sky as well.
    const glm::dvec3 toSun = sun.toSun();
    const std::string key = fmt::format(
        "{}|{},{},{}|{}|{},{},{}|{},{},{}|{}|{},{}|{},{}|{}|{}|{}", dlm.cacheKey(), toSun.x, toSun.y, toSun.z,
        sun.intensity, sun.colour.r, sun.colour.g, sun.colour.b, s.step_voxels, s.step_growth_max, s.min_transmittance,
        int(s.multiple_scattering), s.g_ice, s.g_water, s.samples_per_pixel, divisor, s.atmosphere, s.terrain, passes_);
    sample_offset = temporal_.begin(view, key);
  }
  if (s.temporal_history <= 0 && motion_depth_tex_) {  // turned off: its 92 bytes per pixel go
    temporal_.release();
    motion_depth_tex_ = {};
    background_tex_ = {};
  }
  if (temporal && (motion_depth_tex_.width() != w || motion_depth_tex_.height() != h)) {
    motion_depth_tex_ = gl::Texture::create2D(GL_R32F, w, h).label("cloud layer's mean depth");
    background_tex_ = gl::Texture::create2D(GL_RGBA32F, w, h).label("background, its depth");
  }
  EyePassFeatures f = features(volume, dlm, s);
  f.motion_depth = temporal;
  if (f.radiance_volume) {  // traced when the sun, the data or its settings change (its cache key)
    if (!radiance_volume_) radiance_volume_ = std::make_unique<RadianceVolume>();
    RadianceVolumeSettings rv = radiance_volume_settings_;
    rv.g_ice = float(s.g_ice);
    rv.g_water = float(s.g_water);
    rv.photons_per_column = std::uint32_t(std::max(0, s.radiance_volume_photons_per_column));
    radiance_volume_->build(volume, sun.toSun(), rv);
  }
  EyePassFeatures lowFeatures = f, fullFeatures = f;
  lowFeatures.cloud_pass = 1;
  lowFeatures.passes = false;  // the full-resolution pass writes them
  lowFeatures.motion_depth = false;
  fullFeatures.cloud_pass = 2;
  const gl::Program& p = program(divisor > 1 ? fullFeatures : f);
  const gl::Program* lowProgram = divisor > 1 ? &program(lowFeatures) : nullptr;
  p.use();
  volume.bind();
  dlm.bindForLookup();
  // The count of marches llvmpipe's loop limiter ended (clouds.comp raycastCutShort), per frame.
  if (raycast_stats_.id() == 0) raycast_stats_ = gl::Buffer::create(sizeof(std::uint32_t)).label("ray cast stats");
  const std::uint32_t zero = 0;
  glClearNamedBufferData(raycast_stats_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_RAYCAST_STATS, raycast_stats_.id());
  if (f.radiance_volume) {
    radiance_volume_->bind();
    const glm::vec3 boxMin(volume.frame().min_m());
    const glm::vec3 extent(glm::dvec3(radiance_volume_->cells()) * radiance_volume_->cellSize_m());
    for (const gl::Program* q : {&p, lowProgram}) {
      if (q == nullptr) continue;
      q->set("u_mc_box_min_m", boxMin);
      q->set("u_mc_extent_m", extent);
    }
  }
  glBindTextureUnit(gl::binding::UNIT_BASEMAP, basemap_ ? basemap_.id() : blank_.id());
  glBindTextureUnit(gl::binding::UNIT_HOST_DEPTH, depth.texture ? depth.texture : blank_.id());
  gl::RaycastBlock b;
  b.size = glm::ivec2(w, h);
  b.cam_pos_m = glm::vec3(view.position_m);
  b.world_from_view = gl::Std140Mat3(glm::mat3(view.world_from_view));
  b.view_from_clip = glm::mat4(view.view_from_clip);
  b.has_host_depth = depth.texture ? 1u : 0u;
  b.to_sun = glm::vec3(globe_ ? globe_to_sun_ : sun.toSun());
  b.sun_radiance = glm::vec3(sun.colour * sun.intensity);
  const lighting::SkyLight sky = lighting::skyLightFor(s, sun.elevation_deg, sun.colour, sun.intensity);
  b.sky_radiance = glm::vec3(sky.above);
  b.below_radiance = glm::vec3(sky.below);
  if (s.atmosphere && !s.sky_below) {
    // The light from below (issue 14, seventeenth session): the ground under the clouds is lit
    // through the air, so its Lambertian bounce is ρ̄/π·E·(μ_s·T_sun + E_sky) at the ground's
    // height (the terrain's mean, true metres), not the unattenuated sun of the clear-sky model
    // above — at a 6° sun that white beam made the bounce 1 : 1.16 : 1.33 where the air's is
    // 1 : 0.71 : 0.54, and the clouds' undersides lilac (docs/atmosphere.md "The golden-hour light").
    const volume::TerrainField& terrain = volume.terrain();
    double ground_m = 0.0;
    if (terrain.present() && !terrain.height_m.empty()) {
      for (float z : terrain.height_m) ground_m += std::max(double(z), 0.0);
      ground_m /= double(terrain.height_m.size());
    }
    const glm::dvec3 e =
        atmosphere::horizontalIrradiance(atmosphere_parameters_, ground_m, glm::radians(sun.elevation_deg));
    b.below_radiance = glm::vec3(s.ground_albedo / std::numbers::pi * sun.colour * sun.intensity * e);
  }
  b.octaves = s.octaves.octaves;
  b.cloud_ms_model = std::int32_t(s.multiple_scattering);
  b.ms_extinction_scale = float(s.octaves.extinction_scale);
  b.ms_energy_scale = float(s.octaves.energy_scale);
  b.ms_anisotropy_scale = float(s.octaves.anisotropy_scale);
  b.height_exaggeration = float(volume.frame().height_exaggeration);
  b.g_ice = float(s.g_ice);
  b.g_water = float(s.g_water);
  const glm::dvec3 voxel = volume.frame().voxel_size_m;
  b.step_m = float(s.step_voxels * std::min({voxel.x, voxel.y, voxel.z}));
  b.step_growth_max = float(std::max(s.step_growth_max, 1.0));
  b.min_transmittance = float(s.min_transmittance);
  b.jitter = s.jitter ? 1u : 0u;
  b.skip_empty = s.empty_space_skipping ? 1u : 0u;
  b.shadows = s.shadows ? 1u : 0u;
  b.has_basemap = basemap_ ? 1u : 0u;
  b.basemap_min_m = glm::vec2(basemap_rect_.min_m);
  b.basemap_max_m = glm::vec2(basemap_rect_.max_m);
  b.ocean_albedo = glm::vec3(s.ocean_albedo);
  b.count_samples = count_samples_ ? 1u : 0u;
  b.globe = globe_ ? 1u : 0u;
  b.atmosphere = s.atmosphere ? 1u : 0u;
  b.write_passes = passes_ ? 1u : 0u;
  if (s.atmosphere) {
    if (!atmosphere_) atmosphere_ = std::make_unique<AtmosphereLuts>(atmosphere_parameters_);
    // The sky-view table serves the flat view (its observer at the camera's altitude above the
    // plane z = 0); the globe marches every ray instead (glsl/atmosphere/sky.glsl).
    if (!globe_) atmosphere_->updateSkyView(view.position_m.z, sun.toSun());
    atmosphere_->bind();
    p.use();
  }
  updateGlobeBlock(view, volume, s, sun.intensity);
  updateTerrainBlock(volume, s);
  // Samples per pixel (RenderSettings::samples_per_pixel; clouds.comp runningMean): one dispatch
  // per sample, each folding into the images the previous ones wrote. With reduced-resolution
  // clouds each sample is two dispatches: the reduced march at the sample's sub-pixel position in
  // the reduced pixel (so the samples spread over the s × s full pixels under it), then the
  // full-resolution pass, which upsamples that sample's clouds and folds the composite into the
  // means; a progressive refinement (first_sample > 0) folds one more such pair.
  const int first = std::max(0, s.first_sample), samples = std::max(1, s.samples_per_pixel);
  auto run = [&](const gl::Program& program, glm::ivec2 size, int role, int k) {
    program.use();
    bindImages(role);
    b.size = size;
    b.write_passes = passes_ && role != 1 ? 1u : 0u;
    b.subpixel = subpixelPosition(k + sample_offset);
    b.sample_index = std::uint32_t(k);
    b.jitter_index = std::uint32_t(k + sample_offset);
    raycast_block_.update(b);
    raycast_block_.bind();
    program.dispatchCovering({size.x, size.y, 1});
  };
  if (lowProgram) {
    glBindTextureUnit(gl::binding::UNIT_LOW_CLOUD_LAYER, low_cloud_tex_.id());
    glBindTextureUnit(gl::binding::UNIT_LOW_CLOUD_GUIDE, low_guide_tex_.id());
  }
  // The dispatches' own GPU time, for render() only (lastGpuMs, read after the read-back has waited
  // for them): on a real GPU render()'s wall time is mostly host work (docs/benchmarks.md "On an
  // NVIDIA GPU").
  if (time_gpu_) {
    if (!gpu_timer_) gpu_timer_.emplace();
    gpu_timer_->start();
  }
  for (int k = first; k < first + samples; ++k) {
    if (lowProgram) {
      run(*lowProgram, low, 1, k);
      glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
      run(p, {w, h}, 2, k);
      // the next reduced march overwrites what this pass read
      if (k + 1 < first + samples) glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    } else {
      run(p, {w, h}, 0, k);
      if (k + 1 < first + samples) glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
  }
  if (temporal) {
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    temporal_.resolve(frame_tex_, cloud_tex_, motion_depth_tex_, background_tex_, view, s.temporal_history);
  }
  if (time_gpu_) {
    gpu_timer_->stop();
    gpu_timer_running_ = true;
  }
  glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
  if (finish) glFinish();
  gl::checkErrors("cloud ray caster");
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void CloudRenderer::bindImages(int role) const {
  // Role 1 (the reduced march) writes the reduced layer and guide; the frame and the passes stay
  // bound (valid, never written by it).
  const GLuint layer = role == 1 ? low_cloud_tex_.id() : cloud_tex_.id();
  glBindImageTexture(gl::binding::IMAGE_CLOUD_LAYER, layer, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(gl::binding::IMAGE_FRAME, frame_tex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(gl::binding::IMAGE_SAMPLE_COUNT, sample_count_tex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  if (motion_depth_tex_ && role != 1) {
    glBindImageTexture(gl::binding::IMAGE_MOTION_DEPTH, motion_depth_tex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
    glBindImageTexture(gl::binding::IMAGE_TEMPORAL_BACKGROUND, background_tex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                       GL_RGBA32F);
  }
  if (role == 1)
    glBindImageTexture(gl::binding::IMAGE_LOW_CLOUD_GUIDE, low_guide_tex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE,
                       GL_RG32F);
  // Without passes the units stay bound to the frame (valid, never written: u_write_passes is 0).
  const GLuint groundImage = passes_ ? ground_pass_tex_.id() : frame_tex_.id();
  const GLuint skyImage = passes_ ? sky_pass_tex_.id() : frame_tex_.id();
  glBindImageTexture(gl::binding::IMAGE_PASS_GROUND, groundImage, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
  glBindImageTexture(gl::binding::IMAGE_PASS_SKY, skyImage, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
}

double CloudRenderer::lastGpuMs() {
  if (!gpu_timer_ || !gpu_timer_running_) return 0.0;
  gpu_timer_running_ = false;
  return double(gpu_timer_->elapsedNs()) * 1e-6;
}

std::uint64_t CloudRenderer::raysCutShort() const {
  if (raycast_stats_.id() == 0) return 0;
  std::uint32_t cut = 0;
  raycast_stats_.download(0, sizeof(cut), &cut);
  return cut;
}

std::uint64_t CloudRenderer::sampleCount() const {
  if (!count_samples_ || !sample_count_tex_) return 0;
  std::vector<std::uint32_t> counts(std::size_t(count_size_.x) * std::size_t(count_size_.y));
  glGetTextureImage(sample_count_tex_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT,
                    static_cast<GLsizei>(counts.size() * sizeof(std::uint32_t)), counts.data());
  gl::checkErrors("sample count read-back");
  std::uint64_t sum = 0;
  for (std::uint32_t c : counts) sum += c;
  return sum;
}

RenderOutput CloudRenderer::render(const VolumeTextures& volume, const DeepLightMap& dlm, const scene::Camera& camera,
                                   const scene::Sun& sun, const RenderSettings& s, const ReadBack& read_back) {
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  const auto t0 = Clock::now();
  time_gpu_ = true;
  try {
    dispatch(volume, dlm, ViewRays::fromCamera(camera), sun, s, {}, /*finish=*/false);
  } catch (...) {
    time_gpu_ = false;
    throw;
  }
  time_gpu_ = false;
  const auto t1 = Clock::now();
  glFinish();  // the read-back would wait here anyway; waiting first times it apart from the copy
  const auto t2 = Clock::now();
  RenderOutput out;
  readBack(out, camera.width, camera.height, read_back);
  const auto t3 = Clock::now();
  out.gpu_milliseconds = lastGpuMs();
  out.submit_milliseconds = ms(t0, t1);
  out.wait_milliseconds = ms(t1, t2);
  out.readback_milliseconds = ms(t2, t3);
  out.milliseconds = ms(t0, Clock::now());
  log::debug("ray cast {}x{}: set-up and submission {:.1f} ms, wait {:.1f} ms, read-back {:.1f} ms", camera.width,
             camera.height, out.submit_milliseconds, out.wait_milliseconds, out.readback_milliseconds);
  return out;
}

void CloudRenderer::readBack(RenderOutput& out, int w, int h, const ReadBack& what) {
  const std::size_t pixels = std::size_t(w) * std::size_t(h), floats = 4 * pixels;
  struct Image {
    const gl::Texture* texture;
    std::vector<float>* values;
  };
  std::vector<float> ground, sky;  // Two RGBA textures hold four passes: (ground.rgb, shadow) and (sky.rgb, Z).
  std::vector<Image> images{{&frame_tex_, &out.frame.rgba}};
  if (what.cloud_layer) images.push_back({&cloud_tex_, &out.cloud_layer.rgba});
  if (passes_) {
    images.push_back({&ground_pass_tex_, &ground});
    images.push_back({&sky_pass_tex_, &sky});
  }
  out.frame.width = w;
  out.frame.height = h;
  if (what.cloud_layer) {
    out.cloud_layer.width = w;
    out.cloud_layer.height = h;
  }
  const bool direct =
      what.path == ReadBack::Path::Direct || (what.path == ReadBack::Path::Auto && gl::softwareRasteriser());
  if (direct) {
    for (const Image& img : images) {
      img.values->resize(floats);
      glGetTextureImage(img.texture->id(), 0, GL_RGBA, GL_FLOAT, GLsizei(floats * sizeof(float)), img.values->data());
    }
  } else {
    // Every image into one pack buffer (kept: an animation reads the same sizes every frame), then
    // one map: the driver's copies overlap each other, and the host copies out of memory the
    // driver chose instead of faulting the caller's fresh pages in under the driver's copy.
    const std::size_t image_bytes = floats * sizeof(float), bytes = image_bytes * images.size();
    if (pack_buffer_.size() < bytes)
      pack_buffer_ = gl::Buffer::create(bytes, nullptr, GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT).label("read-back");
    GLint previous = 0;
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &previous);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, pack_buffer_.id());
    for (std::size_t i = 0; i < images.size(); ++i)
      glGetTextureImage(images[i].texture->id(), 0, GL_RGBA, GL_FLOAT, GLsizei(image_bytes),
                        reinterpret_cast<void*>(i * image_bytes));
    glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(previous));
    const auto* mapped = static_cast<const std::uint8_t*>(
        glMapNamedBufferRange(pack_buffer_.id(), 0, GLsizeiptr(bytes), GL_MAP_READ_BIT));
    if (!mapped) throw GlError("cloud ray caster read-back: the pixel-pack buffer could not be mapped");
    struct Unmap {  // also when an allocation below throws: the next frame packs into the buffer again
      GLuint id;
      ~Unmap() { glUnmapNamedBuffer(id); }
    } unmap{pack_buffer_.id()};
    for (std::size_t i = 0; i < images.size(); ++i) {
      *images[i].values = hugePageFloats(floats);
      std::memcpy(images[i].values->data(), mapped + i * image_bytes, image_bytes);
    }
  }
  if (passes_) {
    scene::FramePasses& p = out.passes.emplace();
    p.width = w;
    p.height = h;
    p.ground_rgb.resize(3 * pixels);
    p.sky_rgb.resize(3 * pixels);
    p.shadow.resize(pixels);
    p.depth_m.resize(pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
      for (std::size_t c = 0; c < 3; ++c) {
        p.ground_rgb[3 * i + c] = ground[4 * i + c];
        p.sky_rgb[3 * i + c] = sky[4 * i + c];
      }
      p.shadow[i] = ground[4 * i + 3];
      p.depth_m[i] = sky[4 * i + 3];
    }
  }
  gl::checkErrors("cloud ray caster read-back");
}

}  // namespace nph::render
