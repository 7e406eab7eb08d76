#include "scene/image_codec.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "core/error.h"
#include "core/log.h"
#include "scene/codec/image_codec_module.h"

namespace nph::scene::image_codec {
namespace {

struct Loaded {
  const ModuleV1* module = nullptr;
  std::string path;
};

Loaded tryLoad(const std::vector<std::string>& candidates, const std::string& what) {
  std::string tried;
  for (const std::string& path : candidates) {
    if (path.empty()) continue;
    // RTLD_LOCAL: OpenImageIO's symbols stay the module's; never closed (its plugins keep state).
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = ::dlerror();  // names the file
      tried += fmt::format("{}{}", tried.empty() ? "" : "; ", why != nullptr ? why : path + ": cannot be loaded");
      continue;
    }
    using Entry = const ModuleV1* (*)();
    auto entry = reinterpret_cast<Entry>(::dlsym(handle, "nph_image_codec_v1"));
    const ModuleV1* m = entry != nullptr ? entry() : nullptr;
    if (m == nullptr || m->version != kModuleVersion) {
      tried += fmt::format("{}{}: not nephele's image codec module version {}", tried.empty() ? "" : "; ", path,
                           kModuleVersion);
      ::dlclose(handle);
      continue;
    }
    return {m, path};
  }
  throw IoError(fmt::format(
      "{}: cannot write or read images: the image codec module (nephele_image_codec.so, OpenImageIO) did not "
      "load ({}); set NEPHELE_IMAGE_CODEC to its path, or reinstall nephele (it belongs in <libdir>/nephele/)",
      what, tried.empty() ? std::string("no path to try") : tried));
}

std::vector<std::string> defaultCandidates() {
  if (const char* env = std::getenv("NEPHELE_IMAGE_CODEC"); env != nullptr && *env != '\0') return {env};
  std::vector<std::string> c;
  // Beside the program or library this code is linked into, as installed (bin/nephele,
  // lib/libnephele.so, the Python module, a host's plugin): a relocated prefix finds its own.
  Dl_info self{};
  if (::dladdr(reinterpret_cast<void*>(&defaultCandidates), &self) != 0 && self.dli_fname != nullptr) {
    const std::filesystem::path dir = std::filesystem::path(self.dli_fname).parent_path();
    for (const char* rel :
         {"nephele", "../" NEPHELE_INSTALL_LIBDIR "/nephele", "../../" NEPHELE_INSTALL_LIBDIR "/nephele"})
      if (std::error_code ec; std::filesystem::is_regular_file(dir / rel / "nephele_image_codec.so", ec))
        c.push_back((dir / rel / "nephele_image_codec.so").lexically_normal().string());
  }
  c.emplace_back(NEPHELE_IMAGE_CODEC_BUILD);
  c.emplace_back(NEPHELE_IMAGE_CODEC_INSTALL);
  return c;
}

/// The module, loaded on first use; a failed load is retried by the next call (and reported again).
const Loaded& module(const std::string& what) {
  static std::mutex mutex;
  static Loaded loaded;
  const std::lock_guard<std::mutex> lock(mutex);
  if (loaded.module == nullptr) {
    loaded = tryLoad(defaultCandidates(), what);
    log::debug("image codec: {}", loaded.path);
  }
  return loaded;
}

}  // namespace

std::string loadFrom(const std::vector<std::string>& candidates, const std::string& what) {
  return tryLoad(candidates, what).path;
}

std::string modulePath(const std::string& what) { return module(what).path; }

void write(const std::string& file, const std::string& format_path, const WriteSpec& spec, const void* pixels,
           Type given) {
  const std::string why = module(format_path).module->write(file, format_path, spec, pixels, given);
  if (!why.empty()) throw IoError(fmt::format("{}: cannot write the image: {}", format_path, why));
}

std::optional<FloatImage> readFloat(const std::string& path, const std::function<void(int, int)>& check) {
  const ModuleV1& m = *module(path).module;
  FloatImage img;
  if (m.probeFloat(path, &img.width, &img.height, &img.channels) != 0) return std::nullopt;
  check(img.width, img.height);
  img.pixels.resize(std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels));
  const std::string why = m.readFloat(path, img.channels, img.pixels.data());
  if (!why.empty()) throw InputError(fmt::format("{}: cannot decode the image: {}", path, why));
  return img;
}

}  // namespace nph::scene::image_codec
