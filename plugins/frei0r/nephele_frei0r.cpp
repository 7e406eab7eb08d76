// frei0r source plugin "nephele_clouds": cloud frames of a WRF/ICON dataset for video tools
// (ffmpeg's frei0r_src, MLT, GStreamer's frei0r elements), rendered through the plugin C API
// (nephele/nephele.h) in a headless GL context of its own.
//
// frei0r hosts may call an instance from any thread, while a nephele renderer is bound to the
// thread that created it (docs/plugin-api.md, threading). So every instance owns one render
// thread: it creates the context (EGL device → EGL surfaceless → OSMesa, NEPHELE_GL picks one, as
// for `nephele render`), the renderer and an RGBA8 target, and f0r_update hands it the frame to
// fill and waits.
//
// Output: 8-bit sRGB RGBA, row 0 at the top (frei0r's layout). By default the clouds over the
// lit ground, display-transformed exactly like `nephele render`'s PNG (ACES, sRGB, alpha 1);
// with clouds_only the cloud layer alone with straight alpha, for keying over other video.
extern "C" {
#include <dlfcn.h>
#include <frei0r.h>  // has no extern "C" of its own
}

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "nephele/nephele.h"
#include "render/gl/context.h"
#include "render/gl/gl.h"

namespace {

// frei0r parameters are conventionally in [0, 1]; angles are therefore fractions of their range.
enum Param { kDataset, kTime, kCamera, kSunAzimuth, kSunElevation, kQuality, kCloudsOnly, kClock, kParamCount };
constexpr double kAzimuthRangeDeg = 360.0, kElevationRangeDeg = 90.0;
/// `clock` 1 = this many timesteps per second of stream time (GStreamer's frei0r elements clamp
/// double parameters to [0, 1], so the range is a fraction like the angles).
constexpr double kClockRangeTimestepsPerS = 10.0;

const f0r_param_info_t kParamInfo[kParamCount] = {
    {"dataset", F0R_PARAM_STRING, "path of a .nph cache or a WRF wrfout / ICON NetCDF file"},
    {"time", F0R_PARAM_DOUBLE, "position in the dataset's timesteps: 0 = first, 1 = last, blended between"},
    {"camera", F0R_PARAM_STRING, "camera preset: overview, oblique or top"},
    {"sun_azimuth", F0R_PARAM_DOUBLE, "sun azimuth / 360 deg, clockwise from grid north (0.375 = 135 deg)"},
    {"sun_elevation", F0R_PARAM_DOUBLE, "sun elevation / 90 deg above the horizon (0.5 = 45 deg)"},
    {"quality", F0R_PARAM_STRING, "quality preset: draft, broadcast or reference"},
    {"clouds_only", F0R_PARAM_BOOL, "1: the cloud layer alone with alpha; 0: clouds over the lit ground"},
    {"clock", F0R_PARAM_DOUBLE,
     "advance with the host's stream clock: timesteps per second / 10 (0.1 = one timestep per second), "
     "added to `time`; 0 = `time` alone places every frame"},
};

struct Params {
  std::string dataset;
  double time = 0.0;
  std::string camera = "overview";
  double sun_azimuth = 135.0 / kAzimuthRangeDeg;
  double sun_elevation = 45.0 / kElevationRangeDeg;
  std::string quality = "broadcast";
  bool clouds_only = false;
  double clock = 0.0;  ///< timesteps per second / kClockRangeTimestepsPerS
};

/// The fractional timestep of a frame: `time` places the start in [0, last] and the host's stream
/// clock (f0r_update's time, seconds) advances it at `clock` × 10 timesteps/s; clamped to the data.
double frameTimestep(const Params& p, double stream_time_s, int32_t timesteps) {
  const double last = double(std::max(timesteps - 1, 0));
  const double clock =
      std::isfinite(p.clock) && std::isfinite(stream_time_s) ? p.clock * kClockRangeTimestepsPerS * stream_time_s : 0.0;
  return std::clamp(std::clamp(p.time, 0.0, 1.0) * last + clock, 0.0, last);
}

// libnephele is loaded on first use, not when the host loads this module: hosts scan every
// plugin at start-up (a GStreamer registry probe calls f0r_init and f0r_get_plugin_info of each),
// and libnephele brings the image, colour and NetCDF libraries with it (~265 shared objects). The
// module itself needs only libEGL and the C++ runtime (nephele::headless). libnephele.so.0 is
// found through this module's RUNPATH (the build tree, or $ORIGIN/.. once installed next to
// lib/frei0r-1), then the usual dlopen search.
const nph_api_v1* api() {
  static const nph_api_v1* table = []() -> const nph_api_v1* {
    void* lib = dlopen("libnephele.so.0", RTLD_NOW | RTLD_LOCAL);
    if (lib == nullptr) {
      std::fprintf(stderr, "nephele_clouds: cannot load libnephele.so.0: %s\n", dlerror());
      return nullptr;
    }
    const auto get = reinterpret_cast<nph_get_api_fn>(dlsym(lib, "nph_get_api"));
    const auto* t = get != nullptr ? static_cast<const nph_api_v1*>(get(1)) : nullptr;
    if (t == nullptr) std::fprintf(stderr, "nephele_clouds: libnephele.so.0 has no API version 1\n");
    return t;
  }();
  return table;
}

// The host's GetProcAddress as the C API types it (nph_get_proc_address_fn: returns nph_gl_proc).
// libnephele calls what it is given through that type, so handing it the context's own
// void* (*)(const char*) cast to it (as this plugin did until session 19) is a call through a
// pointer to another function type: undefined behaviour ([expr.call]; UBSan's -fsanitize=function
// aborted api.frei0r and both frei0r host tests under `make test-sanitize`). One trampoline of the
// API's type per backend: a headless backend has one GetProcAddress per process, which the
// trampoline calls with the type it has. A distinct function per backend also keeps libnephele's
// "entry points loaded from this GetProcAddress" check (api.cpp, loadEntryPoints) per backend.
using ContextProc = void* (*)(const char*);
std::atomic<ContextProc> g_egl_proc{nullptr}, g_osmesa_proc{nullptr};
nph_gl_proc eglContextProc(const char* name) { return reinterpret_cast<nph_gl_proc>(g_egl_proc.load()(name)); }
nph_gl_proc osmesaContextProc(const char* name) { return reinterpret_cast<nph_gl_proc>(g_osmesa_proc.load()(name)); }
/// The API's GetProcAddress for `context`; nullptr for a backend without one here (renderer_create
/// then refuses it, naming the field).
nph_get_proc_address_fn apiProcAddress(const nph::gl::Context& context) {
  switch (context.info().backend) {
    case nph::gl::Backend::Egl: g_egl_proc = context.getProcAddress(); return &eglContextProc;
    case nph::gl::Backend::OSMesa: g_osmesa_proc = context.getProcAddress(); return &osmesaContextProc;
    default: return nullptr;
  }
}

class Instance {
 public:
  Instance(int width, int height) : width_(width), height_(height), thread_([this] { loop(); }) {}
  ~Instance() {
    run([this] { teardown(); });
    {
      std::lock_guard lock(mutex_);
      quit_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }

  Params params;             // set by f0r_set_param_value on the host's thread
  std::string string_value;  // what f0r_get_param_value returned last for a string

  void update(double stream_time_s, std::uint32_t* out) {
    const Params p = params;
    run([this, &p, stream_time_s, out] { renderFrame(p, stream_time_s, out); });
  }

 private:
  /// Runs `job` on the render thread and waits for it.
  void run(std::function<void()> job) {
    std::unique_lock lock(mutex_);
    job_ = std::move(job);
    wake_.notify_all();
    done_.wait(lock, [this] { return !job_; });
  }

  void loop() {
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return quit_ || job_; });
      if (quit_) return;
      job_();
      job_ = nullptr;
      done_.notify_all();
    }
  }

  void report(const char* what, const void* handle) {
    // API messages name the call already ("dataset_open: /x.nph: no such file").
    const char* text = api() != nullptr ? api()->last_error(handle) : "";
    const std::string message = text[0] != '\0' ? std::string(text) : std::string(what);
    if (message != last_message_) std::fprintf(stderr, "nephele_clouds: %s\n", message.c_str());
    last_message_ = message;
  }

  bool ensureContext() {
    if (context_) return true;
    try {
      nph::gl::ContextOptions o;
      o.backend = nph::gl::backendFromEnvironment();
      if (o.backend == nph::gl::Backend::Glfw) o.backend = nph::gl::Backend::Auto;  // headless only
      o.visible = false;
      o.width = width_;
      o.height = height_;
      context_ = nph::gl::createHeadlessContext(o);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "nephele_clouds: no OpenGL 4.5 context: %s\n", e.what());
      return false;
    }
    glCreateTextures(GL_TEXTURE_2D, 1, &colour_);
    glTextureStorage2D(colour_, 1, GL_RGBA8, width_, height_);
    glCreateFramebuffers(1, &framebuffer_);
    glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, colour_, 0);
    return true;
  }

  bool ensureRenderer(const Params& p) {
    if (renderer_ != nullptr && p.dataset == dataset_path_ && p.quality == quality_) return true;
    closeRenderer();
    if (p.dataset.empty()) {
      report("no dataset", nullptr);
      return false;
    }
    if (api()->dataset_open(p.dataset.c_str(), &dataset_) != NPH_OK) {
      report("dataset_open", nullptr);
      return false;
    }
    api()->dataset_timestep_count(dataset_, &timesteps_);
    nph_renderer_desc desc = NPH_RENDERER_DESC_INIT;
    desc.get_proc_address = apiProcAddress(*context_);
    desc.quality_preset = p.quality.c_str();
    if (api()->renderer_create(dataset_, &desc, &renderer_) != NPH_OK) {
      report("renderer_create", dataset_);
      closeRenderer();
      return false;
    }
    dataset_path_ = p.dataset;
    quality_ = p.quality;
    api()->set_parameter(renderer_, "display_transform", 1.0);
    return true;
  }

  void renderFrame(const Params& p, double stream_time_s, std::uint32_t* out) {
    const std::size_t pixels = std::size_t(width_) * std::size_t(height_);
    std::fill(out, out + pixels, 0u);
    if (api() == nullptr || !ensureContext() || !ensureRenderer(p)) return;
    const double t = frameTimestep(p, stream_time_s, timesteps_);
    nph_renderer* r = renderer_;
    if (api()->set_time(r, t) != NPH_OK || api()->set_camera_preset(r, p.camera.c_str(), width_, height_) != NPH_OK ||
        api()->set_sun(r, p.sun_azimuth * kAzimuthRangeDeg, p.sun_elevation * kElevationRangeDeg) != NPH_OK ||
        api()->set_parameter(r, "ground", p.clouds_only ? 0.0 : 1.0) != NPH_OK) {
      report("parameters", r);
      return;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glViewport(0, 0, width_, height_);
    const float transparent[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, transparent);
    if (api()->render(r) != NPH_OK) {
      report("render", r);
      return;
    }
    std::vector<std::uint8_t> rgba(pixels * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    auto* dst = reinterpret_cast<std::uint8_t*>(out);
    const std::size_t row = std::size_t(width_) * 4;
    for (int y = 0; y < height_; ++y) {  // GL rows bottom-first → frei0r rows top-first
      std::copy_n(&rgba[std::size_t(height_ - 1 - y) * row], row, &dst[std::size_t(y) * row]);
    }
    if (p.clouds_only) {  // premultiplied → straight alpha, as video tools expect
      for (std::size_t i = 0; i < pixels; ++i) {
        std::uint8_t* px = &dst[4 * i];
        if (px[3] == 0) continue;
        for (int c = 0; c < 3; ++c) px[c] = std::uint8_t(std::min(255, (px[c] * 255 + px[3] / 2) / px[3]));
      }
    }
  }

  void closeRenderer() {
    if (renderer_ != nullptr) api()->renderer_destroy(renderer_);
    if (dataset_ != nullptr) api()->dataset_close(dataset_);
    renderer_ = nullptr;
    dataset_ = nullptr;
    dataset_path_.clear();
  }

  void teardown() {
    if (!context_) return;
    closeRenderer();
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteTextures(1, &colour_);
    context_.reset();
  }

  const int width_, height_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::function<void()> job_;
  bool quit_ = false;
  // Render-thread state.
  std::unique_ptr<nph::gl::Context> context_;
  GLuint colour_ = 0, framebuffer_ = 0;
  nph_dataset* dataset_ = nullptr;
  nph_renderer* renderer_ = nullptr;
  int32_t timesteps_ = 0;
  std::string dataset_path_, quality_, last_message_;
  std::thread thread_;  // last: starts after everything above is initialised
};

}  // namespace

extern "C" {

int f0r_init(void) { return 1; }  // libnephele is loaded by the first instance (api())
void f0r_deinit(void) {}

void f0r_get_plugin_info(f0r_plugin_info_t* info) {
  info->name = "nephele_clouds";
  info->author = "nephele";
  info->plugin_type = F0R_PLUGIN_TYPE_SOURCE;
  info->color_model = F0R_COLOR_MODEL_RGBA8888;
  info->frei0r_version = FREI0R_MAJOR_VERSION;
  info->major_version = 0;
  info->minor_version = 1;
  info->num_params = kParamCount;
  info->explanation = "Volumetric clouds of a WRF/ICON weather model run (deep light maps, GPU ray casting)";
}

void f0r_get_param_info(f0r_param_info_t* info, int index) {
  if (index >= 0 && index < kParamCount) *info = kParamInfo[index];
}

f0r_instance_t f0r_construct(unsigned int width, unsigned int height) {
  if (api() == nullptr) return nullptr;  // the message is on stderr
  try {
    return new Instance(int(width), int(height));
  } catch (...) {
    return nullptr;
  }
}

void f0r_destruct(f0r_instance_t instance) { delete static_cast<Instance*>(instance); }

void f0r_set_param_value(f0r_instance_t instance, f0r_param_t param, int index) {
  auto* in = static_cast<Instance*>(instance);
  if (in == nullptr || param == nullptr) return;
  Params& p = in->params;
  auto text = [param] {
    const char* s = *static_cast<f0r_param_string*>(param);
    return std::string(s ? s : "");
  };
  const double value = index == kDataset || index == kCamera || index == kQuality ? 0.0 : *static_cast<double*>(param);
  switch (index) {
    case kDataset: p.dataset = text(); break;
    case kTime: p.time = value; break;
    case kCamera: p.camera = text(); break;
    case kSunAzimuth: p.sun_azimuth = value; break;
    case kSunElevation: p.sun_elevation = value; break;
    case kQuality: p.quality = text(); break;
    case kCloudsOnly: p.clouds_only = value >= 0.5; break;
    case kClock: p.clock = value; break;
    default: break;
  }
}

void f0r_get_param_value(f0r_instance_t instance, f0r_param_t param, int index) {
  auto* in = static_cast<Instance*>(instance);
  if (in == nullptr || param == nullptr) return;
  const Params& p = in->params;
  auto text = [&](const std::string& s) {
    in->string_value = s;
    *static_cast<f0r_param_string*>(param) = in->string_value.data();
  };
  switch (index) {
    case kDataset: text(p.dataset); break;
    case kTime: *static_cast<double*>(param) = p.time; break;
    case kCamera: text(p.camera); break;
    case kSunAzimuth: *static_cast<double*>(param) = p.sun_azimuth; break;
    case kSunElevation: *static_cast<double*>(param) = p.sun_elevation; break;
    case kQuality: text(p.quality); break;
    case kCloudsOnly: *static_cast<double*>(param) = p.clouds_only ? 1.0 : 0.0; break;
    case kClock: *static_cast<double*>(param) = p.clock; break;
    default: break;
  }
}

void f0r_update(f0r_instance_t instance, double time, const uint32_t* /*inframe*/, uint32_t* outframe) {
  auto* in = static_cast<Instance*>(instance);
  if (in == nullptr || outframe == nullptr) return;
  try {
    in->update(time, outframe);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nephele_clouds: %s\n", e.what());
  }
}

}  // extern "C"
