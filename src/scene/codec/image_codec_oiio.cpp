// nephele_image_codec.so: the only code that includes OpenImageIO (scene/image_codec.h explains
// why it is a module). Self-contained: OpenImageIO and the C++ runtime, no nephele library.
#include <OpenImageIO/imageio.h>

#include "scene/codec/image_codec_module.h"

namespace {

using nph::scene::image_codec::Type;
using nph::scene::image_codec::WriteSpec;

OIIO::TypeDesc typeOf(Type t) {
  switch (t) {
    case Type::UInt8: return OIIO::TypeDesc::UINT8;
    case Type::UInt16: return OIIO::TypeDesc::UINT16;
    case Type::Half: return OIIO::TypeDesc::HALF;
    case Type::Float: return OIIO::TypeDesc::FLOAT;
  }
  return OIIO::TypeDesc::UNKNOWN;
}

std::string write(const std::string& file, const std::string& format_path, const WriteSpec& s, const void* pixels,
                  Type given) {
  OIIO::ImageSpec spec(s.width, s.height, s.channels, typeOf(s.format));
  if (!s.channel_names.empty()) spec.channelnames = s.channel_names;
  spec.channelformats.clear();
  for (Type t : s.channel_formats) spec.channelformats.push_back(typeOf(t));
  spec.alpha_channel = s.alpha_channel;
  spec.z_channel = s.z_channel;
  for (const auto& [name, value] : s.text) spec.attribute(name, value);
  for (const auto& [name, value] : s.integers) spec.attribute(name, value);
  auto out = OIIO::ImageOutput::create(format_path);
  if (!out) return OIIO::geterror();
  if (!out->open(file, spec)) return out->geterror();
  if (!out->write_image(typeOf(given), pixels)) {
    std::string why = out->geterror();
    out->close();
    return why;
  }
  if (!out->close()) return out->geterror();
  return {};
}

bool linear(const OIIO::ImageSpec& spec) {
  const auto b = spec.format.basetype;
  return b == OIIO::TypeDesc::HALF || b == OIIO::TypeDesc::FLOAT || b == OIIO::TypeDesc::DOUBLE;
}

int probeFloat(const std::string& path, int* width, int* height, int* channels) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    (void)OIIO::geterror();
    return 1;
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (!linear(spec) || spec.nchannels < 1 || spec.nchannels > 4 || spec.depth > 1) return 1;
  *width = spec.width;
  *height = spec.height;
  *channels = spec.nchannels;
  return 0;
}

std::string readFloat(const std::string& path, int channels, float* pixels) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return OIIO::geterror();
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels)) return in->geterror();
  return {};
}

const nph::scene::image_codec::ModuleV1 kModule{nph::scene::image_codec::kModuleVersion, &write, &probeFloat,
                                                &readFloat};

}  // namespace

extern "C" __attribute__((visibility("default"))) const nph::scene::image_codec::ModuleV1* nph_image_codec_v1() {
  return &kModule;
}
