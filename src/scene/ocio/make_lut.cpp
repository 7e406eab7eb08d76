// Writes nephele_aces_fitted.spi1d for config.ocio (issue 15): the ACES fitted tone curve of
// glsl/common/display.glsl (Narkowicz 2016, via scene::applyToneCurve — the very function the PNG
// writer uses) sampled on [0, kDomainMax] linear. Beyond the domain OCIO clamps to the ends; the
// curve reaches 1 at c ≈ 13 (output_image.h), so clamping at 16 changes nothing.
// usage: nephele_ocio_lut OUT.spi1d
#include <cstdio>
#include <fstream>

#include "scene/output_image.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.spi1d\n", argv[0]);
    return 2;
  }
  // 16384 samples over [0, 16]: linear interpolation between them is within 3e-6 of the curve
  // (its second derivative is < 10 there), 1e-3 of an 8-bit code after sRGB encoding.
  constexpr int kSamples = 16384;
  constexpr double kDomainMax = 16.0;
  std::ofstream out(argv[1]);
  out << "Version 1\nFrom 0.0 " << kDomainMax << "\nLength " << kSamples << "\nComponents 1\n{\n";
  out.precision(9);
  for (int i = 0; i < kSamples; ++i) {
    const double c = kDomainMax * i / (kSamples - 1);
    out << "    " << nph::scene::applyToneCurve(static_cast<float>(c), nph::scene::ToneCurve::AcesFitted) << "\n";
  }
  out << "}\n";
  out.close();
  if (!out) {
    std::fprintf(stderr, "%s: cannot write the LUT\n", argv[1]);
    return 1;
  }
  return 0;
}
