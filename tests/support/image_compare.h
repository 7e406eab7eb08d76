#pragma once
// Golden-image comparison for tests (STYLE.md 8, after Magnum's CompareImageToFile{max, mean}).
// Images are compared channel by channel as floats; a comparison passes when the maximum absolute
// difference is <= max_abs and the mean absolute difference is <= mean_abs. Every call site states
// why its tolerances are what they are. On failure actual, expected and a diff image (|a-e| scaled
// so the largest difference is white) are written with OpenImageIO to
//   <build>/test-output/<name>.{actual,expected,diff}.exr
#include <string>
#include <vector>

namespace nph::test {

/// A float image in memory, channels interleaved, rows top to bottom.
struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;
  float& at(int x, int y, int c) {
    return pixels[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(channels) + std::size_t(c)];
  }
  float at(int x, int y, int c) const {
    return pixels[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(channels) + std::size_t(c)];
  }
};

struct Tolerance {
  double max_abs = 0.0;
  double mean_abs = 0.0;
};

struct CompareResult {
  bool pass = false;
  double max_abs = 0.0;
  double mean_abs = 0.0;
  std::string message;    ///< human-readable summary (and where the files went on failure)
  std::string diff_path;  ///< empty when nothing was written
};

/// Compares two in-memory images.
CompareResult compareImages(const Image& actual, const Image& expected, Tolerance tolerance, const std::string& name);

/// Compares against an image file (EXR, PNG, ...) read with OpenImageIO. PNG data is in [0, 1].
CompareResult compareToFile(const Image& actual, const std::string& expectedPath, Tolerance tolerance,
                            const std::string& name);

Image readImage(const std::string& path);
void writeImage(const Image& image, const std::string& path);

/// Directory that failing comparisons write into (created on demand).
std::string testOutputDir();

}  // namespace nph::test
