#pragma once
// The entry point of nephele_image_codec.so (scene/image_codec.h). Built by the same compiler in
// the same build as its loader, so C++ types cross it; errors come back as strings, not exceptions.
#include <string>

#include "scene/image_codec.h"

namespace nph::scene::image_codec {

inline constexpr int kModuleVersion = 1;

struct ModuleV1 {
  int version;
  /// "" on success, else OpenImageIO's reason.
  std::string (*write)(const std::string& file, const std::string& format_path, const WriteSpec& spec,
                       const void* pixels, Type given);
  /// 0: a linear image of width × height × channels; 1: none OpenImageIO reads as one.
  int (*probeFloat)(const std::string& path, int* width, int* height, int* channels);
  /// "" on success (pixels sized width·height·channels), else OpenImageIO's reason.
  std::string (*readFloat)(const std::string& path, int channels, float* pixels);
};

}  // namespace nph::scene::image_codec

/// The module's one exported symbol.
extern "C" const nph::scene::image_codec::ModuleV1* nph_image_codec_v1();
