#pragma once
// Image files through OpenImageIO, loaded only when an image is read or written (issue 19, "image
// libraries loaded only when an image is written"). OpenImageIO pulls in ~150 shared libraries of
// its own (codecs, OpenCV, FFmpeg, …): linked into every program they cost each start-up ≈ 0.3 s
// and ≈ 100 MB resident, also for a host of the plugin API, `nephele view` or `nephele info` that
// never writes an image. The OpenImageIO code lives in a module, nephele_image_codec.so
// (codec/image_codec_oiio.cpp), that the first read or write dlopens, from
//   1. $NEPHELE_IMAGE_CODEC (a path to the module; nothing else then),
//   2. <libdir>/nephele/ beside the program or library the loader is linked into (an installed,
//      possibly relocated prefix: bin/nephele, lib/libnephele.so, the Python module),
//   3. the build tree's module (where it was built),
//   4. the configured install prefix's <libdir>/nephele/.
// A missing module is an IoError that names the image, the paths tried and why they failed.
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace nph::scene::image_codec {

enum class Type : int { UInt8, UInt16, Half, Float };

/// What is written: OpenImageIO's ImageSpec, in the few fields nephele sets.
struct WriteSpec {
  int width = 0, height = 0, channels = 0;
  Type format = Type::UInt8;               ///< the file's pixel type
  std::vector<std::string> channel_names;  ///< empty: OpenImageIO's R, G, B, A
  std::vector<Type> channel_formats;       ///< empty: every channel `format`
  int alpha_channel = -1, z_channel = -1;
  std::vector<std::pair<std::string, std::string>> text;  ///< string attributes
  std::vector<std::pair<std::string, int>> integers;      ///< integer attributes
};

/// Writes `pixels` (channel-interleaved rows top to bottom, of type `given`) into `file`, in the
/// format that `format_path`'s extension names (the two differ for a temporary written first and
/// renamed). Throws IoError("<format_path>: cannot write the image: <why>").
void write(const std::string& file, const std::string& format_path, const WriteSpec& spec, const void* pixels,
           Type given);

struct FloatImage {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;  ///< interleaved, top row first
};

/// A linear (half, float or double) 2-D image of 1–4 channels that OpenImageIO reads (EXR, HDR),
/// or nullopt when it reads none or the image is integer-coded. `check(width, height)` runs before
/// the pixels are allocated (and may throw). Throws InputError when the pixels do not decode.
std::optional<FloatImage> readFloat(const std::string& path, const std::function<void(int, int)>& check);

/// The module's file, loading it if needed (what `write`/`readFloat` use); an IoError naming `what`
/// when it does not load. A command that will write images calls it first, so a missing module
/// stops it before the render rather than after.
std::string modulePath(const std::string& what = "the image codec");

/// Loads the module from the first of `candidates` that opens and exports its entry point;
/// throws IoError naming `what` (the image asked for) and every candidate with its error. The
/// loader behind modulePath(), exposed for its tests.
std::string loadFrom(const std::vector<std::string>& candidates, const std::string& what);

}  // namespace nph::scene::image_codec
