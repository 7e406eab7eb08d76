// The C entry points of nephele/nephele.h: argument, handle, thread and context checks, then the
// C++ objects (Renderer, engine::Dataset). Every entry point is noexcept and goes through
// guarded(), which turns exceptions into status codes and per-handle messages.
#include <cmath>
#include <cstddef>
#include <cstring>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "api/handles.h"
#include "api/renderer.h"
#include "engine/dataset.h"
#include "render/gl/gl.h"
#include "scene/passes.h"

namespace nph::api {
namespace {

struct DatasetObject {
  std::shared_ptr<const engine::Dataset> dataset;
};

struct RendererObject {
  std::thread::id owner;
  nph_get_proc_address_fn get_proc = nullptr;
  std::unique_ptr<Renderer> renderer;
};

// ---- GL entry points ----------------------------------------------------------------------
// nephele's GL entry points are one process-wide table (render/gl/gl.h). Calls that touch GL hold
// this mutex and (re)load the table from the renderer's GetProcAddress when another one loaded it
// last, so renderers in contexts of different libraries (EGL, GLX, OSMesa) may coexist; GL work of
// several renderers on several threads is serialised.
std::mutex& glMutex() {
  static std::mutex m;
  return m;
}
nph_get_proc_address_fn g_loaded_from = nullptr;  // guarded by glMutex
nph_get_proc_address_fn g_loading = nullptr;      // the one being loaded (for the trampoline)

void* trampoline(const char* name) { return reinterpret_cast<void*>(g_loading(name)); }

void loadEntryPoints(nph_get_proc_address_fn get_proc) {
  if (g_loaded_from == get_proc) return;
  g_loaded_from = nullptr;
  g_loading = get_proc;
  gl::loadGlFunctions(&trampoline, "host context");
  g_loaded_from = get_proc;
}

bool contextCurrent() { return glGetString(GL_VERSION) != nullptr; }

/// The renderer of `handle`, checked for thread; with `gl`, also for its context being current
/// (the caller holds glMutex then).
RendererObject& rendererOf(const void* handle, std::shared_ptr<RendererObject>& keep, bool gl) {
  keep = require<RendererObject>(handle, Kind::Renderer, "renderer");
  if (keep->owner != std::this_thread::get_id()) {
    throw ApiError(NPH_ERROR_WRONG_THREAD, "called from a thread other than the one that created the renderer");
  }
  if (gl) {
    loadEntryPoints(keep->get_proc);
    if (glIsVertexArray(keep->renderer->contextProbe()) == GL_FALSE) {
      throw ApiError(NPH_ERROR_WRONG_CONTEXT, contextCurrent() ? "the current GL context is not the renderer's"
                                                               : "no GL context is current on this thread");
    }
  }
  return *keep;
}

template <class T>
void requireArg(const T* p, const char* name) {
  if (p == nullptr) throw ApiError(NPH_ERROR_INVALID_ARGUMENT, std::string(name) + " is NULL");
}

std::string stringArg(const char* s, const char* name) {
  requireArg(s, name);
  return s;
}

// ---- entry points ---------------------------------------------------------------------------

const char* libraryVersion() { return NEPHELE_VERSION_STRING; }

const char* statusName(nph_status s) {
  switch (s) {
    case NPH_OK: return "NPH_OK";
    case NPH_ERROR_INVALID_HANDLE: return "NPH_ERROR_INVALID_HANDLE";
    case NPH_ERROR_INVALID_ARGUMENT: return "NPH_ERROR_INVALID_ARGUMENT";
    case NPH_ERROR_WRONG_THREAD: return "NPH_ERROR_WRONG_THREAD";
    case NPH_ERROR_WRONG_CONTEXT: return "NPH_ERROR_WRONG_CONTEXT";
    case NPH_ERROR_WRONG_ORDER: return "NPH_ERROR_WRONG_ORDER";
    case NPH_ERROR_INPUT: return "NPH_ERROR_INPUT";
    case NPH_ERROR_GL: return "NPH_ERROR_GL";
    case NPH_ERROR_OUT_OF_MEMORY: return "NPH_ERROR_OUT_OF_MEMORY";
    case NPH_ERROR_INTERNAL: return "NPH_ERROR_INTERNAL";
    default: return "NPH_UNKNOWN_STATUS";
  }
}

const char* lastErrorOf(const void* handle) {
  try {
    return lastError(handle);
  } catch (...) {
    return "";
  }
}

nph_status datasetOpen(const char* path, nph_dataset** out) {
  return guarded(nullptr, "dataset_open", [&] {
    requireArg(out, "out");
    *out = nullptr;
    const std::string p = stringArg(path, "path");
    auto object = std::make_shared<DatasetObject>();
    object->dataset = engine::Dataset::open(p);
    if (object->dataset->timestepCount() == 0) throw ApiError(NPH_ERROR_INPUT, p + ": no timesteps");
    *out = static_cast<nph_dataset*>(const_cast<void*>(registerHandle(Kind::Dataset, std::move(object))));
  });
}

nph_status datasetClose(nph_dataset* dataset) {
  return guarded(dataset, "dataset_close", [&] {
    if (!unregisterHandle(dataset, Kind::Dataset)) require<DatasetObject>(dataset, Kind::Dataset, "dataset");
  });
}

nph_status datasetTimestepCount(const nph_dataset* dataset, int32_t* count) {
  return guarded(dataset, "dataset_timestep_count", [&] {
    const auto d = require<DatasetObject>(dataset, Kind::Dataset, "dataset");
    requireArg(count, "count");
    *count = int32_t(d->dataset->timestepCount());
  });
}

nph_status datasetTimestepUtc(const nph_dataset* dataset, int32_t index, const char** time_utc) {
  return guarded(dataset, "dataset_timestep_utc", [&] {
    const auto d = require<DatasetObject>(dataset, Kind::Dataset, "dataset");
    requireArg(time_utc, "time_utc");
    const auto n = d->dataset->timestepCount();
    if (index < 0 || std::size_t(index) >= n) {
      throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("timestep {} out of range 0..{}", index, n - 1));
    }
    *time_utc = d->dataset->isoTime(std::size_t(index)).c_str();
  });
}

nph_status rendererCreate(nph_dataset* dataset, const nph_renderer_desc* desc, nph_renderer** out) {
  return guarded(dataset, "renderer_create", [&] {
    requireArg(out, "out");
    *out = nullptr;
    const auto d = require<DatasetObject>(dataset, Kind::Dataset, "dataset");
    requireArg(desc, "desc");
    if (desc->struct_size < sizeof(nph_renderer_desc)) {
      throw ApiError(NPH_ERROR_INVALID_ARGUMENT,
                     fmt::format("desc->struct_size {} < {}: initialise with NPH_RENDERER_DESC_INIT", desc->struct_size,
                                 sizeof(nph_renderer_desc)));
    }
    if (desc->get_proc_address == nullptr) throw ApiError(NPH_ERROR_INVALID_ARGUMENT, "desc->get_proc_address is NULL");
    RendererOptions o;
    if (desc->quality_preset != nullptr) o.quality_preset = desc->quality_preset;
    o.time_index = desc->time_index;
    o.height_exaggeration = desc->height_exaggeration == 0.0 ? 1.0 : desc->height_exaggeration;
    auto object = std::make_shared<RendererObject>();
    object->owner = std::this_thread::get_id();
    object->get_proc = desc->get_proc_address;
    std::lock_guard lock(glMutex());
    loadEntryPoints(object->get_proc);
    if (!contextCurrent()) throw ApiError(NPH_ERROR_WRONG_CONTEXT, "no GL context is current on this thread");
    GLint major = 0, minor = 0;  // core or compatibility profile: both have what nephele uses
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 45) {
      throw ApiError(NPH_ERROR_GL, fmt::format("the current context is OpenGL {}.{} ({}); nephele needs 4.5", major,
                                               minor, reinterpret_cast<const char*>(glGetString(GL_VERSION))));
    }
    object->renderer = std::make_unique<Renderer>(d->dataset, o);
    *out = static_cast<nph_renderer*>(const_cast<void*>(registerHandle(Kind::Renderer, std::move(object))));
  });
}

nph_status rendererDestroy(nph_renderer* renderer) {
  return guarded(renderer, "renderer_destroy", [&] {
    std::shared_ptr<RendererObject> keep;
    std::lock_guard lock(glMutex());
    try {
      rendererOf(renderer, keep, /*gl=*/true);
    } catch (const ApiError& e) {
      // The host may destroy its context first: with none current, GL names died with it and
      // the GL calls of the destructors are no-ops. Another context current: refuse.
      if (e.status() != NPH_ERROR_WRONG_CONTEXT || contextCurrent()) throw;
    }
    unregisterHandle(renderer, Kind::Renderer);
    keep->renderer.reset();
  });
}

/// Runs `f(Renderer&)` on a checked renderer handle inside guarded(); with `gl`, holding glMutex
/// with the renderer's context checked.
template <class F>
nph_status onRenderer(const void* handle, const char* call, bool gl, F&& f) {
  return guarded(handle, call, [&] {
    std::shared_ptr<RendererObject> keep;
    std::unique_lock lock(glMutex(), std::defer_lock);
    if (gl) lock.lock();
    f(*rendererOf(handle, keep, gl).renderer);
  });
}

/// Column-major float[16] <-> glm::dmat4.
glm::dmat4 toMatrix(const float* m) {
  requireArg(m, "matrix");
  glm::dmat4 out;
  for (int i = 0; i < 16; ++i) out[i / 4][i % 4] = double(m[i]);
  return out;
}
void fromMatrix(const glm::dmat4& m, float* out) {
  for (int i = 0; i < 16; ++i) out[i] = float(m[i / 4][i % 4]);
}

nph_status worldBounds(const nph_renderer* renderer, double min_m[3], double max_m[3]) {
  return onRenderer(renderer, "world_bounds", false, [&](const Renderer& r) {
    requireArg(min_m, "min_m");
    requireArg(max_m, "max_m");
    const glm::dvec3 lo = r.frame().min_m(), hi = r.frame().max_m();
    for (int i = 0; i < 3; ++i) {
      min_m[i] = lo[i];
      max_m[i] = hi[i];
    }
  });
}

nph_status setTime(nph_renderer* renderer, double time_index) {
  return onRenderer(renderer, "set_time", false, [&](Renderer& r) { r.setTime(time_index); });
}

nph_status setCamera(nph_renderer* renderer, const float view_from_world[16], const float clip_from_view[16],
                     int32_t width, int32_t height) {
  return onRenderer(renderer, "set_camera", false, [&](Renderer& r) {
    r.setCamera({toMatrix(view_from_world), toMatrix(clip_from_view), width, height});
  });
}

nph_status setCameraPreset(nph_renderer* renderer, const char* preset, int32_t width, int32_t height) {
  return onRenderer(renderer, "set_camera_preset", false,
                    [&](Renderer& r) { r.setCameraPreset(stringArg(preset, "preset"), width, height); });
}

nph_status getCamera(const nph_renderer* renderer, float view_from_world[16], float clip_from_view[16]) {
  return onRenderer(renderer, "get_camera", false, [&](const Renderer& r) {
    requireArg(view_from_world, "view_from_world");
    requireArg(clip_from_view, "clip_from_view");
    if (!r.camera()) throw ApiError(NPH_ERROR_WRONG_ORDER, "no camera yet: call set_camera or set_camera_preset first");
    fromMatrix(r.camera()->view_from_world, view_from_world);
    fromMatrix(r.camera()->clip_from_view, clip_from_view);
  });
}

nph_status setSun(nph_renderer* renderer, double azimuth_deg, double elevation_deg) {
  return onRenderer(renderer, "set_sun", false, [&](Renderer& r) { r.setSun(azimuth_deg, elevation_deg); });
}

nph_status setQualityPreset(nph_renderer* renderer, const char* preset) {
  return onRenderer(renderer, "set_quality_preset", false,
                    [&](Renderer& r) { r.setQualityPreset(stringArg(preset, "preset")); });
}

nph_status setParameter(nph_renderer* renderer, const char* name, double value) {
  return onRenderer(renderer, "set_parameter", false,
                    [&](Renderer& r) { r.setParameter(stringArg(name, "name"), value); });
}

nph_status getParameter(const nph_renderer* renderer, const char* name, double* value) {
  return onRenderer(renderer, "get_parameter", false, [&](const Renderer& r) {
    requireArg(value, "value");
    *value = r.parameter(stringArg(name, "name"));
  });
}

nph_status setHostDepth(nph_renderer* renderer, uint32_t texture) {
  return onRenderer(renderer, "set_host_depth", false, [&](Renderer& r) { r.setHostDepth(texture); });
}

nph_status render(nph_renderer* renderer) {
  return onRenderer(renderer, "render", true, [&](Renderer& r) { r.render(); });
}

nph_status renderToTexture(nph_renderer* renderer, uint32_t texture, int32_t level) {
  return onRenderer(renderer, "render_to_texture", true, [&](Renderer& r) {
    if (texture == 0) throw ApiError(NPH_ERROR_INVALID_ARGUMENT, "texture 0: name a host GL_TEXTURE_2D");
    r.render(texture, level);
  });
}

nph_status getStats(const nph_renderer* renderer, nph_stats* stats) {
  return onRenderer(renderer, "get_stats", false, [&](const Renderer& r) {
    requireArg(stats, "stats");
    if (stats->struct_size < sizeof(nph_stats)) {
      throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("stats->struct_size {} < {}: set it to sizeof(nph_stats)",
                                                             stats->struct_size, sizeof(nph_stats)));
    }
    if (!r.stats()) throw ApiError(NPH_ERROR_WRONG_ORDER, "no frame rendered yet");
    *stats = *r.stats();
  });
}

nph_status setPasses(nph_renderer* renderer, int32_t enabled) {
  return onRenderer(renderer, "set_passes", false, [&](Renderer& r) {
    if (enabled != 0 && enabled != 1)
      throw ApiError(NPH_ERROR_INVALID_ARGUMENT, fmt::format("enabled {}: expected 0 or 1", enabled));
    r.setPasses(enabled == 1);
  });
}

nph_status passToTexture(nph_renderer* renderer, const char* pass, uint32_t texture, int32_t level) {
  return onRenderer(renderer, "pass_to_texture", true, [&](Renderer& r) {
    const std::string name = stringArg(pass, "pass");
    const auto p = scene::passFromName(name);
    if (!p)
      throw ApiError(NPH_ERROR_INVALID_ARGUMENT,
                     fmt::format("pass '{}': expected one of {}", name, scene::passNames()));
    r.passToTexture(*p, texture, level);
  });
}

// Version 1: frozen. Append-only is not allowed either: a v2 is a new struct and a new table.
const nph_api_v1 kApiV1 = {
    1u,
    sizeof(nph_api_v1),
    &libraryVersion,
    &statusName,
    &lastErrorOf,
    &datasetOpen,
    &datasetClose,
    &datasetTimestepCount,
    &datasetTimestepUtc,
    &rendererCreate,
    &rendererDestroy,
    &worldBounds,
    &setTime,
    &setCamera,
    &setCameraPreset,
    &getCamera,
    &setSun,
    &setQualityPreset,
    &setParameter,
    &getParameter,
    &setHostDepth,
    &render,
    &renderToTexture,
    &getStats,
};

// Version 2: version 1's members in the same order (a v1 pointer to it stays valid), then the
// compositing passes. Frozen from its release on, as version 1.
const nph_api_v2 kApiV2 = {
    2u,
    sizeof(nph_api_v2),
    &libraryVersion,
    &statusName,
    &lastErrorOf,
    &datasetOpen,
    &datasetClose,
    &datasetTimestepCount,
    &datasetTimestepUtc,
    &rendererCreate,
    &rendererDestroy,
    &worldBounds,
    &setTime,
    &setCamera,
    &setCameraPreset,
    &getCamera,
    &setSun,
    &setQualityPreset,
    &setParameter,
    &getParameter,
    &setHostDepth,
    &render,
    &renderToTexture,
    &getStats,
    &setPasses,
    &passToTexture,
};
// The prefix a version-1 host reads through its nph_api_v1 pointer.
static_assert(offsetof(nph_api_v2, get_stats) == offsetof(nph_api_v1, get_stats) &&
              offsetof(nph_api_v2, set_passes) == sizeof(nph_api_v1));

}  // namespace
}  // namespace nph::api

extern "C" NPH_EXPORT const void* nph_get_api(uint32_t version) {
  if (version == 1u) return &nph::api::kApiV1;
  if (version == 2u) return &nph::api::kApiV2;
  return nullptr;
}
