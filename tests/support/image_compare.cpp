#include "support/image_compare.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

namespace nph::test {

std::string testOutputDir() {
  std::filesystem::create_directories(NEPHELE_TEST_OUTPUT_DIR);
  return NEPHELE_TEST_OUTPUT_DIR;
}

Image readImage(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw std::runtime_error("readImage: " + path + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.channels = spec.nchannels;
  img.pixels.resize(std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels));
  if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data())) {
    throw std::runtime_error("readImage: " + path + ": " + in->geterror());
  }
  return img;
}

void writeImage(const Image& image, const std::string& path) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error("writeImage: " + path + ": " + OIIO::geterror());
  const bool isExr = path.size() > 4 && path.substr(path.size() - 4) == ".exr";
  OIIO::ImageSpec spec(image.width, image.height, image.channels,
                       isExr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) || !out->close()) {
    throw std::runtime_error("writeImage: " + path + ": " + out->geterror());
  }
}

CompareResult compareImages(const Image& actual, const Image& expected, Tolerance tolerance, const std::string& name) {
  CompareResult r;
  if (actual.width != expected.width || actual.height != expected.height || actual.channels != expected.channels) {
    r.message = fmt::format("{}: size mismatch: actual {}x{}x{}, expected {}x{}x{}", name, actual.width, actual.height,
                            actual.channels, expected.width, expected.height, expected.channels);
    return r;
  }
  Image diff = actual;
  double sum = 0.0;
  std::size_t nonFinite = 0;
  for (std::size_t i = 0; i < actual.pixels.size(); ++i) {
    const double a = actual.pixels[i];
    const double e = expected.pixels[i];
    double d = std::abs(a - e);
    if (!std::isfinite(d)) {
      ++nonFinite;
      d = std::numeric_limits<double>::infinity();
    }
    diff.pixels[i] = static_cast<float>(d);
    r.max_abs = std::max(r.max_abs, d);
    sum += std::isfinite(d) ? d : 0.0;
  }
  r.mean_abs = actual.pixels.empty() ? 0.0 : sum / double(actual.pixels.size());
  r.pass = nonFinite == 0 && r.max_abs <= tolerance.max_abs && r.mean_abs <= tolerance.mean_abs;
  r.message = fmt::format("{}: max |diff| {:.3g} (tolerance {:.3g}), mean |diff| {:.3g} (tolerance {:.3g}){}", name,
                          r.max_abs, tolerance.max_abs, r.mean_abs, tolerance.mean_abs,
                          nonFinite ? fmt::format(", {} non-finite", nonFinite) : std::string());
  if (!r.pass) {
    const std::string base = testOutputDir() + "/" + name;
    const double scale = (std::isfinite(r.max_abs) && r.max_abs > 0.0) ? 1.0 / r.max_abs : 1.0;
    for (float& d : diff.pixels) d = std::isfinite(d) ? static_cast<float>(double(d) * scale) : 1.0f;
    writeImage(actual, base + ".actual.exr");
    writeImage(expected, base + ".expected.exr");
    writeImage(diff, base + ".diff.exr");
    r.diff_path = base + ".diff.exr";
    r.message += "\n  wrote " + base + ".{actual,expected,diff}.exr";
  }
  return r;
}

CompareResult compareToFile(const Image& actual, const std::string& expectedPath, Tolerance tolerance,
                            const std::string& name) {
  return compareImages(actual, readImage(expectedPath), tolerance, name);
}

}  // namespace nph::test
