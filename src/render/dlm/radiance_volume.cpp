#include "render/dlm/radiance_volume.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "reference/mc_radiance_volume.h"
#include "render/gl/bindings.h"
#include "render/gl/context.h"
#include "render/gl/debug.h"
#include "volume/reconstruction.h"

namespace nph::render {
namespace {

// The fixed-point bound of glsl/dlm/radiance_volume.comp: one addition is w·ℓ·Y_lm with ℓ ≤ the
// cell's diagonal, |Y_lm| ≤ √(9/(4π)) at l = 4 (the addition theorem) and w ≤ kWeightBound.
constexpr double kMaxHarmonic = 0.8462843753216345;  // √(9/(4π))
// Roulette leaves w = (n + 1)/D after n ≥ D collisions (reference/path_tracer.h): w = 16 needs
// 16 000 collisions at D = 1000 (a photon diffusing that long survives to them with 1/16).
constexpr double kWeightBound = 16.0;
constexpr double kInt32Bound = 2147483520.0;  // float's largest below 2³¹ (the shader's clamp)
// llvmpipe's loop limiter (glsl/dlm/radiance_volume.comp, header): every loop of a shader ends
// once a SIMD group of up to 16 invocations has taken 65 535 back-edges in all. A photon's steps
// per dispatch, weighted by the back-edges they may cost, stay below 2048, so 16 of them (and the
// last flight's tally, which cannot pause) stay below the limit with room.
constexpr int kStepBudget = 2048;
// Dispatches before the photons still paused are given up (counted as cut): far more than any
// case needs (the hurricane's longest photon takes a few dozen).
constexpr int kMaxDispatches = 100000;
constexpr std::size_t kPhotonBytes = 48;  // McPhoton: vec4, vec4, uvec4 (std430)

}  // namespace

RadianceVolume::RadianceVolume(bool tally_every_crossing)
    : build_(tally_every_crossing ? gl::Program::compute("dlm/radiance_volume.comp", {{"TALLY_EVERY_CROSSING", "1"}})
                                  : gl::Program::compute("dlm/radiance_volume.comp")),
      resolve_(gl::Program::compute("dlm/radiance_volume_resolve.comp")),
      stats_buffer_(gl::Buffer::create(8 * sizeof(std::uint32_t)).label("radiance volume stats")) {}

bool RadianceVolume::build(const VolumeTextures& volume, const glm::dvec3& to_sun,
                           const RadianceVolumeSettings& settings) {
  if (settings.photons < 1) throw UsageError("radiance volume: photons must be at least 1");
  if (settings.coarsen_xy < 1 || settings.coarsen_z < 1)
    throw UsageError("radiance volume: the coarsening must be at least 1");
  if (settings.roulette_after_events < 0 || settings.roulette_after_events == 1)
    throw UsageError("radiance volume: roulette_after_events must be 0 (off) or at least 2");
  if (settings.max_events < 1) throw UsageError("radiance volume: max_events must be at least 1");
  if (!(std::abs(settings.g_ice) < 1.0f) || !(std::abs(settings.g_water) < 1.0f))
    throw UsageError("radiance volume: the phase asymmetries must lie in (−1, 1)");
  if (!(glm::length(to_sun) > 0.0)) throw UsageError("radiance volume: the sun direction is zero");
  const glm::dvec3 sun = glm::normalize(to_sun);
  const volume::VolumeFrame& frame = volume.frame();
  // The coarse grid (the CPU twin's gridOf): ⌈voxels / c⌉ cells of c voxels from the box's corner.
  const glm::ivec3 c(settings.coarsen_xy, settings.coarsen_xy, settings.coarsen_z);
  const glm::ivec3 cells = (frame.voxels + c - 1) / c;
  cell_m_ = glm::dvec3(c) * frame.voxel_size_m;
  RadianceVolumeSettings s = settings;  // photons: the count this grid gets
  s.photons = photonsFor(cells, settings);
  const bool cpu = tracesOnCpu(volume, s);
  const std::string key = fmt::format(
      "{}|sun={:.9g},{:.9g},{:.9g}|e={:.9g}|n={}|seed={}|c={}x{}|o={}|r={}|m={}|g={:.9g},{:.9g}|{}", volume.identity(),
      sun.x, sun.y, sun.z, frame.height_exaggeration, s.photons, s.seed, s.coarsen_xy, s.coarsen_z, s.min_order,
      s.roulette_after_events, s.max_events, s.g_ice, s.g_water, cpu ? "cpu" : "gpu");
  if (key == key_ && built()) {
    stats_.rebuilt = false;
    ++stats_.reuses;
    return false;
  }
  const auto t0 = std::chrono::steady_clock::now();
  if (!moments_[0] || moments_[0].width() != cells.x || moments_[0].height() != cells.y ||
      moments_[0].depth() != cells.z)
    for (int k = 0; k < kRadianceVolumeTextures; ++k)
      moments_[k] = gl::Texture::create3D(GL_RGBA32F, cells.x, cells.y, cells.z)
                        .label(fmt::format("radiance volume moments {}", k))
                        .sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
  key_.clear();  // a build that throws leaves no volume claiming the new key
  // Seconds to a minute on a software rasteriser: say what is being done before doing it.
  log::info("radiance volume: tracing {} photons into {}x{}x{} cells on the {}", s.photons, cells.x, cells.y, cells.z,
            cpu ? "CPU (the GL driver is a software rasteriser)" : "GPU");
  if (cpu) buildOnCpu(volume, sun, s, cells);
  else buildOnGpu(volume, sun, s, cells);
  glFinish();
  gl::checkErrors("radiance volume");
  stats_.photons = s.photons;
  stats_.cpu = cpu;
  stats_.cells = cells;
  stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  stats_.rebuilt = true;
  ++stats_.builds;
  key_ = key;
  if (stats_.clamped > 0)
    log::warn("radiance volume: {} tally additions past the fixed-point bound were clamped", stats_.clamped);
  if (stats_.cut_short > 0)
    log::warn("radiance volume: {} loops ended by the driver's loop limiter (photons cut short)", stats_.cut_short);
  log::info("radiance volume ({}): {} photons, {:.1f} collisions per photon, {}x{}x{} cells, {} dispatches, {:.0f} ms",
            cpu ? "CPU twin" : "GPU", s.photons, double(stats_.collisions) / double(s.photons), cells.x, cells.y,
            cells.z, stats_.dispatches, stats_.build_ms);
  return true;
}

std::uint32_t RadianceVolume::photonsFor(const glm::ivec3& cells, const RadianceVolumeSettings& s) {
  const std::uint64_t columns = std::uint64_t(std::max(cells.x, 0)) * std::uint64_t(std::max(cells.y, 0));
  const std::uint64_t perColumn = std::min<std::uint64_t>(columns * s.photons_per_column, kRadianceVolumeMaxPhotons);
  return std::max<std::uint32_t>(s.photons, std::uint32_t(perColumn));
}

bool RadianceVolume::tracesOnCpu(const VolumeTextures& volume, const RadianceVolumeSettings& s) {
  // The twin traces the filtered voxels (reference::ExtinctionField): not the detail, and not the
  // interpolating spline, whose textures hold its coefficients rather than the voxels.
  const bool traceable = !volume.detail().on() && !volume::readsSplineCoefficients(volume.reconstruction());
  switch (s.backend) {
    case RadianceVolumeBackend::Gpu: return false;
    case RadianceVolumeBackend::Cpu:
      if (!traceable)
        throw UsageError(
            "radiance volume: the CPU backend traces neither the sub-grid detail nor the interpolating spline; use "
            "the GPU backend");
      return true;
    case RadianceVolumeBackend::Auto: break;
  }
  return traceable && gl::softwareRasteriser();
}

void RadianceVolume::buildOnGpu(const VolumeTextures& volume, const glm::dvec3& sun, const RadianceVolumeSettings& s,
                                const glm::ivec3& cells) {
  const volume::VolumeFrame& frame = volume.frame();
  const std::size_t cellCount = std::size_t(cells.x) * std::size_t(cells.y) * std::size_t(cells.z);
  const std::size_t words = cellCount * kRadianceVolumeMoments * 2;
  if (tally_.id() == 0 || tally_.size() != words * sizeof(std::uint32_t))
    tally_ = gl::Buffer::create(words * sizeof(std::uint32_t)).label("radiance volume tallies");
  const std::uint32_t zero = 0;
  glClearNamedBufferData(tally_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glClearNamedBufferData(stats_buffer_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  // The support box (the filter's support past the box, as glsl/dlm/radiance_volume.comp
  // supportPad_m: the reach of the upload, detail included, less ½ voxel) and the power per photon.
  const double reach = volume::reachVoxels(volume.reconstruction()) + volume.detail().reach_voxels;
  const glm::dvec3 size = frame.size_m() + 2.0 * (reach - 0.5) * frame.voxel_size_m;
  const glm::dvec3 faces(size.y * size.z, size.x * size.z, size.x * size.y);
  const glm::dvec3 projected = faces * glm::abs(sun);
  const double power = (projected.x + projected.y + projected.z) / double(s.photons);
  const double diagonal = glm::length(cell_m_);
  quantum_m_ = kWeightBound * kMaxHarmonic * diagonal / kInt32Bound;
  moment_unit_ = quantum_m_ * power / (cell_m_.x * cell_m_.y * cell_m_.z);

  build_.use();
  volume.bind();
  build_.set("u_photons", int(s.photons));  // set as int: Program has no uint setter; ≤ 2³¹ − 1
  build_.set("u_seed", int(s.seed));
  build_.set("u_to_sun", glm::vec3(sun));
  build_.set("u_projected_m2", glm::vec3(projected));
  build_.set("u_min_order", s.min_order);
  build_.set("u_cells", cells);
  build_.set("u_cell_m", glm::vec3(cell_m_));
  build_.set("u_quantum_m", float(quantum_m_));
  build_.set("u_g_ice", s.g_ice);
  build_.set("u_g_water", s.g_water);
  build_.set("u_height_exaggeration", float(std::max(frame.height_exaggeration, 1e-6)));
  build_.set("u_roulette_after", s.roulette_after_events);
  build_.set("u_max_events", s.max_events);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_MC_TALLY, tally_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_MC_STATS, stats_buffer_.id());
  // Resumable photons (the shader's header): dispatch until no photon is paused.
  if (photons_.id() == 0 || photons_.size() < std::size_t(s.photons) * kPhotonBytes)
    photons_ = gl::Buffer::create(std::size_t(s.photons) * kPhotonBytes).label("radiance volume photons");
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_MC_PHOTONS, photons_.id());
  build_.set("u_step_budget", kStepBudget);
  std::uint32_t paused = 0;
  int dispatches = 0;
  do {
    build_.set("u_start", dispatches == 0 ? 1 : 0);
    glClearNamedBufferSubData(stats_buffer_.id(), GL_R32UI, 5 * sizeof(std::uint32_t), sizeof(std::uint32_t),
                              GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    build_.dispatchCovering({int(s.photons), 1, 1});
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    stats_buffer_.download(5 * sizeof(std::uint32_t), sizeof(paused), &paused);
    ++dispatches;
  } while (paused > 0 && dispatches < kMaxDispatches);
  resolve_.use();
  resolve_.set("u_cells", cells);
  resolve_.set("u_scale", float(moment_unit_));
  for (int k = 0; k < kRadianceVolumeTextures; ++k)
    glBindImageTexture(GLuint(gl::binding::IMAGE_MC_MOMENTS + k), moments_[k].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY,
                       GL_RGBA32F);
  resolve_.dispatchCovering(cells);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);

  std::uint32_t st[8] = {};
  stats_buffer_.download(0, sizeof(st), st);
  stats_.collided = st[0];
  stats_.collisions = st[1];
  stats_.rouletted = st[2];
  stats_.truncated = st[3] + paused;  // paused: still paused after kMaxDispatches (not expected)
  stats_.clamped = st[4];
  stats_.cut_short = st[6];
  stats_.dispatches = dispatches;
}

void RadianceVolume::buildOnCpu(const VolumeTextures& volume, const glm::dvec3& sun, const RadianceVolumeSettings& s,
                                const glm::ivec3& cells) {
  // The twin with the GPU build's settings (tests/render/radiance_volume_gl_test.cpp pairs them
  // the same way): the field the eye pass reads, read back from the textures it reads.
  const ExtinctionVolumes field = volume.readBackExtinction();
  reference::McTallySpec spec;
  spec.coarsen_xy = s.coarsen_xy;
  spec.coarsen_z = s.coarsen_z;
  spec.min_order = s.min_order;
  spec.max_l = 4;
  static_assert(kRadianceVolumeMoments == reference::harmonicsUpTo(4));
  reference::McSettings ms;
  ms.photons = s.photons;
  ms.seed = s.seed;
  ms.roulette_after_events = s.roulette_after_events;
  ms.max_events = s.max_events;
  ms.phase.ice = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, double(s.g_ice)};
  ms.phase.water = physics::PhaseFunction{physics::PhaseModel::HenyeyGreenstein, double(s.g_water)};
  ms.reconstruction = volume.reconstruction();
  reference::McStats st;
  const reference::McRadianceVolume mc =
      reference::traceMcRadianceVolumes(field, volume.frame(), sun, {spec}, ms, &st).front();
  if (mc.cells != cells) throw UsageError("radiance volume: the CPU twin's grid differs from the GPU's");
  // Moment k goes to texture k / 4, channel k mod 4 (the resolve pass's layout).
  const std::size_t cellCount = std::size_t(cells.x) * std::size_t(cells.y) * std::size_t(cells.z);
  std::vector<float> rgba(cellCount * 4);
  for (int t = 0; t < kRadianceVolumeTextures; ++t) {
    for (std::size_t c = 0; c < cellCount; ++c)
      for (int ch = 0; ch < 4; ++ch) {
        const int k = 4 * t + ch;
        rgba[4 * c + std::size_t(ch)] = k < kRadianceVolumeMoments ? float(mc.moment(c, k)) : 0.0f;
      }
    glTextureSubImage3D(moments_[t].id(), 0, 0, 0, 0, cells.x, cells.y, cells.z, GL_RGBA, GL_FLOAT, rgba.data());
  }
  tally_ = {};  // no integer sums on this path (readBackSums: empty)
  quantum_m_ = 0.0;
  moment_unit_ = 0.0;
  stats_.collided = st.collided;
  stats_.collisions = st.collisions;
  stats_.rouletted = st.rouletted;
  stats_.truncated = st.truncated;
  stats_.clamped = 0;
  stats_.cut_short = 0;
  stats_.dispatches = 0;
}

void RadianceVolume::bind() const {
  for (int k = 0; k < kRadianceVolumeTextures; ++k)
    glBindTextureUnit(GLuint(gl::binding::UNIT_MC_MOMENTS + k), moments_[k].id());
}

std::vector<std::int64_t> RadianceVolume::readBackSums() const {
  std::vector<std::int64_t> out;
  if (tally_.id() == 0) return out;
  std::vector<std::uint32_t> w(tally_.size() / sizeof(std::uint32_t));
  tally_.download(0, tally_.size(), w.data());
  out.resize(w.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = std::int64_t((std::uint64_t(w[2 * i + 1]) << 32) | std::uint64_t(w[2 * i]));
  return out;
}

std::vector<float> RadianceVolume::readBackMoments() const {
  std::vector<float> out;
  if (!built()) return out;
  const glm::ivec3 n = stats_.cells;
  const std::size_t cells = std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z);
  out.assign(cells * kRadianceVolumeMoments, 0.0f);
  std::vector<float> rgba(cells * 4);
  for (int k = 0; k < kRadianceVolumeTextures; ++k) {
    glGetTextureImage(moments_[k].id(), 0, GL_RGBA, GL_FLOAT, GLsizei(rgba.size() * sizeof(float)), rgba.data());
    for (std::size_t c = 0; c < cells; ++c)
      for (int ch = 0; ch < 4; ++ch)
        if (4 * k + ch < kRadianceVolumeMoments)
          out[c * kRadianceVolumeMoments + std::size_t(4 * k + ch)] = rgba[4 * c + std::size_t(ch)];
  }
  return out;
}

std::size_t RadianceVolume::textureBytes() const {
  std::size_t b = tally_.size() + photons_.size();
  for (const gl::Texture& t : moments_) b += t ? t.bytes() : 0;
  return b;
}

}  // namespace nph::render
