#include "render/dlm/deep_light_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "render/gl/bindings.h"
#include "render/gl/debug.h"

namespace nph::render {
namespace {

// The light space as glsl/dlm/light_space.glsl reads it (float, like the GPU).
gl::LightSpaceBlock lightSpaceBlock(const lighting::LightSpace& ls) {
  gl::LightSpaceBlock b;
  b.origin_m = glm::vec3(ls.origin_m);
  b.depth_m = float(ls.depth_m);
  b.u = glm::vec3(ls.u);
  b.v = glm::vec3(ls.v);
  b.w = glm::vec3(ls.w);
  b.texel_m = glm::vec2(ls.texelSize_m());
  b.texels = ls.texels;
  return b;
}

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Process CPU ms since `c0` (std::clock: every thread, so llvmpipe's workers count) — the log's
// per-pass CPU time, readable on a machine whose wall times other jobs inflate.
double cpuMsSince(std::clock_t c0) { return 1000.0 * double(std::clock() - c0) / CLOCKS_PER_SEC; }

// Pass 1's compaction along one axis (glsl/dlm/march.comp passOneTexel): pass 2 reads the blend
// corners floor(t_c) and floor(t_c) + 1 of each cell centre t_c = (c + ½)·n/cells − ½; a centre
// within the margin of an integer may floor either way in float, so its axis takes a third slot.
// Compaction needs cells at least 2 texels apart (scale ≥ 2; else every texel is read anyway).
constexpr double kPassOneReadMargin = 0.01;  // texels; glsl/dlm/march.comp kReadMargin
struct PassOneAxis {
  int cells = 0;   ///< 0: no compaction, every texel
  int slots = 1;   ///< invocations per cell
  int texels = 0;  ///< distinct texels marched
};
PassOneAxis passOneAxis(int n, int cells) {
  const double scale = double(n) / double(cells);
  if (scale < 2.0) return {0, 1, n};
  PassOneAxis a{cells, 2, 0};
  std::vector<char> marched(std::size_t(n), 0);
  for (int c = 0; c < cells; ++c) {
    const double t = (c + 0.5) * scale - 0.5;
    const int lo = int(std::floor(t - kPassOneReadMargin)), hi = int(std::floor(t + kPassOneReadMargin)) + 1;
    if (hi - lo == 2) a.slots = 3;
    for (int k = std::max(lo, 0); k <= std::min(hi, n - 1); ++k) marched[std::size_t(k)] = 1;
  }
  a.texels = int(std::count(marched.begin(), marched.end(), char(1)));
  return a;
}

std::vector<std::uint32_t> readCounts(const gl::Texture& counts, glm::ivec2 n) {
  std::vector<std::uint32_t> c(std::size_t(n.x) * std::size_t(n.y));
  glGetTextureImage(counts.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(c.size() * 4), c.data());
  return c;
}

}  // namespace

DeepLightMap::DeepLightMap()
    : march_(gl::Program::compute("dlm/march.comp")),
      march_peripheral_(gl::Program::compute("dlm/march.comp", {{"PERIPHERAL", "1"}})),
      scatter_(gl::Program::compute("dlm/scatter.comp")),
      scatter_runs_(gl::Program::compute("dlm/scatter_runs.comp")),
      uncompressed_(gl::Program::compute("dlm/march.comp", {{"UNCOMPRESSED", "1"}})),
      light_cache_bake_(gl::Program::compute("dlm/light_cache.comp")),
      light_space_block_(
          gl::UniformBuffer<gl::LightSpaceBlock>::create(lightSpaceBlock(light_space_), "light space block")) {}

void DeepLightMap::setBaseline(const DlmBaseline& baseline) {
  baseline_ = baseline;
  gl::Defines central, scatter, peripheral = {{"PERIPHERAL", "1"}};
  if (baseline.binary_search) scatter.emplace_back("DLM_LOOKUP_BINARY_SEARCH", "1");
  if (baseline.slice_breaks) peripheral.emplace_back("DLM_BASELINE_SLICE_BREAKS", "1");
  if (baseline.no_pruning) {
    for (gl::Defines* d : {&central, &scatter, &peripheral}) d->emplace_back("DLM_BASELINE_NO_PRUNING", "1");
  }
  march_ = gl::Program::compute("dlm/march.comp", central);
  scatter_ = gl::Program::compute("dlm/scatter.comp", scatter);
  march_peripheral_ = gl::Program::compute("dlm/march.comp", peripheral);
  key_.clear();
}

double DeepLightMap::timeUncompressedLightVolume(const VolumeTextures& volume, std::size_t& bytes) {
  const glm::ivec2 n = light_space_.texels;
  bytes = std::size_t(n.x) * std::size_t(n.y) * (std::size_t(steps_) + 1) * sizeof(float);
  auto buffer = gl::Buffer::create(bytes).label("uncompressed light volume");
  const gl::Program& p = uncompressed_;
  p.use();
  volume.bind();
  light_space_block_.bind();
  p.set("u_step_m", float(step_m_));
  p.set("u_steps", steps_);
  p.set("u_central_fraction", float(fractions_.central));
  p.set("u_optical_depth_scale", float(depth_scale_));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_LIGHT_VOLUME, buffer.id());
  glFinish();
  const auto t0 = std::chrono::steady_clock::now();
  p.dispatchCovering({n.x, n.y, 1});
  glFinish();
  const double ms = msSince(t0);
  gl::checkErrors("uncompressed light volume");
  return ms;
}

void DeepLightMap::bindForLookup() const {
  glBindTextureUnit(gl::binding::UNIT_DLM_NODES, nodes_.id());
  glBindTextureUnit(gl::binding::UNIT_DLM_COUNTS, counts_.id());
  if (light_cache_) glBindTextureUnit(gl::binding::UNIT_LIGHT_CACHE, light_cache_.id());
  light_space_block_.bind();
}

// The light cache (glsl/dlm/light_cache.comp): ⌈n / light_cache_voxels⌉ cells per axis of the
// extinction grid's n, at least 2 (GL_LINEAR then still interpolates across the box).
double DeepLightMap::bakeLightCache(const VolumeTextures& volume) {
  if (!(settings_.light_cache_voxels > 0.0)) {
    light_cache_ = gl::Texture();
    stats_.light_cache_texels = glm::ivec3(0);
    return 0.0;
  }
  const glm::ivec3 voxels = volume.frame().voxels;
  glm::ivec3 n;
  for (int a = 0; a < 3; ++a)
    n[a] = std::max(2, int(std::ceil(double(voxels[a]) / settings_.light_cache_voxels - 1e-9)));
  const auto t0 = std::chrono::steady_clock::now();
  if (light_cache_.width() != n.x || light_cache_.height() != n.y || light_cache_.depth() != n.z) {
    light_cache_ = gl::Texture::create3D(GL_R16F, n.x, n.y, n.z).label("light cache (DLM sunlight per world cell)");
    light_cache_.sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
  }
  light_cache_bake_.use();
  volume.bind();
  bindForLookup();
  light_cache_bake_.set("u_cache_texels", n);
  glBindImageTexture(gl::binding::IMAGE_LIGHT_CACHE, light_cache_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16F);
  light_cache_bake_.dispatchCovering(n);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  if (stats_read_back_) glFinish();  // timed only with the statistics (setStatsReadBack)
  stats_.light_cache_texels = n;
  gl::checkErrors("light cache bake");
  return stats_read_back_ ? msSince(t0) : 0.0;
}

std::size_t DeepLightMap::textureBytes() const {
  std::size_t b = 0;
  for (const gl::Texture* t : {&nodes_, &counts_, &texel_eps_, &scatter_map_, &scatter_runs_map_, &light_cache_})
    b += t->bytes();
  return b;
}

void DeepLightMap::march(const VolumeTextures& volume, const gl::Program& p, double epsilon, bool onlyOverflowed,
                         glm::ivec2 invocations, int retrySlot, GLintptr indirect) {
  p.use();
  volume.bind();
  light_space_block_.bind();
  p.set("u_step_m", float(step_m_));
  p.set("u_steps", steps_);
  p.set("u_central_fraction", float(fractions_.central));
  p.set("u_optical_depth_scale", float(depth_scale_));
  p.set("u_skip_empty", settings_.empty_space_skipping ? 1 : 0);
  p.set("u_only_overflowed", onlyOverflowed ? 1 : 0);
  p.set("u_step_growth", std::max(settings_.step_growth_max, 1));
  p.set("u_growth_budget", float(settings_.step_growth_budget * settings_.epsilon));
  p.set("u_max_nodes", settings_.max_nodes);
  p.set("u_epsilon", float(epsilon));
  glBindImageTexture(gl::binding::IMAGE_DLM_NODES, nodes_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RG32F);
  glBindImageTexture(gl::binding::IMAGE_DLM_COUNTS, counts_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
  glBindImageTexture(gl::binding::IMAGE_DLM_TEXEL_EPSILON, texel_eps_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_DLM_MARCH_STATS, march_stats_.id());
  const glm::ivec3 g = p.workGroupSize();
  p.set("u_retry_slot", retrySlot);
  p.set("u_retry_groups_x", (invocations.x + g.x - 1) / g.x);
  if (retrySlot >= 0 || indirect >= 0) {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, gl::binding::SSBO_DLM_RETRY_ARGS, retry_args_.id());
  }
  if (indirect >= 0) {
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, retry_args_.id());
    glDispatchComputeIndirect(indirect);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  } else {
    p.dispatchCovering({invocations.x, invocations.y, 1});
  }
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                  GL_BUFFER_UPDATE_BARRIER_BIT);
}

bool DeepLightMap::build(const VolumeTextures& volume, const glm::dvec3& lightDirection,
                         const lighting::DlmSettings& settings) {
  const glm::dvec3 dir = glm::normalize(lightDirection);
  // Height exaggeration keeps the data's optical depth: β along the light is scaled by f(light)
  // (volume::VolumeFrame::opticalDepthScale; docs/rendering.md "Conventions" 3).
  const double depthScale = volume.frame().opticalDepthScale(dir);
  const std::string key = fmt::format("{}|{:.12f},{:.12f},{:.12f}|{:.12f}|{}", volume.identity(), dir.x, dir.y, dir.z,
                                      depthScale, settings.key());
  if (key == key_) {
    ++stats_.reuses;
    stats_.rebuilt = false;
    return false;
  }
  if (stats_pending_) {  // the last build's, before this one clears its counts
    if (stats_read_back_ || !stats_fence_ ||
        glClientWaitSync(stats_fence_.get(), GL_SYNC_FLUSH_COMMANDS_BIT, 0) != GL_TIMEOUT_EXPIRED) {
      readStats();
    } else {
      log::debug("deep light map: the last build's statistics are not copied yet; not waiting for them");
      stats_pending_ = false;
    }
  }
  if (settings.max_nodes < 2) throw UsageError("DLM settings: max_nodes must be at least 2");
  if (settings.forward_peak_ice >= 0.0 || settings.forward_peak_water >= 0.0)
    throw UsageError("DLM settings: forward_peak_ice/water (a per-medium forward peak) exist in the CPU reference "
                     "(reference::DlmReference, `nephele-bench accuracy --decompose`) only, not in the GPU builder");
  depth_scale_ = depthScale;
  if (settings.scatter_slice_steps < 2 || settings.scatter_slice_steps % 2 != 0) {
    throw UsageError("DLM settings: scatter_slice_steps must be even and >= 2");
  }
  if (!(settings.epsilon >= 0.0)) throw UsageError("DLM settings: epsilon must be >= 0");
  gl::DebugGroup group("deep light map");
  settings_ = settings;
  fractions_ = lighting::forwardFractions(settings);

  // Light space fitted to the non-empty part of the volume.
  glm::dvec3 lo, hi;
  volume.nonEmptyBox(lo, hi);
  lighting::LightSpace basis;
  lighting::lightBasis(dir, basis.u, basis.v, basis.w);
  const glm::dvec3 voxel = volume.frame().voxel_size_m;
  light_space_ = lighting::fitLightSpace(dir, lo, hi, lighting::lightTexelSize(basis, voxel, settings.texel_voxels),
                                         settings.max_texels);
  light_space_block_.update(lightSpaceBlock(light_space_));
  step_m_ = settings.step_voxels * std::min({voxel.x, voxel.y, voxel.z});
  if (!(step_m_ > 0.0)) throw UsageError("DLM settings: step_voxels must be positive");
  // The bound is checked on the double, before the cast (dx = 1e-300 m made the step count
  // overflow int: undefined behaviour that the old check after the cast could not see).
  const double steps = std::ceil(light_space_.depth_m / step_m_ - 1e-9);
  constexpr double kMaxSteps = 1 << 22;
  if (!(steps <= kMaxSteps)) {
    throw UsageError(fmt::format("DLM: {} steps per ray is absurd (depth {} m, step {} m; at most {})", steps,
                                 light_space_.depth_m, step_m_, kMaxSteps));
  }
  steps_ = static_cast<int>(std::max(steps, 0.0));

  const glm::ivec2 n = light_space_.texels;
  if (nodes_.width() != n.x || nodes_.height() != n.y || nodes_.depth() != settings.max_nodes) {
    nodes_ = gl::Texture::create3D(GL_RG32F, n.x, n.y, settings.max_nodes).label("DLM nodes (depth, intensity)");
    nodes_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
    counts_ = gl::Texture::create2D(GL_R32UI, n.x, n.y).label("DLM node counts");
    counts_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
    texel_eps_ = gl::Texture::create2D(GL_R32F, n.x, n.y).label("DLM texel epsilon");
  }
  const std::uint32_t zero = 0;
  glClearTexImage(counts_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  const std::uint32_t noCounts[4] = {0, 0, 0, 0};
  if (march_stats_.size() == 0) march_stats_ = gl::Buffer::create(sizeof(noCounts)).label("DLM march counts");
  march_stats_.upload(0, sizeof(noCounts), noCounts);

  const int doublings = std::max(settings.max_epsilon_doublings, 0);
  auto runWithOverflowRule = [&](const gl::Program& program, glm::ivec2 invocations) {
    if (!stats_read_back_) {
      // Retry d's indirect arguments in slot d − 1: (0, groups y, 1) until a texel of the march
      // before it overflows and sets x (glsl/dlm/march.comp u_retry_args).
      const glm::ivec3 g = program.workGroupSize();
      const auto gy = std::uint32_t((invocations.y + g.y - 1) / g.y);
      std::vector<std::uint32_t> args;
      for (int d = 0; d < doublings; ++d) args.insert(args.end(), {0u, gy, 1u});
      if (args.empty()) args.assign(3, 0u);
      const std::size_t bytes = args.size() * sizeof(std::uint32_t);
      if (retry_args_.size() < bytes) retry_args_ = gl::Buffer::create(bytes).label("DLM overflow retries (indirect)");
      retry_args_.upload(0, bytes, args.data());
      march(volume, program, settings.epsilon, false, invocations, doublings > 0 ? 0 : -1);
      for (int d = 1; d <= doublings; ++d) {
        glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
        march(volume, program, settings.epsilon * std::ldexp(1.0, d), true, invocations, d < doublings ? d : -1,
              GLintptr(3 * sizeof(std::uint32_t) * std::size_t(d - 1)));
      }
      return;
    }
    march(volume, program, settings.epsilon, false, invocations);
    for (int d = 1; d <= doublings; ++d) {
      const auto counts = readCounts(counts_, n);
      ++stats_.build_read_backs;
      if (std::none_of(counts.begin(), counts.end(),
                       [](std::uint32_t c) { return (c & gl::binding::DLM_COUNT_UNBOUNDED) != 0; }))
        break;
      march(volume, program, settings.epsilon * std::ldexp(1.0, d), true, invocations);
    }
  };

  const bool peripheral = settings.peripheral && fractions_.peripheral > 0.0 && steps_ > 0;
  const int ds = std::max(1, settings.scatter_downsample);
  const glm::ivec2 scatterCells = (n + ds - 1) / ds;
  // With a scatter map, pass 1's map is read by pass 2 alone, at its cell centres: pass 1 marches
  // only those texels, compacted (glsl/dlm/march.comp passOneTexel; pass 3 rebuilds every texel).
  PassOneAxis axis[2] = {{0, 1, n.x}, {0, 1, n.y}};
  if (peripheral && !baseline_.no_pruning) {
    axis[0] = passOneAxis(n.x, scatterCells.x);
    axis[1] = passOneAxis(n.y, scatterCells.y);
    if (axis[0].cells == 0 || axis[1].cells == 0) {  // cells under 2 texels wide: every texel is read
      axis[0] = {0, 1, n.x};
      axis[1] = {0, 1, n.y};
    }
  }
  const glm::ivec2 pass1Invocations =
      axis[0].cells > 0 ? glm::ivec2(axis[0].cells * axis[0].slots, axis[1].cells * axis[1].slots) : n;
  march_.set("u_pass1_cells", glm::ivec2(axis[0].cells, axis[1].cells));
  march_.set("u_pass1_slots", glm::ivec2(axis[0].slots, axis[1].slots));
  stats_.pass1_texels = std::int64_t(axis[0].texels) * axis[1].texels;
  // Each pass timed with glFinish only with the statistics read back (setStatsReadBack).
  const bool timed = stats_read_back_;
  auto finish = [timed] {
    if (timed) glFinish();
  };
  finish();  // the pass times below are the passes' own, not the uploads queued before them
  auto t0 = std::chrono::steady_clock::now();
  std::clock_t c0 = std::clock();
  runWithOverflowRule(march_, pass1Invocations);
  finish();
  const double pass1 = timed ? msSince(t0) : 0.0;
  double cpu[3] = {cpuMsSince(c0), 0.0, 0.0};

  double pass2 = 0.0, pass3 = 0.0;
  stats_.scatter_cells = glm::ivec3(0);
  if (peripheral) {
    t0 = std::chrono::steady_clock::now();
    c0 = std::clock();
    // The slices must fit GL_MAX_3D_TEXTURE_SIZE (2048 on llvmpipe): lengthen them (keeping the
    // step count per slice even) when a long ray at a fine step would need more. The effective
    // value is in settings().scatter_slice_steps.
    GLint max3D = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3D);
    int sliceSteps = lighting::scatterSliceSteps(settings, light_space_, step_m_);
    while ((steps_ + sliceSteps - 1) / sliceSteps + 1 > max3D) sliceSteps += 2;
    settings_.scatter_slice_steps = sliceSteps;
    const glm::ivec3 cells(scatterCells, (steps_ + sliceSteps - 1) / sliceSteps + 1);
    stats_.scatter_cells = cells;
    if (scatter_map_.width() != cells.x || scatter_map_.height() != cells.y || scatter_map_.depth() != cells.z) {
      scatter_map_ = gl::Texture::create3D(GL_R32F, cells.x, cells.y, cells.z).label("DLM scatter map");
      scatter_map_.sampling(GL_LINEAR, GL_CLAMP_TO_EDGE);
    }
    const float zerof = 0.0f;
    glClearTexImage(scatter_map_.id(), 0, GL_RED, GL_FLOAT, &zerof);
    const double sliceM = step_m_ * sliceSteps;
    scatter_.use();
    volume.bind();
    bindForLookup();
    scatter_.set("u_cells", glm::ivec2(cells));
    scatter_.set("u_slice_m", float(sliceM));
    scatter_.set("u_slice_samples", lighting::scatterSliceSamples(sliceSteps));
    scatter_.set("u_central_fraction", float(fractions_.central));
    scatter_.set("u_peripheral_fraction", float(fractions_.peripheral));
    scatter_.set("u_optical_depth_scale", float(depth_scale_));
    glBindImageTexture(gl::binding::IMAGE_SCATTER_MAP, scatter_map_.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32F);
    for (int k = 1; k < cells.z; ++k) {
      scatter_.set("u_slice", k);
      scatter_.dispatchCovering({cells.x, cells.y, 1});
      glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    if (!baseline_.slice_breaks) {
      // The flat runs of P per cell column (glsl/dlm/scatter_runs.comp), for pass 3's skipping.
      if (scatter_runs_map_.width() != cells.x || scatter_runs_map_.height() != cells.y ||
          scatter_runs_map_.depth() != cells.z) {
        // Slice indices ≤ cells.z ≤ GL_MAX_3D_TEXTURE_SIZE (2048 on llvmpipe, 16384 at most on
        // GPUs): 16 bits hold them exactly, half the bytes of this transient map (issue 19, memory).
        if (cells.z > 32767) throw UsageError(fmt::format("DLM: {} scatter slices exceed 16 bits", cells.z));
        scatter_runs_map_ = gl::Texture::create3D(GL_R16I, cells.x, cells.y, cells.z).label("DLM scatter flat runs");
        scatter_runs_map_.sampling(GL_NEAREST, GL_CLAMP_TO_EDGE);
      }
      scatter_runs_.use();
      scatter_runs_.set("u_cells", cells);
      glBindImageTexture(gl::binding::IMAGE_SCATTER_MAP, scatter_map_.id(), 0, GL_TRUE, 0, GL_READ_ONLY, GL_R32F);
      glBindImageTexture(gl::binding::IMAGE_SCATTER_RUNS, scatter_runs_map_.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY,
                         GL_R16I);
      scatter_runs_.dispatchCovering({cells.x, cells.y, 1});
      glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    finish();
    pass2 = timed ? msSince(t0) : 0.0;
    cpu[1] = cpuMsSince(c0);

    t0 = std::chrono::steady_clock::now();
    c0 = std::clock();
    march_peripheral_.use();
    glBindTextureUnit(gl::binding::UNIT_SCATTER_MAP, scatter_map_.id());
    if (!baseline_.slice_breaks) glBindTextureUnit(gl::binding::UNIT_SCATTER_RUNS, scatter_runs_map_.id());
    march_peripheral_.set("u_scatter_slice_m", float(sliceM));
    march_peripheral_.set("u_scatter_slices", cells.z);
    march_peripheral_.set("u_slice_steps", sliceSteps);
    glClearTexImage(counts_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    runWithOverflowRule(march_peripheral_, n);
    finish();
    pass3 = timed ? msSince(t0) : 0.0;
    cpu[2] = cpuMsSince(c0);
    // Passes 2 and 3 are the scatter map's only readers: the look-up (glsl/dlm/lookup.glsl), the
    // light-cache bake and the eye pass read the nodes alone. Freed here rather than held through
    // the frame (issue 19, memory; textureBytes() drops by their size); the next build allocates
    // them again, which costs little beside the passes that fill them.
    scatter_map_ = gl::Texture();
    scatter_runs_map_ = gl::Texture();
  }
  const double bake = bakeLightCache(volume);
  gl::checkErrors("deep light map build");
  key_ = key;
  ++stats_.builds;
  stats_.rebuilt = true;
  stats_.timed = timed;
  stats_.pass1_ms = pass1;
  stats_.pass2_ms = pass2;
  stats_.pass3_ms = pass3;
  stats_.light_cache_ms = bake;
  stats_pending_ = true;
  if (!stats_read_back_) {  // summarised when asked for (stats()) or before the next build
    queueStatsCopy();
    return true;
  }
  readStats();
  stats_.build_read_backs += 3;  // the counts, ε and march counters, inside the build
  log::debug(
      "DLM built: {}x{} texels ({} in pass 1), {} steps of {:.1f} m, scatter map {}x{}x{}, mean {:.2f} nodes, {} "
      "unbounded, {:.1f}+{:.1f}+{:.1f} ms (CPU {:.0f}+{:.0f}+{:.0f} ms), light cache {:.1f} ms; {} steps marched, {} "
      "in {} runs",
      n.x, n.y, stats_.pass1_texels, steps_, step_m_, stats_.scatter_cells.x, stats_.scatter_cells.y,
      stats_.scatter_cells.z, stats_.mean_nodes, stats_.unbounded_texels, pass1, pass2, pass3, cpu[0], cpu[1], cpu[2],
      bake, stats_.marched_steps, stats_.run_steps, stats_.runs);
  return true;
}

const DlmStats& DeepLightMap::stats() const {
  if (stats_pending_) readStats();
  return stats_;
}

void DeepLightMap::SyncDeleter::operator()(GLsync s) const { glDeleteSync(s); }

void DeepLightMap::queueStatsCopy() {
  const glm::ivec2 n = light_space_.texels;
  const std::size_t texels = std::size_t(n.x) * std::size_t(n.y), plane = texels * 4, bytes = 2 * plane + 16;
  if (stats_pack_.size() < bytes) {
    stats_pack_ = gl::Buffer::create(bytes, nullptr, GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT).label("DLM statistics");
  }
  GLint previous = 0;
  glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &previous);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, stats_pack_.id());
  glGetTextureImage(counts_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(plane), nullptr);
  glGetTextureImage(texel_eps_.id(), 0, GL_RED, GL_FLOAT, GLsizei(plane), reinterpret_cast<void*>(plane));
  glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(previous));
  glCopyNamedBufferSubData(march_stats_.id(), stats_pack_.id(), 0, GLintptr(2 * plane), 16);
  stats_fence_.reset(glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0));
}

void DeepLightMap::readStats() const {
  stats_pending_ = false;
  const glm::ivec2 n = light_space_.texels;
  const std::size_t texels = std::size_t(n.x) * std::size_t(n.y);
  if (!stats_read_back_ && stats_fence_) {  // the build's asynchronous copies (queueStatsCopy)
    // Waits only for those copies (usually long done); no deadline: the GPU finishes them.
    while (glClientWaitSync(stats_fence_.get(), GL_SYNC_FLUSH_COMMANDS_BIT, 1000000000) == GL_TIMEOUT_EXPIRED) {
    }
    const std::size_t plane = texels * 4;
    const auto* mapped = static_cast<const std::uint8_t*>(
        glMapNamedBufferRange(stats_pack_.id(), 0, GLsizeiptr(2 * plane + 16), GL_MAP_READ_BIT));
    if (!mapped) throw GlError("deep light map statistics: the buffer could not be mapped");
    std::vector<std::uint32_t> counts(texels), march(4);
    std::vector<float> eps(texels);
    std::memcpy(counts.data(), mapped, plane);
    std::memcpy(eps.data(), mapped + plane, plane);
    std::memcpy(march.data(), mapped + 2 * plane, 16);
    glUnmapNamedBuffer(stats_pack_.id());
    summariseStats(counts.data(), eps.data(), march.data());
    return;
  }
  const auto counts = readCounts(counts_, n);
  std::vector<float> eps(counts.size());
  glGetTextureImage(texel_eps_.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(eps.size() * 4), eps.data());
  std::uint32_t march[4] = {0, 0, 0, 0};
  march_stats_.download(0, sizeof(march), march);
  summariseStats(counts.data(), eps.data(), march);
}

void DeepLightMap::summariseStats(const std::uint32_t* counts, const float* eps, const std::uint32_t* march) const {
  const glm::ivec2 n = light_space_.texels;
  const std::size_t texels = std::size_t(n.x) * std::size_t(n.y);
  stats_.texels = n;
  stats_.steps = steps_;
  stats_.step_m = step_m_;
  stats_.node_histogram.assign(std::size_t(settings_.max_nodes) + 1, 0);
  stats_.texels_per_epsilon_doubling.assign(std::size_t(settings_.max_epsilon_doublings) + 1, 0);
  stats_.unbounded_texels = 0;
  stats_.overflowed_texels = 0;
  stats_.max_nodes_used = 0;
  double total = 0.0;
  for (std::size_t i = 0; i < texels; ++i) {
    const int c = int(counts[i] & gl::binding::DLM_COUNT_MASK);
    total += c;
    stats_.max_nodes_used = std::max(stats_.max_nodes_used, c);
    stats_.node_histogram[std::size_t(std::min(c, settings_.max_nodes))]++;
    if (counts[i] & gl::binding::DLM_COUNT_UNBOUNDED) ++stats_.unbounded_texels;
    const double ratio = settings_.epsilon > 0.0 ? double(eps[i]) / settings_.epsilon : 1.0;
    const int d = ratio > 1.0 ? int(std::lround(std::log2(ratio))) : 0;
    if (d > 0) ++stats_.overflowed_texels;
    stats_.texels_per_epsilon_doubling[std::size_t(std::clamp(d, 0, settings_.max_epsilon_doublings))]++;
  }
  if (stats_.unbounded_texels > 0 && stats_.overflowed_texels < stats_.unbounded_texels) {
    stats_.overflowed_texels = stats_.unbounded_texels;
  }
  stats_.mean_nodes = texels == 0 ? 0.0 : total / double(texels);
  stats_.bytes = std::size_t(n.x) * std::size_t(n.y) * (std::size_t(settings_.max_nodes) * 8 + 4 + 4);
  const double uncompressed = double(n.x) * double(n.y) * double(steps_ + 1) * 4.0;
  stats_.compression_ratio = total > 0.0 ? uncompressed / (total * 8.0) : 0.0;
  if (stats_.unbounded_texels > 0) {
    log::warn("DLM: {} texels exceed the node budget ({}) even at eps x{}; their error bound is not kept",
              stats_.unbounded_texels, settings_.max_nodes, 1 << settings_.max_epsilon_doublings);
  }
  stats_.marched_steps = march[0];
  stats_.run_steps = march[1];
  stats_.runs = march[2];
  stats_.cut_short = march[3];
  if (stats_.cut_short > 0) {
    log::warn("deep light map: {} texels' marches were cut short by the GL driver's loop limit (Mesa llvmpipe ends a "
              "shader's loops after 65 535 iterations): their light beyond the cut is missing; raise quality "
              "dlm_step_voxels or render on a GPU (docs/rendering.md \"llvmpipe's loop limit\")",
              stats_.cut_short);
  }
}

DeepLightMap::Readback DeepLightMap::readBack() const {
  const glm::ivec2 n = light_space_.texels;
  const int m = settings_.max_nodes;
  std::vector<glm::vec2> raw(std::size_t(n.x) * std::size_t(n.y) * std::size_t(m));
  glGetTextureImage(nodes_.id(), 0, GL_RG, GL_FLOAT, static_cast<GLsizei>(raw.size() * sizeof(glm::vec2)), raw.data());
  const auto counts = readCounts(counts_, n);
  Readback r;
  r.texel_epsilon.resize(counts.size());
  glGetTextureImage(texel_eps_.id(), 0, GL_RED, GL_FLOAT, static_cast<GLsizei>(counts.size() * 4),
                    r.texel_epsilon.data());
  r.nodes.resize(counts.size());
  r.unbounded.resize(counts.size());
  for (std::size_t t = 0; t < counts.size(); ++t) {
    const int c = int(counts[t] & gl::binding::DLM_COUNT_MASK);
    r.unbounded[t] = (counts[t] & gl::binding::DLM_COUNT_UNBOUNDED) != 0;
    for (int k = 0; k < c; ++k) {
      const glm::vec2 node = raw[(std::size_t(k) * std::size_t(n.y)) * std::size_t(n.x) + t];
      r.nodes[t].push_back({node.x, node.y});
    }
  }
  return r;
}

double DeepLightMap::lookup(const Readback& map, const lighting::LightSpace& ls, const glm::dvec3& world_m) {
  return lighting::blendTexels(ls, ls.lightFromWorld(world_m), [&](int a, int b, double z) {
    const auto& nodes = map.nodes[std::size_t(b) * std::size_t(ls.texels.x) + std::size_t(a)];
    return lighting::evaluateLightFunction(nodes.data(), int(nodes.size()), z);
  });
}

}  // namespace nph::render
