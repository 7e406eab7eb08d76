#pragma once
// Deep light map builder (Nes 2008 §5.3; model and discretisation in lighting/dlm_model.h):
//   pass 1  glsl/dlm/march.comp     central light per texel, ε-compressed node lists; with a
//           scatter map only at the texels pass 2 reads (issue 19: ¼ of them at 4 × 4 per cell)
//   pass 2  glsl/dlm/scatter.comp   low-resolution light-aligned scatter map, slice by slice
//           (clear cells keep P without looking their neighbours up)
//   pass 3  march.comp + PERIPHERAL re-march adding the peripheral light, re-compressed within ε;
//           it skips empty bricks across the scatter map's flat runs (glsl/dlm/scatter_runs.comp,
//           issue 19) instead of stopping at every slice centre
// Storage: nodes in an RG32F 3-D texture (nu × nv × max_nodes; layer k = node k: depth [m] from
// the ray's entry, intensity), node counts in an R32UI 2-D texture, the ε each texel was built
// with in an R32F 2-D texture.
//
// Node budget overflow rule (never silent): a texel that needs more than max_nodes nodes is
// rebuilt with ε doubled, up to max_epsilon_doublings times; its ε is stored per texel and the
// stats give the count per ε. A texel that still overflows keeps its first max_nodes − 1 nodes
// plus the ray's final sample: its bound is not kept, it is flagged (DLM_COUNT_UNBOUNDED in the
// count, render/gl/bindings.h) and counted in stats.unbounded_texels.
//
// Cache key: volume identity + sun direction + settings; build() returns false and does nothing
// when the key is unchanged (an unchanged DLM is never rebuilt).
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "lighting/dlm_model.h"
#include "lighting/light_function.h"
#include "lighting/light_space.h"
#include "render/dlm/volume_textures.h"
#include "render/gl/objects.h"
#include "render/gl/program.h"
#include "render/gl/uniform_blocks.h"

namespace nph::render {

struct DlmStats {
  glm::ivec2 texels{0};
  int steps = 0;  ///< samples per ray N
  double step_m = 0.0;
  double mean_nodes = 0.0;
  int max_nodes_used = 0;
  std::vector<int> node_histogram;  ///< [k] = texels with k nodes (k = 0 … max_nodes)
  std::size_t bytes = 0;            ///< GPU memory of nodes + counts + ε
  double compression_ratio = 0.0;   ///< uncompressed light volume (nu·nv·(N+1) floats) / bytes of used nodes
  int overflowed_texels = 0;        ///< needed more than max_nodes at the requested ε
  std::vector<int> texels_per_epsilon_doubling;  ///< [d] = texels built with ε·2^d
  int unbounded_texels = 0;                      ///< still overflowing after all doublings
  glm::ivec3 scatter_cells{0};
  double pass1_ms = 0.0, pass2_ms = 0.0, pass3_ms = 0.0;  ///< wall time incl. glFinish
  std::int64_t pass1_texels = 0;  ///< texels pass 1 marched (only those pass 2 reads when there is a scatter map)
  /// The march of passes 1 and 3 (with overflow retries): fine steps Δ outside the empty-space
  /// skip, those of them taken in runs of the adaptive step (DlmSettings::step_growth_max), runs.
  std::int64_t marched_steps = 0, run_steps = 0, runs = 0;
  /// Texels (passes 1 and 3, counted per march) whose march the driver's loop limiter ended
  /// before the far side (llvmpipe; docs/rendering.md "llvmpipe's loop limit"). 0 on a GPU.
  std::int64_t cut_short = 0;
  glm::ivec3 light_cache_texels{0};  ///< the light cache's size (0 without one; DlmSettings::light_cache_voxels)
  double light_cache_ms = 0.0;       ///< its bake, wall time incl. glFinish
  /// Whether the pass and bake times above were measured (glFinish after each; only with the
  /// statistics read back, DeepLightMap::setStatsReadBack). 0 ms when not.
  bool timed = false;
  /// Synchronous GPU → CPU read-backs made inside build() so far, each a wait for the GPU (the
  /// overflow rule's counts, the statistics): 0 without the statistics read back.
  std::uint64_t build_read_backs = 0;
  bool rebuilt = false;
  std::uint64_t builds = 0, reuses = 0;
};

/// Baselines for benchmarks and tests (issue 19), not user settings: the build as it was before
/// its speed-ups (tests/bench/frame_benchmark.cpp measures against them).
struct DlmBaseline {
  bool binary_search = false;  ///< pass 2's DLM look-up by binary search (glsl/dlm/lookup.glsl)
  bool slice_breaks = false;   ///< pass 3 stops at every scatter-slice centre in empty space
  /// The passes without issue 19's pruning ("nothing computed that a scene does not need"): pass 1
  /// marches every texel, not only those pass 2 reads; pass 2 looks up the neighbours of clear
  /// cells too; passes 1 and 3 evaluate the empty-space skip under a lane mask at every step.
  /// The same map bit for bit.
  bool no_pruning = false;
};

class DeepLightMap {
 public:
  DeepLightMap();

  /// Builds the map for `volume` lit along `lightDirection` (the direction sunlight travels,
  /// i.e. −Sun::toSun()). Returns false when the cache key is unchanged and nothing was done.
  bool build(const VolumeTextures& volume, const glm::dvec3& lightDirection, const lighting::DlmSettings& settings);

  const lighting::LightSpace& lightSpace() const { return light_space_; }
  /// The last build's statistics. Without the statistics read back (setStatsReadBack(false)) the
  /// build queues asynchronous copies of its counts into a buffer and a fence; they are summarised
  /// here, the first time they are asked for (waiting for the fence if the GPU is still busy), and
  /// logged as the build would have (the node budget and loop-limit warnings). The next build
  /// summarises them first if nobody asked and the fence has passed — no wait — so a warning is
  /// lost only when the GPU is still a whole build behind, or after the last build of a session.
  /// It may read GL (a pending build's copies): call it with the map's context current.
  const DlmStats& stats() const;
  /// Statistics read back inside every build (the default: the overflow rule's retries decided
  /// from the counts on the CPU, each pass timed with glFinish, the counts and ε summarised), or
  /// not (issue 19 item 2, "stats read-back optional in the per-frame path": engine::Session for
  /// `nephele view` and the plugin API unless NEPHELE_LOG=debug). Without, build() never waits for
  /// the GPU: the retries are dispatched indirectly (glDispatchComputeIndirect) with group counts
  /// the march itself sets when a texel overflows (glsl/dlm/march.comp u_retry_args), so a retry
  /// nothing needs costs no group; no pass is timed (DlmStats::timed). The map is the same bit for
  /// bit (DeepLightMapTest.WithoutStatsReadBackTheMapIsTheSame).
  void setStatsReadBack(bool on) { stats_read_back_ = on; }
  /// Builds and reuses so far (DlmStats::builds, reuses) without reading anything back.
  std::uint64_t builds() const { return stats_.builds; }
  std::uint64_t reuses() const { return stats_.reuses; }
  bool statsReadBack() const { return stats_read_back_; }
  /// The settings of the last build as applied (scatter_slice_steps may have been lengthened to
  /// fit GL_MAX_3D_TEXTURE_SIZE) — pass these to the CPU reference.
  const lighting::DlmSettings& settings() const { return settings_; }
  const std::string& cacheKey() const { return key_; }

  /// Binds the node and count textures (UNIT_DLM_NODES, UNIT_DLM_COUNTS), the LightSpaceBlock
  /// of glsl/dlm/light_space.glsl (UBO_LIGHT_SPACE) and the light cache if there is one
  /// (UNIT_LIGHT_CACHE), for any program that includes glsl/dlm/lookup.glsl.
  void bindForLookup() const;

  /// The light cache of the last build (DlmSettings::light_cache_voxels > 0; glsl/dlm/
  /// light_cache.comp): R16F over the volume's box, GL_LINEAR, GL_CLAMP_TO_EDGE. Empty without one.
  const gl::Texture& lightCache() const { return light_cache_; }
  bool hasLightCache() const { return bool(light_cache_); }
  /// Bytes of the map's GL textures held between builds (nodes, counts, ε, light cache;
  /// gl::Texture::bytes; the scatter map and its runs are freed at the end of build()): issue 19's
  /// memory accounting.
  std::size_t textureBytes() const;

  /// Benchmark/test baseline (DlmBaseline): recompiles passes 2 and 3; the next build() rebuilds.
  void setBaseline(const DlmBaseline& baseline);

  /// Benchmark baseline for pass 1: the same march over the last build's light space storing every
  /// sample uncompressed (no skipping, no compression) in a buffer. Returns wall ms incl. glFinish;
  /// `bytes` receives the size of that light volume.
  double timeUncompressedLightVolume(const VolumeTextures& volume, std::size_t& bytes);

  /// Reads the whole map back (tests, CPU comparisons): node lists per texel (a + b·nu).
  struct Readback {
    std::vector<std::vector<lighting::LightNode>> nodes;
    std::vector<float> texel_epsilon;
    std::vector<bool> unbounded;
  };
  Readback readBack() const;
  /// The GPU look-up (glsl/dlm/lookup.glsl) on the CPU, on a read-back map: bilinear across
  /// texels, 1 outside the footprint, constant past the ends of each node list.
  static double lookup(const Readback& map, const lighting::LightSpace& lightSpace, const glm::dvec3& world_m);

 private:
  /// One march dispatch over `invocations` (the texels, or pass 1's compacted texels).
  /// `retrySlot` ≥ 0: an overflowing texel sets that slot of retry_args_ (march.comp u_retry_args);
  /// `indirect` ≥ 0: dispatched with glDispatchComputeIndirect from that byte offset of retry_args_.
  void march(const VolumeTextures& volume, const gl::Program& program, double epsilon, bool onlyOverflowed,
             glm::ivec2 invocations, int retrySlot = -1, GLintptr indirect = -1);
  /// Reads the counts, ε and march counters of the last build into stats_ and logs its warnings:
  /// from the textures (with the statistics read back) or from stats_pack_ once its fence says the
  /// copies are done (without).
  void readStats() const;
  /// Without the statistics read back: queues copies of the counts, ε and march counters into
  /// stats_pack_ (asynchronous: a pixel-pack buffer and a buffer copy) and a fence after them.
  void queueStatsCopy();
  /// Summarises counts and ε of the last build's texels and its march counters into stats_.
  void summariseStats(const std::uint32_t* counts, const float* eps, const std::uint32_t* march) const;
  double bakeLightCache(const VolumeTextures& volume);

  gl::Program march_, march_peripheral_, scatter_, scatter_runs_, uncompressed_, light_cache_bake_;
  gl::Texture nodes_, counts_, texel_eps_, scatter_map_, scatter_runs_map_, light_cache_;
  gl::Buffer march_stats_;  ///< SSBO_DLM_MARCH_STATS: 4 uint counters (DlmStats::marched_steps …)
  gl::Buffer retry_args_;   ///< SSBO_DLM_RETRY_ARGS: indirect dispatch arguments of the retries
  gl::Buffer stats_pack_;   ///< the statistics copied asynchronously (setStatsReadBack(false))
  struct SyncDeleter {
    void operator()(GLsync s) const;
  };
  std::unique_ptr<std::remove_pointer_t<GLsync>, SyncDeleter> stats_fence_;  ///< after the copies
  bool stats_read_back_ = true;
  mutable bool stats_pending_ = false;  ///< a build whose statistics were not read yet
  DlmBaseline baseline_;
  lighting::LightSpace light_space_;
  gl::UniformBuffer<gl::LightSpaceBlock> light_space_block_;  // light_space_ for the GLSL passes
  lighting::DlmSettings settings_;
  lighting::ForwardFractions fractions_;
  double step_m_ = 0.0;
  double depth_scale_ = 1.0;  ///< β scale along the light (VolumeFrame::opticalDepthScale)
  int steps_ = 0;
  std::string key_;
  mutable DlmStats stats_;  // mutable: stats() reads a pending build's counts (setStatsReadBack)
};

}  // namespace nph::render
