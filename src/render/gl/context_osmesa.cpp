// OSMesa backend. libOSMesa exports its own gl* symbols, so it is never linked into nephele: it is
// loaded with dlopen(RTLD_LOCAL) and every GL entry point comes from OSMesaGetProcAddress through
// the generated loader. OSMesaCreateContextAttribs asks for a 4.5 core profile (Mesa llvmpipe).
#include <dlfcn.h>

#include <string>
#include <vector>

#include "core/env.h"
#include "core/error.h"
#include "render/gl/context.h"
#include "render/gl/gl.h"

namespace nph::gl {
namespace {

// From <GL/osmesa.h> (Mesa), which cannot be included here: it pulls in <GL/gl.h>, whose
// prototypes clash with the loader's gl* macros. Values are part of OSMesa's frozen ABI.
struct osmesa_context;
using OSMesaContext = osmesa_context*;
using OSMESAproc = void (*)();
constexpr int OSMESA_FORMAT = 0x22;
constexpr int OSMESA_RGBA = 0x1908;  // GL_RGBA
constexpr int OSMESA_DEPTH_BITS = 0x30;
constexpr int OSMESA_STENCIL_BITS = 0x31;
constexpr int OSMESA_PROFILE = 0x33;
constexpr int OSMESA_CORE_PROFILE = 0x34;
constexpr int OSMESA_CONTEXT_MAJOR_VERSION = 0x36;
constexpr int OSMESA_CONTEXT_MINOR_VERSION = 0x37;

using CreateContextAttribsFn = OSMesaContext (*)(const int*, OSMesaContext);
using MakeCurrentFn = GLboolean (*)(OSMesaContext, void*, GLenum, GLsizei, GLsizei);
using DestroyContextFn = void (*)(OSMesaContext);
using GetProcAddressFn = OSMESAproc (*)(const char*);
using GetCurrentContextFn = OSMesaContext (*)();

struct OSMesaLibrary {
  void* handle = nullptr;
  std::string path;
  CreateContextAttribsFn createContextAttribs = nullptr;
  MakeCurrentFn makeCurrent = nullptr;
  DestroyContextFn destroyContext = nullptr;
  GetProcAddressFn getProcAddress = nullptr;
  GetCurrentContextFn getCurrentContext = nullptr;
};

template <class Fn>
Fn symbol(void* handle, const char* name) {
  return reinterpret_cast<Fn>(dlsym(handle, name));
}

/// Loads libOSMesa once per process (NEPHELE_OSMESA_LIBRARY overrides the search).
const OSMesaLibrary& library() {
  static const OSMesaLibrary lib = [] {
    OSMesaLibrary l;
    std::vector<std::string> candidates = {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"};
    if (auto v = env::get("NEPHELE_OSMESA_LIBRARY")) candidates.insert(candidates.begin(), *v);
    std::string errors;
    for (const auto& c : candidates) {
      l.handle = dlopen(c.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (l.handle != nullptr) {
        l.path = c;
        break;
      }
      errors += "\n    " + std::string(dlerror());
    }
    if (l.handle == nullptr) {
      throw GlError("osmesa: libOSMesa could not be loaded (Debian package libosmesa6):" + errors);
    }
    l.createContextAttribs = symbol<CreateContextAttribsFn>(l.handle, "OSMesaCreateContextAttribs");
    l.makeCurrent = symbol<MakeCurrentFn>(l.handle, "OSMesaMakeCurrent");
    l.destroyContext = symbol<DestroyContextFn>(l.handle, "OSMesaDestroyContext");
    l.getProcAddress = symbol<GetProcAddressFn>(l.handle, "OSMesaGetProcAddress");
    l.getCurrentContext = symbol<GetCurrentContextFn>(l.handle, "OSMesaGetCurrentContext");
    if (!l.createContextAttribs || !l.makeCurrent || !l.destroyContext || !l.getProcAddress || !l.getCurrentContext) {
      throw GlError("osmesa: " + l.path + " lacks OSMesaCreateContextAttribs or another entry point");
    }
    return l;
  }();
  return lib;
}

void* osmesaProc(const char* name) { return reinterpret_cast<void*>(library().getProcAddress(name)); }

class OSMesaGlContext final : public Context {
 public:
  OSMesaGlContext(OSMesaContext ctx, int width, int height, bool debug)
      : ctx_(ctx), width_(width), height_(height), buffer_(std::size_t(width) * std::size_t(height) * 4u) {
    makeCurrentRaw();
    finishInit(Backend::OSMesa, "OSMesa (" + library().path + "), dlopen", debug, &osmesaProc);
  }
  ~OSMesaGlContext() override { library().destroyContext(ctx_); }
  void makeCurrent() override {
    makeCurrentRaw();
    ensureEntryPoints();
  }
  void doneCurrent() override {
    // OSMesa cannot release a context without making another current; NULL unbinds.
    library().makeCurrent(nullptr, nullptr, 0, 0, 0);
  }

 private:
  void makeCurrentRaw() {
    if (library().makeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, width_, height_) != GL_TRUE) {
      throw GlError("osmesa: OSMesaMakeCurrent failed");
    }
  }
  OSMesaContext ctx_;
  int width_, height_;
  std::vector<unsigned char> buffer_;  // the default framebuffer's colour buffer (RGBA8)
};

}  // namespace

std::unique_ptr<Context> createOSMesaContext(const ContextOptions& options) {
  const auto& lib = library();
  const bool debug = options.debug.value_or(false);
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_STENCIL_BITS,
                         8,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         4,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         5,
                         0};
  OSMesaContext ctx = lib.createContextAttribs(attribs, nullptr);
  if (ctx == nullptr) {
    throw GlError("osmesa: OSMesaCreateContextAttribs(4.5 core) failed (" + lib.path + ")");
  }
  const int w = options.width > 0 ? options.width : 1;
  const int h = options.height > 0 ? options.height : 1;
  try {
    return std::make_unique<OSMesaGlContext>(ctx, w, h, debug);
  } catch (...) {
    // The constructor threw before ownership was established.
    lib.destroyContext(ctx);
    throw;
  }
}

}  // namespace nph::gl
