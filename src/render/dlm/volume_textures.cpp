#include "render/dlm/volume_textures.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/packing.hpp>

#include "core/error.h"
#include "render/gl/bindings.h"
#include "render/gl/debug.h"
#include "render/gl/program.h"
#include "volume/column_depth.h"
#include "volume/spline_coefficients.h"

namespace nph::render {

namespace {
gl::Texture upload3D(const std::vector<float>& data, glm::ivec3 size, const char* label) {
  auto t = gl::Texture::create3D(GL_R32F, size.x, size.y, size.z).label(label);
  glTextureSubImage3D(t.id(), 0, 0, 0, 0, size.x, size.y, size.z, GL_RED, GL_FLOAT, data.data());
  return t;
}
// Voxels the shaders can take: finite, ≥ 0 and at most kMaxExtinction_per_m. NaN or Inf would
// make the DLM and the eye pass output NaN (exp(−NaN), ∞/∞ in the phase mix), a negative β a
// transmittance above 1; 1e6 /m (optical depth 1 per millimetre, ~10³ × the densest cloud core)
// keeps β_ice + β_water and β·Δ far from float overflow. The loaders already reject non-finite
// fields (io/field_checks.h); this guards volumes from caches and hosts (stress-tested).
constexpr float kMaxExtinction_per_m = 1e6f;
void checkVoxels(const float* a, std::size_t n, std::size_t base, const char* name) {
  for (std::size_t i = 0; i < n; ++i) {
    if (!(a[i] >= 0.0f && a[i] <= kMaxExtinction_per_m)) {
      throw InputError(
          fmt::format("VolumeTextures::upload: {} voxel {} is {}, expected a finite extinction in [0, {:g}] 1/m", name,
                      base + i, a[i], kMaxExtinction_per_m));
    }
  }
}
bool anyPositive(const float* a, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (a[i] > 0.0f) return true;
  return false;
}
}  // namespace

VolumeTextures VolumeTextures::upload(const ExtinctionVolumes& v, const volume::VolumeFrame& frame,
                                      std::string identity, const UploadOptions& o) {
  return upload(VolumeSlices(v), frame, std::move(identity), o);
}

VolumeTextures VolumeTextures::upload(const ExtinctionSlices& data, const volume::VolumeFrame& frame,
                                      std::string identity, const UploadOptions& o) {
  const ExtinctionVolumes& header = data.volumes();
  if (header.voxelCount() == 0) throw UsageError("VolumeTextures::upload: empty volume");
  const volume::Reconstruction reconstruction = o.reconstruction;
  const volume::Detail detail = o.detail;
  VolumeTextures t;
  t.frame_ = frame;
  t.identity_ = std::move(identity);
  if (reconstruction != volume::Reconstruction::Trilinear)
    t.identity_ += fmt::format("|{}", volume::kReconstructionNames[std::size_t(reconstruction)]);
  t.reconstruction_ = reconstruction;
  t.detail_ = volume::detailParameters(detail, frame);
  if (t.detail_.on()) {
    t.identity_ += fmt::format("|detail={}", volume::kDetailNames[std::size_t(detail)]);
    const volume::MassPattern& d = volume::kMassPattern;
    if (o.mass.rays_per_axis != d.rays_per_axis || o.mass.step_layers != d.step_layers ||
        o.mass.occupied_only != d.occupied_only)
      t.identity_ += fmt::format("|mass={},{},{}", o.mass.rays_per_axis, o.mass.step_layers, int(o.mass.occupied_only));
  }
  const glm::ivec3 n(header.nx, header.ny, header.nz);
  const std::size_t layer = std::size_t(n.x) * std::size_t(n.y);
  // Memory (issue 19, docs/benchmarks.md "Memory"): the packed texture holds β (RG16F) and the
  // column depths τ_up (R16F; τ_down = T − τ_up with T per column, volume/column_depth.h) in 6 bytes
  // per voxel. Where it serves (the trilinear filter without sub-grid detail) a Compact upload
  // makes it the only copy: the R32F ice and water and the RG16F column depths (τ_up, T) are made
  // only for the cubic filter and the detail, whose fetches need the zero border or displaced
  // positions, and for VolumeStorage::Reference (the float baseline; its packed eye pass then reads
  // τ_up from the RG16F texture's first channel).
  const bool packed = reconstruction == volume::Reconstruction::Trilinear && !t.detail_.on();
  const bool separate = !packed || o.storage == VolumeStorage::Reference;
  t.separate_ = separate;
  // T, the column's total optical depth (as the half the depths are stored as), per column.
  std::vector<float> columnTotals(layer, 0.0f);
  // The voxel checks and which phases are present, a layer at a time (an absent phase reads 0).
  const auto check = [&](int k, const ExtinctionSlices::Slice& s) {
    checkVoxels(s.ice, layer, std::size_t(k) * layer, "ice_per_m");
    checkVoxels(s.water, layer, std::size_t(k) * layer, "water_per_m");
    t.has_ice_ = t.has_ice_ || anyPositive(s.ice, layer);
    t.has_water_ = t.has_water_ || anyPositive(s.water, layer);
  };
  // The packed texture alone is read in two passes over the layers, upwards (a `.nph` source
  // decodes its chunk once per pass, cache::NphReader::readSlices): the checks with the column
  // totals, then the texture with the occupancy. Other paths check in a pass of their own.
  std::optional<ColumnDepthSlices> depths;
  if (packed && !separate) {
    depths.emplace(data, check);
  } else {
    std::vector<float> scratch;
    for (int k = 0; k < n.z; ++k) check(k, data.slice(k, scratch));
  }
  // cubic_interpolating (volume/spline_coefficients.h): from here on every texture, the column
  // depths, the detail's controls and the occupancy are made from the spline's coefficients, which
  // the cubic B-spline then evaluates — the field passes through the checked voxels.
  // The column depths are the coefficients' sums (the integral of the field the filter makes); the
  // detail's controls stay the voxels' own, on both sides (ExtinctionSampler).
  std::optional<ExtinctionVolumes> decodedData;
  std::optional<VolumeSlices> coefficients;
  const ExtinctionVolumes* dataWhole = data.whole();
  if (volume::readsSplineCoefficients(reconstruction)) {
    if (!dataWhole) dataWhole = &decodedData.emplace(data.materialise());
    coefficients.emplace(std::make_shared<const ExtinctionVolumes>(volume::splineCoefficientVolumes(*dataWhole)));
  }
  const ExtinctionSlices& src = coefficients ? *coefficients : data;
  if (packed && separate) t.identity_ += "|reference";  // its DLM reads β in float: another map
  // The float volume whole, where a path reads the grid at once (the separate textures, the
  // detail's controls and mass): the source's own, or decoded here (a layer-by-layer source).
  std::optional<ExtinctionVolumes> decoded;
  const ExtinctionVolumes* whole = src.whole();
  if (!whole && (separate || t.detail_.on())) whole = &decoded.emplace(src.materialise());
  if (separate && t.has_ice_) {
    t.ice_ = upload3D(whole->ice_per_m, n, "ice extinction [1/m]");
    t.ice_.sampling(GL_LINEAR, GL_CLAMP_TO_BORDER);
  }
  if (separate && t.has_water_) {
    t.water_ = upload3D(whole->water_per_m, n, "water extinction [1/m]");
    t.water_.sampling(GL_LINEAR, GL_CLAMP_TO_BORDER);
  }
  // Vertical optical depths above each voxel and through its column for the sky light
  // (volume/column_depth.h), interleaved (τ_up, T) as RG16F: 0.1 % precision is far below the
  // two-stream model's own error, and the 65504 ceiling of a half float is a column no sky light
  // crosses anyway. Built as half bit patterns, for the separate texture over the whole grid (4
  // bytes per voxel, transient), for the packed one slice by slice (ColumnDepthSlices: the same
  // values, two doubles per column).
  if (separate) {
    const std::vector<std::uint16_t> rg = columnDepthsHalf(*whole);
    t.column_depth_ = gl::Texture::create3D(GL_RG16F, n.x, n.y, n.z).label("column optical depth (up, total)");
    glTextureSubImage3D(t.column_depth_.id(), 0, 0, 0, 0, n.x, n.y, n.z, GL_RG, GL_HALF_FLOAT, rg.data());
    t.column_depth_.sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
    for (std::size_t c = 0; c < layer; ++c) columnTotals[c] = glm::unpackHalf1x16(rg[2 * c + 1]);
  }
  // The packed texture (issue 19 item 3; hasPacked): (β_ice, β_water) per voxel, RG16F, with τ_up
  // beside it (R16F; the RG16F (τ_up, T) of the separate textures where those exist) and T per
  // column (the columns' texture): a view-ray step reads β, τ_up and T in three fetches, two of
  // them 3-D, instead of ice, water and the column depths (8-tap fetches each). β is stored per kilometre (a
  // half's normal range starts at 6.1e-5: β of thin cloud, ~1e-6 /m, keeps 11 significant bits as
  // 1e-3 /km), or coarser where the largest β would overflow the half's 65504. Clamp to edge, as
  // the column depths need; the zero border the extinction's trilinear filter fades to outside the
  // box is applied in the shader instead (glsl/dlm/volume.glsl packedTexel). Uploaded slice by
  // slice from the bottom: an interleaved half slice and the column sums are the only transients. The
  // slice goes up as GL_HALF_FLOAT: the column depths are already the CPU twin's halves, and β is
  // rounded to half here once (glm::packHalf1x16, round to nearest), so the driver converts nothing.
  // The occupancy (below) of the packed path is built in its texture's pass.
  volume::OccupancyBuilder occupancy(header, o.brick_voxels, reconstruction);
  if (packed) {
    const float maxBeta = std::max({header.max_ice_per_m, header.max_water_per_m, 1e-30f});
    const float storedPerM = std::min(1000.0f, 60000.0f / maxBeta);
    t.packed_beta_unit_per_m_ = 1.0f / storedPerM;
    if (!depths) depths.emplace(src);
    t.packed_ = gl::Texture::create3D(GL_RG16F, n.x, n.y, n.z).label("packed (ice, water)");
    if (!separate) t.column_depth_ = gl::Texture::create3D(GL_R16F, n.x, n.y, n.z).label("column optical depth (up)");
    std::vector<std::uint16_t> slice(2 * layer), up(separate ? 0 : layer);
    const std::uint16_t zero = glm::packHalf1x16(0.0f);
    for (int k = 0; k < n.z; ++k) {
      const std::vector<std::uint16_t>& rg = depths->next(k);
      const ExtinctionSlices::Slice& beta = depths->beta();  // layer k, as the depths read it
      occupancy.add(k, beta);
      for (std::size_t i = 0; i < layer; ++i) {
        slice[2 * i] = t.has_ice_ ? glm::packHalf1x16(beta.ice[i] * storedPerM) : zero;
        slice[2 * i + 1] = t.has_water_ ? glm::packHalf1x16(beta.water[i] * storedPerM) : zero;
      }
      glTextureSubImage3D(t.packed_.id(), 0, 0, 0, k, n.x, n.y, 1, GL_RG, GL_HALF_FLOAT, slice.data());
      if (separate) continue;  // the RG16F (τ_up, T) above holds the same halves
      for (std::size_t i = 0; i < layer; ++i) up[i] = rg[2 * i];
      if (k == 0)
        for (std::size_t c = 0; c < layer; ++c) columnTotals[c] = glm::unpackHalf1x16(rg[2 * c + 1]);
      glTextureSubImage3D(t.column_depth_.id(), 0, 0, 0, k, n.x, n.y, 1, GL_RED, GL_HALF_FLOAT, up.data());
    }
    t.packed_.sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
    t.column_depth_.sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
  }
  // The terrain's surface: its interpolating spline's coefficients (TerrainField::spline_m),
  // fetched texel by texel (glsl/common/terrain.glsl interpolates itself: fixed-function bilinear
  // weights have 8 bits on most GPUs, which would terrace the normals).
  t.terrain_ = volume::terrainOf(header, frame, o.dem);
  {
    const bool present = t.terrain_.present();
    const int w = present ? t.terrain_.size.x : 1, h = present ? t.terrain_.size.y : 1;
    t.terrain_tex_ = gl::Texture::create2D(GL_R32F, w, h).label("terrain spline [m]");
    const float zero = 0.0f;
    glTextureSubImage2D(t.terrain_tex_.id(), 0, 0, 0, w, h, GL_RED, GL_FLOAT,
                        present ? t.terrain_.spline_m.data() : &zero);
    t.terrain_tex_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
    // A user DEM's far field (glsl/common/terrain.glsl terrainFarHeight_m), row 0 south as the
    // mass points.
    const bool far = present && t.terrain_.hasFar();
    const int fw = far ? t.terrain_.far_size.x : 1, fh = far ? t.terrain_.far_size.y : 1;
    t.far_terrain_tex_ = gl::Texture::create2D(GL_R32F, fw, fh).label("far terrain height [m]");
    glTextureSubImage2D(t.far_terrain_tex_.id(), 0, 0, 0, fw, fh, GL_RED, GL_FLOAT,
                        far ? t.terrain_.far_height_m.data() : &zero);
    t.far_terrain_tex_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
  }
  // Units of absent phases get a 1-voxel zero texture so that no unit is left unbound.
  t.zero_ = upload3D(std::vector<float>{0.0f}, {1, 1, 1}, "zero");
  t.zero_rgba_ = gl::Texture::create3D(GL_RGBA8, 1, 1, 1).label("zero rgba8");
  {
    const std::uint8_t zero[4] = {0, 0, 0, 0};
    glTextureSubImage3D(t.zero_rgba_.id(), 0, 0, 0, 0, 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, zero);
  }
  if (t.detail_.on()) {
    // Sub-grid detail (volume/detail.h): the controls at data resolution and the noise tile.
    const volume::DetailControls controls = volume::buildDetailControls(coefficients ? *dataWhole : *whole);
    t.controls_ = gl::Texture::create3D(GL_RGBA8, n.x, n.y, n.z).label("detail controls");
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(t.controls_.id(), 0, 0, 0, 0, n.x, n.y, n.z, GL_RGBA, GL_UNSIGNED_BYTE, controls.rgba.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    t.controls_.sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
    t.noise_ = o.noise ? o.noise : NoiseTexture::generate();
  }
  // The horizontal wind that advects the noise (volume/detail.h DetailFlow), where the data has U, V.
  volume::DetailFlow flow;
  if (t.detail_.on()) {
    const ExtinctionVolumes& voxels = coefficients ? *dataWhole : *whole;
    const volume::DetailWind wind = volume::buildDetailWind(voxels);
    flow = volume::detailFlow(voxels.detail_clock_s, !wind.empty());
    if (!wind.empty()) {
      t.wind_ = gl::Texture::create3D(GL_RG32F, n.x, n.y, n.z).label("detail wind [m/s]");
      glTextureSubImage3D(t.wind_.id(), 0, 0, 0, 0, n.x, n.y, n.z, GL_RG, GL_FLOAT, wind.uv.data());
      t.wind_.sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
    }
  }
  gl::VolumeBlock block;
  block.box_min_m = glm::vec3(t.frame_.min_m());
  block.box_size_m = glm::vec3(t.frame_.size_m());
  block.voxels = t.frame_.voxels;
  // The brick the occupancy below is built with (t.occupancy_ is still the default here: reading
  // its brick gave 8 whatever the option, and the majorants of another size were misread).
  block.brick_voxels = o.brick_voxels;
  block.has_ice = t.hasIce() ? 1u : 0u;
  block.has_water = t.hasWater() ? 1u : 0u;
  block.reconstruction = volume::cubicWeights(reconstruction) ? 1 : 0;  // the shaders' RECONSTRUCTION_CUBIC
  block.reach_voxels = float(volume::reachVoxels(reconstruction) + t.detail_.reach_voxels);
  block.packed_beta_unit_per_m = t.packed_beta_unit_per_m_;
  block.packed_only = packed && !separate ? 1u : 0u;
  if (t.detail_.on()) {
    const volume::NoiseStats& st = volume::noiseVolume().stats;
    block.detail = static_cast<std::int32_t>(detail);
    block.detail_amplitude = float(t.detail_.amplitude);
    block.noise_period_m = glm::vec3(t.detail_.period_m);
    block.displacement_m = glm::vec3(t.detail_.reach_m);
    volume::packNoiseStats(st, block.noise_stats_ra, block.noise_stats_gs, block.noise_stats_c);
    // w: 1 where the noise is advected (the data has U, V), 0 in still air (DETAIL_WIND_ON).
    block.detail_flow =
        glm::vec4(float(flow.tau_s.x), float(flow.tau_s.y), float(flow.weight_a), t.wind_ ? 1.0f : 0.0f);
  }
  t.block_ = gl::UniformBuffer<gl::VolumeBlock>::create(block, "volume block");
  // Per model column, RG32F (UNIT_COLUMNS): the detail's mass correction (volume/detail.h;
  // measured with the correction at 1, solved on the CPU; the occupancy maxima then bound
  // ρ·c ≤ 2·max c; 1 without detail), read by texelFetch and blended in the shader, and the column's
  // total optical depth T, read bilinearly (GL_LINEAR, clamped to the edge like the depths).
  float maxScale = 1.0f;
  std::vector<float> correction(layer, 1.0f);
  if (t.detail_.on()) {
    // measured before the columns' texture exists: measureRayMasses binds a 1-texel correction of 1
    const volume::RayMasses masses = t.measureRayMasses(*whole, o.mass);
    correction = volume::solveDetailCorrection(masses);
    maxScale = float(volume::kMaxDetailDensity) * *std::max_element(correction.begin(), correction.end());
  }
  {
    std::vector<float> rg(2 * layer);
    for (std::size_t c = 0; c < layer; ++c) {
      rg[2 * c] = correction[c];
      rg[2 * c + 1] = columnTotals[c];
    }
    t.columns_ = gl::Texture::create2D(GL_RG32F, n.x, n.y).label("per column (detail correction, total depth)");
    glTextureSubImage2D(t.columns_.id(), 0, 0, 0, n.x, n.y, GL_RG, GL_FLOAT, rg.data());
    t.columns_.sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
  }
  t.occupancy_ = packed ? occupancy.finish()
                 : t.detail_.on()
                     ? volume::buildOccupancy(src, o.brick_voxels, reconstruction, t.detail_.reach_voxels, maxScale)
                     : volume::buildOccupancy(src, o.brick_voxels, reconstruction);
  {
    // RG32F (max, lower bound) per brick (volume/occupancy.h): one fetch serves the empty-space
    // skip (max) and the DLM's adaptive light step (max − min; glsl/dlm/march.comp).
    const glm::ivec3 b = t.occupancy_.bricks;
    std::vector<float> rg(2 * t.occupancy_.max_per_m.size());
    for (std::size_t i = 0; i < t.occupancy_.max_per_m.size(); ++i) {
      rg[2 * i] = t.occupancy_.max_per_m[i];
      rg[2 * i + 1] = t.occupancy_.min_per_m[i];
    }
    t.occupancy_tex_ = gl::Texture::create3D(GL_RG32F, b.x, b.y, b.z).label("occupancy max, min [1/m]");
    glTextureSubImage3D(t.occupancy_tex_.id(), 0, 0, 0, 0, b.x, b.y, b.z, GL_RG, GL_FLOAT, rg.data());
  }
  t.occupancy_tex_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
  return t;
}

volume::RayMasses VolumeTextures::measureRayMasses(const ExtinctionVolumes& v,
                                                   const volume::MassPattern& pattern) const {
  volume::RayMasses m;
  m.nx = frame_.voxels.x;
  m.ny = frame_.voxels.y;
  m.rays_per_column = 2 * pattern.rays_per_axis;
  const glm::ivec2 h(m.rays_per_column * m.nx, m.rays_per_column * m.ny);
  auto image = gl::Texture::create2D(GL_RG32F, h.x, h.y).label("detail ray masses");
  // The step range per model column (volume/detail.h massStepRanges), as the CPU twin marches it.
  const int filterReach = volume::reachVoxels(reconstruction_);
  const std::vector<glm::ivec2> ranges =
      volume::massStepRanges(v, filterReach, filterReach + detail_.reach_voxels, pattern);
  auto rangeImage = gl::Texture::create2D(GL_RG32I, m.nx, m.ny).label("detail mass step ranges");
  glTextureSubImage2D(rangeImage.id(), 0, 0, 0, m.nx, m.ny, GL_RG_INTEGER, GL_INT, ranges.data());
  const gl::Program program = gl::Program::compute("render/detail_mass.comp");
  program.use();
  program.set("u_rays_per_axis", pattern.rays_per_axis);
  program.set("u_step_layers", float(pattern.step_layers));
  bind();
  // The uncorrected detailed field: the correction at 1 (after upload, bind() binds the solved c).
  auto one = gl::Texture::create2D(GL_R32F, 1, 1).label("detail correction (none)");
  const float unity = 1.0f;
  glTextureSubImage2D(one.id(), 0, 0, 0, 1, 1, GL_RED, GL_FLOAT, &unity);
  one.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
  glBindTextureUnit(gl::binding::UNIT_COLUMNS, one.id());
  glBindImageTexture(gl::binding::IMAGE_DETAIL_MASS, image.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
  glBindImageTexture(gl::binding::IMAGE_DETAIL_MASS_RANGE, rangeImage.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RG32I);
  program.dispatchCovering({h.x, h.y, 1});
  glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
  std::vector<float> rg(2 * std::size_t(h.x) * std::size_t(h.y));
  glGetTextureImage(image.id(), 0, GL_RG, GL_FLOAT, GLsizei(rg.size() * sizeof(float)), rg.data());
  m.plain.resize(rg.size() / 2);
  m.detailed.resize(rg.size() / 2);
  for (std::size_t i = 0; i < m.plain.size(); ++i) {
    m.plain[i] = double(rg[2 * i]);
    m.detailed[i] = double(rg[2 * i + 1]);
  }
  return m;
}

void VolumeTextures::nonEmptyBox(glm::dvec3& lo, glm::dvec3& hi) const {
  if (occupancy_.empty()) {
    lo = frame_.min_m();
    hi = glm::dvec3(frame_.max_m().x, frame_.max_m().y, frame_.min_m().z);
    return;
  }
  // The filter's reach: β is non-zero up to `reach` voxel centre-distances past a non-zero voxel,
  // including the fading shell outside the box (glsl/dlm/volume.glsl).
  const int reach = occupancy_.dilation_voxels;
  const glm::dvec3 a = glm::dvec3(occupancy_.nonEmptyMinVoxel - reach);
  const glm::dvec3 b = glm::dvec3(occupancy_.nonEmptyMaxVoxel + 1 + reach);
  lo = frame_.worldFromGrid(a);
  hi = frame_.worldFromGrid(b);
}

std::vector<std::uint16_t> VolumeTextures::readBackPacked() const {
  if (!packed_) return {};
  const glm::ivec3 n = frame_.voxels;
  const std::size_t voxels = std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z);
  const std::size_t columns = std::size_t(n.x) * std::size_t(n.y);
  std::vector<std::uint16_t> texels(3 * voxels + columns);
  const auto bytes = [](std::size_t values) { return GLsizei(values * sizeof(std::uint16_t)); };
  glGetTextureImage(packed_.id(), 0, GL_RG, GL_HALF_FLOAT, bytes(2 * voxels), texels.data());
  glGetTextureImage(column_depth_.id(), 0, GL_RED, GL_HALF_FLOAT, bytes(voxels), texels.data() + 2 * voxels);
  std::vector<float> rg(2 * columns);
  glGetTextureImage(columns_.id(), 0, GL_RG, GL_FLOAT, GLsizei(rg.size() * sizeof(float)), rg.data());
  for (std::size_t c = 0; c < columns; ++c) texels[3 * voxels + c] = glm::packHalf1x16(rg[2 * c + 1]);
  gl::checkErrors("reading the packed texture back");
  return texels;
}

ExtinctionVolumes VolumeTextures::readBackExtinction() const {
  const glm::ivec3 n = frame_.voxels;
  ExtinctionVolumes v = ExtinctionVolumes::zeros(n.x, n.y, n.z, frame_.voxel_size_m.x, frame_.voxel_size_m.z, 0.0);
  const std::size_t layer = std::size_t(n.x) * std::size_t(n.y);
  const auto bytes = [](const std::vector<float>& a) { return GLsizei(a.size() * sizeof(float)); };
  if (hasSeparateTextures()) {  // an absent phase is all zero
    if (ice_) glGetTextureImage(ice_.id(), 0, GL_RED, GL_FLOAT, bytes(v.ice_per_m), v.ice_per_m.data());
    if (water_) glGetTextureImage(water_.id(), 0, GL_RED, GL_FLOAT, bytes(v.water_per_m), v.water_per_m.data());
  } else if (packed_) {
    std::vector<float> rg(2 * layer);
    for (int k = 0; k < n.z; ++k) {
      glGetTextureSubImage(packed_.id(), 0, 0, 0, k, n.x, n.y, 1, GL_RG, GL_FLOAT, bytes(rg), rg.data());
      for (std::size_t i = 0; i < layer; ++i) {
        v.ice_per_m[std::size_t(k) * layer + i] = rg[2 * i] * packed_beta_unit_per_m_;
        v.water_per_m[std::size_t(k) * layer + i] = rg[2 * i + 1] * packed_beta_unit_per_m_;
      }
    }
  }
  gl::checkErrors("reading the extinction back");
  v.updateMaxima();
  return v;
}

std::size_t VolumeTextures::bytes() const {
  std::size_t b = 0;
  for (const gl::Texture* tex : {&ice_, &water_, &occupancy_tex_, &column_depth_, &zero_, &terrain_tex_,
                                 &far_terrain_tex_, &controls_, &zero_rgba_, &columns_, &packed_, &wind_})
    b += tex->bytes();
  return b;
}

void VolumeTextures::bind() const {
  glBindTextureUnit(gl::binding::UNIT_ICE_PER_M, ice_ ? ice_.id() : zero_.id());
  glBindTextureUnit(gl::binding::UNIT_WATER_PER_M, water_ ? water_.id() : zero_.id());
  glBindTextureUnit(gl::binding::UNIT_OCCUPANCY_PER_M, occupancy_tex_.id());
  glBindTextureUnit(gl::binding::UNIT_COLUMN_DEPTH, column_depth_ ? column_depth_.id() : zero_.id());
  glBindTextureUnit(gl::binding::UNIT_TERRAIN, terrain_tex_.id());
  glBindTextureUnit(gl::binding::UNIT_FAR_TERRAIN, far_terrain_tex_.id());
  glBindTextureUnit(gl::binding::UNIT_DETAIL_CONTROLS, controls_ ? controls_.id() : zero_rgba_.id());
  glBindTextureUnit(gl::binding::UNIT_DETAIL_NOISE, noise_ ? noise_->texture().id() : zero_rgba_.id());
  glBindTextureUnit(gl::binding::UNIT_COLUMNS, columns_.id());
  glBindTextureUnit(gl::binding::UNIT_DETAIL_WIND, wind_ ? wind_.id() : zero_.id());  // no wind: calm
  glBindTextureUnit(gl::binding::UNIT_PACKED_VOLUME, packed_ ? packed_.id() : zero_rgba_.id());
  block_.bind();
}

}  // namespace nph::render
